// SPDX-License-Identifier: Apache-2.0
// DynamicDeblurrer's restoration stage: decode, restore, encode, fill what the frame never saw.
#include "precomp.hpp"

#include "imaging/psf_generator.hpp"
#include "pipeline/frame_rate_preset.hpp"
#include "pipeline/frame_restoration.hpp"
#include "pipeline/half_color.hpp"

#include <opencv2/imgproc.hpp>

namespace cv {
namespace dynblur {
namespace detail {

namespace {

//! The frame's color planes; a fourth channel, alpha, goes to `alpha`: coverage, not light, it passes through.
Mat withoutAlpha(const Mat& input, Mat& alpha)
{
    if (input.channels() != 4)
        return input;
    std::vector<Mat> planes;
    split(input, planes);
    alpha = planes[3];
    planes.pop_back();
    Mat color;
    merge(planes, color);
    return color;
}

//! `latent` (linear) into `restored` in the input's encoding (8-bit sRGB or linear), alpha put back.
void encode(const Mat& latent, int inputDepth, const Mat& alpha, OutputArray restored)
{
    if (alpha.empty())
    {
        linearToSrgb(latent, restored, CV_8U);  // an 8-bit frame, encoded straight into the output
        return;
    }
    Mat encoded;
    if (inputDepth == CV_8U)
        linearToSrgb(latent, encoded, CV_8U);
    else
        encoded = latent;
    std::vector<Mat> planes;
    split(encoded, planes);
    planes.push_back(alpha);
    merge(planes, encoded);
    encoded.copyTo(restored);
}

//! The pixels the frame never saw (`mask` 0), as `fill` (UnobservedFill) says; the restoration left
//! them filled from the nearest observed pixels.
void fillUnobserved(const Mat& recorded, const Mat& mask, int fill, Mat restored)
{
    if (fill == UNOBSERVED_NEAREST || countNonZero(mask) == int(mask.total()))
        return;
    const Mat unobserved = mask == 0;
    if (fill == UNOBSERVED_RECORDED)
        recorded.copyTo(restored, unobserved);
    else
        restored.setTo(Scalar(0, 0, 0, recorded.depth() == CV_8U ? 255 : 1), unobserved);
}

//! Whether the color phase runs at half resolution for a frame of `channels` color planes.
bool colorAtHalfResolution(const RestorationSettings& settings, const RLParams& params, int channels)
{
    return settings.method == DEBLUR_RICHARDSON_LUCY && settings.colorResolution == DEBLUR_COLOR_HALF_RESOLUTION &&
           channels == 3 && params.colorIterations >= 0 && params.colorIterations < params.iterations;
}

}  // namespace

void passThrough(const Mat& input, OutputArray restored, OutputArray validMask)
{
    input.copyTo(restored);
    if (validMask.needed())
    {
        validMask.create(input.size(), CV_8U);
        validMask.setTo(Scalar::all(255));
    }
}

FrameRestorer::FrameRestorer(const Ptr<CameraModel>& camera) : camera_(camera)
{
    workspace_.persistent = true;
    halfWorkspace_.persistent = true;
}

void FrameRestorer::restore(const Mat& input, const PsfBank& bank, const ViewMotion& view,
                            const RollingShutter& shutter, const PsfGenerator& generator,
                            const RestorationSettings& settings, OutputArray restored, OutputArray validMask)
{
    const RLParams params = settings.iterationsByNeed ? frameRateIterations(bank, settings.params) : settings.params;
    // Decode: the color planes, in linear light. The color at half resolution decodes an 8-bit frame as it reads it.
    Mat alpha;
    const Mat color = withoutAlpha(input, alpha);
    const bool halfColor = colorAtHalfResolution(settings, params, color.channels());
    const Mat linear = color.depth() == CV_8U && !halfColor ? linearized(color) : color;

    /* A frame without alpha is restored straight into the output (written last, after every read of
       the frame, so restoring in place works) when it is linear, or 8-bit with the color at half
       resolution (encoded as it is written); others go through latent_. */
    const bool direct = alpha.empty() && (input.depth() == CV_32F || halfColor);
    // Restoring in place overwrites the frame: the recorded pixels are kept for the fill first.
    const bool inPlace = restored.isMat() && !restored.empty() && restored.getMat().data == input.data;
    const Mat recorded = settings.unobservedFill == UNOBSERVED_RECORDED && inPlace ? input.clone() : input;
    // Restore, then encode as the frame was, and fill what it never saw.
    const Mat latent = restoreLinear(linear, bank, view, shutter, generator, settings, params, halfColor, direct,
                                     input.depth(), restored);
    if (!direct)
        encode(latent, input.depth(), alpha, restored);
    fillUnobserved(recorded, mask_, settings.unobservedFill, restored.getMat());
    if (validMask.needed())
        mask_.copyTo(validMask);
}

bool FrameRestorer::moveBack(const Mat& input, const FrameSharpness& sharpness, int unobservedFill,
                             OutputArray restored, OutputArray validMask)
{
    if (!recordedPositions(sharpness, input.size(), mapX_, mapY_))
        return false;
    Mat alpha;
    const Mat color = withoutAlpha(input, alpha);
    /* Bicubic, in the frame's own encoding. A bilinear tap half a pixel off averages two pixels and
       halves the finest detail, which on fine texture costs more than the sub-pixel shift it undoes;
       in linear light (decode, resample, encode) SharpQuality's moved-back frames gained 0.05 dB less
       on average and took 1.4× the time. */
    remap(color, latent_, mapX_, mapY_, INTER_CUBIC, BORDER_REPLICATE);
    if (color.depth() == CV_32F)
        parallel_for_(Range(0, latent_.rows), [&](const Range& rows) {
            for (int y = rows.start; y < rows.end; y++)
                clampRowToUnit(latent_.ptr<float>(y), latent_.cols * latent_.channels());
        });
    // Observed: read within the frame (half a pixel beyond its edge pixels' centres).
    const float right = float(input.cols) - 0.5f, bottom = float(input.rows) - 0.5f;
    mask_ = (mapX_ >= -0.5f) & (mapX_ <= right) & (mapY_ >= -0.5f) & (mapY_ <= bottom);
    const bool inPlace = restored.isMat() && !restored.empty() && restored.getMat().data == input.data;
    const Mat recorded = unobservedFill == UNOBSERVED_RECORDED && inPlace ? input.clone() : input;
    if (alpha.empty())
        latent_.copyTo(restored);
    else
    {
        std::vector<Mat> planes;
        split(latent_, planes);
        planes.push_back(alpha);
        merge(planes, restored);
    }
    fillUnobserved(recorded, mask_, unobservedFill, restored.getMat());
    if (validMask.needed())
        mask_.copyTo(validMask);
    return true;
}

Mat FrameRestorer::linearized(const Mat& color)
{
    srgbToLinear(color, linear_);
    return linear_;
}

Mat FrameRestorer::restoreLinear(const Mat& linear, const PsfBank& bank, const ViewMotion& view,
                                 const RollingShutter& shutter, const PsfGenerator& generator,
                                 const RestorationSettings& settings, const RLParams& params, bool halfColor,
                                 bool direct, int inputDepth, OutputArray restored)
{
    Mat latent = direct ? Mat() : latent_;
    _OutputArray target = direct ? restored : _OutputArray(latent);
    if (settings.method == DEBLUR_WIENER)
    {
        wienerDeconvolve(linear, bank, target, settings.wienerNoiseToSignal);
        mask_.create(linear.size(), CV_8U);
        mask_.setTo(Scalar::all(255));
    }
    else if (halfColor)
        restoreWithHalfColor(linear, bank, view, shutter, generator, settings.psfModel, params, target,
                             direct ? inputDepth : CV_32F);
    else
        restoreVariant(linear, bank, params, workspace_, target, mask_, true);
    if (direct)
        latent = restored.getMat();
    else
        latent_ = latent;
    // Wiener may overshoot at edges; the output is an image in [0, 1] (RL's keeps itself there).
    if (settings.method == DEBLUR_WIENER)
        parallel_for_(Range(0, latent.rows), [&](const Range& rows) {
            for (int y = rows.start; y < rows.end; y++)
                clampRowToUnit(latent.ptr<float>(y), latent.cols * latent.channels());
        });
    return latent;
}

void FrameRestorer::restoreWithHalfColor(const Mat& frame, const PsfBank& bank, const ViewMotion& view,
                                         const RollingShutter& shutter, const PsfGenerator& generator, int psfModel,
                                         const RLParams& params, const _OutputArray& target, int depth)
{
    const PsfBank halfBank =
        generatePsfBank(*halfGenerator(generator, bank), psfModel, view, halfResolutionShutter(shutter));
    // Both restorations run in place (restoreVariant writes its output after its last read of the frame).
    halveAndAverageChannels(frame, halfColor_, luminance_);
    RLParams colorParams = params;
    colorParams.iterations = params.colorIterations;  // 0: the start, the frame moved back
    colorParams.colorIterations = -1;
    restoreVariant(halfColor_, halfBank, colorParams, halfWorkspace_, halfColor_, noArray(), true);

    RLParams luminanceParams = params;
    luminanceParams.colorIterations = -1;
    restoreVariant(luminance_, bank, luminanceParams, workspace_, luminance_, mask_, true);
    // Written last: the frame may be the output (restoring in place). Below a millionth of
    // full well a pixel's color has no chromaticity to keep: the change is added.
    combineLuminanceAndHalfColor(luminance_, halfColor_, 1e-6f, depth, target);
}

/* A tile grid takes half the bank's columns, the same node spacing in its own pixels, which is what
   the automatic rule gives at half the width below its cap of 16: neighbouring kernels then differ
   by as many (half-size) pixels as at full resolution. DeblurQuality measured 8 columns within
   0.08 dB of 16 in window I, 4 columns 0.6 dB below. */
const Ptr<PsfGenerator>& FrameRestorer::halfGenerator(const PsfGenerator& generator, const PsfBank& bank)
{
    if (!halfCamera_)
    {
        halfCamera_ = halfResolutionCamera(*camera_);
        halfGenerator_ = PsfGenerator::create(halfCamera_);
    }
    halfGenerator_->setMaxKernelSize(generator.getMaxKernelSize());
    halfGenerator_->setAutoTolerance(0.5 * generator.getAutoTolerance());
    const int bandRows = generator.getBandRows(), gridRows = generator.getTileGrid().height;
    halfGenerator_->setBandRows(bandRows > 0 ? std::max(1, bandRows / 2) : 0);
    halfGenerator_->setTileGrid(Size((int(bank.nodeCols.size()) + 1) / 2, gridRows > 0 ? std::max(1, gridRows / 2) : 0));
    return halfGenerator_;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
