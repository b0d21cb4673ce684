// SPDX-License-Identifier: Apache-2.0
// Private: the Richardson–Lucy iteration shared by richardsonLucy and richardsonLucyVariant.
#ifndef OPENCV_DYNBLUR_DECONV_RL_HPP
#define OPENCV_DYNBLUR_DECONV_RL_HPP

#include "restore/deconv_operator.hpp"
#include "restore/rl/fill_unobserved.hpp"
#include "restore/rl/frame_planes.hpp"
#include "restore/rl/restored_planes.hpp"
#include "restore/rl/rl_rows.hpp"
#include "restore/rl/rl_terms.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief Buffers the restoration keeps between calls. Fresh memory costs a page fault per 4 KiB
on first touch, which for a 1280×960 RGB frame's dozen planes takes longer than the iterations
themselves; DynamicDeblurrer keeps one workspace, so a stream of frames allocates nothing. */
struct RLWorkspace
{
    std::vector<Mat> estimate, other;
    std::vector<Mat> observed;  // the frame's planes, when it has several
    Mat step;                   // the running plane's last RL step, bfloat16 (CV_16U)
    Mat ratio, reblurred, correction;  // shared by the planes
    Mat packedEstimate, packedRatio;   // packRowPair rows of the estimate and of ratio − 1, when the operator reads them
                                       // (ratio: unless it takes the pairs as they come, takesPackedPairs)
    Mat normalizer, valid;
    //! Keep the iterations' planes after a call (for the next frame) instead of freeing them before the output is written.
    bool persistent = false;
};

/** @brief Runs RL on every channel plane with one operator.

x ← x ⊙ Aᵀ(damped(b / A x)) / (Aᵀ1 − λ div(∇x/|∇x|)), with Biggs–Andrews extrapolation of x when
params.accelerate, stopping early at params.tolerance; each plane is its own problem (extrapolation
and stopping per plane). With 3–4 planes and params.colorIterations
in [0, iterations), the iterations after the first colorIterations run on the planes' mean alone,
whose change then scales every plane (left to the caller: see `change`).
@param op the blur. @param blurred the frame, CV_32F with one channel per estimate plane.
@param observed observeFrame(blurred); the luminance phase may overwrite its planes.
@param normalizer Aᵀ1 (latent size); empty: 1 everywhere, the unnormalised update of scikit-image's
richardson_lucy. Latent pixels whose normaliser is ≤ kUnobserved are not updated.
@param estimate in: the start (latent-sized planes, ≥ 0); out: the result, with a luminance phase
before its change.
@param workspace buffers, reused when their sizes fit.
@param change out: the luminance phase's change, which `estimate` has not taken yet (its
`restored` is empty when no luminance phase ran).
@return the iterations run (the most any plane ran). */
CV_EXPORTS int iterateRichardsonLucy(BlurOperator& op, const Mat& blurred, const ObservedFrame& observed,
                                     const Mat& normalizer, const RLParams& params, std::vector<Mat>& estimate,
                                     RLWorkspace& workspace, LuminanceChange& change);

/** @brief richardsonLucyVariant in a workspace, without its argument checks (the caller has made
them): the frame-rate path of DynamicDeblurrer.
@param observed the frame, CV_32F, 1–4 channels, the bank's size, finite.
@param clampToUnit clamp the output to [0, 1] as it is written (saves DynamicDeblurrer a pass). */
void restoreVariant(const Mat& observed, const PsfBank& bank, const RLParams& params, RLWorkspace& workspace,
                    OutputArray latent, OutputArray validMask, bool clampToUnit = false);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
