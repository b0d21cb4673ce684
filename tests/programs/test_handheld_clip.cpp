// SPDX-License-Identifier: Apache-2.0
// The hand-held clip simulator (samples/simulation/handheld_clip.hpp, plane_render.hpp,
// clip_writer.hpp): its gyro log against its motion, its frames against their truth and the library's
// forward model, the blur it reports against a rendered point, the files it writes read back, and the
// descriptions it refuses.
#include "bad_input_rows.hpp"
#include "test_common.hpp"

#include "clip_writer.hpp"
#include "plane_render.hpp"
#include "recording.hpp"
#include "scene.hpp"

#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

using namespace cv;
using namespace cv::dynblur;
using namespace dynblur_samples;
using namespace dynblur_test;

namespace {

const double kDeg = CV_PI / 180;

//! A small rolling-shutter clip: 160×120 at f = 150 px (56° across), 12 frames, up to 8 px of blur, no noise.
HandHeldClip smallClip()
{
    HandHeldClip clip;
    clip.frameSize = Size(160, 120);
    clip.focalPx = 150;
    clip.frames = 12;
    clip.exposure = 0.010;
    clip.readoutTime = 0.020;
    clip.rotation.maxBlurPx = 8;
    clip.fullWellElectrons = 0;
    return clip;
}

//! The angle of the rotation A·Bᵀ, radians.
double angleBetween(const Matx33d& A, const Matx33d& B)
{
    const Matx33d D = A * B.t();
    return std::acos(std::min(1.0, std::max(-1.0, 0.5 * (trace(D) - 1))));
}

double meanAbsDiff(const Mat& a, const Mat& b)
{
    Mat d;
    absdiff(a, b, d);
    const Scalar s = mean(d);
    return (s[0] + s[1] + s[2]) / 3;
}

std::string scratchDir(const std::string& name)
{
    const std::string dir = ::testing::TempDir() + format("dynblur_clip_%d_", (int)::getpid()) + name;
    utils::fs::createDirectories(dir);
    return dir;
}

}  // namespace

// The log's rates, their bias removed, integrate to the true rotation: at 200 Hz and at 100 Hz, over
// 2 s of shake with up to 8 px of blur per 10 ms exposure.
TEST(HandHeldClip, GyroLogIntegratesToTheTrueMotion)
{
    for (double rateHz : {200.0, 100.0})
    {
        HandHeldClip clip = smallClip();
        clip.frames = 60;
        clip.gyro.rateHz = rateHz;
        clip.gyro.bias = Vec3d(1.0, -0.5, 0.7) * kDeg;
        clip.gyro.timeOffset = 0.73;
        const HandHeldSimulator sim(clip);
        GyroLog log = sim.gyroLog();
        log.bias = clip.gyro.bias;
        const double t0 = log.times.front() - clip.gyro.timeOffset;  // the log's first sample, camera clock
        const Ptr<CameraMotion> integrated = log.toMotion(sim.motion()->orientation(t0));
        double worst = 0;
        for (double t = 0; t <= clip.end(); t += 0.005)
            worst = std::max(worst, angleBetween(integrated->orientation(t + clip.gyro.timeOffset),
                                                 sim.motion()->orientation(t)));
        std::printf("%g Hz: largest orientation error over %.2f s: %.3g rad = %.3g px at f = %g px\n", rateHz,
                    clip.end() - t0, worst, worst * clip.focalPx, clip.focalPx);
        EXPECT_LT(worst * clip.focalPx, rateHz == 200 ? 0.05 : 0.5) << rateHz << " Hz";
    }
}

