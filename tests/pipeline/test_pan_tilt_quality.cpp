// SPDX-License-Identifier: Apache-2.0
// A pan-tilt head's diagonal saccade (10° pan + 6° tilt, MountPlanner, coordinated), its frames of
// exposure windows I, II, III and a global shutter restored with the mount's exact motion: against the
// seed's single PSF, against RL with the exact model, and back into either resting view.
#include "test_common.hpp"

#include "image_metrics.hpp"
#include "mount_scene.hpp"
#include "pan_tilt.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <tuple>

using namespace cv;
using namespace cv::dynblur;
using dynblur_samples::maskedPsnr;
using dynblur_test::MountScene;
using dynblur_test::seedPanTilt;
using dynblur_test::shutterInWindow;

namespace {

const double kDeg = CV_PI / 180, kNaN = std::numeric_limits<double>::quiet_NaN();

/* The bars: the default over the seed's single PSF, and the default's shortfall against RL with
   the exact model, dB. */
const double kOverUniform = 3.0, kBelowExact = 1.0;

/* The geometry error back into either resting view, px: the bar is 1 px; measured up to 0.24 px
   (docs/quality.md), held 10 % above. */
const double kGeometryPx = 0.27;

/* RL with the exact model: tiles every 20 px (32 × 24 nodes, each kernel the exact path of its pixel),
   where the default takes 8 to 48 columns and the cheapest model within 0.25 px. In window I it is not
   converged: there the default's 48 columns over finer row bands beat it by 0.6-0.9 dB
   (DISABLED_WindowITileColumns, docs/quality.md). */
const Size kExactGrid(32, 24);

//! The head's tilt: the seed's 14.4 Hz, or a stiffer one.
const double kTiltHz[] = {14.4, 20.0};

//! A 10° pan + 6° tilt, coordinated, from rest at 0 starting at t = 0, and the head's motion.
struct PanTiltSaccade
{
    Ptr<CameraMotion> motion;
    double tiltHz;

