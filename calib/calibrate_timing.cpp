// SPDX-License-Identifier: Apache-2.0
// dynblur_calibrate_timing: the offset between the camera's clock and the actuator's, the line delay
// and (optionally) the plant's wn and zeta, from a recording (frames, frame log, command log; formats
// in docs/recording-format.md), by calibrateTiming over frames taken during moves, each against the
// still frame before or after its move.
//
//     dynblur_calibrate_timing --video rec/frame_%04d.png --frames rec/frames.csv
//                              --commands rec/commands.csv --camera rec/camera.xml --plant rec/plant.yml
//     dynblur_calibrate_timing --simulate rec --true-offset 0.0012      (a recording with a drifted truth)
//     dynblur_calibrate_timing --gyro Gyroscope.csv --video clip.mp4 --camera camera.xml --exposure 0.01
//                                                                       (a hand-held clip: docs/hand-held.md)
//
// Writes the timing file (TimingCalibration::save, atomically) and a plot of the objective around
// the result (TIMING_objective.png).
#include "atomic_file.hpp"  // samples/support
#include "cli_args.hpp"
#include "gyro_recording.hpp"
#include "gyro_timing.hpp"
#include "mount_recording.hpp"  // samples/simulation
#include "objective_plot.hpp"
#include "plant_file.hpp"
#include "recording.hpp"
#include "reference_pairing.hpp"
#include "scene.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <sys/stat.h>
#include <vector>

using namespace cv;
using namespace cv::dynblur;
using namespace dynblur_samples;

static CliOptions calibrateTimingOptions()
{
    CliOptions options("dynblur_calibrate_timing");
    options.synopsis("--video V --frames FRAMES.csv --commands COMMANDS.csv [options]")
        .synopsis("--recording DIR [options]")
        .synopsis("--gyro LOG --video V [--frames FRAMES.csv] [options]")
        .synopsis("--simulate DIR [simulation options]")
        .description("Estimates, from a recording, the offset between the camera's clock and the actuator's (s), the "
                     "line delay and optionally the plant's natural frequency and damping, as one correction for the "
                     "whole recording (calibrateTiming): frames taken during moves are compared with the still frame "
                     "before the move (a frame that starts at rest) or after it (a frame that ends at rest).")
        .group(recordingOptions())
        .option("refine", "LIST", "offset,line-delay", "what to estimate: offset, line-delay, plant, comma-separated")
        .option("max-frames", "N", "10", "moving frames used, at most")
        .option("max-offset", "S", "", "the offset is searched within +-S seconds (default 0.02; 2 for a clip in "
                                       "continuous motion: see the gyro mode)")
        .option("out", "FILE.yml", "timing.yml", "timing file to write (with --recording: DIR/timing.yml)")
        .option("plot", "FILE.png", "", "objective around the result (default: OUT_objective.png)")
        .flag("no-png", "do not write the plot")
        .heading("Simulation (writes a recording and exits; nothing is calibrated):")
        .option("simulate", "DIR", "",
                "renders frame_%04d.png, frames.csv, commands.csv, camera.xml and plant.yml into DIR: saccades between "
                "0 and 10 deg seen by a 640x480 webcam at 30 fps; DIR/truth/ gets the sharp scene and the truth that "
                "moved the camera (dynblur_restore_video --truth DIR/truth compares each frame with it); with --mount "
                "FILE, diagonal saccades of the mount's axes (--to) and mount.yml in place of plant.yml")
        .flag("as-video", "the frames go to frames.avi (MJPG, as a C270 streams them)")
        .option("true-offset", "S", "0.0012", "the truth's clock offset, seconds")
        .option("true-line-delay-scale", "X", "0.95", "the truth's line delay over the frame log's")
        .option("true-hz-scale", "X", "1.03", "the truth's natural frequency over the plant file's")
        .option("true-zeta-scale", "X", "1.1", "the truth's damping ratio over the plant file's")
        .option("saccades", "N", "4", "saccades in the recording")
        .option("to", "DEG,DEG", "10,6",
                "with --mount: the far end of the diagonal saccades, degrees per axis (planned by MountPlanner)")
        .option("true-axis1-hz-scale", "X", "0.97", "with --mount: the truth's natural frequency of axis 1 over the file's")
        .option("true-axis1-zeta-scale", "X", "0.9", "with --mount: the truth's damping ratio of axis 1 over the file's")
        .group(gyroTimingOptions())
        .footer("Exit status: 0 calibrated (or simulated), 1 bad or unusable recording (the message says why), 2 bad "
                "usage.");
    return options;
}

