// Private: the Richardson–Lucy iteration shared by richardsonLucy and richardsonLucyVariant.
#ifndef OPENCV_DYNBLUR_DECONV_RL_HPP
#define OPENCV_DYNBLUR_DECONV_RL_HPP

#include "deconv_operator.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief Runs RL on every channel plane with one operator.

x ← x ⊙ Aᵀ(damped(b / A x)) / (Aᵀ1 − λ div(∇x/|∇x|)), with Biggs–Andrews extrapolation of x when
params.accelerate, stopping early at params.tolerance.
@param op the blur. @param blurred frame-sized CV_32FC1 planes.
@param normalizer Aᵀ1 (latent size); empty: 1 everywhere, the unnormalised update of scikit-image's
richardson_lucy. Latent pixels whose normaliser is ≤ kUnobserved are not updated.
@param estimate in: the start (latent-sized planes, ≥ 0); out: the result.
@return the iterations run. */
int iterateRichardsonLucy(BlurOperator& op, const std::vector<Mat>& blurred, const Mat& normalizer,
                          const RLParams& params, std::vector<Mat>& estimate);

//! Normaliser below which a latent pixel counts as not seen by any frame pixel.
constexpr float kUnobserved = 1e-3f;

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
