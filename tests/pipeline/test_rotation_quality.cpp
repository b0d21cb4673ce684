// SPDX-License-Identifier: Apache-2.0
// Restoration of frames blurred by a 3-axis hand-held shake (CameraMotion): the spatially variant
// pipeline against the seed's single PSF and against a dense operator close to the exact blur.
#include "image_metrics.hpp"
#include "pipeline/frame_rate_preset.hpp"
#include "rotation_motion.hpp"
#include "saccade_scene.hpp"
#include "shake_scene.hpp"
#include "test_common.hpp"

#include <gtest/gtest.h>
#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <functional>

using namespace cv;
using namespace cv::dynblur;
using dynblur_samples::maskedPsnr;
using dynblur_test::ShakeScene;

namespace {

struct Figures
{
    double blurred, uniform, variant, dense, preset;
};

/* PSNR against the truth of the frame and of four restorations, over the pixels every restoration
   observed, 16 px in from the border: the seed's single kernel (the frame centre's), the default
   (tiles), tiles at 64 × 120 nodes, whose blur is within a few hundredths of a pixel of the
   forward model (RotationBlur.ThreeAxisPointSourcesMatchTheRendererEverywhere), and
   DEBLUR_PRESET_FRAME_RATE. */
Figures restoreFourWays(const ShakeScene& s, const RollingShutter& shutter, const Mat& frame)
{
    Mat judged(480, 640, CV_8U, Scalar(0));
    judged(Rect(16, 16, 640 - 32, 480 - 32)).setTo(255);
    Mat restored[4];
    for (int k = 0; k < 4; k++)
    {
        Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(s.camera);
        if (k == 0)
            deblurrer->setPsfModel(PSF_UNIFORM);
        if (k == 2)
            deblurrer->getPsfGenerator()->setTileGrid(Size(64, 120));
        if (k == 3)
            deblurrer->setPreset(DEBLUR_PRESET_FRAME_RATE);
        Mat valid;
        deblurrer->deblur(frame, s.motion, shutter, restored[k], NAN, valid);
        EXPECT_TRUE(deblurrer->getLastCorrection().applied);
        judged &= valid;
    }
    EXPECT_GT(countNonZero(judged), 640 * 480 / 2);
    return Figures{maskedPsnr(s.truth, frame, judged, 255), maskedPsnr(s.truth, restored[0], judged, 255),
                   maskedPsnr(s.truth, restored[1], judged, 255), maskedPsnr(s.truth, restored[2], judged, 255),
                   maskedPsnr(s.truth, restored[3], judged, 255)};
}

/* The 24 frames: three images × shakes of up to 30 and 90 °/s per axis (blur paths up to 13 and
   41 px) × rolling (30 ms readout) and global shutter × 10 and 20 ms exposures, each given to `use`
   with its image's name, the shake's peak rate (deg/s), the scene and the shutter. */
void forEachShakeFrame(
    const std::function<void(const char*, double, const ShakeScene&, const RollingShutter&, const Mat&)>& use)
{
    for (const char* name : {"building.jpg", "fruits.jpg", "baboon.jpg"})
    {
        DYNBLUR_REQUIRE_DATA(path, name);
        for (double peakRate : {30.0, 90.0})
        {
            const ShakeScene scene(path, peakRate);
            for (double lineDelay : {0.030 / 480, 0.0})
                for (double exposure : {0.010, 0.020})
                {
                    const RollingShutter shutter(0.1, exposure, lineDelay, 480);
                    use(name, peakRate, scene, shutter, scene.capture(shutter, 7));
                }
        }
    }
}

// Floors, ~90 % of the measured means (docs/quality.md).
const double kRollingOverUniform = 9.1, kGlobalOverUniform = 2.9;
// The frame-rate preset against the default on every frame: the bound, dB.
const double kPresetGap = 0.5;

}  // namespace

