// SPDX-License-Identifier: Apache-2.0
#include "precomp.hpp"

#include "restore/arguments.hpp"
#include "restore/deconv_operator.hpp"
#include "restore/deconv_rl.hpp"
#include "restore/fft_kernel.hpp"
#include "restore/simd_clones.hpp"

#include <opencv2/imgproc.hpp>

#include <climits>
#include <cstring>

namespace cv {
namespace dynblur {

RLParams::RLParams()
    : iterations(20), damping(0), tvWeight(0.002), boundary(RL_BOUNDARY_PAD), accelerate(true), tolerance(0),
      colorIterations(-1), blurPrecision(RL_BLUR_FLOAT32)
{
}

namespace {

using detail::BankBlurOperator;
using detail::BlurOperator;
using detail::UniformBlurOperator;
using detail::kUnobserved;
using detail::writeOutput;

//! A pixel counts as observed (validMask 255) when at least this fraction of its light reached the frame.
constexpr float kObservedFraction = 0.1f;

//! Automatic damping, in noise standard deviations: updates within the noise are suppressed (3σ is
//! deconvlucy's documented choice).
constexpr double kAutoDampingSigmas = 3.0;

//! The parameters with an automatic damping (NaN) replaced by the multiple of the frame's noise.
RLParams resolveDamping(const RLParams& params, const detail::ObservedFrame& observed)
{
    RLParams resolved = params;
    if (std::isnan(resolved.damping))
        resolved.damping = kAutoDampingSigmas * observed.noiseSigma;
    return resolved;
}

//! Validates a kernel and returns it as CV_32F normalised to sum 1.
Mat normalizedKernel(InputArray psf, const char* name, const char* function)
{
    if (psf.empty())
        CV_Error(Error::StsBadArg, format("%s: '%s' is empty", function, name));
    if (psf.channels() != 1 || (psf.depth() != CV_32F && psf.depth() != CV_64F))
        CV_Error(Error::StsUnsupportedFormat,
                 format("%s: '%s' must be one channel, CV_32F or CV_64F", function, name));
    const Size size = psf.size();
    if (size.width % 2 == 0 || size.height % 2 == 0)
        CV_Error(Error::StsBadArg,
                 format("%s: '%s' is %dx%d; both sides must be odd so the kernel has a centre element", function,
                        name, size.width, size.height));
    Mat kernel;
    psf.getMat().convertTo(kernel, CV_32F);
    if (!checkRange(kernel, true))
        CV_Error(Error::StsBadArg, format("%s: '%s' contains NaN or Inf", function, name));
    double minValue = 0;
    minMaxLoc(kernel, &minValue);
    if (minValue < 0)
        CV_Error(Error::StsBadArg,
                 format("%s: '%s' has a negative element (%g); a PSF must be >= 0", function, name, minValue));
    const double total = sum(kernel)[0];
    if (!(total > 0))
        CV_Error(Error::StsBadArg, format("%s: '%s' sums to %g; it must sum to a positive value", function, name,
                                          total));
    kernel *= 1.0 / total;
    return kernel;
}

//! The frame planes moved into a latent domain: the frame at `origin`, borders replicated.
std::vector<Mat> embedPlanes(const std::vector<Mat>& frame, const BlurOperator& op)
{
    const Point o = op.origin();
    const Size latent = op.latentSize(), size = op.frameSize();
    std::vector<Mat> planes(frame.size());
    for (size_t c = 0; c < frame.size(); c++)
        copyMakeBorder(frame[c], planes[c], o.y, latent.height - size.height - o.y, o.x,
                       latent.width - size.width - o.x, BORDER_REPLICATE);
    return planes;
}

/* out = max(moved / normaliser, 0) where the normaliser exceeds kUnobserved, `fill` elsewhere: the
   start's row. The quotient is taken everywhere (its divisor kept ≥ 1e-3) and then selected, so
   the loop vectorises. */
DYNBLUR_SIMD_CLONES
void normalizedRow(const float* __restrict moved, const float* __restrict normalizer, float fill, int n,
                   float* __restrict out)
{
    for (int x = 0; x < n; x++)
    {
        const float quotient = std::max(moved[x] / std::max(normalizer[x], kObservedFraction * 1e-2f), 0.f);
        out[x] = normalizer[x] > kUnobserved ? quotient : fill;
    }
}

}  // namespace

void richardsonLucy(InputArray blurred, InputArray psf, OutputArray latent, const RLParams& params, InputArray initial)
{
    const char* fn = "richardsonLucy";
    checkImage(blurred, "blurred", fn, true);
    checkRLParams(params, fn);
    const Mat kernel = normalizedKernel(psf, "psf", fn);
    if (!initial.empty())
    {
        checkImage(initial, "initial", fn, true);
        if (initial.size() != blurred.size() || initial.type() != blurred.type())
            CV_Error(Error::StsBadSize, format("%s: 'initial' must have the size and type of 'blurred'", fn));
    }

    /* RL is homogeneous, but FFTW's float transforms of a frame near 1e-30 (or 1e30) push its small
       (large) coefficients out of the normal range. The frame is run at the power of two that brings
       its mean near 1, which changes no rounding, and the result is scaled back. */
    const Scalar channelMeans = mean(blurred);
    double level = 0;
    for (int c = 0; c < blurred.channels(); c++)
        level += channelMeans[c] / blurred.channels();
    // Within 2^±100, so that the factor and its inverse are normal floats too.
    const double unit = level > 0 ? std::ldexp(1.0, -std::min(std::max(std::ilogb(level), -100), 100)) : 1.0;
    const Mat observed = unit == 1.0 ? blurred.getMat() : Mat(blurred.getMat() * unit);
    detail::RLWorkspace workspace;
    const detail::ObservedFrame observedFrame =
        detail::observeFrame(observed, workspace.observed, std::isnan(params.damping));
    std::vector<Mat> start;
    if (initial.empty())
        start = observedFrame.planes;  // embedPlanes copies them
    else
        split(initial.getMat() * unit, start);
    RLParams scaled = params;
    if (!std::isnan(params.damping))
        scaled.damping *= unit;  // intensity units
    scaled = resolveDamping(scaled, observedFrame);  // an automatic damping is taken on the scaled frame

    const bool pad = params.boundary == RL_BOUNDARY_PAD;
    UniformBlurOperator op(blurred.size(), kernel, pad);
    std::vector<Mat> estimate = embedPlanes(start, op);
    for (Mat& e : estimate)
        e = max(e, 0.f);
    Mat normalizer;  // ZERO: scikit-image's unnormalised update (Aᵀ1 taken as 1)
    if (pad)
        op.adjoint(Mat::ones(blurred.size(), CV_32F), normalizer);
    detail::LuminanceChange change;
    detail::iterateRichardsonLucy(op, observed, observedFrame, normalizer, scaled, estimate, workspace, change);

    writeOutput(estimate, latent, false, change, Rect(op.origin(), op.frameSize()));
    if (unit != 1.0)
    {
        Mat out = latent.getMat();
        out *= 1.0 / unit;
    }
}

namespace detail {

void restoreVariant(const Mat& observed, const PsfBank& bank, const RLParams& params, RLWorkspace& ws,
                    OutputArray latent, OutputArray validMask, bool clampToUnit)
{
    const bool pad = params.boundary == RL_BOUNDARY_PAD;
    std::unique_ptr<BlurOperator> blur = createBankOperator(bank, pad, params.blurPrecision == RL_BLUR_BFLOAT16);
    BlurOperator& op = *blur;
    const Size frameSize = observed.size(), latentSize = op.latentSize();
    // The frame of ones lives in the (packed) ratio plane, which the iterations fill later: no memory of its own.
    op.adjointOfOnes(ws.normalizer, op.gathersPackedRows() ? ws.packedRatio : ws.ratio);

    /* Start: the frame moved back by each node's displacement (the normalised adjoint of the
       displacement-only blur), so content begins where the view at θ_ref has it and RL only has to
       sharpen; latent pixels that displacement does not reach start at the channel's mean. */
    const ObservedFrame observedFrame = observeFrame(observed, ws.observed, std::isnan(params.damping));
    const std::vector<Mat>& observedPlanes = observedFrame.planes;
    const Scalar& channelMean = observedFrame.channelMean;
    std::vector<Mat>& estimate = ws.estimate;
    estimate.resize(observedPlanes.size());
    for (Mat& e : estimate)
        e.create(latentSize, CV_32F);
    displacementAdjoint(bank, displacementShifts(bank), latentSize, op.origin(), observedPlanes,
                        [&](int y, const float* weight, const float* const* moved) {
                            for (size_t c = 0; c < estimate.size(); c++)
                                normalizedRow(moved[c], weight, float(std::max(channelMean[int(c)], 0.0)),
                                              latentSize.width, estimate[c].ptr<float>(y));
                        });

    LuminanceChange change;
    iterateRichardsonLucy(op, observed, observedFrame, ws.normalizer, resolveDamping(params, observedFrame), estimate,
                          ws, change);

    if (!ws.persistent)
    {
        ws.observed.clear();
        ws.other.clear();
        ws.step.release();
        ws.ratio.release();
    }
    const Rect frame(op.origin(), frameSize);
    compare(ws.normalizer(frame), kObservedFraction, ws.valid, CMP_GT);
    writeOutput(estimate, latent, clampToUnit, change, frame);
    // The fill's distance transform allocates: the planes it no longer needs go first.
    change.restored.release();
    if (!ws.persistent)
        ws.estimate.clear();
    Mat output = latent.getMat();
    fillFromNearest(output, ws.valid);
    if (validMask.needed())
        ws.valid.copyTo(validMask);
}

}  // namespace detail

void richardsonLucyVariant(InputArray blurred, const PsfBank& bank, OutputArray latent, const RLParams& params,
                           OutputArray validMask)
{
    const char* fn = "richardsonLucyVariant";
    checkImage(blurred, "blurred", fn, true);
    checkRLParams(params, fn);
    checkBank(bank, blurred.size(), fn);
    detail::RLWorkspace workspace;
    detail::restoreVariant(blurred.getMat(), bank, params, workspace, latent, validMask);
}

void applyPsfBank(InputArray latent, const PsfBank& bank, OutputArray blurred)
{
    const char* fn = "applyPsfBank";
    checkImage(latent, "latent", fn, false);
    checkBank(bank, latent.size(), fn);
    std::vector<Mat> planes;
    split(latent.getMat(), planes);
    std::unique_ptr<BlurOperator> op = detail::createBankOperator(bank, false);
    std::vector<Mat> out(planes.size());
    for (size_t c = 0; c < planes.size(); c++)
        op->forward(planes[c], out[c]);
    writeOutput(out, blurred);
}

}  // namespace dynblur
}  // namespace cv
