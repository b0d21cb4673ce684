// SPDX-License-Identifier: Apache-2.0
// Private: element-wise loops over rows, vectorised by the compiler.
#ifndef OPENCV_DYNBLUR_RESTORE_ROW_ARITHMETIC_HPP
#define OPENCV_DYNBLUR_RESTORE_ROW_ARITHMETIC_HPP


namespace cv {
namespace dynblur {
namespace detail {

//! sum[x] += p[x] for x in [0, n), in the CPU's widest vectors.
void addRow(const float* p, int n, float* sum);

//! dst[x] += w · src[x] for x in [begin, end).
void accumulateScaled(float* dst, const float* src, float w, int begin, int end);

//! dst[x] = a[x] · b[x] for x in [0, n).
void multiplyInto(float* dst, const float* a, const float* b, int n);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
