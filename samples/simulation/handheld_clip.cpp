// SPDX-License-Identifier: Apache-2.0
// The hand-held clip simulator (handheld_clip.hpp): the description's checks, the motion scaled as
// asked, the scene, the gyro log and each frame on request.
#include "handheld_clip.hpp"

#include "plane_render.hpp"
#include "scene.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace dynblur_samples {

using namespace cv;
using namespace cv::dynblur;

namespace {

//! The camera centres of a sweep about a pivot `pivot` metres behind the camera, at the rotation's samples.
Mat sweepPositions(const CameraPath& rotation, double pivot, int samples)
{
    Mat positions(samples, 3, CV_64F);
    for (int k = 0; k < samples; k++)
    {
        const Matx33d Q = rotation.rotation->orientation(rotation.start + k / rotation.sampleRateHz);
        const Vec3d c = (Q - Matx33d::eye()) * Vec3d(0, 0, pivot);
        for (int i = 0; i < 3; i++)
            positions.at<double>(k, i) = c[i];
    }
    return positions;
}

//! Throws naming the field, its value and the allowed range when `ok` is false.
void require(bool ok, const char* field, double value, const std::string& range)
{
    if (!ok)
        CV_Error(Error::StsOutOfRange, format("HandHeldClip: %s = %g must be %s", field, value, range.c_str()));
}

bool within(double value, double lo, double hi)
{
    return value >= lo && value <= hi;  // false for NaN
}

void requireWeights(const Vec3d& w, const char* field)
{
    for (int i = 0; i < 3; i++)
        require(within(w[i], 0, 1e3), format("%s[%d]", field, i).c_str(), w[i], "in [0, 1000] (a relative weight)");
    require(w[0] + w[1] + w[2] > 0, format("%s[0] + [1] + [2]", field).c_str(), w[0] + w[1] + w[2],
            "> 0 (some axis must move)");
}

void requireBand(double lowHz, double highHz, const char* low, const char* high)
{
    require(within(lowHz, 1e-3, 200), low, lowHz, "in [0.001, 200] (Hz)");
    require(highHz > lowHz && highHz <= 200, high, highHz, format("in (%s = %g, 200] (Hz)", low, lowHz));
}

//! The motion's span around the frames: the gyro log's lead on both sides, and the home view's fade-in before.
const double kBeforeLead = 0.2, kAfterLead = 0.05;

}  // namespace