/* On the 24 frames of forEachShakeFrame the default gains over the seed's single PSF and stays
   within 0.3 dB of the dense operator on every frame (measured: 0.12 at most), and the frame-rate
   preset stays within kPresetGap of the default. Mean and worst frame in docs/quality.md. */
TEST(RotationQuality, ShakeRestoredBeyondTheSeedsSinglePsf)
{
    struct Gain
    {
        bool rolling;
        double overUniform, belowDense, overBlurred;
    };
    std::vector<Gain> gains;
    forEachShakeFrame([&](const char* name, double peakRate, const ShakeScene& scene, const RollingShutter& shutter,
                          const Mat& frame) {
        const Figures f = restoreFourWays(scene, shutter, frame);
        const bool rolling = shutter.lineDelay > 0;
        std::printf("[ measured ] 3-axis shake %.0f deg/s, %s, %s shutter, %.0f ms: blurred %.2f dB, seed uniform %.2f "
                    "dB, default %.2f dB, dense %.2f dB, frame-rate preset %.2f dB (preset - default %+.2f dB)\n",
                    peakRate, name, rolling ? "rolling" : "global", shutter.exposure * 1e3, f.blurred, f.uniform,
                    f.variant, f.dense, f.preset, f.preset - f.variant);
        EXPECT_LE(f.dense - f.variant, 0.3) << name << ", " << peakRate << " deg/s";
        EXPECT_GE(f.preset - f.variant, -kPresetGap)
            << name << ", " << peakRate << " deg/s, " << shutter.exposure * 1e3 << " ms";
        gains.push_back(Gain{rolling, f.variant - f.uniform, f.dense - f.variant, f.variant - f.blurred});
    });
    for (int rolling = 1; rolling >= 0; rolling--)
    {
        double mean = 0, worst = 1e9, meanBlurred = 0;
        int n = 0;
        for (const Gain& g : gains)
            if (g.rolling == bool(rolling))
            {
                mean += g.overUniform;
                meanBlurred += g.overBlurred;
                worst = std::min(worst, g.overUniform);
                n++;
            }
        mean /= n;
        meanBlurred /= n;
        std::printf("[ measured ] 3-axis shake, %s shutter, %d frames: default - seed uniform mean %+.2f dB, worst "
                    "%+.2f dB; default - blurred mean %+.2f dB\n",
                    rolling ? "rolling" : "global", n, mean, worst, meanBlurred);
        EXPECT_GE(mean, rolling ? kRollingOverUniform : kGlobalOverUniform) << (rolling ? "rolling" : "global");
    }
}

/* A gyroscope on the one-axis positioner: the plant's own rate θ'(t)·e_x, sampled at 1 and 5 kHz and
   integrated by fromAngularVelocity from the orientation at the first sample, restores a window III
   frame as the plant does (deblur with the schedule), to the reference at the final rest. At 1 kHz
   the samples do not resolve the switches' jumps of θ'' (the kernels differ by up to 0.07 px, the
   restorations by about 0.2 dB either way); at 5 kHz the kernels agree within 0.006 px. */
