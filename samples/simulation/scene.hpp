// SPDX-License-Identifier: Apache-2.0
// A generated test scene, so the demo needs no image file: textures at many scales (text, edges,
// fine stripes, a Siemens star, smooth gradients), the kinds of detail motion blur destroys.
#ifndef DYNBLUR_SAMPLES_SCENE_HPP
#define DYNBLUR_SAMPLES_SCENE_HPP

#include <opencv2/core.hpp>

namespace dynblur_samples {

/** Deterministic 8-bit sRGB BGR scene of the given size (pixels). */
cv::Mat makeScene(const cv::Size& size, unsigned seed = 20261122u);

}  // namespace dynblur_samples

#endif