// The log's clock reads camera time + timeOffset: the lag that best aligns the log's rates with the
// true motion's, searched over ±2.5 s, is the offset; the noise has the standard deviation asked for.
TEST(HandHeldClip, ClockOffsetIsWhereTheTruthSays)
{
    for (double offset : {-1.87, 0.0, 1.42})
    {
        HandHeldClip clip = smallClip();
        clip.frames = 45;
        clip.gyro.timeOffset = offset;
        const HandHeldSimulator sim(clip);
        const GyroLog& log = sim.gyroLog();
        auto mismatch = [&](double lag) {
            double sum = 0;
            int n = 0;
            for (size_t k = 0; k < log.times.size(); k++)
            {
                const double t = log.times[k] - lag;
                if (t < 0 || t > clip.end())
                    continue;
                const Vec3d d = Vec3d(log.rates.ptr<double>(int(k))) - sim.motion()->angularVelocity(t);
                sum += d.dot(d);
                n++;
            }
            return n > 100 ? sum / n : 1e300;
        };
        double best = 0;
        for (double lag = -2.5; lag <= 2.5; lag += 0.01)
            best = mismatch(lag) < mismatch(best) ? lag : best;
        for (double lag = best - 0.01; lag <= best + 0.01; lag += 0.0002)
            best = mismatch(lag) < mismatch(best) ? lag : best;
        EXPECT_NEAR(best, offset, 0.0005);
        // The frames lie inside the log, with the lead on both sides.
        EXPECT_LE(log.times.front(), offset - clip.gyro.leadSeconds + 1 / clip.gyro.rateHz);
        EXPECT_GE(log.times.back(), offset + clip.end() + clip.gyro.leadSeconds - 1 / clip.gyro.rateHz);
    }

    HandHeldClip noisy = smallClip();
    noisy.frames = 60;
    noisy.gyro.noise = 0.2 * kDeg;
    noisy.gyro.bias = Vec3d(0.8, -1.0, 0.3) * kDeg;
    noisy.gyro.rateScale = 1.02;
    const HandHeldSimulator sim(noisy);
    const GyroLog& log = sim.gyroLog();
    Vec3d sum, squares;
    for (size_t k = 0; k < log.times.size(); k++)
    {
        const Vec3d e = Vec3d(log.rates.ptr<double>(int(k))) - 1.02 * sim.motion()->angularVelocity(log.times[k]) -
                        noisy.gyro.bias;
        sum += e;
        squares += e.mul(e);
    }
    const double n = double(log.times.size());
    for (int i = 0; i < 3; i++)
    {
        EXPECT_NEAR(sum[i] / n, 0.0, 4 * noisy.gyro.noise / std::sqrt(n)) << "axis " << i;
        EXPECT_NEAR(std::sqrt(squares[i] / n), noisy.gyro.noise, 0.1 * noisy.gyro.noise) << "axis " << i;
    }
}

// With a zero exposure and a global shutter, a frame (renderBlurred, the library's forward model) is the
// truth view (the simulator's own warp of the scene) at the frame's start, and not the next frame's.
TEST(HandHeldClip, ZeroExposureFrameIsTheTruthView)
{
    DYNBLUR_REQUIRE_DATA(building, "building.jpg");
    HandHeldClip clip = smallClip();
    clip.image = building;
    clip.exposure = 0;
    clip.readoutTime = 0;
    clip.rotation.maxBlurPx = 0;
    clip.rotation.peakRate = 60 * kDeg;
    const HandHeldSimulator sim(clip);
    const ClipFrame five = sim.render(5), six = sim.render(6);
    EXPECT_DOUBLE_EQ(five.referenceTime, five.shutter.frameStart);
    const double same = meanAbsDiff(five.image, five.truth), next = meanAbsDiff(six.image, five.truth);
    std::printf("mean |frame - truth| %.3f DN; against the next frame's truth %.2f DN\n", same, next);
    EXPECT_LT(same, 0.5);  // warpPerspective interpolates at 1/32 px
    EXPECT_GT(next, 10 * same + 1);
}

// Rendering has no state: a frame is the same whichever frames were rendered before it, so a stream
// can start anywhere.
TEST(HandHeldClip, FramesDoNotDependOnTheOrderTheyAreRendered)
{
    HandHeldClip clip = smallClip();
    clip.fullWellElectrons = 4000;
    const HandHeldSimulator sim(clip);
    const ClipFrame late = sim.render(9), early = sim.render(2), lateAgain = sim.render(9);
    EXPECT_EQ(norm(late.image, lateAgain.image, NORM_INF), 0.0);
    EXPECT_EQ(norm(late.truth, lateAgain.truth, NORM_INF), 0.0);
    EXPECT_GT(norm(late.image, early.image, NORM_L1), 0.0);
}

