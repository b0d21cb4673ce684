// SPDX-License-Identifier: Apache-2.0
// The fit's residuals: each frame's still carried through the blur a correction predicts, compared
// with the frame in units of its noise.
#include "precomp.hpp"

#include "imaging/psf_generator.hpp"
#include "motion/axis_chain_motion.hpp"
#include "motion/corrected_motion.hpp"
#include "refine/level_residuals.hpp"
#include "restore/deconv_operator.hpp"

#include <opencv2/imgproc.hpp>

namespace cv {
namespace dynblur {
namespace detail {

namespace {

/* Pixel noise is never taken below this (linear intensity): an 8-bit frame's quantisation alone is
   about this much, and a synthetic noise-free frame must not make every model inconsistent. */
const double kNoiseFloor = 1e-3;
/* Node columns of the fit's kernels. Tiles, not rows: a reference at another angle than the frame
   is displaced by the whole move, and the projective rotation spreads that displacement across
   the columns by several pixels, which one kernel per row smears (RefinementQuality: window I
   against the still frame before the move kept 18 % of the gain with 4 columns). */
const int kFitTileColumns = 8;
// Light counted in a frame pixel from the reference, below which the pixel is left out.
const float kMinCoverage = 0.98f;
// Pixels at or above this (linear) may be clipped by the sensor: the linear model fails there.
const float kSaturated = 0.99f;
// The brightness gain between a frame and its still is sought within [1/kMaxGain, kMaxGain].
const double kMaxGain = 2;

}  // namespace

LevelResiduals::LevelResiduals(const Ptr<Plant>& plant, const std::vector<FitFrame>& frames, int width)
    : plant_(plant), frames_(frames)
{
    for (const FitFrame& f : frames)
    {
        const int level = levelAtMostWide(*f.reference, width);
        levels_.push_back(level);
        sigma_.push_back(std::max(kNoiseFloor, f.reference->noiseSigma[size_t(level)]));
    }
}

void LevelResiduals::fixMasks(const MotionCorrection& c)
{
    masks_.assign(frames_.size(), Mat());
    gains_.assign(frames_.size(), 1.0);
    weights_.assign(frames_.size(), Mat());
    pixels_ = 0;
    for (size_t i = 0; i < frames_.size(); i++)
    {
        Mat predicted, coverage;
        predict(i, c, predicted, coverage);
        const Mat& frame = frames_[i].frame.images[size_t(levels_[i])];
        const Mat& reference = frames_[i].reference->images[size_t(levels_[i])];
        Mat mask = (coverage >= kMinCoverage) & (frame < kSaturated) & (predicted < kSaturated);
        mask.setTo(0, reference >= kSaturated);  // the reference's clipped pixels spread through the blur
        erode(mask, mask, getStructuringElement(MORPH_RECT, Size(5, 5)), Point(-1, -1), 1, BORDER_CONSTANT,
              Scalar(0));
        masks_[i] = mask;
        mask.convertTo(weights_[i], CV_32F, 1.0 / 255);
        pixels_ += size_t(countNonZero(mask));
    }
}

void LevelResiduals::residuals(const MotionCorrection& c, std::vector<float>& out, std::vector<double>* perFrame)
{
    if (perFrame)
        perFrame->assign(frames_.size(), 0.0);
    for (size_t i = 0; i < frames_.size(); i++)
    {
        Mat predicted, coverage;
        predict(i, c, predicted, coverage);
        const Mat& frame = frames_[i].frame.images[size_t(levels_[i])];
        // Light that fell outside the reference is made up from what fell inside.
        predicted = predicted / max(coverage, 0.5);
        /* The still may be brighter or darker than the frame (a webcam's automatic exposure, the
           lighting): the gain that fits best, in closed form (least squares over the mask). */
        const double cross = predicted.dot(frame.mul(weights_[i]));
        const double power = predicted.dot(predicted.mul(weights_[i]));
        gains_[i] = power > 0 ? std::min(kMaxGain, std::max(1 / kMaxGain, cross / power)) : 1.0;
        const float gain = float(gains_[i]);
        const float inverseSigma = float(1.0 / sigma_[i]);
        double sum = 0;
        size_t count = 0;
        for (int y = 0; y < frame.rows; y++)
        {
            const uchar* m = masks_[i].ptr<uchar>(y);
            const float *b = frame.ptr<float>(y), *p = predicted.ptr<float>(y);
            for (int x = 0; x < frame.cols; x++)
            {
                if (!m[x])
                    continue;
                const float r = (b[x] - gain * p[x]) * inverseSigma;
                out.push_back(r);
                sum += double(r) * r;
                count++;
            }
        }
        if (perFrame)
            (*perFrame)[i] = count ? sum / double(count) : std::numeric_limits<double>::quiet_NaN();
    }
}

void LevelResiduals::predict(size_t i, const MotionCorrection& c, Mat& predicted, Mat& coverage)
{
    const FitFrame& f = frames_[i];
    const int level = levels_[i];
    const Ptr<CameraModel>& camera = f.reference->cameras[size_t(level)];
    const Mat& reference = f.reference->images[size_t(level)];
    const RollingShutter shutter = shutterAtLevel(c.correctShutter(f.shutter), level);
    PsfBank bank;
    if (f.motion)
    {
        Ptr<PsfGenerator> generator = PsfGenerator::create(camera);
        generator->setTileGrid(Size(kFitTileColumns, 0));
        ViewMotion view;
        if (asAxisChainMotion(*f.motion))
        {
            // A mount's still is at rest, where its plants' scales do not move it.
            view.motion = c.correctMotion(f.motion);
            view.reference = f.referenceOrientation;
        }
        else  // the still lies at its capture time on the same clock as the frame: the offset moves both
            view = correctedView(f.motion, c, f.referenceTime, shutter);
        bank = generatePsfBank(*generator, PSF_TILES, view, shutter);
    }
    else
    {
        Ptr<PsfGenerator> generator = PsfGenerator::create(c.correctPlant(plant_), camera);
        generator->setTileGrid(Size(kFitTileColumns, 0));
        bank = generator->generate(PSF_TILES, f.schedule, shutter, f.referenceAngle);
    }
    std::unique_ptr<BlurOperator> op = createBankOperator(bank, false);
    op->forward(reference, predicted);
    if (ones_.size() != reference.size())
        ones_ = Mat::ones(reference.size(), CV_32F);
    op->forward(ones_, coverage);
    evaluations_++;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
