// SPDX-License-Identifier: Apache-2.0
// Private: the element-wise terms of a Richardson–Lucy iteration shared by its row loops and the
// half-resolution color's combination.
#ifndef OPENCV_DYNBLUR_RESTORE_RL_TERMS_HPP
#define OPENCV_DYNBLUR_RESTORE_RL_TERMS_HPP

#include "restore/kernels/update_terms.hpp"

#include <algorithm>

namespace cv {
namespace dynblur {
namespace detail {

/** Half the Poisson deviance of data `b` against a model's `ab` (both ≥ 0, one unit),
b ln(b / ab) − b + ab, which the damped ratio compares with its threshold @cite White1994Damped.
It is ab · φ(e) with φ(e) = (1 + e) ln(1 + e) − e and the relative residual e = b / ab − 1, taken
here in φ's [2/1] Padé form 3e² / (6 + 2e) @cite Baker1996Pade: 1.5 (b − ab)² / (2 ab + b), without
a log. It agrees to third order in e, where the damping acts (there the exact form subtracts
nearly equal terms), and falls short by e²/18 relative for small e: 0.06 % at e = ±0.1, 1 % at
0.5, 2.2 % at −0.5, 25 % at b = 0 (0.75 ab for ab). A pair of zeros gives 0. */
inline float halfPoissonDeviance(float b, float ab)
{
    const float difference = b - ab;
    return 1.5f * difference * difference / (2.f * ab + b + 1e-30f);  // + 1e-30: 0 / 0 would be NaN
}

/** One channel's `value` after the luminance's change from `before` to `after`: times `gain` =
after / before where `lit` (before above the black level), plus after − before elsewhere, kept
within [0, upper]. The one rule of LuminanceChange::applyRow and of the half-resolution color's
combination; both loops compute both results and select, so they vectorise. */
inline float luminanceChanged(float value, bool lit, float gain, float after, float before, float upper)
{
    return std::min(std::max(lit ? value * gain : value + after - before, 0.f), upper);
}

//! Normaliser below which a latent pixel counts as not seen by any frame pixel.
constexpr float kUnobserved = kernels::kUpdateUnobserved;

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