// The plane renderer without translation reproduces renderBlurred (no shared code: warpPerspective's
// 1/32-px interpolation against renderBlurred's own), rolling and global; with a translation at 1 m the
// blur grows beyond what the rotation alone predicts.
TEST(HandHeldClip, PlaneRendererReducesToRenderBlurred)
{
    const Size size(200, 150);
    const int margin = 60;
    Mat scene;
    srgbToLinear(makeScene(Size(size.width + 2 * margin, size.height + 2 * margin)), scene);
    const HandShake shake(-0.3, 0.5, ShakeStretches(), 7);
    const Mat rotation = shake.rotationVectors(1, 20, Vec3d(1, 1, 0.5), 0.8);
    const CameraPath path = shake.path(rotation, Mat(), 0);
    const Ptr<CameraModel> camera = CameraModel::create(180, 180, 99.5, 74.5, 200, 150);
    for (double lineDelay : {0.02 / 150, 0.0})
    {
        const RollingShutter shutter(0.1, 0.012, lineDelay, 150);
        Mat reference;
        renderBlurred(scene, path.rotation, camera, shutter, reference, path.start);
        const Mat plane = renderPlaneBlurred(scene, margin, path, camera->cameraMatrix(), size, shutter, 0.25);
        const double blur = frameBlurPx(path, camera->cameraMatrix(), size, shutter);
        Mat d;
        absdiff(reference, plane, d);
        const Scalar m = mean(d);
        double largest = 0;
        minMaxLoc(d.reshape(1), nullptr, &largest);
        std::printf("line delay %g s, blur %.1f px: mean |plane - renderBlurred| %.2e, largest %.2e (linear)\n",
                    lineDelay, blur, (m[0] + m[1] + m[2]) / 3, largest);
        EXPECT_GT(blur, 3.0);
        EXPECT_LT((m[0] + m[1] + m[2]) / 3, 1e-3);
        EXPECT_LT(largest, 0.03);
    }

    const Mat positions = shake.positions(1, 20, Vec3d(1, 1, 0.5), 0.05);
    const CameraPath moving = shake.path(rotation, positions, 1.0);
    const RollingShutter shutter(0.1, 0.012, 0.02 / 150, 150);
    const double rotationBlur = frameBlurPx(moving, camera->cameraMatrix(), size, shutter, true);
    const double blur = frameBlurPx(moving, camera->cameraMatrix(), size, shutter);
    EXPECT_DOUBLE_EQ(rotationBlur, frameBlurPx(path, camera->cameraMatrix(), size, shutter));
    EXPECT_GT(std::abs(blur - rotationBlur), 0.05) << blur << " px against " << rotationBlur << " px";
}

// The plane's homography is the ray–plane intersection: a view pixel's ray, turned by Q and from the
// camera centre c, meets the plane z = d at a point the home camera sees at homeFromView·p.
TEST(HandHeldClip, PlaneHomographyIsTheRayPlaneIntersection)
{
    const HandShake shake(-0.3, 0.5, ShakeStretches(), 11);
    const CameraPath path = shake.path(shake.rotationVectors(1, 20, Vec3d(1, 1, 1), 2.0),
                                       shake.positions(1, 20, Vec3d(1, 1, 1), 0.5), 1.5);
    const Matx33d K(300, 0, 160, 0, 300, 120, 0, 0, 1);
    for (double t : {0.05, 0.21, 0.44})
    {
        const Matx33d Q = path.rotation->orientation(t);
        const Vec3d c = path.position(t);
        ASSERT_GT(norm(c), 1e-3) << "the camera must have moved";
        for (const Point2d p : {Point2d(0, 0), Point2d(319, 17), Point2d(160, 120), Point2d(40, 239)})
        {
            const Vec3d ray = Q * (K.inv() * Vec3d(p.x, p.y, 1));
            const Vec3d X = c + ray * ((1.5 - c[2]) / ray[2]);
            const Vec3d home = K * X, mapped = path.homeFromView(t, K) * Vec3d(p.x, p.y, 1);
            EXPECT_NEAR(mapped[0] / mapped[2], home[0] / home[2], 1e-9);
            EXPECT_NEAR(mapped[1] / mapped[2], home[1] / home[2], 1e-9);
        }
    }
}