    explicit PanTiltSaccade(double tiltHzIn) : tiltHz(tiltHzIn)
    {
        const Ptr<Mount> mount = seedPanTilt(14.4, tiltHz);
        const MountMove move = MountPlanner::create(mount)->plan({0, 0}, {10 * kDeg, 6 * kDeg}, 0.0);
        motion = mount->motion(move.schedules);
    }
};

//! A frame of the saccade: its window's name and timing.
struct WindowCase
{
    const char* name;
    int window;
    double lineDelay;  //!< s; 0: global shutter
};

/* The C270's 30 fps readout for windows I and III; window II needs a readout shorter than the move
   (6 ms, as the one-axis test); the global frame is the seed's window III. */
const WindowCase kWindows[] = {{"I rolling", EXPOSURE_I, 1.0 / 30 / 480},
                               {"II rolling", EXPOSURE_II, 0.006 / 480},
                               {"III rolling", EXPOSURE_III, 1.0 / 30 / 480},
                               {"III global", EXPOSURE_III, 0.0}};

//! A deblurrer of the mount's frames: the default, the seed's single PSF, or RL with the exact model.
Ptr<DynamicDeblurrer> deblurrer(const MountScene& scene, const String& which)
{
    Ptr<DynamicDeblurrer> d = DynamicDeblurrer::create(scene.camera);
    if (which == "uniform")
        d->setPsfModel(PSF_UNIFORM);
    if (which == "exact")
    {
        d->setPsfModel(PSF_TILES);
        d->getPsfGenerator()->setTileGrid(kExactGrid);
    }
    return d;
}

std::string imageName(const std::string& file) { return file.substr(0, file.find('.')); }

/* The default's gain over the seed's single PSF, dB, as measured (docs/quality.md), per
   "<tilt Hz> Hz tilt, <window>, <image>". Asserted at 0.92 × (as DeblurQuality's). */
const std::map<std::string, double>& documentedGains()
{
    static const std::map<std::string, double> gains = {
        {"14.4 Hz tilt, I rolling, building", 13.97},
        {"14.4 Hz tilt, II rolling, building", 5.35},
        {"14.4 Hz tilt, III rolling, building", 9.52},
        {"14.4 Hz tilt, III global, building", 3.04},
        {"14.4 Hz tilt, I rolling, fruits", 11.29},
        {"14.4 Hz tilt, II rolling, fruits", 5.13},
        {"14.4 Hz tilt, III rolling, fruits", 3.04},
        {"14.4 Hz tilt, III global, fruits", 0.47},
        {"14.4 Hz tilt, I rolling, baboon", 11.27},
        {"14.4 Hz tilt, II rolling, baboon", 3.60},
        {"14.4 Hz tilt, III rolling, baboon", 7.22},
        {"14.4 Hz tilt, III global, baboon", 1.21},
        {"20.0 Hz tilt, I rolling, building", 15.00},
        {"20.0 Hz tilt, II rolling, building", 5.69},
        {"20.0 Hz tilt, III rolling, building", 8.86},
        {"20.0 Hz tilt, III global, building", 3.39},
        {"20.0 Hz tilt, I rolling, fruits", 11.42},
        {"20.0 Hz tilt, II rolling, fruits", 5.13},
        {"20.0 Hz tilt, III rolling, fruits", 2.96},
        {"20.0 Hz tilt, III global, fruits", 0.48},
        {"20.0 Hz tilt, I rolling, baboon", 12.02},
        {"20.0 Hz tilt, II rolling, baboon", 3.78},
        {"20.0 Hz tilt, III rolling, baboon", 6.97},
        {"20.0 Hz tilt, III global, baboon", 1.69},
    };
    return gains;
}

class PanTiltQuality : public testing::TestWithParam<std::tuple<double, std::string>>
{
};

/* The pixels judged: those every restoration observed, less a 16-pixel border. */
Mat judgedPixels(const std::vector<Mat>& valid)
{
    Mat judged(480, 640, CV_8U, Scalar(0));
    judged(Rect(16, 16, 640 - 32, 480 - 32)).setTo(255);
    for (const Mat& v : valid)
        judged &= v;
    return judged;
}

}  // namespace

/* Each window's frame restored by the default (PSF_AUTO), by the seed's single PSF and by RL with the
   exact model, PSNR over the pixels all three observed. The default beats the single PSF by the issue's
   3 dB wherever RL with the exact model can (a global frame's blur is nearly the same everywhere: there
   even the exact model gains less, and the bound is printed), and stays within 1 dB of the exact
   model's RL. */
TEST_P(PanTiltQuality, EveryWindowBeyondTheSeedsSinglePsfNearTheExactModel)
{
    const double tiltHz = std::get<0>(GetParam());
    const std::string file = std::get<1>(GetParam());
    DYNBLUR_REQUIRE_DATA(path, file);
    const MountScene scene(path);
    const PanTiltSaccade saccade(tiltHz);
    for (const WindowCase& w : kWindows)
    {
        SCOPED_TRACE(w.name);
        const RollingShutter shutter = shutterInWindow(saccade.motion, w.window, w.lineDelay);
        const Mat frame = scene.capture(saccade.motion, shutter, 7);
        std::vector<Mat> restored(3), valid(3);
        const char* which[] = {"default", "uniform", "exact"};
        for (int k = 0; k < 3; k++)
            deblurrer(scene, which[k])->deblur(frame, saccade.motion, shutter, restored[size_t(k)], kNaN,
                                               valid[size_t(k)]);
        const Mat judged = judgedPixels(valid);
        ASSERT_GT(countNonZero(judged), 640 * 480 / 2);
        const double blurred = maskedPsnr(scene.truth, frame, judged, 255),
                     dflt = maskedPsnr(scene.truth, restored[0], judged, 255),
                     uniform = maskedPsnr(scene.truth, restored[1], judged, 255),
                     exact = maskedPsnr(scene.truth, restored[2], judged, 255);
        const std::string key = format("%.1f Hz tilt, %s, %s", tiltHz, w.name, imageName(file).c_str());
        std::printf("[ measured ] pan-tilt 10+6 deg, %s (frame at %.2f ms): blurred %.2f, single PSF %.2f, default "
                    "%.2f, exact model %.2f dB; default - single PSF %+.2f dB (exact model's bound %+.2f), default - "
                    "exact model %+.2f dB\n",
                    key.c_str(), shutter.frameStart * 1e3, blurred, uniform, dflt, exact, dflt - uniform,
                    exact - uniform, dflt - exact);
        // The bar, where RL with the exact model reaches it.
        if (exact - uniform >= kOverUniform)
        {
            EXPECT_GE(dflt - uniform, kOverUniform) << key;
        }
        EXPECT_GE(dflt - exact, -kBelowExact) << key;
        const auto documented = documentedGains().find(key);
        if (documented == documentedGains().end())
            ADD_FAILURE() << "no documented figure for '" << key << "' (measured " << dflt - uniform << " dB)";
        else
            EXPECT_GE(dflt - uniform, 0.92 * documented->second) << key;
    }
}

