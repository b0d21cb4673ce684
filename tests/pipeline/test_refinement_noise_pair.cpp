// SPDX-License-Identifier: Apache-2.0
// Refinement with the noise measured from two stills (DynamicDeblurrer::setNoiseFrames): wrong models
// are refused and right ones kept, on rendered frames and after a webcam's JPEG (MJPEG) round trip.
#include "test_common.hpp"

#include "image_metrics.hpp"
#include "refinement_cases.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>
#include <tuple>

using namespace cv;
using namespace cv::dynblur;
using namespace dynblur_test;
using dynblur_samples::maskedPsnr;

namespace {

//! An 8-bit frame after a JPEG round trip at `quality` (a USB webcam's MJPEG); quality 0: as rendered.
Mat throughCodec(const Mat& frame, int quality)
{
    if (quality == 0)
        return frame;
    std::vector<uchar> bytes;
    imencode(".jpg", frame, bytes, {IMWRITE_JPEG_QUALITY, quality});
    return imdecode(bytes, IMREAD_COLOR);
}

//! What one image and codec gave: wrong models' worst outcome, right (drifted) models' gain and refusals.
struct PairFigures
{
    double worst = 1e9;      // dB, output vs blurred, over the wrong models
    int worse = 0;           // wrong models restored worse than the blurred frame by more than 0.1 dB
    int wrong = 0;
    double keptSum = 0;      // drifted frames: the fraction of the truth's gain kept, summed
    double keptWorst = 1e9;
    int drifted = 0, refused = 0;
    double rightMax = 0;     // the highest consistency of a right model
    double wrongMin = 1e9;   // the lowest consistency of a wrong model restored worse
};

/* The deblurrer refining frames against `reference`, with the noise measured from two consecutive
   stills (`stillA`, `stillB`) and the consistency limit `limit` (NaN: the default). */
Ptr<DynamicDeblurrer> pairDeblurrer(const SaccadeScene& s, const Mat& reference, double angle, const Mat& stillA,
                                    const Mat& stillB, double limit)
{
    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(s.plant, s.camera);
    deblurrer->setReferenceFrame(reference, angle);
    deblurrer->setNoiseFrames(stillA, stillB);
    if (!std::isnan(limit))
        deblurrer->setConsistencyLimit(limit);
    return deblurrer;
}

/* RefinementNeverWorse's 24 wrong models (another move, late, the other sign, a moving object, a
   still moved or relit; windows I, III and global III) and drifted frames told the nominal model
   (`drifts`, of kDrifts), on `image` through a JPEG round trip at `quality` (0: as rendered). */
PairFigures measurePair(const std::string& path, const std::string& image, int quality,
                        const std::vector<int>& drifts, double limit)
{
    SaccadeScene s(path);
    const WrongSchedules wrongSchedules(s);
    PairFigures f;
    const char* codec = quality ? "jpeg q80" : "rendered";
    for (const WindowCase& w : kWindows)
    {
        const bool after = w.window != EXPOSURE_I;
        const DriftedFrame d = captureDrifted(s, w.window, w.lineDelay, wrongSchedules.drift, 11);
        const RollingShutter stillShutter(after ? 1.0 : -0.2, d.told.exposure, d.told.lineDelay, d.told.rows);
        const Mat next = throughCodec(s.capture(stillShutter, 71), quality);
        const std::vector<WrongModel> wrong =
            wrongModels(s, wrongSchedules, d, [&](const Mat& m) { return throughCodec(m, quality); });
        const Mat& still = wrong[0].still;  // the still as captured (through the codec)
        for (const WrongModel& t : wrong)
        {
            const double angle = s.plant->restingAngle(after ? t.schedule.finalLevel() : t.schedule.initialLevel);
            Ptr<DynamicDeblurrer> deblurrer = pairDeblurrer(s, t.still, angle, still, next, limit);
            Mat restored;
            deblurrer->deblur(t.frame, t.schedule, d.told, restored);
            const MotionCorrection c = deblurrer->getLastCorrection();
            const Mat judged = judgedPixels(Mat(restored.size(), CV_8U, Scalar(255)), Range(0, 480));
            const double blurred = maskedPsnr(s.truth, t.frame, judged, 255);
            const double change = maskedPsnr(s.truth, restored, judged, 255) - blurred;
            std::printf("[ measured ] pair %s %s window %-10s wrong %-20s: consistency %.2f, output %+.2f dB, %s\n",
                        image.c_str(), codec, w.name, t.name, c.consistency, change,
                        c.applied ? "restored" : "returned unchanged");
            f.worse += change < -0.1 ? 1 : 0;
            f.worst = std::min(f.worst, change);
            if (c.applied && change < -0.1)
                f.wrongMin = std::min(f.wrongMin, c.consistency);
            f.wrong++;
        }
        for (int k : drifts)
        {
            const Drift& drift = kDrifts[k];
            if (w.lineDelay == 0 && drift.lineDelayScale != 1 && drift.timeOffset == 0)
                continue;  // a global shutter has no line delay to be wrong
            const DriftedFrame dd = captureDrifted(s, w.window, w.lineDelay, drift, 7);
            const Mat driftedFrame = throughCodec(dd.frame, quality), driftedStill = throughCodec(dd.still, quality);
            Mat truthRestored, valid, restored;
            DynamicDeblurrer::create(drift.plant(s), s.camera)
                ->deblur(driftedFrame, s.schedule, drift.shutter(dd.told), truthRestored, kNaN, valid);
            const Mat judged = judgedPixels(valid, judgedRows(s, w, dd.told));
            const double blurred = maskedPsnr(s.truth, driftedFrame, judged, 255);
            const double truthGain = maskedPsnr(s.truth, truthRestored, judged, 255) - blurred;
            Ptr<DynamicDeblurrer> deblurrer = pairDeblurrer(s, driftedStill, dd.stillAngle, driftedStill, next, limit);
            deblurrer->deblur(driftedFrame, s.schedule, dd.told, restored);
            const MotionCorrection c = deblurrer->getLastCorrection();
            const double kept = (maskedPsnr(s.truth, restored, judged, 255) - blurred) / truthGain;
            std::printf("[ measured ] pair %s %s window %-10s drift %-20s: consistency %.2f, %.0f %% of the truth's "
                        "gain (%.2f dB), %s\n",
                        image.c_str(), codec, w.name, drift.name, c.consistency, 100 * kept, truthGain,
                        c.applied ? "restored" : "returned unchanged");
            f.keptSum += kept;
            f.keptWorst = std::min(f.keptWorst, kept);
            f.rightMax = std::max(f.rightMax, c.consistency);
            f.refused += c.applied ? 0 : 1;
            f.drifted++;
        }
    }
    std::printf("[ measured ] pair %s %s: wrong models: worst %+.2f dB, %d of %d worse by > 0.1 dB, lowest "
                "consistency of one restored worse %s; drifted: %.1f %% of the truth's gain on average (worst "
                "%.0f %%), %d of %d refused, highest consistency %.2f\n",
                image.c_str(), codec, f.worst, f.worse, f.wrong,
                f.worse ? format("%.2f", f.wrongMin).c_str() : "(none)", 100 * f.keptSum / std::max(1, f.drifted),
                100 * f.keptWorst, f.refused, f.drifted, f.rightMax);
    return f;
}

class RefinementNoisePair : public testing::TestWithParam<std::tuple<std::string, int>>
{
};

std::string imageName(const std::string& file)
{
    return file.substr(0, file.find('.'));
}

}  // namespace

