// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_DECONV_HPP
#define OPENCV_DYNBLUR_DECONV_HPP

#include <opencv2/dynblur/psf.hpp>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_restoration
//! @{

//! How the restoration treats the frame's edges.
enum RLBoundary
{
    RL_BOUNDARY_ZERO = 0,   //!< zero outside the frame (scikit-image's richardson_lucy); rings at edges
    RL_BOUNDARY_PAD = 1     //!< the latent domain extends past the frame by the kernels' reach; no ringing
};

/** @brief The arithmetic of a spatially variant blur and its adjoint inside the RL iterations
(RLParams::blurPrecision). */
enum RLBlurPrecision
{
    RL_BLUR_FLOAT32 = 0,  //!< float images, weights and sums
    /** bfloat16 images and weights (8 significant bits, float's range), float sums @cite Kalamkar2019Bfloat16:
        the ratio is rounded as its deviation from 1, and both blurs of an iteration read pairs of rows
        packed in one 32-bit word, two multiply-adds per instruction on CPUs with AVX512-BF16 (others
        widen the halves to floats, with the same rounding). Blurred values are within 2^-8 of the
        float ones; the restorations differ by a few hundredths of a dB (10 iterations), by up to
        0.13 dB after 20 tile-wise ones. What it gains in time depends on the CPU: much where
        bfloat16 multiply-adds outpace float FMAs, little where they barely do (BM_FrameRatePaired's
        float32_over_rows in perf/perf_deblurrer.cpp measures it; figures in docs/performance.md). A
        tile-wise restoration holds fewer frame planes per channel (test DeconvMemory). */
    RL_BLUR_BFLOAT16 = 1
};

/** @brief Options of Richardson–Lucy deconvolution @cite Richardson1972Bayesian @cite Lucy1974Iterative. */
struct CV_EXPORTS_W_SIMPLE RLParams
{
    CV_WRAP RLParams();
    CV_PROP_RW int iterations;     //!< iterations, ≥ 1 (default 20)
    /** DAMPAR of MATLAB's deconvlucy @cite White1994Damped, linear intensity units, ≥ 0 (0: off): where the
        re-blurred estimate is within it of the data, the update is suppressed, so noise is not fitted.
        The Poisson deviance it is measured by is taken in its [2/1] Padé form, without a log
        @cite Baker1996Pade: within 0.06 % of it where the relative residual is ±0.1, 2.2 % at ±0.5
        (never above it).
        NaN: automatic, 3 × the noise standard deviation estimated from the blurred image
        @cite Immerkaer1996Noise (DynamicDeblurrer's default). Default 0, as in deconvlucy. */
    CV_PROP_RW double damping;
    CV_PROP_RW double tvWeight;    //!< total-variation regularisation weight λ, ≥ 0 (0: off) @cite Dey2006RLTV
    CV_PROP_RW int boundary;       //!< RLBoundary
    CV_PROP_RW bool accelerate;    //!< Biggs–Andrews vector extrapolation @cite Biggs1997Acceleration
    CV_PROP_RW double tolerance;   //!< stop a plane early when the relative change of its iteration falls below it, ≥ 0 (0: never)
    /** Iterations run on every color plane of a 3- or 4-channel image, ≥ 0; the remaining ones
        restore the luminance (the planes' mean) alone and scale every plane by its change, which
        keeps each pixel's chromaticity. Fine detail is mostly luminance, so the result stays close
        to full color RL while a luminance iteration costs a third of a color one. −1 (default) or ≥ iterations: every iteration in
        color. Ignored for 1–2 channels. DynamicDeblurrer can run them on the frame halved instead, the
        luminance taking every iteration (DEBLUR_COLOR_HALF_RESOLUTION). */
    CV_PROP_RW int colorIterations;
    /** RLBlurPrecision of the blurs in richardsonLucyVariant and DynamicDeblurrer (default
        RL_BLUR_FLOAT32); richardsonLucy's single-kernel FFT ignores it. */
    CV_PROP_RW int blurPrecision;
};

/** @brief Richardson–Lucy deconvolution with one kernel, using FFTW (single precision, threaded,
plans cached) @cite Frigo2005Fftw.
@param blurred observed image, CV_32F, 1–4 channels, linear intensity, finite and ≥ 0 (clip data
       with a subtracted dark level at 0, as a sensor does).
@param psf kernel, CV_32F or CV_64F, one channel, odd size, non-negative, normalised to sum 1 here.
@param latent output, same size and type as blurred.
@param params iterations, damping, regularisation, boundary, acceleration.
@param initial start estimate (same size and type as blurred, finite and ≥ 0); empty: the blurred image.

With RL_BOUNDARY_ZERO the update is scikit-image's, x ← x ⊙ (k★(b / (k⊛x))) without the Aᵀ1
normaliser, so the result matches its richardson_lucy (clip=False) from the same start. With
RL_BOUNDARY_PAD the latent grows by the kernel's half-size on each side (border replicated as the
start) and the update is divided by Aᵀ1. */
CV_EXPORTS_W void richardsonLucy(InputArray blurred, InputArray psf, OutputArray latent,
                                 const RLParams& params = RLParams(), InputArray initial = noArray());

/** @brief Spatially variant Richardson–Lucy: one global iteration whose forward operator and
adjoint are the bank's blended blur, so tiles and row bands leave no seams
@cite Hirsch2010Efficient.
@param blurred observed image, CV_32F, 1–4 channels, linear intensity (finite, ≥ 0), the bank's image size.
@param bank the kernels (PsfGenerator::generate).
@param latent output, same size and type as blurred: the view at θ_ref.
@param params iterations, damping, regularisation, boundary, acceleration.
@param validMask optional output, CV_8U, 255 where the latent pixel was observed by the frame.

The update is x ← x ⊙ Aᵀ(b / A x) / Aᵀ1 (with damping, TV and acceleration as in RLParams). It
starts from the frame moved back by each node's displacement (kernel centroid plus shift). A
latent pixel counts as observed when Aᵀ1 > 0.1 (at least a tenth of its light reached the
frame); the others (content the frame never saw at θ_ref) get the value of the nearest observed
pixel and 0 in validMask. */
CV_EXPORTS_W void richardsonLucyVariant(InputArray blurred, const PsfBank& bank, OutputArray latent,
                                        const RLParams& params = RLParams(), OutputArray validMask = noArray());

/** @brief Applies the bank's forward blur B = A·L (the operator richardsonLucyVariant inverts).
@param latent CV_32F, 1–4 channels, the bank's image size.
@param bank the kernels.
@param blurred output, same size and type (zero outside the frame). */
CV_EXPORTS_W void applyPsfBank(InputArray latent, const PsfBank& bank, OutputArray blurred);

/** @brief Wiener deconvolution: the non-iterative fast path @cite Wiener1949Extrapolation.
For a variant bank each node's kernel is inverted over its region and the results are blended
with the bank's weights.
@param blurred observed image, CV_32F, 1–4 channels, the bank's image size.
@param bank the kernels.
@param latent output, same size and type.
@param noiseToSignal noise-to-signal power ratio, > 0.

Each node's region (plus a margin, mirrored past the frame and faded to its mean so the FFT's
wrap adds no ringing) is filtered with conj(K)/(|K|² + noiseToSignal) and written back at its
displacement, so a pure shift comes back exactly placed (scaled by 1/(1 + noiseToSignal)). Latent
pixels no node covers take the nearest covered value. */
CV_EXPORTS_W void wienerDeconvolve(InputArray blurred, const PsfBank& bank, OutputArray latent,
                                   double noiseToSignal = 1e-2);

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