static int usageError(const std::string& message)
{
    std::cerr << "error: " << message << "\n(see dynblur_calibrate_timing --help)\n";
    return 2;
}

static const double kDeg = CV_PI / 180.0;

// ---------------------------------------------------------------------------------------------
// Simulation

/* What a rendered recording's frames are compared with (dynblur_restore_video --truth): the sharp
   scene (the view at sceneAngle, wider than a frame by the same margin on each side; 8-bit sRGB) and
   the correction from the nominal model to the motion that rendered the frames. */
static void writeTruth(const std::string& dir, const Mat& linearScene, double sceneAngle, const MotionCorrection& drift)
{
    ::mkdir(dir.c_str(), 0755);
    Mat srgb;
    linearToSrgb(linearScene, srgb, CV_8U);
    if (!imwrite(dir + "/scene.png", srgb))
        CV_Error(Error::StsError, "cannot write '" + dir + "/scene.png'");
    FileStorage fs(dir + "/truth.yml", FileStorage::WRITE);
    fs.writeComment("the truth of a rendered recording: scene.png is the view at sceneAngle (radians); the "
                    "frames were rendered with the nominal plant and frame log corrected by the rest");
    fs << "sceneAngle" << sceneAngle << "timeOffset" << drift.timeOffset << "lineDelayScale" << drift.lineDelayScale
       << "naturalFreqScale" << drift.naturalFreqScale << "dampingScale" << drift.dampingScale;
}

/* A mount's recording: the base's drift from --true-hz-scale and --true-zeta-scale, axis 1's from its
   own options. */
static int simulateMount(const CliArgs& args, const std::string& dir, const MotionCorrection& drift, int saccades)
{
    MountRecordingSpec spec;
    spec.mount = Mount::load(args.str("mount"));
    spec.drift = drift;
    spec.drift.axisNaturalFreqScales[0] = args.num("true-axis1-hz-scale");
    spec.drift.axisDampingScales[0] = args.num("true-axis1-zeta-scale");
    spec.saccades = saccades;
    spec.asVideo = args.has("as-video");
    for (double deg : args.numbers("to"))
        spec.targetAngles.push_back(deg * kDeg);
    if (int(spec.targetAngles.size()) != spec.mount->getAxisCount())
        return usageError(format("--to gives %zu angles but the mount '%s' (--mount) has %d axes: one per axis, degrees",
                                 spec.targetAngles.size(), args.str("mount").c_str(), spec.mount->getAxisCount()));
    if (!(spec.drift.axisNaturalFreqScales[0] > 0.5 && spec.drift.axisNaturalFreqScales[0] < 1.5) ||
        !(spec.drift.axisDampingScales[0] > 0.2 && spec.drift.axisDampingScales[0] < 3))
        return usageError("--true-axis1-hz-scale within (0.5, 1.5), --true-axis1-zeta-scale within (0.2, 3)");
    const int count = renderMountRecording(dir, spec);
    std::printf("wrote %d frames, frames.csv, commands.csv (%d axes), camera.xml and mount.yml to %s\n"
                "truth: clock offset %+.4f ms, line delay x%.4f, axis 0 wn x%.4f zeta x%.4f, axis 1 wn x%.4f zeta x%.4f\n",
                count, spec.mount->getAxisCount(), dir.c_str(), drift.timeOffset * 1e3, drift.lineDelayScale,
                drift.naturalFreqScale, drift.dampingScale, spec.drift.axisNaturalFreqScales[0],
                spec.drift.axisDampingScales[0]);
    return 0;
}

