// SPDX-License-Identifier: Apache-2.0
#include "visual_servo.hpp"

#include "frame_timing.hpp"
#include "plot.hpp"
#include "scene.hpp"

#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpImage.h>
#include <visp3/core/vpPixelMeterConversion.h>
#include <visp3/visual_features/vpFeaturePoint.h>
#include <visp3/vs/vpServo.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <fstream>

using namespace cv;
using namespace cv::dynblur;

namespace dynblur_samples {

namespace {

const double kDeg = CV_PI / 180.0;
const double kDepth = 1.0;  // metres to the plane; only scales the (unused) translation columns

double hostNow()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// ---- the simulated world ------------------------------------------------------------------------

// The plane as the camera sees it at θ = 0 (linear intensity, grey), wider than the frame by the
// same margin on each side so rows exposed away from θ = 0 see real content. The tag is placed
// where the centre pixel looks when θ = target; moving it to another place keeps the background.
struct World
{
    Mat background;         // CV_8U sRGB grey, the plane without the tag, with margins
    Point margin;           // where the frame's (0, 0) lies in `background` at θ = 0
    Mat sharpLinear;        // CV_32F, the view at θ = 0 with the tag
    std::vector<Point2d> tagsAtZero;  // each tag's centre in the frame's coordinates at θ = 0, pixels
    std::vector<double> tagOffsets;   // each tag's centre below the target's, pixels (in the view that centres the target)
};

World makeWorld(const Ptr<CameraModel>& camera, int maxShiftPx)
{
    const Size frame = camera->getImageSize();
    World world;
    world.margin = Point(40, maxShiftPx + 40);
    Mat color = makeScene(Size(frame.width + 2 * world.margin.x, frame.height + 2 * world.margin.y), 20261122u);
    cvtColor(color, world.background, COLOR_BGR2GRAY);
    return world;
}

void placeTarget(World& world, const Ptr<CameraModel>& camera, double targetRad, int tagCellPx, int tags)
{
    Mat grey = world.background.clone();
    world.tagsAtZero.clear();
    world.tagOffsets.clear();
    for (int k = 0; k < tags; ++k)
    {
        const double offset = (k - (tags - 1) / 2.0) * 9 * tagCellPx;
        const Point2d centre = camera->viewToReference(Point2d(camera->getCx(), camera->getCy() + offset), targetRad);
        const Mat tag = aprilTag36h11(k, tagCellPx);
        const Point topLeft(cvRound(centre.x + world.margin.x - (tag.cols - 1) / 2.0),
                            cvRound(centre.y + world.margin.y - (tag.rows - 1) / 2.0));
        tag.copyTo(grey(Rect(topLeft, tag.size())));
        world.tagsAtZero.emplace_back(topLeft.x - world.margin.x + (tag.cols - 1) / 2.0,
                                      topLeft.y - world.margin.y + (tag.rows - 1) / 2.0);
        world.tagOffsets.push_back(offset);
    }
    srgbToLinear(grey, world.sharpLinear);
}

// Where tag k's centre appears at tilt θ (the inverse of viewToReference for a pure rotation).
Point2d tagInView(const Ptr<CameraModel>& camera, const World& world, size_t k, double thetaRad)
{
    return camera->viewToReference(world.tagsAtZero[k], -thetaRad);
}

// Where the target's centre (its tags' mean centre, as the detector measures it) appears at tilt θ.
Point2d targetInView(const Ptr<CameraModel>& camera, const World& world, double thetaRad)
{
    Point2d sum;
    for (size_t k = 0; k < world.tagsAtZero.size(); ++k)
        sum += tagInView(camera, world, k, thetaRad);
    return sum / static_cast<double>(world.tagsAtZero.size());
}

// How far a tag's centre travels (along the true trajectory) while the sensor row that sees it is
// exposed, pixels, for the tag that travels farthest: the blur the detector has to cope with on the
// target, whatever the frame's window.
double tagMotionPx(const Ptr<Plant>& plant, const SwitchSchedule& history, const Ptr<CameraModel>& camera,
                   const World& world, const RollingShutter& shutter)
{
    const int samples = 24;
    Mat t(samples + 1, 1, CV_64F), theta;
    double farthest = 0;
    for (size_t k = 0; k < world.tagsAtZero.size(); ++k)
    {
        double row = camera->getCy() + world.tagOffsets[k];
        for (int pass = 0; pass < 4; ++pass)  // the row where the tag is seen depends on when that row is exposed
        {
            const Vec2d interval = shutter.rowInterval(cvRound(std::min(std::max(row, 0.0), shutter.rows - 1.0)));
            t.at<double>(0) = 0.5 * (interval[0] + interval[1]);
            plant->response(history, t.rowRange(0, 1), theta);
            row = tagInView(camera, world, k, theta.at<double>(0)).y;
        }
        const Vec2d interval = shutter.rowInterval(cvRound(std::min(std::max(row, 0.0), shutter.rows - 1.0)));
        for (int i = 0; i <= samples; ++i)
            t.at<double>(i) = interval[0] + (interval[1] - interval[0]) * i / samples;
        plant->response(history, t, theta);
        double travel = 0;
        for (int i = 1; i <= samples; ++i)
            travel += norm(tagInView(camera, world, k, theta.at<double>(i)) -
                           tagInView(camera, world, k, theta.at<double>(i - 1)));
        farthest = std::max(farthest, travel);
    }
    return farthest;
}

// ---- the positioner: the plant directly, or the actuator controller over the bus ------------------

class Positioner
{
public:
    Positioner(const ServoConfig& config, const Ptr<Plant>& plant)
    {
        if (config.busUri.empty())
            return;
        ActuatorLimits limits;
        limits.maxLevel = config.maxLevel;
        limits.minDwell = 1e-3;
        driver_ = ActuatorDriver::create(ActuatorBus::create(config.busUri, config.busTimeout, 2), limits);
        const ActuatorInfo info = driver_->connect();
        if (info.maxLevel < config.maxLevel)
            CV_Error(Error::StsBadArg, format("the controller at %s accepts levels up to %d, the servo needs %d",
                                              config.busUri.c_str(), info.maxLevel, config.maxLevel));
        (void)plant;
    }
    ~Positioner()
    {
        // The camera holds its last level after a run; on an error it goes to the safe level.
        if (driver_ && std::uncaught_exceptions() > 0)
        {
            try { driver_->stop(); } catch (...) {}
        }
    }

