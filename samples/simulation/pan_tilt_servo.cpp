// SPDX-License-Identifier: Apache-2.0
#include "pan_tilt_servo.hpp"

#include "scene.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/imgproc.hpp>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpPixelMeterConversion.h>
#include <visp3/visual_features/vpFeaturePoint.h>
#include <visp3/vs/vpServo.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <fstream>
#include <limits>

using namespace cv;
using namespace cv::dynblur;

namespace dynblur_samples {

namespace {

const double kDeg = CV_PI / 180.0;
const double kDepth = 1.0;        // metres to the plane; only scales the (unused) translation columns
const double kHistoryStart = -1;  // every axis rests at level 0 from here on; the world is the view there

double hostNow()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// ---- the simulated world: the plane seen at rest (every joint at 0), the target placed by rotation ----

struct World
{
    Mat background;                    // CV_8U sRGB grey, the plane without the target, with margins
    Point margin;                      // where the frame's (0, 0) lies in `background`
    Mat sharpLinear;                   // CV_32F, the view at rest with the target
    std::vector<Point2d> tagsAtRest;   // each tag's centre in the view at rest, pixels
    std::vector<double> tagOffsets;    // each tag's centre below the target's, pixels
};

World makeWorld(const Size& frame, int maxShiftPx)
{
    World world;
    world.margin = Point(maxShiftPx + 40, maxShiftPx + 40);
    const Mat color = makeScene(Size(frame.width + 2 * world.margin.x, frame.height + 2 * world.margin.y), 20261122u);
    cvtColor(color, world.background, COLOR_BGR2GRAY);
    return world;
}

// Pastes the target where the view at orientation `centring` has its centre.
void placeTarget(World& world, const Ptr<CameraModel>& camera, const Matx33d& centring, int tagCellPx, int tags)
{
    Mat grey = world.background.clone();
    world.tagsAtRest.clear();
    world.tagOffsets.clear();
    for (int k = 0; k < tags; ++k)
    {
        const double offset = (k - (tags - 1) / 2.0) * 9 * tagCellPx;
        const Point2d centre = camera->viewToReference(Point2d(camera->getCx(), camera->getCy() + offset), centring);
        const Mat tag = aprilTag36h11(k, tagCellPx);
        const Point topLeft(cvRound(centre.x + world.margin.x - (tag.cols - 1) / 2.0),
                            cvRound(centre.y + world.margin.y - (tag.rows - 1) / 2.0));
        tag.copyTo(grey(Rect(topLeft, tag.size())));
        world.tagsAtRest.emplace_back(topLeft.x - world.margin.x + (tag.cols - 1) / 2.0,
                                      topLeft.y - world.margin.y + (tag.rows - 1) / 2.0);
        world.tagOffsets.push_back(offset);
    }
    srgbToLinear(grey, world.sharpLinear);
}

// Where tag k appears in the view at orientation Q (a point of the view at rest seen from Q).
Point2d tagInView(const Ptr<CameraModel>& camera, const World& world, size_t k, const Matx33d& orientation)
{
    return camera->viewToReference(world.tagsAtRest[k], orientation.t());
}

Point2d targetInView(const Ptr<CameraModel>& camera, const World& world, const Matx33d& orientation)
{
    Point2d sum;
    for (size_t k = 0; k < world.tagsAtRest.size(); ++k)
        sum += tagInView(camera, world, k, orientation);
    return sum / static_cast<double>(world.tagsAtRest.size());
}

// How far a tag travels while the sensor row that sees it is exposed, pixels (the farthest tag's).
double tagMotionPx(const Ptr<CameraMotion>& motion, const Ptr<CameraModel>& camera, const World& world,
                   const RollingShutter& shutter)
{
    const int samples = 24;
    auto rowAt = [&](double y) { return shutter.rowInterval(cvRound(std::min(std::max(y, 0.0), shutter.rows - 1.0))); };
    double farthest = 0;
    for (size_t k = 0; k < world.tagsAtRest.size(); ++k)
    {
        double row = camera->getCy() + world.tagOffsets[k];
        for (int pass = 0; pass < 4; ++pass)  // the row that sees the tag depends on when it is exposed
        {
            const Vec2d interval = rowAt(row);
            row = tagInView(camera, world, k, motion->orientation(0.5 * (interval[0] + interval[1]))).y;
        }
        const Vec2d interval = rowAt(row);
        double travel = 0;
        Point2d previous = tagInView(camera, world, k, motion->orientation(interval[0]));
        for (int i = 1; i <= samples; ++i)
        {
            const Point2d p = tagInView(camera, world, k,
                                        motion->orientation(interval[0] + (interval[1] - interval[0]) * i / samples));
            travel += norm(p - previous);
            previous = p;
        }
        farthest = std::max(farthest, travel);
    }
    return farthest;
}

// ---- the mount's chain ---------------------------------------------------------------------------

/* ω = J·q̇ restricted to ωx, ωy and axes 0 and 1: axis i turns the camera about (R_{i+1}⋯R_n)ᵀ·a_i,
   with R_1⋯R_i·R_{i+1}⋯R_n = Q(q) (DESIGN §2, Rotation). */
Matx22d pointingJacobian(const Ptr<Mount>& mount, const std::vector<double>& q)
{
    const Matx33d orientation = mount->orientation(q);
    Matx33d carried = Matx33d::eye();  // R_1⋯R_i
    Matx22d jacobian;
    for (int i = 0; i < 2; ++i)
    {
        Matx33d turn;
        Rodrigues(mount->getAxis(i) * q[size_t(i)], turn);
        carried = carried * turn;
        const Vec3d column = (carried.t() * orientation).t() * mount->getAxis(i);
        jacobian(0, i) = column[0];
        jacobian(1, i) = column[1];
    }
    return jacobian;
}

std::vector<double> restingAngles(const Ptr<Mount>& mount, const std::vector<int>& levels)
{
    std::vector<double> angles;
    for (size_t i = 0; i < levels.size(); ++i)
        angles.push_back(mount->getPlant(int(i))->restingAngle(levels[i]));
    return angles;
}

SwitchSchedule hold(int level, double at)
{
    return SwitchSchedule(std::vector<double>{at}, std::vector<int>{level}, level);
}

void checkMount(const Ptr<Mount>& mount, const std::vector<Vec2d>& targetsDeg)
{
    CV_CheckGE(mount->getAxisCount(), 2, "mount axes: a pan-tilt servo needs a mount of two axes or more");
    CV_Check(targetsDeg.size(), !targetsDeg.empty(), "target places: at least one");
    for (size_t p = 0; p < targetsDeg.size(); ++p)
        for (int i = 0; i < 2; ++i)
        {
            const Vec2d range = mount->getAngleRange(i);
            const double deg = targetsDeg[p][i];
            if (!(deg * kDeg >= range[0] && deg * kDeg <= range[1]))
                CV_Error(Error::StsOutOfRange,
                         format("target place %zu: axis %d must turn to %.2f deg to centre it, beyond its range "
                                "[%.2f, %.2f] deg (its levels x gain)",
                                p, i, deg, range[0] / kDeg, range[1] / kDeg));
        }
    const double det = determinant(pointingJacobian(mount, std::vector<double>(size_t(mount->getAxisCount()), 0.0)));
    if (!(std::abs(det) > 0.1))
        CV_Error(Error::StsBadArg, format("mount: its first two axes must turn the optical axis both ways, as a pan "
                                          "(0, 1, 0) and a tilt (1, 0, 0) do (det %.3f of their x-y rates)",
                                          det));
}

// ---- the positioner: the plants directly, or every axis over the bus --------------------------------

class MountPositioner
{
public:
    MountPositioner(const ServoConfig& config, const Ptr<Mount>& mount)
    {
        if (config.busUri.empty())
            return;
        int needed = 0;
        for (int i = 0; i < mount->getAxisCount(); ++i)
            needed = std::max({needed, -mount->getLevelRange(i)[0], mount->getLevelRange(i)[1]});
        ActuatorLimits limits;
        limits.maxLevel = needed;
        limits.minDwell = 1e-3;
        driver_ = MultiAxisDriver::create(ActuatorBus::create(config.busUri, config.busTimeout, 2),
                                          mount->getAxisCount(), limits);
        const ActuatorInfo info = driver_->connect();
        if (info.maxLevel < needed)
            CV_Error(Error::StsBadArg, format("the controller at %s accepts levels up to %d, the mount needs %d",
                                              config.busUri.c_str(), info.maxLevel, needed));
    }
    ~MountPositioner()
    {
        if (driver_ && std::uncaught_exceptions() > 0)  // on an error every axis goes to its safe level
        {
            try { driver_->stop(); } catch (...) {}
        }
    }