void HandHeldClip::validate() const
{
    require(within(frameSize.width, 16, 8192), "frameSize.width", frameSize.width, "in [16, 8192] (pixels)");
    require(within(frameSize.height, 16, 8192), "frameSize.height", frameSize.height, "in [16, 8192] (pixels)");
    require(within(focalPx, 10, 1e5), "focalPx", focalPx, "in [10, 100000] (pixels)");
    require(fps > 0 && fps <= 1000, "fps", fps, "in (0, 1000] (frames per second)");
    require(within(exposure, 0, 1 / fps), "exposure", exposure,
            format("in [0, 1/fps = %g] (seconds; more is taken for milliseconds)", 1 / fps));
    require(within(readoutTime, 0, 1 / fps), "readoutTime", readoutTime,
            format("in [0, 1/fps = %g] (seconds, 0: global shutter)", 1 / fps));
    require(within(frames, 1, 1e6), "frames", frames, "in [1, 1000000]");

    requireBand(rotation.lowHz, rotation.highHz, "rotation.lowHz", "rotation.highHz");
    require(within(rotation.peakRate, 0, 100), "rotation.peakRate", rotation.peakRate,
            "in [0, 100] (rad/s; 0: set by rotation.maxBlurPx)");
    require(within(rotation.maxBlurPx, 0, 1000), "rotation.maxBlurPx", rotation.maxBlurPx,
            "in [0, 1000] (pixels; 0: set by rotation.peakRate)");
    require((rotation.peakRate > 0) != (rotation.maxBlurPx > 0), "rotation.peakRate", rotation.peakRate,
            format("> 0 with rotation.maxBlurPx = 0, or 0 with rotation.maxBlurPx > 0 (got %g): exactly one "
                   "scales the shake",
                   rotation.maxBlurPx));
    require(!(rotation.maxBlurPx > 0 && exposure == 0), "rotation.maxBlurPx", rotation.maxBlurPx,
            "0 with exposure = 0 (a zero exposure has no blur; scale by rotation.peakRate)");
    requireWeights(rotation.axisWeights, "rotation.axisWeights");

    require(translation.planeDepth == 0 || within(translation.planeDepth, 0.1, 1000), "translation.planeDepth",
            translation.planeDepth, "0 (no translation) or in [0.1, 1000] (metres)");
    if (translation.planeDepth > 0)
    {
        requireBand(translation.lowHz, translation.highHz, "translation.lowHz", "translation.highHz");
        require(translation.peakSpeed > 0 && translation.peakSpeed <= 10, "translation.peakSpeed",
                translation.peakSpeed, "in (0, 10] (m/s)");
        requireWeights(translation.axisWeights, "translation.axisWeights");
        require(within(translation.pivotDistance, 0, 2), "translation.pivotDistance", translation.pivotDistance,
                "in [0, 2] (metres)");
    }

    require(within(stretches.stillSeconds, 0, 1e4), "stretches.stillSeconds", stretches.stillSeconds,
            "in [0, 10000] (seconds; 0: shaky throughout)");
    if (stretches.stillSeconds > 0)
    {
        require(stretches.shakySeconds > 0 && stretches.shakySeconds <= 1e4, "stretches.shakySeconds",
                stretches.shakySeconds, "in (0, 10000] (seconds)");
        require(within(stretches.rampSeconds, 0, stretches.shakySeconds / 2), "stretches.rampSeconds",
                stretches.rampSeconds, format("in [0, shakySeconds / 2 = %g] (seconds)", stretches.shakySeconds / 2));
    }

    require(within(gyro.rateHz, 10, 1e4), "gyro.rateHz", gyro.rateHz, "in [10, 10000] (samples per second)");
    require(within(gyro.noise, 0, 1), "gyro.noise", gyro.noise, "in [0, 1] (rad/s per sample)");
    for (int i = 0; i < 3; i++)
        require(within(gyro.bias[i], -0.2, 0.2), format("gyro.bias[%d]", i).c_str(), gyro.bias[i],
                "within +-0.2 (rad/s; 1 deg/s is 0.01745)");
    require(within(gyro.rateScale, 0.5, 2), "gyro.rateScale", gyro.rateScale, "in [0.5, 2]");
    require(within(gyro.timeOffset, -10, 10), "gyro.timeOffset", gyro.timeOffset,
            "within +-10 (seconds; more is taken for milliseconds)");
    require(within(gyro.leadSeconds, 0, 60), "gyro.leadSeconds", gyro.leadSeconds, "in [0, 60] (seconds)");

    require(within(fullWellElectrons, 0, 1e7), "fullWellElectrons", fullWellElectrons,
            "in [0, 1e7] (electrons; 0: no sensor noise)");
    require(within(readNoiseElectrons, 0, 1e4), "readNoiseElectrons", readNoiseElectrons, "in [0, 10000] (electrons)");
    require(within(darkElectrons, 0, 1e6), "darkElectrons", darkElectrons, "in [0, 1e6] (electrons)");
    require(maxStepPx > 0 && maxStepPx <= 1, "maxStepPx", maxStepPx, "in (0, 1] (pixels)");
}

double HandHeldClip::end() const
{
    return (frames - 1) / fps + (frameSize.height - 1) * lineDelay() + exposure;
}

HandHeldSimulator::HandHeldSimulator(const HandHeldClip& clip) : clip_(clip)
{
    clip_.validate();
    const Size size = clip_.frameSize;
    camera_ = CameraModel::create(clip_.focalPx, clip_.focalPx, 0.5 * (size.width - 1), 0.5 * (size.height - 1),
                                  size.width, size.height);
    K_ = camera_->cameraMatrix();
    const HandShake shake(-clip_.gyro.leadSeconds - kBeforeLead, clip_.end() + clip_.gyro.leadSeconds + kAfterLead,
                          clip_.stretches, clip_.seed);
    scaleMotion(shake);
    makeScene();
    makeGyroLog();
}