namespace {

//! The 9 points the geometry is measured at: a 3 × 3 grid at 1/4, 1/2 and 3/4 of the frame, px.
std::vector<Point2d> geometryPoints()
{
    std::vector<Point2d> points;
    for (int gy = 1; gy <= 3; gy++)
        for (int gx = 1; gx <= 3; gx++)
            points.emplace_back(640 * gx / 4.0 - 0.5, 480 * gy / 4.0 - 0.5);
    return points;
}

//! A dark scene with a Gaussian spot (σ = 1.5 px) at each geometry point of the reference view, linear.
Mat spotScene()
{
    Mat scene(480 + 2 * MountScene::marginY, 640 + 2 * MountScene::marginX, CV_32FC3, Scalar::all(0.05));
    for (const Point2d& p : geometryPoints())
        for (int dy = -8; dy <= 8; dy++)
            for (int dx = -8; dx <= 8; dx++)
            {
                const int x = cvRound(p.x) + dx + MountScene::marginX, y = cvRound(p.y) + dy + MountScene::marginY;
                const double ex = x - MountScene::marginX - p.x, ey = y - MountScene::marginY - p.y;
                scene.at<Vec3f>(y, x) += Vec3f::all(float(0.9 * std::exp(-(ex * ex + ey * ey) / (2 * 1.5 * 1.5))));
            }
    return scene;
}

/* The geometry error of `restored` (8-bit sRGB of spotScene's view), px: each spot's centroid (of the
   intensity above the background, in a 25 × 25 window around where the reference view has it) against
   that place, the largest over the spots the frame observed (`valid`); `observed` counts them. */
double geometryError(const Mat& restored, const Mat& valid, int& observed, std::string& where)
{
    Mat linear, gray;
    srgbToLinear(restored, linear);
    cvtColor(linear, gray, COLOR_BGR2GRAY);
    double worst = 0;
    observed = 0;
    for (const Point2d& p : geometryPoints())
    {
        const Rect box(cvRound(p.x) - 12, cvRound(p.y) - 12, 25, 25);
        if (countNonZero(valid(box)) < box.area())
            continue;
        Mat w;
        threshold(gray(box) - 0.1, w, 0, 0, THRESH_TOZERO);
        const Moments m = moments(w);
        const Point2d centroid(box.x + m.m10 / m.m00, box.y + m.m01 / m.m00);
        where += format(" (%.0f, %.0f): %.2f", p.x, p.y, norm(centroid - p));
        worst = std::max(worst, norm(centroid - p));
        observed++;
    }
    return worst;
}

}  // namespace

/* Windows I and II restored into the view at rest before the move (a time before it) and after it (NaN,
   the default): a scene of 9 spots, each put back where that view has it within the 1 px (see
   kGeometryPx). */