    /** Runs a move planned to start at `plannedStart` (simulation clock); returns the schedules as the
    axes execute them, the start's lateness (ms) and, over the bus, each axis's start report. The
    controller starts every axis's entry 0 at one START, so each axis's schedule first holds its level
    from the move's first switch (a delayed follower keeps its delay). */
    std::vector<SwitchSchedule> run(const std::vector<SwitchSchedule>& planned, double plannedStart, double& latencyMs,
                                    std::vector<StartReport>& starts)
    {
        latencyMs = 0;
        starts.clear();
        if (!driver_)
            return planned;
        double origin = planned[0].times.front();
        for (const SwitchSchedule& s : planned)
            origin = std::min(origin, s.times.front());
        std::vector<SwitchSchedule> sent = planned;
        for (SwitchSchedule& s : sent)
            if (s.times.front() >= origin + driver_->getLimits().minDwell)
            {
                s.times.insert(s.times.begin(), origin);
                s.levels.insert(s.levels.begin(), s.initialLevel);
            }
        driver_->waitUntilDone(2.0);  // the previous move (real time) must be over
        driver_->upload(sent);
        const double asked = hostNow();
        starts = driver_->start();
        const double simStart = plannedStart + std::max(0.0, starts[0].hostStartTime - asked);
        latencyMs = 1e3 * (simStart - plannedStart);
        for (SwitchSchedule& s : sent)  // the device holds µs offsets from entry 0, started at simStart
        {
            const double first = s.times.front();
            for (double& t : s.times)
                t = simStart + std::round((t - first) * 1e6) * 1e-6;
        }
        return sent;
    }

private:
    Ptr<MultiAxisDriver> driver_;
};

Ptr<DynamicDeblurrer> makeDeblurrer(const ServoConfig& config, const Ptr<CameraModel>& camera)
{
    const Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(camera);
    deblurrer->setPsfModel(config.psfModel);
    RLParams rl = deblurrer->getRLParams();
    rl.iterations = config.rlIterations;
    deblurrer->setRLParams(rl);
    return deblurrer;
}

}  // namespace

Ptr<Mount> panTiltMount(const ServoConfig& positioner)
{
    Ptr<Mount> mount = Mount::create();
    for (const Vec3d& axis : {Vec3d(0, 1, 0), Vec3d(1, 0, 0)})
        mount->addAxis(axis,
                       Plant::create(positioner.naturalFreqHz, positioner.dampingRatio,
                                     positioner.gainDegPerLevel * kDeg),
                       -positioner.maxLevel, positioner.maxLevel);
    return mount;
}

PanTiltConfig diagonalJumps(int places, int cyclesPerTarget, unsigned seed, Vec2d startDeg, double minJumpDeg,
                            double maxJumpDeg, double limitDeg)
{
    CV_CheckGT(places, 0, "places");
    CV_CheckGT(cyclesPerTarget, 0, "cycles per place");
    CV_Assert(0 <= minJumpDeg && minJumpDeg <= maxJumpDeg && maxJumpDeg / std::sqrt(2.0) <= limitDeg);
    CV_Assert(std::abs(startDeg[0]) <= limitDeg && std::abs(startDeg[1]) <= limitDeg);
    PanTiltConfig config;
    RNG rng(0x7a9u + seed);
    config.targetsDeg.push_back(startDeg);
    for (int i = 1; i < places; ++i)
    {
        const double step = rng.uniform(minJumpDeg, maxJumpDeg) / std::sqrt(2.0);  // along a diagonal
        Vec2d next = config.targetsDeg.back();
        for (int a = 0; a < 2; ++a)
        {
            const double here = next[a], there = rng.uniform(0, 2) ? here + step : here - step;
            next[a] = std::abs(there) > limitDeg ? 2 * here - there : there;
        }
        config.targetsDeg.push_back(next);
    }
    config.loop.cyclesPerTarget = cyclesPerTarget;
    config.loop.cycles = places * cyclesPerTarget;
    config.loop.latencyJitter = 1.0 / config.loop.fps;
    config.loop.noiseSeed = 7u + seed;
    return config;
}

PanTiltConfig circleScenario(int places, double radiusDeg, int cyclesPerTarget, unsigned seed)
{
    CV_CheckGE(places, 3, "places per turn of the circle");
    CV_CheckGT(cyclesPerTarget, 0, "cycles per place");
    CV_Check(radiusDeg, radiusDeg > 0, "circle radius, degrees");
    PanTiltConfig config;
    for (int i = 0; i < places; ++i)
        config.targetsDeg.emplace_back(radiusDeg * std::cos(2 * CV_PI * i / places),
                                       radiusDeg * std::sin(2 * CV_PI * i / places));
    config.loop.cyclesPerTarget = cyclesPerTarget;
    config.loop.cycles = places * cyclesPerTarget;
    config.loop.latencyJitter = 1.0 / config.loop.fps;
    config.loop.noiseSeed = 7u + seed;
    return config;
}

void checkPanTiltConfig(const PanTiltConfig& config)
{
    checkServoConfig(config.loop);
    checkMount(config.mount.empty() ? panTiltMount(config.loop) : config.mount, config.targetsDeg);
}

PanTiltReport runPanTiltServo(const PanTiltConfig& config, const std::function<void(const PanTiltReport&)>& progress)
{
    checkPanTiltConfig(config);
    const ServoConfig& loop = config.loop;
    const Ptr<Mount> mount = config.mount.empty() ? panTiltMount(loop) : config.mount;
    const size_t axes = size_t(mount->getAxisCount());

    // The system: mount, planner, camera, deblurrer; the mount as it really moves (the loop knows only `mount`).
    const Ptr<MountPlanner> planner = MountPlanner::create(mount, loop.plannerMode);
    const Size size = loop.imageSize;
    const Ptr<CameraModel> camera = CameraModel::create(loop.focalPx, loop.focalPx, (size.width - 1) / 2.0,
                                                        (size.height - 1) / 2.0, size.width, size.height);
    const Point2d imageCentre(camera->getCx(), camera->getCy());
    MotionCorrection drift;
    drift.naturalFreqScale = loop.trueFreqScale;
    drift.dampingScale = loop.trueDampingScale;
    drift.axisNaturalFreqScales = Vec2d::all(loop.trueFreqScale);
    drift.axisDampingScales = Vec2d::all(loop.trueDampingScale);
    const Ptr<DynamicDeblurrer> deblurrer = makeDeblurrer(loop, camera);
    MountPositioner positioner(loop, mount);

    // The scene and the target's places.
    PanTiltReport report;
    report.targetsDeg = config.targetsDeg;
    double farthestDeg = 0;
    auto centring = [&](size_t place) {
        std::vector<double> q(axes, 0.0);
        q[0] = config.targetsDeg[place][0] * kDeg;
        q[1] = config.targetsDeg[place][1] * kDeg;
        return mount->orientation(q);
    };
    for (size_t p = 0; p < config.targetsDeg.size(); ++p)
    {
        const double deg = std::acos(std::min(1.0, centring(p)(2, 2))) / kDeg;
        report.loop.targetsDeg.push_back(deg);
        farthestDeg = std::max(farthestDeg, deg);
    }
    World world = makeWorld(size, cvCeil(loop.focalPx * std::tan(farthestDeg * kDeg * 1.3 + 2 * kDeg)));
    int target = 0;
    placeTarget(world, camera, centring(0), loop.tagCellPx, loop.targetTags);

    // Visual servoing task (ViSP): the target's centre s to the image centre s*, eye-in-hand, ωx and ωy.
    const vpCameraParameters cam(loop.focalPx, loop.focalPx, camera->getCx(), camera->getCy());
    vpFeaturePoint s, sStar;
    sStar.buildFrom(0.0, 0.0, kDepth);
    vpServo task;
    task.setServo(vpServo::EYEINHAND_CAMERA);
    task.setInteractionMatrixType(vpServo::CURRENT);
    task.setLambda(loop.lambda);
    vpColVector dof(6, 0.0);
    dof[3] = dof[4] = 1.0;  // the pan and the tilt turn the camera about its x and y axes
    task.setCameraDoF(dof);
    task.addFeature(s, sStar);
    TargetDetector detector;

    const double period = 1.0 / loop.fps;
    // "Moving" for this camera: faster than 0.2 px per exposure (a mount's motion is classified by its rate).
    const double angleTol = 0.25 / loop.focalPx, velocityTol = 0.2 / loop.focalPx / loop.exposure;
    std::vector<SwitchSchedule> history(axes, hold(0, kHistoryStart));  // every switch so far
    std::vector<int> levels(axes, 0);
    Ptr<CameraMotion> command, truth = drift.correctMotion(mount->motion(history));
    Mat lastStill;
    int frameIndex = 0, lastStillIndex = -1, referenceIndex = -1;
    RNG jitter(loop.noiseSeed * 2654435761ull + 1u);

    auto takeFrame = [&](int cycle) {
        ServoFrame frame;
        frame.cycle = cycle;
        frame.target = target;
        frame.index = frameIndex;
        frame.frameStart = frameIndex * period;
        const RollingShutter shutter(frame.frameStart, loop.exposure, loop.lineDelay, size.height);
        const RollingShutter trueShutter(frame.frameStart + loop.clockOffset, loop.exposure, loop.lineDelay,
                                         size.height);
        Mat blurred, noisy;
        renderBlurred(world.sharpLinear, truth, camera, trueShutter, blurred, kHistoryStart);
        addSensorNoise(blurred, noisy, 4000.0, 8.0, 5.0, loop.noiseSeed * 100003ull + static_cast<uint64>(frameIndex));
        const Vec2d readout = trueShutter.readoutInterval();
        frame.thetaDeg = std::acos(std::min(1.0, truth->orientation(0.5 * (readout[0] + readout[1]))(2, 2))) / kDeg;
        frame.tagMotionPx = tagMotionPx(truth, camera, world, trueShutter);
        frame.window = command ? classifyExposure(command, shutter, angleTol, velocityTol) : int(EXPOSURE_IV);
        Mat restored;  // its own buffer: the raw frame is searched too
        if (frame.window == EXPOSURE_IV)
        {
            restored = noisy;  // a still frame: nothing to undo
            lastStill = noisy;
            lastStillIndex = frameIndex;
        }
        else
        {
            const double t0 = static_cast<double>(getTickCount());
            if (loop.refine && !lastStill.empty() && lastStillIndex != referenceIndex)
            {
                deblurrer->setReferenceFrame(lastStill);  // every axis at its resting angle before the move
                referenceIndex = lastStillIndex;
            }
            deblurrer->deblur(noisy, command, shutter, restored);
            frame.correction = deblurrer->getLastCorrection();
            frame.restoreSec = (static_cast<double>(getTickCount()) - t0) / getTickFrequency();
        }
        Mat raw8, restored8;
        linearToSrgb(noisy, raw8, CV_8U);
        linearToSrgb(restored, restored8, CV_8U);
        frame.raw = detector.detect(raw8, world.tagOffsets);
        frame.restored = detector.detect(restored8, world.tagOffsets);
        if (loop.keepImages)
        {
            frame.rawImage = raw8;
            frame.restoredImage = restored8;
        }
        ++frameIndex;
        return frame;
    };

    report.loop.frames.push_back(takeFrame(-1));  // frame 0: the camera at rest
    Detection latest = report.loop.frames.back().restored;
    int cycleOfTarget = 0;
    for (int c = 0; c < loop.cycles; ++c)
    {
        // The target moves to its next place between two frames; the frame this cycle measures sees it there.
        if (loop.cyclesPerTarget > 0 && c > 0 && c % loop.cyclesPerTarget == 0 &&
            target + 1 < static_cast<int>(config.targetsDeg.size()))
        {
            ++target;
            cycleOfTarget = 0;
            placeTarget(world, camera, centring(size_t(target)), loop.tagCellPx, loop.targetTags);
            command.release();
            report.loop.frames.push_back(takeFrame(c - 1));
            latest = report.loop.frames.back().restored;
        }
        const std::vector<double> from = restingAngles(mount, levels);
        ServoCycle cycle;
        cycle.cycle = c;
        cycle.target = target;
        cycle.cycleOfTarget = cycleOfTarget++;
        cycle.trueErrorPx = norm(targetInView(camera, world, mount->orientation(from)) - imageCentre);
        PanTiltMove move;
        move.fromLevels = Vec2i(levels[0], levels[1]);

        // 1. Measure the target's centre in the latest restored frame (the view at the resting angles).
        Vec2d dq(0, 0);
        if (latest.tagsFound > 0)
            cycle.measuredErrorPx = norm(latest.centre - imageCentre);
        if (latest.tagsFound > 0 && cycle.measuredErrorPx > loop.deadbandPx)
        {
            double x = 0, y = 0;
            vpPixelMeterConversion::convertPoint(cam, latest.centre.x, latest.centre.y, x, y);
            s.buildFrom(x, y, kDepth);
            // 2. Control law: the camera's rates for one cycle; the chain turns ωx, ωy into joint increments.
            const vpColVector v = task.computeControlLaw();
            dq = pointingJacobian(mount, from).inv() * Vec2d(v[3], v[4]);
        }
        move.deltaDeg = dq * (1.0 / kDeg);

        // 3. Plan every axis (coordinated), starting once the measured frame is read out and processed.
        std::vector<int> goal = levels;
        for (int i = 0; i < 2; ++i)
        {
            const Vec2i range = mount->getLevelRange(i);
            const double gain = mount->getPlant(i)->getGain();
            goal[size_t(i)] = std::max(range[0], std::min(range[1], static_cast<int>(std::lround(from[size_t(i)] / gain + dq[i] / gain))));
        }
        const RollingShutter last(report.loop.frames.back().frameStart, loop.exposure, loop.lineDelay, size.height);
        const double latency = loop.latency + (loop.latencyJitter > 0 ? jitter.uniform(0.0, loop.latencyJitter) : 0.0);
        cycle.latencyMs = 1e3 * latency;
        const double plannedStart = last.readoutInterval()[1] + latency;
        command.release();
        double moveStart = std::numeric_limits<double>::infinity();  // the first switch of any axis
        if (goal != levels)
        {
            const MountMove planned = planner->plan(from, restingAngles(mount, goal), plannedStart);
            std::vector<SwitchSchedule> schedules = planned.schedules;
            for (size_t i = 0; i < axes; ++i)
                if (schedules[i].times.empty())
                    schedules[i] = hold(levels[i], plannedStart);
            cycle.settleMs = 1e3 * planned.settleTime;
            move.peakRateDegS = planned.peakRate / kDeg;
            move.pathDeviationDeg = planned.pathDeviation / kDeg;
            // 4. Apply: on the plants, or uploaded to the controller and started.
            schedules = positioner.run(schedules, plannedStart, cycle.startLatencyMs, move.starts);
            for (size_t i = 0; i < axes; ++i)
            {
                moveStart = std::min(moveStart, schedules[i].times.front());
                cycle.switches += schedules[i].times.size();
                history[i].times.insert(history[i].times.end(), schedules[i].times.begin(), schedules[i].times.end());
                history[i].levels.insert(history[i].levels.end(), schedules[i].levels.begin(), schedules[i].levels.end());
            }
            command = mount->motion(schedules);
            truth = drift.correctMotion(mount->motion(history));
            levels = goal;
        }
        move.toLevels = Vec2i(levels[0], levels[1]);
        cycle.fromLevel = move.fromLevels[1];
        cycle.toLevel = move.toLevels[1];
        cycle.deltaDeg = norm(move.deltaDeg);

        // 5. The camera keeps taking frames while the mount moves: classify, restore, detect. The latest
        // frame read out after the move began that shows every tag wins; failing that, the one that shows the most.
        Detection seen;
        for (int f = 0; f < loop.framesPerCycle; ++f)
        {
            report.loop.frames.push_back(takeFrame(c));
            const ServoFrame& frame = report.loop.frames.back();
            const RollingShutter shutter(frame.frameStart, loop.exposure, loop.lineDelay, size.height);
            const bool beforeMove = command && shutter.readoutInterval()[1] <= moveStart;
            if (!beforeMove && (frame.restored.found || (!seen.found && frame.restored.tagsFound >= seen.tagsFound)))
                seen = frame.restored;
        }
        latest = seen;
        report.loop.cycles.push_back(cycle);
        report.moves.push_back(move);
        if (progress)
            progress(report);
    }
    return report;
}

void writePanTiltOutputs(const PanTiltReport& report, const std::string& outDir)
{
    utils::fs::createDirectories(outDir);
    {
        std::ofstream csv(outDir + "/cycles.csv");
        csv << "cycle,target,cycle_of_target,target_pan_deg,target_tilt_deg,measured_error_px,true_error_px,"
               "from_pan_level,from_tilt_level,to_pan_level,to_tilt_level,delta_pan_deg,delta_tilt_deg,latency_ms,"
               "switches,settle_ms,peak_rate_deg_s,path_deviation_deg,start_latency_ms\n";
        for (size_t i = 0; i < report.loop.cycles.size(); ++i)
        {
            const ServoCycle& c = report.loop.cycles[i];
            const PanTiltMove& m = report.moves[i];
            const Vec2d place = report.targetsDeg[size_t(c.target)];
            csv << format("%d,%d,%d,%.3f,%.3f,%.3f,%.3f,%d,%d,%d,%d,%.4f,%.4f,%.2f,%zu,%.2f,%.1f,%.4f,%.3f\n", c.cycle,
                          c.target, c.cycleOfTarget, place[0], place[1], c.measuredErrorPx, c.trueErrorPx,
                          m.fromLevels[0], m.fromLevels[1], m.toLevels[0], m.toLevels[1], m.deltaDeg[0],
                          m.deltaDeg[1], c.latencyMs, c.switches, c.settleMs, m.peakRateDegS, m.pathDeviationDeg,
                          c.startLatencyMs);
        }
        if (!csv)
            CV_Error(Error::StsError, "cannot write " + outDir + "/cycles.csv");
    }
    writeServoFigures(report.loop, outDir);
}

}  // namespace dynblur_samples