/* The translation scales exactly (positions are linear in the scale); the rotation's rate and blur
are nearly linear in its scale (small angles), so a few rescalings bring either to 0.1 % of its target. */
void HandHeldSimulator::scaleMotion(const HandShake& shake)
{
    const double start = shake.start(), rate = HandShake::kSampleRateHz, end = clip_.end();
    const int first = int(std::floor(-start * rate)), last = int(std::ceil((end - start) * rate));
    Mat positions;
    const TranslationShake& move = clip_.translation;
    if (move.planeDepth > 0 && move.pivotDistance == 0)
    {
        positions = shake.positions(move.lowHz, move.highHz, move.axisWeights, 1.0);
        double fastest = 0;
        for (int k = std::max(first, 1); k <= last; k++)
            fastest = std::max(fastest, norm(positions.row(k) - positions.row(k - 1)) * rate);
        if (!(fastest > 0))
            CV_Error(Error::StsBadArg, "HandHeldClip: the translation never moves during the frames (the "
                                       "stretches keep every frame still); set translation.planeDepth = 0");
        positions *= move.peakSpeed / fastest;
        peakSpeed_ = move.peakSpeed;
    }
    const RotationShake& turn = clip_.rotation;
    const bool byBlur = turn.maxBlurPx > 0;
    const double target = byBlur ? turn.maxBlurPx : turn.peakRate;
    double scale = 1.0;
    for (int iteration = 0; iteration < 6; iteration++)
    {
        const Mat rotationVectors = shake.rotationVectors(turn.lowHz, turn.highHz, turn.axisWeights, scale);
        if (move.planeDepth > 0 && move.pivotDistance > 0)
            positions = sweepPositions(shake.path(rotationVectors, Mat(), 0), move.pivotDistance,
                                       rotationVectors.rows);
        path_ = shake.path(rotationVectors, positions, move.planeDepth);
        peakRate_ = 0;
        for (int k = first; k <= last; k++)
            peakRate_ = std::max(peakRate_, norm(path_.rotation->angularVelocity(start + k / rate)));
        double reached = peakRate_;
        if (byBlur)
        {
            reached = 0;
            for (int f = 0; f < clip_.frames; f++)
                reached = std::max(reached, frameBlurPx(path_, K_, clip_.frameSize, shutter(f), true));
        }
        if (!(reached > 0))
            CV_Error(Error::StsBadArg, format("HandHeldClip: no frame moves: the stretches keep every frame still; "
                                              "shorten stretches.stillSeconds = %g (s) or add frames = %d",
                                              clip_.stretches.stillSeconds, clip_.frames));
        if (std::abs(reached / target - 1) < 1e-3)
            break;
        scale *= target / reached;
    }
    const double stray = viewStrayPx(path_, K_, clip_.frameSize, 0, end);
    margin_ = int(std::ceil(stray)) + 4;
    if (margin_ > std::max(clip_.frameSize.width, clip_.frameSize.height))
        CV_Error(Error::StsBadArg,
                 format("HandHeldClip: the view strays %.0f px from the home view, more than the frame's size: lower "
                        "rotation.peakRate = %g (rad/s) or rotation.maxBlurPx = %g (px) or raise rotation.lowHz = %g "
                        "(Hz)",
                        stray, turn.peakRate, turn.maxBlurPx, turn.lowHz) +
                     (move.planeDepth > 0 ? format("; or lower translation.peakSpeed = %g (m/s)", move.peakSpeed) : ""));
}