static int simulate(const CliArgs& args, const std::string& dir)
{
    // The truth that moved the camera, as the correction from the nominal model to it.
    MotionCorrection drift;
    drift.timeOffset = args.num("true-offset");
    drift.lineDelayScale = args.num("true-line-delay-scale");
    drift.naturalFreqScale = args.num("true-hz-scale");
    drift.dampingScale = args.num("true-zeta-scale");
    const int saccades = args.integer("saccades");
    if (!(std::abs(drift.timeOffset) < 0.1) || !(drift.lineDelayScale > 0.5 && drift.lineDelayScale < 1.5) ||
        !(drift.naturalFreqScale > 0.5 && drift.naturalFreqScale < 1.5) ||
        !(drift.dampingScale > 0.2 && drift.dampingScale < 3) || saccades < 1 || saccades > 20)
        return usageError("--true-offset within +-0.1 s, the scales within (0.5, 1.5) ((0.2, 3) for zeta), "
                          "--saccades in [1, 20]");
    if (args.has("mount"))
        return simulateMount(args, dir, drift, saccades);
    ::mkdir(dir.c_str(), 0755);
    const Ptr<Plant> nominal = Plant::create(14.4, 0.12, kDeg);
    const Ptr<Plant> truth = drift.correctPlant(nominal);
    const Ptr<CameraModel> camera = CameraModel::create(615.0, 615.0, 319.5, 239.5, 640, 480);
    const double exposure = 0.008, lineDelay = 1.0 / 30 / 480;

    // Saccades between 0 and 10 degrees, about 0.6 s apart, planned on the nominal plant.
    CommandLog commands;
    commands.times.push_back(0.0);
    commands.levels = {{0}};
    Ptr<SwitchPlanner> planner = SwitchPlanner::create(nominal, 16);
    for (int k = 0; k < saccades; k++)
    {
        const double from = (k % 2) * 10 * kDeg, to = ((k + 1) % 2) * 10 * kDeg;
        // Each move starts 7 ms later in the frame period than the one before: the frames see every phase.
        const SwitchSchedule move = planner->plan(from, to, 0.5 + 0.6 * k + 0.007 * k);
        for (size_t i = 0; i < move.times.size(); i++)
            commands.times.push_back(move.times[i]), commands.levels[0].push_back(move.levels[i]);
    }
    const SwitchSchedule all(commands.times, commands.levels[0], 0);

    // The scene is the view at 5 degrees, wide enough for both ends of the moves.
    const double thetaRef = 5 * kDeg;
    const int marginY = int(std::ceil(615.0 * std::tan(6 * kDeg))) + 24;
    // A webcam's lens is softer than the generated scene's finest stripes and text.
    Mat scene;
    srgbToLinear(makeScene(Size(640 + 48, 480 + 2 * marginY)), scene);
    GaussianBlur(scene, scene, Size(0, 0), 1.0);
    std::vector<FrameRecord> frames;
    const int count = int(std::ceil((0.5 + 0.6 * saccades + 0.3) * 30));
    // A webcam's MJPG stream (as a C270 delivers it), or lossless PNG frames.
    const bool asVideo = args.has("as-video");
    VideoWriter writer;
    if (asVideo && !writer.open(dir + "/frames.avi", VideoWriter::fourcc('M', 'J', 'P', 'G'), 30.0, Size(640, 480)))
        CV_Error(Error::StsError, "cannot write '" + dir + "/frames.avi'");
    for (int k = 0; k < count; k++)
    {
        FrameRecord f;
        f.frame = k;
        f.frameStart = k / 30.0;
        f.exposure = exposure;
        f.lineDelay = lineDelay;
        const RollingShutter happened = drift.correctShutter(RollingShutter(f.frameStart, exposure, lineDelay, 480));
        Mat blurred, noisy, frame;
        renderBlurred(scene, truth, all, camera, happened, blurred, thetaRef);
        addSensorNoise(blurred, noisy, 4000.0, 8.0, 5.0, 1000 + uint64(k));
        linearToSrgb(noisy, frame, CV_8U);
        if (asVideo)
        {
            writer.write(frame);
        }
        else
        {
            char name[64];
            std::snprintf(name, sizeof name, "/frame_%04d.png", k);
            if (!imwrite(dir + name, frame))
                CV_Error(Error::StsError, "cannot write '" + dir + name + "'");
        }
        frames.push_back(f);
        std::printf("\rrendering frame %d of %d", k + 1, count);
        std::fflush(stdout);
    }
    std::printf("\n");
    writer.release();
    writeFrameLog(dir + "/frames.csv", frames);
    writeTruth(dir + "/truth", scene, thetaRef, drift);
    writeCommandLog(dir + "/commands.csv", commands);
    camera->save(dir + "/camera.xml");
    savePlantFile(dir + "/plant.yml", *nominal, 16, "the nominal plant the recording's commands were planned on");
    std::printf("wrote %d frames (%s), frames.csv, commands.csv, camera.xml and plant.yml to %s\n"
                "truth: clock offset %+.4f ms, line delay x%.4f, wn x%.4f, zeta x%.4f\n",
                count, asVideo ? "frames.avi" : "frame_%04d.png", dir.c_str(), drift.timeOffset * 1e3,
                drift.lineDelayScale, drift.naturalFreqScale, drift.dampingScale);
    return 0;
}