// The shake is scaled as asked: the largest frame blur is maxBlurPx (40 px, and a nearly sharp 0.8 px),
// or the largest rate is peakRate; and a frame's blur is the length of a rendered point's streak.
TEST(HandHeldClip, BlurIsAsAsked)
{
    for (double asked : {40.0, 0.8})
    {
        HandHeldClip clip = smallClip();
        clip.frames = 30;
        clip.rotation.maxBlurPx = asked;
        clip.exposure = 0.020;
        const HandHeldSimulator sim(clip);
        double largest = 0, smallest = 1e9;
        for (int k = 0; k < clip.frames; k++)
        {
            largest = std::max(largest, sim.truth(k).blurPx);
            smallest = std::min(smallest, sim.truth(k).blurPx);
        }
        std::printf("asked %.1f px: frames blurred %.2f to %.2f px, peak rate %.1f deg/s\n", asked, smallest,
                    largest, sim.peakRate() / kDeg);
        EXPECT_NEAR(largest, asked, 0.002 * asked);
        EXPECT_GT(smallest, 0.05 * asked) << "a frame without blur in a clip shaky throughout";
    }
    HandHeldClip byRate = smallClip();
    byRate.rotation.maxBlurPx = 0;
    byRate.rotation.peakRate = 30 * kDeg;
    EXPECT_NEAR(HandHeldSimulator(byRate).peakRate(), 30 * kDeg, 0.001 * 30 * kDeg);

    // A pan seen through a narrow lens (f = 3000 px over 320 px: the blur is the same everywhere to 1 %):
    // a point's streak is the frame's blur, to the bilinear splat's pixel on each end.
    HandHeldClip pan = smallClip();
    pan.frameSize = Size(320, 240);
    pan.focalPx = 3000;
    pan.readoutTime = 0;
    pan.exposure = 0.02;
    pan.rotation.axisWeights = Vec3d(0, 1, 0);
    pan.rotation.maxBlurPx = 15;
    const HandHeldSimulator sim(pan);
    const int m = sim.margin();
    Mat dots = Mat::zeros(240 + 2 * m, 320 + 2 * m, CV_32F);
    dots.at<float>(120 + m, 160 + m) = 1.0f;
    for (int k = 0; k < pan.frames; k++)
    {
        const FrameTruth f = sim.truth(k);
        Mat frame;
        renderBlurred(dots, sim.motion(), sim.camera(), f.shutter, frame, sim.path().start);
        std::vector<Point> lit;
        findNonZero(frame > 1e-7, lit);
        ASSERT_FALSE(lit.empty()) << "frame " << k << ": the point left the frame";
        double extent = 0;
        for (const Point& a : lit)
            for (const Point& b : lit)
                extent = std::max(extent, norm(a - b));
        EXPECT_NEAR(extent, f.blurPx, 2.1) << "frame " << k;
    }
}

// Still stretches are still: no blur, no rate but the bias; the shaky ones between are blurred.
TEST(HandHeldClip, StillStretchesAreStill)
{
    HandHeldClip clip = smallClip();
    clip.frames = 60;
    clip.stretches.stillSeconds = 0.5;
    clip.stretches.shakySeconds = 0.5;
    clip.gyro.bias = Vec3d(0.5, 0.5, -0.5) * kDeg;
    const HandHeldSimulator sim(clip);
    int still = 0, shaky = 0;
    for (int k = 0; k < clip.frames; k++)
    {
        const FrameTruth f = sim.truth(k);
        if (f.still)
        {
            still++;
            EXPECT_LT(f.blurPx, 1e-9) << "frame " << k;
        }
        else if (f.blurPx > 0.5)
            shaky++;
    }
    EXPECT_GE(still, 20);
    EXPECT_GE(shaky, 20);
    const GyroLog& log = sim.gyroLog();
    for (size_t k = 0; k < log.times.size(); k++)
    {
        if (log.times[k] > 1.1 && log.times[k] < 1.4)  // inside the still stretch [1, 1.5)
        {
            EXPECT_LT(norm(Vec3d(log.rates.ptr<double>(int(k))) - clip.gyro.bias), 1e-12) << log.times[k];
        }
    }
}

