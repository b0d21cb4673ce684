// SPDX-License-Identifier: Apache-2.0
// Private: the element-wise row loops of the Richardson–Lucy iteration and of reading a frame in and
// out, each a pass over one row the compiler vectorises (cloned per instruction set: simd_clones.hpp).
#ifndef OPENCV_DYNBLUR_RESTORE_RL_ROWS_HPP
#define OPENCV_DYNBLUR_RESTORE_RL_ROWS_HPP

#include "restore/kernels/update_terms.hpp"

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

// scikit-image adds this to the reblurred image before dividing; kept so ZERO-boundary results match.
constexpr float kRatioEpsilon = 1e-12f;

using kernels::RowTv;
using kernels::UpdateSums;

//! ratio = b / (A x) over one row of n, damped as MATLAB's deconvlucy does (see rl_rows.cpp).
void ratioRow(const float* b, const float* ab, float* r, int n, float scale, float invThreshold);

/** x_{k+1} = y ⊙ correction / (norm − λ curvature) over one row, with the accelerated step's sums,
by the kernels of this CPU (src/restore/kernels/update_terms.hpp says what every argument is). */
void updateRow(const float* y, const float* correction, bool correctionExcess, const float* norm, float rowNorm,
               const RowTv* tv, float tvWeight, float upper, int n, float* out, uint16_t* step, float scale,
               UpdateSums& sums);

//! The value of a row whose elements are all equal, NaN otherwise.
float constantValue(const float* p, int n);

//! y = max(x + a (x − y), 0) over one row: x_{k−1} in, the extrapolated y_k out (RL needs y ≥ 0).
void extrapolateRow(const float* x, float a, int n, float* y);

//! Σ p[x] and max p[x] over a row.
double rowSumAndPeak(const float* p, int n, double& peak);

//! Σ |mask * image| over one row of Immerkær's 3×3 mask, `channels` interleaved (rows a, m, b).
float noiseMaskSumRow(const float* a, const float* m, const float* b, int width, int channels);

//! p[x] = p[x] · factor.
void scaleRow(float* p, float factor, int n);

//! One plane's row takes the luminance's change from `before` to `restored` (luminanceChanged).
void applyLuminanceRow(const float* restored, const float* before, float black, float upper, int n, const float* plane,
                       float* out);

//! out[x] = the mean of the planes' rows y, columns [x0, x0 + n) (the sum in plane order, then times 1 / planes).
void meanRow(const std::vector<Mat>& planes, int y, int x0, int n, float* out);

//! out[x] = the mean of the `channels` interleaved values of pixel x (constant strides, as channelRow).
void channelMeanRow(const float* interleaved, int channels, int n, float* out);

//! p[x] = min(max(p[x], 0), 1) for x in [0, n): an image in [0, 1] from a restoration that overshoots.
void clampRowToUnit(float* p, int n);

//! out[x] = interleaved[x · channels + channel] for x in [0, n).
void channelRow(const float* interleaved, int channels, int channel, int n, float* out);

//! out[x · channels + c] = planes[c][x] for x in [0, n): channelRow's inverse.
void interleaveRow(const float* const* planes, int channels, int n, float* out);

//! Whether a row holds only finite values, and its least and largest.
bool finiteRow(const float* p, int n, float& low, float& high);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