TEST(PanTiltGeometry, WindowsIAndIIBackIntoEitherRestingView)
{
    const MountScene scene(spotScene());
    for (double tiltHz : kTiltHz)
    for (const WindowCase& w : {kWindows[0], kWindows[1]})
        for (double tRef : {-0.1, kNaN})
        {
            const PanTiltSaccade saccade(tiltHz);
            const RollingShutter shutter = shutterInWindow(saccade.motion, w.window, w.lineDelay);
            const Mat frame = scene.capture(saccade.motion, shutter, 11, tRef);
            Mat restored, valid;
            deblurrer(scene, "default")->deblur(frame, saccade.motion, shutter, restored, tRef, valid);
            std::string where;
            int observed = 0;
            const double worst = geometryError(restored, valid, observed, where);
            const std::string key = format("%.1f Hz tilt, %s, into the view %s the move", tiltHz, w.name,
                                           std::isnan(tRef) ? "after" : "before");
            std::printf("[ measured ] pan-tilt 10+6 deg, %s: geometry error %.2f px at worst over %d spots;%s\n",
                        key.c_str(), worst, observed, where.c_str());
            EXPECT_GE(observed, 7) << key;
            EXPECT_LE(worst, kGeometryPx) << key;
        }
}

/* How many tile columns window I needs (docs/quality.md): a pan moves the image along x by an amount that
   changes across x (f·tan(atan(x/f) + θ)), up to ~0.27 px per pixel here, so adjacent kernels' shifts
   part fast along a row. Prints the window I frame restored as PSF_TILES with the automatic grid, with
   16 to 64 columns over the automatic row bands, and with the exact model at two spacings (its
   convergence), with each restoration's time (printed, not asserted), per image. */
TEST_P(PanTiltQuality, DISABLED_WindowITileColumns)
{
    const double tiltHz = std::get<0>(GetParam());
    const std::string file = std::get<1>(GetParam());
    DYNBLUR_REQUIRE_DATA(path, file);
    const MountScene scene(path);
    const PanTiltSaccade saccade(tiltHz);
    const RollingShutter shutter = shutterInWindow(saccade.motion, EXPOSURE_I, kWindows[0].lineDelay);
    const Mat frame = scene.capture(saccade.motion, shutter, 7);
    const std::vector<Size> grids = {Size(0, 0),  Size(16, 0), Size(32, 0), Size(48, 0),
                                     Size(64, 0), kExactGrid,  Size(64, 48)};
    std::vector<Mat> restored(grids.size()), valid(grids.size());
    std::vector<double> ms(grids.size());
    std::vector<Size> nodes(grids.size());
    for (size_t k = 0; k < grids.size(); k++)
    {
        Ptr<DynamicDeblurrer> d = deblurrer(scene, "exact");
        d->getPsfGenerator()->setTileGrid(grids[k]);
        const int64 start = getTickCount();
        d->deblur(frame, saccade.motion, shutter, restored[k], kNaN, valid[k]);
        ms[k] = double(getTickCount() - start) * 1e3 / getTickFrequency();
        nodes[k] = Size(int(d->getLastPsfBank().nodeCols.size()), int(d->getLastPsfBank().nodeRows.size()));
    }
    const Mat judged = judgedPixels(valid);
    for (size_t k = 0; k < grids.size(); k++)
        std::printf("[ measured ] %.1f Hz tilt, %s, window I, tiles %d x %d (0: automatic; %d x %d nodes): %.2f dB, "
                    "%.0f ms\n",
                    tiltHz, imageName(file).c_str(), grids[k].width, grids[k].height, nodes[k].width,
                    nodes[k].height, maskedPsnr(scene.truth, restored[k], judged, 255), ms[k]);
}

INSTANTIATE_TEST_SUITE_P(, PanTiltQuality,
                         testing::Combine(testing::ValuesIn(kTiltHz),
                                          testing::Values("building.jpg", "fruits.jpg", "baboon.jpg")),
                         [](const testing::TestParamInfo<PanTiltQuality::ParamType>& info) {
                             return format("tilt%.0fHz_%s", std::get<0>(info.param),
                                           imageName(std::get<1>(info.param)).c_str());
                         });