// The files read back: the video (frame count, size, timestamps = frame starts) as .avi and .mp4, the
// gcsv and CSV logs through GyroLog::load (their axes mapped back), Sensor Logger's columns, the truth
// and the frame log.
TEST(HandHeldClip, WrittenFilesReadBack)
{
    HandHeldClip clip = smallClip();
    clip.frames = 10;
    clip.fps = 25;
    clip.gyro.timeOffset = -1.25;
    clip.gyro.bias = Vec3d(0.3, -0.2, 0.1) * kDeg;
    clip.gyro.noise = 0.1 * kDeg;
    const HandHeldSimulator sim(clip);
    const GyroLog& truth = sim.gyroLog();
    auto sameLog = [&](const GyroLog& read, double rateTolerance) {
        ASSERT_EQ(read.times.size(), truth.times.size());
        for (size_t k = 0; k < truth.times.size(); k++)
        {
            ASSERT_NEAR(read.times[k], truth.times[k], 1e-9) << k;
            ASSERT_LT(norm(Vec3d(read.rates.ptr<double>(int(k))) - Vec3d(truth.rates.ptr<double>(int(k)))),
                      rateTolerance)
                << k;
        }
    };

    for (const std::string video : {"clip.avi", "clip.mp4"})
    {
        const std::string dir = scratchDir(video.substr(5));
        ClipFiles files;
        files.video = video;
        files.truth = "truth_%02d.png";
        files.gyro.axes = "YxZ";
        files.frameLogLineDelay = 1e-4;
        const WrittenClip written = writeClip(sim, dir, files);
        ASSERT_EQ(written.paths.size(), 6u);
        EXPECT_GT(written.maxBlurPx, 1.0);
        EXPECT_EQ(norm(imread(dir + "/truth_07.png"), sim.render(7).truth, NORM_INF), 0.0);

        VideoCapture capture(dir + "/" + video);
        ASSERT_TRUE(capture.isOpened()) << video;
        EXPECT_EQ(int(capture.get(CAP_PROP_FRAME_COUNT)), clip.frames) << video;
        Mat frame;
        int count = 0;
        while (capture.read(frame))
        {
            EXPECT_EQ(frame.size(), clip.frameSize);
            EXPECT_NEAR(capture.get(CAP_PROP_POS_MSEC), sim.truth(count).shutter.frameStart * 1e3, 0.5)
                << video << " frame " << count;
            count++;
        }
        EXPECT_EQ(count, clip.frames) << video;

        // gcsv states its axes and units: read as written, the log is the simulator's (deg/s to 1e-9 digits).
        sameLog(GyroLog::load(dir + "/gyro.gcsv"), 1e-8);
        const std::vector<FrameRecord> frames = readFrameLog(dir + "/frames.csv", NAN, NAN);
        ASSERT_EQ(int(frames.size()), clip.frames);
        EXPECT_DOUBLE_EQ(frames[3].lineDelay, 1e-4);
        EXPECT_NEAR(frames[3].frameStart, 3 / clip.fps, 1e-9);

        FileStorage fs(dir + "/truth.yml", FileStorage::READ);
        ASSERT_TRUE(fs.isOpened());
        EXPECT_DOUBLE_EQ(double(fs["timeOffset"]), -1.25);
        EXPECT_DOUBLE_EQ(double(fs["lineDelay"]), clip.lineDelay());
        Vec3d bias;
        fs["gyroBias"] >> bias;
        EXPECT_LT(norm(bias - clip.gyro.bias), 1e-15);
        EXPECT_EQ(std::string(fs["gyroAxes"]), "YxZ");
        ASSERT_EQ(int(fs["frames"].size()), clip.frames);
        EXPECT_NEAR(double(fs["frames"][4]["referenceTime"]), sim.truth(4).referenceTime, 1e-12);
        EXPECT_NEAR(double(fs["frames"][4]["blur"]), sim.truth(4).blurPx, 1e-9);
        utils::fs::remove_all(dir);
    }

    // Plain CSV in s and rad/s, sensor axes YxZ: read with its axes, it is the log; read without, it is not.
    const std::string dir = scratchDir("csv");
    GyroFileOptions csv;
    csv.format = GyroFormat::Csv;
    csv.axes = "YxZ";
    csv.timeUnit = 1;
    csv.rateUnit = 1;
    writeGyroLog(truth, dir + "/gyro.csv", csv);
    GyroLogOptions mapped;
    mapped.orientation = "YxZ";
    sameLog(GyroLog::load(dir + "/gyro.csv", mapped), 1e-8);
    const GyroLog unmapped = GyroLog::load(dir + "/gyro.csv");
    EXPECT_GT(norm(unmapped.rates - truth.rates, NORM_INF), 0.1);

    // Sensor Logger: time in ns since the epoch, seconds_elapsed from the first sample, then z, y, x.
    GyroFileOptions phone;
    phone.format = GyroFormat::SensorLogger;
    phone.axes = "Xyz";
    writeGyroLog(truth, dir + "/Gyroscope.csv", phone);
    std::ifstream in(dir + "/Gyroscope.csv");
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "time,seconds_elapsed,z,y,x");
    for (size_t k = 0; std::getline(in, line); k++)
    {
        long long ns = 0;
        double elapsed = 0, z = 0, y = 0, x = 0;
        ASSERT_EQ(std::sscanf(line.c_str(), "%lld,%lf,%lf,%lf,%lf", &ns, &elapsed, &z, &y, &x), 5) << line;
        ASSERT_LT(k, truth.times.size());
        EXPECT_EQ(ns, 1700000000000000000LL + std::llround(truth.times[k] * 1e9));
        EXPECT_NEAR(elapsed, truth.times[k] - truth.times[0], 1e-9);
        const Vec3d w(truth.rates.ptr<double>(int(k)));
        EXPECT_LT(norm(Vec3d(x, -y, -z) - w), 1e-7) << "the phone's axes are the camera's x, -y, -z";
    }
    utils::fs::remove_all(dir);
}