/* With the noise measured from two stills, the default limit: none of RefinementNeverWorse's 24 wrong
   models comes back worse than its blurred frame by more than 0.1 dB (Immerkær's estimate let two of
   baboon's through: -1.52 and -6.50 dB), and drifted frames told the nominal model are all restored
   with the truth's gain, as rendered and after a JPEG round trip at quality 80. The drifts: the
   clock 2 ms late and the line delay 10 % long (the highest consistencies of right models, building
   window I) and combined A. */
TEST_P(RefinementNoisePair, WrongModelsRefusedDriftsKept)
{
    DYNBLUR_REQUIRE_DATA(path, std::get<0>(GetParam()));
    const std::string image = imageName(std::get<0>(GetParam()));
    const int quality = std::get<1>(GetParam());
    const PairFigures f = measurePair(path, image, quality, {1, 8, 10}, kNaN);
    EXPECT_EQ(f.worse, 0);
    EXPECT_GE(f.worst, -0.1);
    EXPECT_EQ(f.refused, 0) << "of " << f.drifted << " drifted frames (5 % of them is less than one)";
    /* The 90 %. Measured 90.9 % (fruits after JPEG: its global-shutter frame 2 ms late keeps
       45 % of a truth's gain of 1.8 dB) to 103.1 % (baboon as rendered). */
    EXPECT_GE(f.keptSum / f.drifted, 0.9);
}

/* Every drift, the consistency limit off: the consistencies of right and wrong models in units of
   the pair's noise, from which the default limit is chosen (docs/refinement.md). */
TEST_P(RefinementNoisePair, DISABLED_Consistencies)
{
    DYNBLUR_REQUIRE_DATA(path, std::get<0>(GetParam()));
    std::vector<int> all;
    for (int k = 1; k < int(sizeof(kDrifts) / sizeof(kDrifts[0])); k++)
        all.push_back(k);
    measurePair(path, imageName(std::get<0>(GetParam())), std::get<1>(GetParam()), all,
                std::numeric_limits<double>::infinity());
}

namespace {

//! A case's name: the image, then how its frames were stored.
std::string caseName(const testing::TestParamInfo<std::tuple<std::string, int>>& info)
{
    return imageName(std::get<0>(info.param)) + (std::get<1>(info.param) ? "_jpeg80" : "_rendered");
}

}  // namespace

/* Each case takes about 40 restorations: the test command runs the cases that failed before the
   pair (baboon's wrong models passed Immerkær's limit; building's drifted frames were refused after
   JPEG with the full-resolution estimate halved per level) and baboon after JPEG. Every image and
   codec: --gtest_filter='*RefinementNoisePair*' with AllImages. */
INSTANTIATE_TEST_SUITE_P(SharedImages, RefinementNoisePair,
                         testing::Values(std::make_tuple("baboon.jpg", 0), std::make_tuple("baboon.jpg", 80),
                                         std::make_tuple("building.jpg", 80)),
                         caseName);
INSTANTIATE_TEST_SUITE_P(DISABLED_AllImages, RefinementNoisePair,
                         testing::Combine(testing::Values("building.jpg", "fruits.jpg", "baboon.jpg"),
                                          testing::Values(0, 80)),
                         caseName);