TEST(RotationQuality, PlantRateAsGyroRestoresAsThePlant)
{
    DYNBLUR_REQUIRE_DATA(path, "building.jpg");
    const dynblur_test::SaccadeScene s(path);
    const RollingShutter shutter = s.shutterInWindow(EXPOSURE_III, 1.0 / 30 / 480);
    const Mat frame = s.capture(shutter, 11);
    Mat valid, byPlant;
    DynamicDeblurrer::create(s.plant, s.camera)->deblur(frame, s.schedule, shutter, byPlant, NAN, valid);
    const Mat judged = dynblur_test::judgedPixels(valid, Range(0, 480));
    const double plantPsnr = maskedPsnr(s.truth, byPlant, judged, 255);
    const double settled = 0.3;  // s: the planned move has come to rest (residual vibration ~1e-11)
    for (double rateHz : {1000.0, 5000.0})
    {
        Mat t(1, int(std::lround(settled * rateHz)) + 1, CV_64F), omega, theta;
        for (int k = 0; k < t.cols; k++)
            t.at<double>(k) = k / rateHz;
        s.plant->velocity(s.schedule, t, omega);
        s.plant->response(s.schedule, t, theta);
        Mat rates = Mat::zeros(t.cols, 3, CV_64F);
        omega.reshape(1, t.cols).copyTo(rates.col(0));
        const double a = theta.at<double>(0);
        const Matx33d start(1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a));
        Mat byGyro;
        DynamicDeblurrer::create(s.camera)->deblur(frame, CameraMotion::fromAngularVelocity(t, rates, start), shutter,
                                                   byGyro, settled);
        const double gyroPsnr = maskedPsnr(s.truth, byGyro, judged, 255);
        std::printf("[ measured ] window III rolling, building: restored from the plant %.2f dB, from its rate as a "
                    "%.0f Hz gyro log %.2f dB (blurred %.2f dB)\n",
                    plantPsnr, rateHz, gyroPsnr, maskedPsnr(s.truth, frame, judged, 255));
        EXPECT_NEAR(gyroPsnr, plantPsnr, rateHz >= 5000 ? 0.1 : 0.3) << rateHz << " Hz";
    }
}

/* What a gyroscope log 5 ms off the camera's clock costs when nobody corrects it: the shake frames
   of ShakeRestoredBeyondTheSeedsSinglePsf (rolling, 20 ms, 30 deg/s) restored with the log's clock
   as told against the truth. Reported (docs/quality.md); the floor holds that the truth stays ahead. */
TEST(RotationQuality, FiveMillisecondClockOffsetUncorrected)
{
    for (const char* name : {"building.jpg", "fruits.jpg", "baboon.jpg"})
    {
        DYNBLUR_REQUIRE_DATA(path, name);
        const ShakeScene scene(path, 30);
        const RollingShutter shutter(0.1, 0.020, 0.030 / 480, 480);
        RollingShutter told = shutter;
        told.frameStart += 0.005;
        const Mat frame = scene.capture(shutter, 7);
        // Both restore the view at the frame's true mid-exposure, so only the blur and the rows' timing differ.
        const double midExposure = shutter.frameStart + 0.5 * (shutter.rows - 1) * shutter.lineDelay + 0.5 * shutter.exposure;
        Mat valid, right, wrong;
        DynamicDeblurrer::create(scene.camera)->deblur(frame, scene.motion, shutter, right, midExposure, valid);
        DynamicDeblurrer::create(scene.camera)->deblur(frame, scene.motion, told, wrong, midExposure);
        Mat judged(480, 640, CV_8U, Scalar(0));
        judged(Rect(16, 16, 640 - 32, 480 - 32)).setTo(255);
        judged &= valid;
        const double blurred = maskedPsnr(scene.truth, frame, judged, 255),
                     truth = maskedPsnr(scene.truth, right, judged, 255),
                     offset = maskedPsnr(scene.truth, wrong, judged, 255);
        std::printf("[ measured ] %s, 3-axis shake 30 deg/s, rolling, 20 ms: blurred %.2f dB, restored with the true "
                    "clock %.2f dB, with the log 5 ms off %.2f dB (keeps %.0f %% of the gain)\n",
                    name, blurred, truth, offset, 100 * (offset - blurred) / (truth - blurred));
        EXPECT_GT(truth, offset + 1.0) << name;
    }
}