// Each field out of range is refused, named with its range; so are writer options and a missing image.
TEST(HandHeldClip, RefusesBadDescriptions)
{
    auto refuse = [](const std::string& input, void (*change)(HandHeldClip&), std::vector<std::string> words) {
        return Row{"HandHeldSimulator", input,
                   [change] {
                       HandHeldClip clip = smallClip();
                       change(clip);
                       HandHeldSimulator sim(clip);
                   },
                   words};
    };
    refuseAll({
        refuse("frameSize 8x120", [](HandHeldClip& c) { c.frameSize.width = 8; }, {"frameSize.width", "[16, 8192]"}),
        refuse("focalPx NaN", [](HandHeldClip& c) { c.focalPx = NAN; }, {"focalPx", "pixels"}),
        refuse("fps 0", [](HandHeldClip& c) { c.fps = 0; }, {"fps", "(0, 1000]"}),
        refuse("exposure 10 (ms)", [](HandHeldClip& c) { c.exposure = 10; }, {"exposure", "milliseconds"}),
        refuse("readoutTime > frame period", [](HandHeldClip& c) { c.readoutTime = 0.05; }, {"readoutTime", "1/fps"}),
        refuse("frames 0", [](HandHeldClip& c) { c.frames = 0; }, {"frames", "[1, 1000000]"}),
        refuse("band 20-1 Hz", [](HandHeldClip& c) { c.rotation.lowHz = 20; c.rotation.highHz = 1; },
               {"rotation.highHz", "rotation.lowHz"}),
        refuse("both peakRate and maxBlurPx", [](HandHeldClip& c) { c.rotation.peakRate = 1; },
               {"rotation.peakRate", "exactly one"}),
        refuse("neither peakRate nor maxBlurPx", [](HandHeldClip& c) { c.rotation.maxBlurPx = 0; },
               {"rotation.peakRate", "exactly one"}),
        refuse("maxBlurPx with a zero exposure", [](HandHeldClip& c) { c.exposure = 0; }, {"rotation.maxBlurPx"}),
        refuse("axisWeights all 0", [](HandHeldClip& c) { c.rotation.axisWeights = Vec3d(); },
               {"rotation.axisWeights", "> 0"}),
        refuse("axisWeights negative", [](HandHeldClip& c) { c.rotation.axisWeights[1] = -1; },
               {"rotation.axisWeights[1]", "[0, 1000]"}),
        refuse("planeDepth 0.01 m", [](HandHeldClip& c) { c.translation.planeDepth = 0.01; },
               {"translation.planeDepth", "metres"}),
        refuse("peakSpeed 0 with a plane", [](HandHeldClip& c) {
                   c.translation.planeDepth = 1;
                   c.translation.peakSpeed = 0;
               }, {"translation.peakSpeed", "m/s"}),
        refuse("pivotDistance 3 m", [](HandHeldClip& c) {
                   c.translation.planeDepth = 1;
                   c.translation.pivotDistance = 3;
               }, {"translation.pivotDistance", "[0, 2]"}),
        refuse("stillSeconds -1", [](HandHeldClip& c) { c.stretches.stillSeconds = -1; }, {"stretches.stillSeconds"}),
        refuse("ramp longer than half the shake", [](HandHeldClip& c) {
                   c.stretches.stillSeconds = 1;
                   c.stretches.shakySeconds = 0.05;
               }, {"stretches.rampSeconds", "shakySeconds / 2"}),
        refuse("every frame still", [](HandHeldClip& c) { c.stretches.stillSeconds = 100; }, {"no frame moves"}),
        refuse("gyro.rateHz 5", [](HandHeldClip& c) { c.gyro.rateHz = 5; }, {"gyro.rateHz", "[10, 10000]"}),
        refuse("gyro.noise -1", [](HandHeldClip& c) { c.gyro.noise = -1; }, {"gyro.noise", "rad/s"}),
        refuse("gyro.bias in deg/s", [](HandHeldClip& c) { c.gyro.bias[2] = 1.0; }, {"gyro.bias[2]", "rad/s"}),
        refuse("gyro.rateScale 0", [](HandHeldClip& c) { c.gyro.rateScale = 0; }, {"gyro.rateScale", "[0.5, 2]"}),
        refuse("gyro.timeOffset in ms", [](HandHeldClip& c) { c.gyro.timeOffset = 1500; },
               {"gyro.timeOffset", "milliseconds"}),
        refuse("gyro.leadSeconds -1", [](HandHeldClip& c) { c.gyro.leadSeconds = -1; }, {"gyro.leadSeconds"}),
        refuse("fullWellElectrons -1", [](HandHeldClip& c) { c.fullWellElectrons = -1; }, {"fullWellElectrons"}),
        refuse("maxStepPx 0", [](HandHeldClip& c) { c.maxStepPx = 0; }, {"maxStepPx", "(0, 1]"}),
        refuse("a shake that looks past a frame", [](HandHeldClip& c) {
                   c.rotation.maxBlurPx = 0;
                   c.rotation.peakRate = 20;
               }, {"strays", "rotation.peakRate"}),
        refuse("a missing image", [](HandHeldClip& c) { c.image = "/nonexistent/scene.png"; },
               {"image", "/nonexistent/scene.png"}),
    });

    const HandHeldSimulator sim(smallClip());
    const std::string dir = scratchDir("refused");
    auto writing = [&](const std::string& input, ClipFiles files, std::vector<std::string> words) {
        return Row{"writeClip", input, [&sim, dir, files] { writeClip(sim, dir, files); }, words};
    };
    ClipFiles mkv, mirrored, quality, jpegs, truthVideo;
    mkv.video = "clip.mkv";
    truthVideo.truth = "truth.avi";
    mirrored.gyro.axes = "XYz";
    quality.videoQuality = 0;
    jpegs.video = "frame_%04d.jpg";
    refuseAll({
        writing("video .mkv", mkv, {"ClipFiles.video", ".avi", ".mp4"}),
        writing("mirrored gyro axes XYz", mirrored, {"XYz"}),
        writing("videoQuality 0", quality, {"videoQuality", "[1, 100]"}),
        writing("an image sequence of JPEGs", jpegs, {"ClipFiles.video", "lossless"}),
        writing("truth frames as a video", truthVideo, {"ClipFiles.truth", "image sequence"}),
        {"gyroFormatFromName", "'gyroflow'", [] { gyroFormatFromName("gyroflow"); }, {"gcsv", "sensor-logger"}},
        {"writeGyroLog", "timeUnit 0", [&sim, dir] {
             GyroFileOptions o;
             o.timeUnit = 0;
             writeGyroLog(sim.gyroLog(), dir + "/gyro.gcsv", o);
         }, {"timeUnit", "(0, 1e6)"}},
        {"writeGyroLog", "logEpoch in ms", [&sim, dir] {
             GyroFileOptions o;
             o.format = GyroFormat::SensorLogger;
             o.logEpoch = 1.7e12;
             writeGyroLog(sim.gyroLog(), dir + "/gyro.gcsv", o);
         }, {"logEpoch", "Unix seconds"}},
    });
    for (const char* name : {"clip.mkv", "clip.avi", "gyro.gcsv", "truth.yml", "camera.xml", "frames.csv"})
        EXPECT_FALSE(utils::fs::exists(dir + "/" + name)) << name << " written although refused";
    utils::fs::remove_all(dir);
}
