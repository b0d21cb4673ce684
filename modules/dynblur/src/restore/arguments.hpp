// SPDX-License-Identifier: Apache-2.0
// Private: the checks of the restoration's arguments, each error naming the argument and what it must be.
#ifndef OPENCV_DYNBLUR_RESTORE_ARGUMENTS_HPP
#define OPENCV_DYNBLUR_RESTORE_ARGUMENTS_HPP

#include "opencv2/dynblur/deconv.hpp"

namespace cv {
namespace dynblur {

/** Throws cv::Exception unless `image` (named `name` in the message, prefixed by `function`) is a
non-empty 2-D CV_32F image of 1 to 4 channels, finite, and with `nonNegative` ≥ 0. */
void checkImage(InputArray image, const char* name, const char* function, bool nonNegative);

//! Throws cv::Exception unless `bank` is a complete, valid bank for images of `imageSize`.
void checkBank(const PsfBank& bank, Size imageSize, const char* function);

//! Throws cv::Exception naming the RLParams field that is out of range; `function` prefixes the message.
void checkRLParams(const RLParams& params, const char* function);

}  // namespace dynblur
}  // namespace cv

#endif
