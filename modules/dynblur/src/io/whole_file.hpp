// SPDX-License-Identifier: Apache-2.0
// Private: a parameter file written whole or not at all.
#ifndef OPENCV_DYNBLUR_IO_WHOLE_FILE_HPP
#define OPENCV_DYNBLUR_IO_WHOLE_FILE_HPP

#include <opencv2/core.hpp>

#include <functional>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief Writes `filename` with cv::FileStorage: `write` fills a temporary file beside it (of the same
extension, which decides the format), renamed over it once complete, so that a reader never sees half
a file and a failed save leaves the old file as it was.
@param filename the file to write.
@param who the caller, for messages ("Mount::save").
@param write fills the open storage; what it throws is passed on, the temporary file removed. */
void saveWhole(const String& filename, const String& who, const std::function<void(FileStorage&)>& write);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