namespace {

/* One setting of PresetAblation: the frame-rate preset's parts as a rule by the longest kernel L
   alone sets them ("by length": 10 iterations up to L = 32 px, else 20, the color at half
   resolution on every frame) or as the default has them. */
struct PresetParts
{
    const char* name;
    int iterations;  // 0: by length
    bool halfColor;  // ceil(L / 6.5) color iterations (3 to 14) at half resolution, else every one in color at full
    bool bfloat16;
    double tolerance;
};

double partsPsnr(const ShakeScene& s, const RollingShutter& shutter, const Mat& frame, const Mat& judged,
                 const PresetParts& parts, double longest)
{
    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(s.camera);
    RLParams params = deblurrer->getRLParams();
    params.iterations = parts.iterations > 0 ? parts.iterations : longest <= 32 ? 10 : 20;
    const int byLength = std::max(3, std::min(14, int(std::ceil(longest / 6.5))));
    params.colorIterations = parts.halfColor ? std::min(params.iterations - 1, byLength) : -1;
    params.blurPrecision = parts.bfloat16 ? RL_BLUR_BFLOAT16 : RL_BLUR_FLOAT32;
    params.tolerance = parts.tolerance;
    deblurrer->setRLParams(params);
    if (parts.halfColor)
        deblurrer->setColorResolution(DEBLUR_COLOR_HALF_RESOLUTION);
    Mat restored;
    deblurrer->deblur(frame, s.motion, shutter, restored);
    return maskedPsnr(s.truth, restored, judged, 255);
}

}  // namespace

/* Which of the frame-rate preset's parts costs the dB on the frames of
   ShakeRestoredBeyondTheSeedsSinglePsf: each setting's PSNR minus the default's, per frame, with
   the frame's longest kernel L and most spread one's N (docs/quality.md, "PSF_AUTO and the
   frame-rate preset"). A measurement, not a check: run with --gtest_also_run_disabled_tests. */
TEST(RotationQuality, DISABLED_PresetAblation)
{
    const PresetParts settings[] = {
        {"by length", 0, true, true, 2e-3},          {"by length, 20 iterations", 20, true, true, 2e-3},
        {"by length, full color", 0, false, true, 2e-3}, {"by length, float blurs", 0, true, false, 2e-3},
        {"by length, no stop", 0, true, true, 0},    {"default, 10 iterations", 10, false, false, 0},
        {"default, half color", 20, true, false, 0}, {"6 in full color", 6, false, true, 2e-3},
        {"8 in full color", 8, false, true, 2e-3},
    };
    std::printf("[ measured ] frame | L, N px | default dB | preset");
    for (const PresetParts& parts : settings)
        std::printf(" | %s", parts.name);
    std::printf(" (each minus the default, dB)\n");
    forEachShakeFrame([&](const char* name, double peakRate, const ShakeScene& scene, const RollingShutter& shutter,
                          const Mat& frame) {
        Mat judged(480, 640, CV_8U, Scalar(0)), valid, byDefault, byPreset;
        judged(Rect(16, 16, 640 - 32, 480 - 32)).setTo(255);
        Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(scene.camera),
                              preset = DynamicDeblurrer::create(scene.camera);
        preset->setPreset(DEBLUR_PRESET_FRAME_RATE);
        deblurrer->deblur(frame, scene.motion, shutter, byDefault, NAN, valid);
        preset->deblur(frame, scene.motion, shutter, byPreset);
        judged &= valid;
        const PsfBank bank = deblurrer->getLastPsfBank();
        const double longest = std::max(bank.maxKernelSize().width, bank.maxKernelSize().height);
        const double reference = maskedPsnr(scene.truth, byDefault, judged, 255);
        std::printf("[ measured ] %s %.0f deg/s %s %.0f ms | %.0f, %.1f | %.2f | %+.2f", name, peakRate,
                    shutter.lineDelay > 0 ? "rolling" : "global", shutter.exposure * 1e3, longest,
                    cv::dynblur::detail::mostSpreadKernelPx(bank), reference,
                    maskedPsnr(scene.truth, byPreset, judged, 255) - reference);
        for (const PresetParts& parts : settings)
            std::printf(" | %+.2f", partsPsnr(scene, shutter, frame, judged, parts, longest) - reference);
        std::printf("\n");
    });
}