// ---------------------------------------------------------------------------------------------
// Calibration

//! One plant's recording: each frame against its still, at the still's angle.
static TimingCalibration calibratePlantRecording(const std::vector<ReferencePairing::Item>& paired,
                                                 const Ptr<Plant>& plant, const Ptr<CameraModel>& camera, int flags,
                                                 double maxOffset)
{
    std::vector<Mat> references, frames;
    std::vector<SwitchSchedule> schedules;
    std::vector<RollingShutter> shutters;
    std::vector<double> angles;
    for (const ReferencePairing::Item& m : paired)
    {
        references.push_back(m.reference);
        frames.push_back(m.image);
        schedules.push_back(m.schedules[0]);
        shutters.push_back(m.shutter);
        angles.push_back(m.referenceAngle);
    }
    return calibrateTiming(plant, camera, references, frames, schedules, shutters, flags, angles, maxOffset);
}

//! A mount's recording: each frame's motion (every axis's schedule) against the still at rest before or after it.
static TimingCalibration calibrateMountRecording(const std::vector<ReferencePairing::Item>& paired,
                                                 const CommandedMotion& motion, const Ptr<CameraModel>& camera,
                                                 int flags, double maxOffset)
{
    std::vector<Mat> references, frames;
    std::vector<Ptr<CameraMotion>> motions;
    std::vector<RollingShutter> shutters;
    std::vector<int> after;
    for (const ReferencePairing::Item& m : paired)
    {
        references.push_back(m.reference);
        frames.push_back(m.image);
        motions.push_back(motion.motion(m.schedules));
        shutters.push_back(m.shutter);
        after.push_back(!m.after.empty() && m.reference.data == m.after.data);
    }
    return calibrateTiming(motions, camera, references, frames, shutters, flags, after, maxOffset);
}

/* The correction and its deviations; an axis's plant scales per axis (up to three), each "held" where
   the frames did not determine it (an axis no move turned, a damping no frame saw ring). */
static void printCalibration(const TimingCalibration& t, int axes)
{
    const MotionCorrection& c = t.correction;
    std::printf("clock offset      %+.4f ms (sd %.4f)\nline delay        x%.4f (sd %.4f)\n", c.timeOffset * 1e3,
                t.timeOffsetStd * 1e3, c.lineDelayScale, t.lineDelayScaleStd);
    const std::vector<RefinementParameter> table = refinementParameters();
    for (int axis = 0; axis < std::min(axes, 3); axis++)
    {
        const double wn = axis ? c.axisNaturalFreqScales[axis - 1] : c.naturalFreqScale;
        const double zeta = axis ? c.axisDampingScales[axis - 1] : c.dampingScale;
        const double wnSd = axis ? t.axisNaturalFreqScaleStd[axis - 1] : t.naturalFreqScaleStd;
        const double zetaSd = axis ? t.axisDampingScaleStd[axis - 1] : t.dampingScaleStd;
        // Each scale's own row: a frame may determine an axis's ωn and hold its ζ.
        const auto held = [&](const char* quantity) {
            for (size_t j = 0; j < table.size(); j++)
                if ((c.heldParameters >> j & 1) && table[j].mountAxis == axis && table[j].name.rfind(quantity, 0) == 0 &&
                    (axes > 1 || table[j].plantMotion))
                    return true;
            return false;
        };
        const std::string name = axes > 1 ? format("axis %d ", axis) : std::string();
        std::printf("%snatural frequency x%.4f (sd %.4f)%s\n%sdamping ratio     x%.4f (sd %.4f)%s\n", name.c_str(), wn,
                    wnSd, held("natural frequency") ? " held: the frames do not determine it" : "", name.c_str(), zeta,
                    zetaSd, held("damping ratio") ? " held: the frames do not determine it" : "");
    }
    std::printf("consistency       %.2f (noise units; about 1 when the model explains the frames)\n", c.consistency);
}