void HandHeldSimulator::makeScene()
{
    const Size sceneSize(clip_.frameSize.width + 2 * margin_, clip_.frameSize.height + 2 * margin_);
    Mat scene;
    if (clip_.image.empty())
        scene = dynblur_samples::makeScene(sceneSize);
    else
    {
        const Mat image = imread(clip_.image, IMREAD_COLOR);
        if (image.empty())
            CV_Error(Error::StsError, "HandHeldClip: image = '" + clip_.image + "' cannot be read as an image");
        const double zoom = std::max(1.0 * sceneSize.width / image.cols, 1.0 * sceneSize.height / image.rows);
        Mat scaled;
        resize(image, scaled, Size(), zoom, zoom, zoom < 1 ? INTER_AREA : INTER_CUBIC);
        scene = scaled(Rect((scaled.cols - sceneSize.width) / 2, (scaled.rows - sceneSize.height) / 2,
                            sceneSize.width, sceneSize.height));
    }
    srgbToLinear(scene, sceneLinear_);
}

void HandHeldSimulator::makeGyroLog()
{
    const GyroModel& g = clip_.gyro;
    const double from = -g.leadSeconds + g.timeOffset, to = clip_.end() + g.leadSeconds + g.timeOffset;
    const long long k0 = (long long)std::ceil(from * g.rateHz), k1 = (long long)std::floor(to * g.rateHz);
    RNG rng(clip_.seed * 4 + 3);
    gyroLog_.times.clear();
    gyroLog_.rates.create(int(k1 - k0 + 1), 3, CV_64F);
    for (long long k = k0; k <= k1; k++)
    {
        const double tau = double(k) / g.rateHz;
        const Vec3d w = g.rateScale * path_.rotation->angularVelocity(tau - g.timeOffset) + g.bias;
        double* row = gyroLog_.rates.ptr<double>(int(k - k0));
        for (int i = 0; i < 3; i++)
            row[i] = w[i] + (g.noise > 0 ? rng.gaussian(g.noise) : 0.0);
        gyroLog_.times.push_back(tau);
    }
    gyroLog_.id = "dynblur_simulation";
    gyroLog_.orientation = "XYZ";
}

RollingShutter HandHeldSimulator::shutter(int index) const
{
    return RollingShutter(index / clip_.fps, clip_.exposure, clip_.lineDelay(), clip_.frameSize.height);
}

FrameTruth HandHeldSimulator::truth(int index) const
{
    CV_CheckGE(index, 0, "HandHeldSimulator: frame index");
    CV_CheckLT(index, clip_.frames, "HandHeldSimulator: frame index");
    FrameTruth f;
    f.index = index;
    f.shutter = shutter(index);
    f.referenceTime =
        f.shutter.frameStart + 0.5 * (f.shutter.rows - 1) * f.shutter.lineDelay + 0.5 * f.shutter.exposure;
    f.rotationBlurPx = frameBlurPx(path_, K_, clip_.frameSize, f.shutter, true);
    f.blurPx = path_.positions.empty() ? f.rotationBlurPx : frameBlurPx(path_, K_, clip_.frameSize, f.shutter);
    const Vec2d readout = f.shutter.readoutInterval();
    f.still = true;
    for (double t = readout[0]; t <= readout[1] + 5e-4 && f.still; t += 1e-3)
        f.still = clip_.stretches.envelope(std::min(t, readout[1])) == 0;
    return f;
}

ClipFrame HandHeldSimulator::render(int index) const
{
    ClipFrame frame;
    static_cast<FrameTruth&>(frame) = truth(index);
    Mat linear, noisy;
    if (path_.positions.empty())
        renderBlurred(sceneLinear_, path_.rotation, camera_, frame.shutter, linear, path_.start, clip_.maxStepPx);
    else
        linear = renderPlaneBlurred(sceneLinear_, margin_, path_, K_, clip_.frameSize, frame.shutter, clip_.maxStepPx);
    if (clip_.fullWellElectrons > 0)
        addSensorNoise(linear, noisy, clip_.fullWellElectrons, clip_.readNoiseElectrons, clip_.darkElectrons,
                       clip_.seed * 1000003 + uint64(index));
    else
        noisy = linear;
    linearToSrgb(noisy, frame.image, CV_8U);
    linearToSrgb(viewAt(sceneLinear_, margin_, path_, K_, clip_.frameSize, frame.referenceTime), frame.truth, CV_8U);
    return frame;
}

}  // namespace dynblur_samples