    /** Runs a saccade planned to start at `plannedStart` (simulation clock). Returns the schedule
    as the mechanism executes it, on the simulation clock; latencyMs receives the start delay. */
    SwitchSchedule run(const SwitchSchedule& planned, double plannedStart, double& latencyMs)
    {
        latencyMs = 0;
        if (!driver_ || planned.times.empty())
            return planned;
        driver_->waitUntilDone(2.0);  // the previous saccade (real time) must be over
        driver_->upload(planned);
        const double asked = hostNow();
        const StartReport report = driver_->start();
        // The controller switched entry 0 at report.hostStartTime; the simulation clock runs at
        // plannedStart when the start was asked for, so the real start delay carries over.
        const double simStart = plannedStart + std::max(0.0, report.hostStartTime - asked);
        latencyMs = 1e3 * (simStart - plannedStart);
        SwitchSchedule started = planned;
        for (size_t i = 0; i < started.times.size(); ++i)  // the device holds µs offsets from entry 0
            started.times[i] = simStart + std::round((planned.times[i] - planned.times[0]) * 1e6) * 1e-6;
        return started;
    }

private:
    Ptr<ActuatorDriver> driver_;
};

void appendSchedule(SwitchSchedule& history, const SwitchSchedule& saccade)
{
    for (size_t i = 0; i < saccade.times.size(); ++i)
    {
        history.times.push_back(saccade.times[i]);
        history.levels.push_back(saccade.levels[i]);
    }
}

Mat toGrey8(const Mat& linear)
{
    Mat srgb;
    linearToSrgb(linear, srgb, CV_8U);
    return srgb;
}

}  // namespace

Mat aprilTag36h11(int id, int cellPx)
{
    // tag36h11 ids 0..2 (AprilTag family table, 36 data bits read row by row from the top-left, 1 = white).
    static const uint64_t codes[kTagIds] = {0xd5d628584ULL, 0xd97f18b49ULL, 0xdd280910eULL};
    CV_CheckGE(id, 0, "tag id");
    CV_CheckLT(id, kTagIds, "tag id");
    const uint64_t code = codes[id];
    Mat tag(10 * cellPx, 10 * cellPx, CV_8U, Scalar(255));
    for (int y = 1; y <= 8; ++y)
        for (int x = 1; x <= 8; ++x)
        {
            bool white = false;
            if (x >= 2 && x <= 7 && y >= 2 && y <= 7)
                white = ((code >> (35 - ((y - 2) * 6 + (x - 2)))) & 1u) != 0;
            tag(Rect(x * cellPx, y * cellPx, cellPx, cellPx)).setTo(white ? 255 : 0);
        }
    return tag;
}

ServoConfig trackingScenario(int places, int cyclesPerTarget, unsigned seed, double startOffsetDeg, double minJumpDeg,
                             double maxJumpDeg, double limitDeg)
{
    CV_CheckGT(places, 0, "places");
    CV_CheckGT(cyclesPerTarget, 0, "cycles per place");
    CV_Assert(0 <= minJumpDeg && minJumpDeg <= maxJumpDeg && maxJumpDeg <= limitDeg && std::abs(startOffsetDeg) <= limitDeg);
    ServoConfig config;
    RNG rng(0x7a9u + seed);
    config.targetsDeg.push_back(startOffsetDeg);
    for (int i = 1; i < places; ++i)
    {
        const double here = config.targetsDeg.back(), jump = rng.uniform(minJumpDeg, maxJumpDeg);
        double next = rng.uniform(0, 2) ? here + jump : here - jump;
        if (std::abs(next) > limitDeg)  // the other way is always within ±limit since jump ≤ limit
            next = 2 * here - next;
        config.targetsDeg.push_back(next);
    }
    config.cyclesPerTarget = cyclesPerTarget;
    config.cycles = places * cyclesPerTarget;
    config.latencyJitter = 1.0 / config.fps;
    config.noiseSeed = 7u + seed;
    return config;
}

void checkServoConfig(const ServoConfig& config)
{
    CV_CheckGT(config.cycles, 0, "cycles");
    CV_CheckGT(config.framesPerCycle, 0, "frames per cycle");
    CV_CheckGT(config.lambda, 0.0, "lambda");
    CV_CheckGT(config.gainDegPerLevel, 0.0, "gain");
    CV_CheckGE(config.maxLevel, 1, "max level");
    CV_CheckGE(config.cyclesPerTarget, 0, "cycles per target");
    CV_Assert(config.latency >= 0 && config.latencyJitter >= 0);
    CV_CheckGE(config.targetTags, 1, "target tags");
    CV_CheckLE(config.targetTags, kTagIds, "target tags");
    CV_CheckGE(config.deadbandPx, 0.0, "dead band");
    // The target must fit in half the frame's height so that it stays in view while the servo works.
    CV_CheckLE((9 * (config.targetTags - 1) + 10) * config.tagCellPx, config.imageSize.height / 2,
               "target height (tags x tag cell)");
}

ServoReport runVisualServo(const ServoConfig& config, const std::function<void(const ServoReport&)>& progress)
{
    checkServoConfig(config);
    const std::vector<double> targetsDeg = config.targetsDeg.empty() ? std::vector<double>{config.startOffsetDeg}
                                                                      : config.targetsDeg;
    double farthestDeg = 0;
    for (double deg : targetsDeg)
        farthestDeg = std::max(farthestDeg, std::abs(deg));
    CV_Assert(farthestDeg < config.maxLevel * config.gainDegPerLevel);

    // The system: positioner, planner, camera, deblurrer.
    const Ptr<Plant> plant = Plant::create(config.naturalFreqHz, config.dampingRatio, config.gainDegPerLevel * kDeg);
    const Ptr<SwitchPlanner> planner = SwitchPlanner::create(plant, config.maxLevel, config.plannerMode);
    const Size size = config.imageSize;
    const Ptr<CameraModel> camera = CameraModel::create(config.focalPx, config.focalPx, (size.width - 1) / 2.0,
                                                        (size.height - 1) / 2.0, size.width, size.height);
    const Point2d imageCentre(camera->getCx(), camera->getCy());
    // The positioner as it really moves (the loop knows only `plant`).
    MotionCorrection drift;
    drift.naturalFreqScale = config.trueFreqScale;
    drift.dampingScale = config.trueDampingScale;
    const Ptr<Plant> truePlant = drift.correctPlant(plant);
    const Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(plant, camera);
    deblurrer->setPsfModel(config.psfModel);
    RLParams rl = deblurrer->getRLParams();
    rl.iterations = config.rlIterations;
    deblurrer->setRLParams(rl);
    Positioner positioner(config, plant);

    // The scene: the tag sits targetsDeg[0] (tilt) away from the image centre, later at the next places.
    ServoReport report;
    report.targetsDeg = targetsDeg;
    const int maxShiftPx = cvCeil(config.focalPx * std::tan(farthestDeg * kDeg * 1.3 + 2 * kDeg));
    World world = makeWorld(camera, maxShiftPx);
    int target = 0;
    placeTarget(world, camera, targetsDeg[0] * kDeg, config.tagCellPx, config.targetTags);

    // Visual servoing task (ViSP): the tag centre s to the image centre s*, eye-in-hand, only ωx.
    const vpCameraParameters cam(config.focalPx, config.focalPx, camera->getCx(), camera->getCy());
    vpFeaturePoint s, sStar;
    sStar.buildFrom(0.0, 0.0, kDepth);
    vpServo task;
    task.setServo(vpServo::EYEINHAND_CAMERA);
    task.setInteractionMatrixType(vpServo::CURRENT);
    task.setLambda(config.lambda);
    vpColVector dof(6, 0.0);
    dof[3] = 1.0;  // the positioner turns the camera about its +x axis (DESIGN §2)
    task.setCameraDoF(dof);
    task.addFeature(s, sStar);
    TargetDetector detector;  // one for the raw and the restored frames alike

    const double period = 1.0 / config.fps;
    // "Moving" for this camera: more than 0.25 px off the final view, or faster than 0.2 px per
    // exposure (classifyExposure's defaults are these figures at fx = 1230 px).
    const double angleTol = 0.25 / config.focalPx, velocityTol = 0.2 / config.focalPx / config.exposure;
    SwitchSchedule history(std::vector<double>(), std::vector<int>(), 0);  // every switch so far: the true motion
    SwitchSchedule saccade = history;                                      // the command of this cycle
    int level = 0, frameIndex = 0;
    Mat lastStill;                          // the last frame taken at rest: the reference of the next move's frames
    /* Which frame lastStill is and which the deblurrer holds as its reference: by index, not by
       buffer address, which a later frame's allocation may reuse. */
    int lastStillIndex = -1, referenceIndex = -1;
    RNG jitter(config.noiseSeed * 2654435761ull + 1u);

    auto takeFrame = [&](int cycle) {
        ServoFrame frame;
        frame.cycle = cycle;
        frame.target = target;
        frame.index = frameIndex;
        frame.frameStart = frameIndex * period;
        const RollingShutter shutter(frame.frameStart, config.exposure, config.lineDelay, size.height);
        const RollingShutter trueShutter(frame.frameStart + config.clockOffset, config.exposure, config.lineDelay,
                                         size.height);
        // The camera: the physical forward model along the true trajectory, plus sensor noise.
        Mat blurred, noisy;
        renderBlurred(world.sharpLinear, truePlant, history, camera, trueShutter, blurred, 0.0);
        addSensorNoise(blurred, noisy, 4000.0, 8.0, 5.0, config.noiseSeed * 100003ull + static_cast<uint64>(frameIndex));
        const Vec2d readout = trueShutter.readoutInterval();
        Mat mid(1, 1, CV_64F, Scalar(0.5 * (readout[0] + readout[1]))), theta;
        truePlant->response(history, mid, theta);
        frame.thetaDeg = theta.at<double>(0) / kDeg;
        frame.tagMotionPx = tagMotionPx(truePlant, history, camera, world, trueShutter);
        // Classify and restore with the cycle's command (the library's prediction).
        frame.window = classifyExposure(plant, saccade, shutter, angleTol, velocityTol);
        Mat restored;
        if (saccade.times.empty() || frame.window == EXPOSURE_IV)
        {
            restored = noisy;  // nothing to undo
            lastStill = noisy;
            lastStillIndex = frameIndex;
        }
        else
        {
            const double t0 = static_cast<double>(getTickCount());
            // The still frame before this cycle's move, at the saccade's initial resting angle.
            if (config.refine && !lastStill.empty() && lastStillIndex != referenceIndex)
            {
                deblurrer->setReferenceFrame(lastStill);
                referenceIndex = lastStillIndex;
            }
            deblurrer->deblur(noisy, saccade, shutter, restored);
            frame.correction = deblurrer->getLastCorrection();
            frame.restoreSec = (static_cast<double>(getTickCount()) - t0) / getTickFrequency();
        }
        const Mat raw8 = toGrey8(noisy), restored8 = toGrey8(restored);
        frame.raw = detector.detect(raw8, world.tagOffsets);
        frame.restored = detector.detect(restored8, world.tagOffsets);
        if (config.keepImages)
        {
            frame.rawImage = raw8;
            frame.restoredImage = restored8;
        }
        ++frameIndex;
        return frame;
    };

    // Frame 0: the camera at rest.
    report.frames.push_back(takeFrame(-1));
    Detection latest = report.frames.back().restored;
    int cycleOfTarget = 0;

    for (int c = 0; c < config.cycles; ++c)
    {
        // The tag moves to its next place between two frames; the camera sees it there first in
        // the frame this cycle measures.
        if (config.cyclesPerTarget > 0 && c > 0 && c % config.cyclesPerTarget == 0 &&
            target + 1 < static_cast<int>(targetsDeg.size()))
        {
            ++target;
            cycleOfTarget = 0;
            placeTarget(world, camera, targetsDeg[static_cast<size_t>(target)] * kDeg, config.tagCellPx, config.targetTags);
            report.frames.push_back(takeFrame(c - 1));
            latest = report.frames.back().restored;
        }
        ServoCycle cycle;
        cycle.cycle = c;
        cycle.target = target;
        cycle.cycleOfTarget = cycleOfTarget++;
        cycle.fromLevel = level;
        cycle.trueErrorPx = norm(targetInView(camera, world, plant->restingAngle(level)) - imageCentre);

        // 1. Measure: the tag centre in the latest restored frame (the view at the resting angle).
        double deltaRad = 0;
        if (latest.tagsFound > 0)
            cycle.measuredErrorPx = norm(latest.centre - imageCentre);
        if (latest.tagsFound > 0 && cycle.measuredErrorPx > config.deadbandPx)
        {
            double x = 0, y = 0;
            vpPixelMeterConversion::convertPoint(cam, latest.centre.x, latest.centre.y, x, y);
            s.buildFrom(x, y, kDepth);
            // 2. Control law: camera velocity for one cycle; the tilt keeps ωx.
            const vpColVector v = task.computeControlLaw();
            deltaRad = v[3];
        }
        cycle.deltaDeg = deltaRad / kDeg;

        // 3. Plan: integer levels, vibration cancelled, starting once the measured frame is read
        // out and processed (the processing time may jitter).
        const int goal = std::max(-config.maxLevel, std::min(config.maxLevel,
                                  level + static_cast<int>(std::lround(deltaRad / plant->getGain()))));
        const RollingShutter last(report.frames.back().frameStart, config.exposure, config.lineDelay, size.height);
        const double latency = config.latency + (config.latencyJitter > 0 ? jitter.uniform(0.0, config.latencyJitter) : 0.0);
        cycle.latencyMs = 1e3 * latency;
        const double plannedStart = last.readoutInterval()[1] + latency;
        saccade = planner->plan(plant->restingAngle(level), plant->restingAngle(goal), plannedStart);
        cycle.switches = saccade.times.size();
        cycle.settleMs = saccade.times.empty() ? 0.0 : 1e3 * saccade.settleTime;

        // 4. Apply: on the plant, or uploaded to the controller and started.
        saccade = positioner.run(saccade, plannedStart, cycle.startLatencyMs);
        appendSchedule(history, saccade);
        level = goal;
        cycle.toLevel = level;

        // 5. The camera keeps taking frames while the mechanism moves: classify, restore, detect.
        Detection seen;
        for (int f = 0; f < config.framesPerCycle; ++f)
        {
            report.frames.push_back(takeFrame(c));
            // A restored frame shows the view at the new resting angle, unless the whole frame was
            // read out before the saccade began (the latency can exceed a frame period). The latest
            // frame that shows every tag wins; failing that, the one that shows the most.
            const ServoFrame& frame = report.frames.back();
            const RollingShutter shutter(frame.frameStart, config.exposure, config.lineDelay, size.height);
            const bool beforeMove = !saccade.times.empty() && shutter.readoutInterval()[1] <= saccade.times.front();
            if (!beforeMove && (frame.restored.found || (!seen.found && frame.restored.tagsFound >= seen.tagsFound)))
                seen = frame.restored;
        }
        latest = seen;
        report.cycles.push_back(cycle);
        if (progress)
            progress(report);
    }
    return report;
}

int ServoReport::cyclesToWithin(double px, int target) const
{
    int first = -1;
    for (const ServoCycle& c : cycles)
    {
        if (c.target != target)
            continue;
        if (c.trueErrorPx <= px && c.measuredErrorPx >= 0 && c.measuredErrorPx <= px)
        {
            if (first < 0)
                first = c.cycleOfTarget;
        }
        else
        {
            first = -1;
        }
    }
    return first;
}

DetectionTally ServoReport::tally(int window, double minTagMotionPx) const
{
    DetectionTally t;
    for (const ServoFrame& f : frames)
    {
        const bool match = window == 0 ? (f.window >= EXPOSURE_I && f.window <= EXPOSURE_III) : f.window == window;
        if (!match || f.tagMotionPx < minTagMotionPx)
            continue;
        ++t.frames;
        t.raw += f.raw.found ? 1 : 0;
        t.restored += f.restored.found ? 1 : 0;
    }
    return t;
}

double ServoReport::meanRestoreSec() const
{
    double sum = 0;
    int n = 0;
    for (const ServoFrame& f : frames)
        if (f.restoreSec > 0)
        {
            sum += f.restoreSec;
            ++n;
        }
    return n ? sum / n : 0.0;
}

std::vector<DetectionRow> detectionSummary(const ServoReport& report)
{
    std::vector<DetectionRow> rows;
    for (int window : {int(EXPOSURE_I), int(EXPOSURE_II), int(EXPOSURE_III), 0})
        rows.push_back({window ? exposureWindowName(window) : "I-III", report.tally(window),
                        report.tally(window, kTagBlurredPx)});
    return rows;
}

namespace {

Mat annotated(const Mat& grey8, const Detection& detection, const std::string& label)
{
    Mat image;
    cvtColor(grey8, image, COLOR_GRAY2BGR);
    const Point2d centre((image.cols - 1) / 2.0, (image.rows - 1) / 2.0);
    drawMarker(image, Point(cvRound(centre.x), cvRound(centre.y)), Scalar(255, 200, 0), MARKER_CROSS, 14, 1);
    if (detection.tagsFound > 0)
    {
        for (const std::vector<Point2d>& tag : detection.corners)
        {
            std::vector<Point> polygon;
            for (const Point2d& p : tag)
                polygon.emplace_back(cvRound(p.x), cvRound(p.y));
            polylines(image, polygon, true, Scalar(0, 220, 0), 2, LINE_AA);
        }
        circle(image, Point(cvRound(detection.centre.x), cvRound(detection.centre.y)), 3, Scalar(0, 0, 255), FILLED);
    }
    rectangle(image, Rect(0, 0, image.cols, 18), Scalar(0, 0, 0), FILLED);
    const std::string found = detection.found       ? "  target found"
                              : detection.tagsFound ? format("  %d tag(s) only", detection.tagsFound)
                                                    : "  no tag";
    putText(image, label + found, Point(4, 13), FONT_HERSHEY_SIMPLEX, 0.4,
            detection.found ? Scalar(120, 255, 120) : Scalar(120, 120, 255), 1, LINE_AA);
    return image;
}

// Bar chart of detection rates: per window, raw and restored over all its frames, then over those
// whose tag was blurred, with "found/frames" above each bar.
Mat detectionChart(const std::vector<DetectionRow>& rows, const std::string& title)
{
    const int barWidth = 46, groupWidth = 4 * barWidth + 60, left = 60, top = 70, plotHeight = 260, bottom = 50;
    const int width = left + groupWidth * static_cast<int>(rows.size()) + 10;
    Mat chart(top + plotHeight + bottom, width, CV_8UC3, Scalar(255, 255, 255));
    const Scalar ink(40, 40, 40), grid(220, 220, 220);
    const Scalar colors[4] = {Scalar(150, 150, 235), Scalar(130, 210, 120), Scalar(50, 50, 190), Scalar(40, 130, 30)};
    const char* names[4] = {"raw, all frames", "restored, all frames",
                            "raw, tag moved >= 2 px", "restored, tag moved >= 2 px"};
    putText(chart, title, Point(left, 22), FONT_HERSHEY_SIMPLEX, 0.55, ink, 1, LINE_AA);
    for (int b = 0; b < 4; ++b)
    {
        const Point at(left + b * 230, 42);
        rectangle(chart, Rect(at.x, at.y - 10, 12, 12), colors[b], FILLED);
        putText(chart, names[b], at + Point(18, 0), FONT_HERSHEY_SIMPLEX, 0.42, ink, 1, LINE_AA);
    }
    for (int percent = 0; percent <= 100; percent += 25)
    {
        const int y = top + plotHeight - plotHeight * percent / 100;
        line(chart, Point(left, y), Point(width - 10, y), grid, 1);
        putText(chart, format("%d%%", percent), Point(8, y + 4), FONT_HERSHEY_SIMPLEX, 0.4, ink, 1, LINE_AA);
    }
    for (size_t g = 0; g < rows.size(); ++g)
    {
        const DetectionTally* tallies[4] = {&rows[g].all, &rows[g].all, &rows[g].tagBlurred, &rows[g].tagBlurred};
        const int x0 = left + groupWidth * static_cast<int>(g) + 30;
        for (int b = 0; b < 4; ++b)
        {
            const DetectionTally& t = *tallies[b];
            const int found = b % 2 ? t.restored : t.raw;
            const int height = t.frames ? cvRound(plotHeight * double(found) / t.frames) : 0;
            const int x = x0 + b * barWidth + (b >= 2 ? 10 : 0);
            rectangle(chart, Rect(x, top + plotHeight - height, barWidth - 4, std::max(height, 1)), colors[b], FILLED);
            putText(chart, format("%d/%d", found, t.frames), Point(x, top + plotHeight - height - 5),
                    FONT_HERSHEY_SIMPLEX, 0.38, ink, 1, LINE_AA);
        }
        putText(chart, "window " + rows[g].window, Point(x0 + 2 * barWidth - 30, top + plotHeight + 24),
                FONT_HERSHEY_SIMPLEX, 0.5, ink, 1, LINE_AA);
    }
    line(chart, Point(left, top + plotHeight), Point(width - 10, top + plotHeight), ink, 1);
    return chart;
}

// Frames for the strip: per window (I, II, III), those whose tag was blurred (else all), sorted by
// how far the tag moved while its row was exposed, then up to `perWindow` of them spread over that
// order (the most and the least blurred tag and some between).
std::vector<const ServoFrame*> stripFrames(const ServoReport& report, size_t perWindow)
{
    std::vector<const ServoFrame*> chosen;
    for (int window : {int(EXPOSURE_I), int(EXPOSURE_II), int(EXPOSURE_III)})
    {
        std::vector<const ServoFrame*> frames;
        for (bool blurredOnly : {true, false})
        {
            for (const ServoFrame& f : report.frames)
                if (f.window == window && !f.rawImage.empty() && (!blurredOnly || f.tagMotionPx >= kTagBlurredPx))
                    frames.push_back(&f);
            if (!frames.empty())
                break;
        }
        std::sort(frames.begin(), frames.end(),
                  [](const ServoFrame* a, const ServoFrame* b) { return a->tagMotionPx > b->tagMotionPx; });
        const size_t n = std::min(perWindow, frames.size());
        for (size_t i = 0; i < n; ++i)
            chosen.push_back(frames[n > 1 ? i * (frames.size() - 1) / (n - 1) : 0]);
    }
    return chosen;
}

}  // namespace

void writeServoOutputs(const ServoReport& report, const std::string& outDir)
{
    utils::fs::createDirectories(outDir);
    {
        std::ofstream csv(outDir + "/cycles.csv");
        csv << "cycle,target,cycle_of_target,target_deg,measured_error_px,true_error_px,from_level,to_level,delta_deg,"
               "latency_ms,switches,settle_ms,start_latency_ms\n";
        for (const ServoCycle& c : report.cycles)
            csv << format("%d,%d,%d,%.3f,%.3f,%.3f,%d,%d,%.4f,%.2f,%zu,%.2f,%.3f\n", c.cycle, c.target, c.cycleOfTarget,
                          report.targetsDeg[static_cast<size_t>(c.target)], c.measuredErrorPx, c.trueErrorPx,
                          c.fromLevel, c.toLevel, c.deltaDeg, c.latencyMs, c.switches, c.settleMs, c.startLatencyMs);
        if (!csv)
            CV_Error(Error::StsError, "cannot write " + outDir + "/cycles.csv");
    }
    writeServoFigures(report, outDir);
}

void writeServoFigures(const ServoReport& report, const std::string& outDir)
{
    utils::fs::createDirectories(outDir);
    {
        std::ofstream csv(outDir + "/frames.csv");
        csv << "cycle,target,frame,frame_start_s,window,theta_deg,tag_motion_px,raw_found,raw_u,raw_v,restored_found,"
               "restored_u,restored_v,restore_ms\n";
        for (const ServoFrame& f : report.frames)
            csv << format("%d,%d,%d,%.6f,%s,%.4f,%.2f,%d,%.2f,%.2f,%d,%.2f,%.2f,%.1f\n", f.cycle, f.target, f.index,
                          f.frameStart, exposureWindowName(f.window), f.thetaDeg, f.tagMotionPx, f.raw.found ? 1 : 0,
                          f.raw.centre.x, f.raw.centre.y, f.restored.found ? 1 : 0, f.restored.centre.x,
                          f.restored.centre.y, 1e3 * f.restoreSec);
        if (!csv)
            CV_Error(Error::StsError, "cannot write " + outDir + "/frames.csv");
    }

    // Error per cycle; with jumps of tens of pixels a second panel shows the last pixels.
    std::vector<double> x, measured, truth;
    double largest = 0;
    for (const ServoCycle& c : report.cycles)
    {
        x.push_back(c.cycle);
        measured.push_back(c.measuredErrorPx >= 0 ? c.measuredErrorPx : std::numeric_limits<double>::quiet_NaN());
        truth.push_back(c.trueErrorPx);
        largest = std::max(largest, c.trueErrorPx);
    }
    const std::string title = report.targetsDeg.size() == 1
                                  ? format("Visual servoing: tag %.1f deg off at the start", report.targetsDeg[0])
                                  : format("Visual servoing: the tag jumps to %zu places", report.targetsDeg.size());
    dynblur_plot::Figure figure(900, title, 300);
    figure.addPanel("image error of the tag centre", "error (px)")
        .hLine(1.0, "1 px")
        .line(x, truth, "true (scene geometry)")
        .line(x, measured, "measured (restored frame)");
    if (largest > 6.0)
        figure.addPanel("the same, 0..3 px", "error (px)")
            .yLimits(0.0, 3.0)
            .hLine(1.0, "1 px")
            .line(x, truth, "true")
            .line(x, measured, "measured");
    figure.xLabel("cycle");
    if (!figure.save(outDir + "/error.png"))
        CV_Error(Error::StsError, "cannot write " + outDir + "/error.png");

    // Detection rates per window, raw vs restored.
    if (!imwrite(outDir + "/detection.png",
                 detectionChart(detectionSummary(report), "Target found (every tag; vpDetectorAprilTag 36h11) in the frames taken while moving")))
        CV_Error(Error::StsError, "cannot write " + outDir + "/detection.png");

    // Strip: raw | restored for frames taken while moving (windows I–III), two pairs per row.
    std::vector<Mat> pairs;
    for (const ServoFrame* f : stripFrames(report, 4))
    {
        const std::string label = format("f%d win %s tag moved %.0fpx", f->index, exposureWindowName(f->window), f->tagMotionPx);
        Mat pair;
        hconcat(annotated(f->rawImage, f->raw, label + " raw"), annotated(f->restoredImage, f->restored, "restored"), pair);
        copyMakeBorder(pair, pair, 0, 4, 0, 4, BORDER_CONSTANT, Scalar(255, 255, 255));
        pairs.push_back(pair);
    }
    if (!pairs.empty())
    {
        std::vector<Mat> rows;
        for (size_t i = 0; i < pairs.size(); i += 2)
        {
            Mat row;
            if (i + 1 < pairs.size())
                hconcat(pairs[i], pairs[i + 1], row);
            else
                hconcat(pairs[i], Mat(pairs[i].size(), pairs[i].type(), Scalar(255, 255, 255)), row);
            rows.push_back(row);
        }
        Mat strip;
        vconcat(rows, strip);
        if (!imwrite(outDir + "/strip.png", strip))
            CV_Error(Error::StsError, "cannot write " + outDir + "/strip.png");
    }
}

}  // namespace dynblur_samples