int main(int argc, char** argv)
{
    try
    {
        const CliOptions options = calibrateTimingOptions();
        const CliArgs args = options.parse(argc, argv);
        if (options.printHelp(args))
            return 0;
        if (args.has("simulate"))
            return simulate(args, args.str("simulate"));
        if (args.has("simulate-gyro"))
            return simulateGyroTiming(args);
        if (args.has("gyro"))
            return calibrateGyroTiming(args, std::string(DYNBLUR_CALIB_DIR) + "/c270_nominal.xml");
        if (!OpenedRecording::named(args))
            return usageError("--recording DIR, or --video, --frames and --commands, are required");
        int flags = 0;
        if (!parseRefinementList(args.str("refine"), REFINE_ALL, flags) || flags == REFINE_NONE)
            return usageError("--refine takes offset, line-delay, plant (or all), comma-separated");
        const int maxFrames = args.integer("max-frames");
        const double maxOffset = args.num("max-offset", 0.02);
        if (maxFrames < 2 || !(maxOffset > 0 && maxOffset <= 1))
            return usageError("--max-frames must be >= 2 and --max-offset in (0, 1] s");
        const std::string out =
            args.has("recording") && !args.has("out") ? args.str("recording") + "/timing.yml" : args.str("out");
        const std::string plotPath = args.str("plot", pathStem(out) + "_objective.png");

        OpenedRecording recording;
        OpenedRecording::open(args, std::string(DYNBLUR_CALIB_DIR) + "/c270_nominal.xml", recording);
        const std::vector<FrameRecord>& log = recording.log;
        const Ptr<CameraModel>& camera = recording.camera;
        const Ptr<Plant>& plant = recording.plant;

        // Stream the recording, pairing each moving frame with the still frame that saw its content.
        ReferencePairing pairing(recording.commanded(), camera, recording.commands, MotionCorrection(), maxOffset);
        std::vector<ReferencePairing::Item> paired;
        const auto take = [&](const std::vector<ReferencePairing::Item>& ready) {
            for (const ReferencePairing::Item& item : ready)
                if (!item.still && !item.reference.empty() && item.window != EXPOSURE_IV &&
                    int(paired.size()) < maxFrames)
                    paired.push_back(item);
        };
        for (size_t i = 0; i < log.size() && int(paired.size()) < maxFrames; i++)
        {
            const FrameRecord& f = log[i];
            const Mat image = recording.read(f);
            take(pairing.push(f, image));
            std::printf("\rreading frame %d of %zu: %zu moving frames paired with a still frame", f.frame + 1,
                        log.size(), paired.size());
            std::fflush(stdout);
        }
        take(pairing.finish());
        std::printf("\n");
        if (paired.size() < 2)
            CV_Error(Error::StsBadArg,
                     format("the recording has %zu moving frames with a still frame before or after their move; "
                            "calibration needs at least two",
                            paired.size()));

        std::printf("calibrating over %zu frames ...\n", paired.size());
        const TimingCalibration t = recording.mount.empty()
                                        ? calibratePlantRecording(paired, plant, camera, flags, maxOffset)
                                        : calibrateMountRecording(paired, recording.commanded(), camera, flags, maxOffset);
        t.save(out);
        printCalibration(t, recording.mount.empty() ? 1 : recording.mount->getAxisCount());
        std::printf("wrote %s\n", out.c_str());
        if (!args.has("no-png"))
            writeObjectivePlot(t, "Timing calibration: objective around the result", "objective over the clock offset",
                               plotPath);
        return 0;
    }
    catch (const std::runtime_error& e)
    {
        return usageError(e.what());
    }
    catch (const cv::Exception& e)
    {
        std::cerr << "error: " << e.err << "\n";
        return 1;
    }
}
