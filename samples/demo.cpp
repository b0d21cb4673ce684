// SPDX-License-Identifier: Apache-2.0
// dynblur_demo — the project's main job.
//
// With no arguments: plans a 10° saccade on the seed's positioner, renders what a C270-like
// rolling-shutter webcam (1280×960 RGB, 30 fps readout) records in exposure windows I, II and III
// and what a global shutter records, restores each frame with the seed's uniform PSF and with
// the spatially variant pipeline, then a hand-held frame restored from its gyro log and a pan-tilt
// head's diagonal saccade, prints PSNR/SSIM/timings, and writes pictures to --out.
// With --frame: restores one real frame from its schedule, camera and plant files.
#include "demo/demo_panels.hpp"
#include "frame_timing.hpp"
#include "image_metrics.hpp"
#include "cli_args.hpp"
#include "plant_file.hpp"
#include "plot.hpp"
#include "restoration_options.hpp"
#include "scene.hpp"

#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/dynblur.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>

using namespace cv;
using namespace cv::dynblur;
using namespace dynblur_samples;
using namespace dynblur_demo;

namespace {

CliOptions demoOptions()
{
    CliOptions options("dynblur_demo");
    options.synopsis("[options]")
        .synopsis("--frame FILE --schedule FILE.yml --frame-start S [options]")
        .description("Restores frames blurred by a robotic camera's own motion, with the blur predicted from the plant "
                     "dynamics and the commands. Without --frame it runs the synthetic demo (10 deg saccade, rolling "
                     "shutter windows I-III and a global shutter). Options take --name value or --name=value.")
        .option("out", "DIR", "demo_out", "folder for the pictures and the restored frames")
        .option("image", "FILE", "", "scene image (any size; scaled to fill the view) instead of the generated scene")
        .option("iterations", "N", "20", "Richardson-Lucy iterations")
        .option("mode", "NAME", "robust",
                "planner mode: robust (tolerates a 10% error in the natural frequency) or fast")
        .option(modelOption())
        .option("camera", "FILE.xml", "", "camera (ViSP format); default: the nominal C270 at 1280x960")
        .option("plant", "FILE.yml", "", "plant file (naturalFreqHz, dampingRatio, gain, maxLevel); default: the seed's")
        .option("exposure", "S", "0.008", "exposure of one row, seconds")
        .option("line-delay", "S", "34.7e-6", "rolling-shutter line delay, seconds (0: global shutter)")
        .heading("Real-frame mode:")
        .option("frame", "FILE", "", "the blurred frame to restore")
        .option("schedule", "FILE.yml", "", "its switching schedule (dynblur_plan writes one; SwitchSchedule::save format)")
        .option("frame-start", "S", "", "start of row 0's exposure, seconds, on the schedule's clock")
        .option("timing", "FILE.yml", "",
                "the recording's calibration (dynblur_calibrate_timing): clock offset, line delay and plant corrections "
                "applied to the model")
        .option("theta-ref", "RAD", "", "reference angle, radians (default: the schedule's final angle)")
        .footer("Exit status: 0 done, 1 a file or value the demo cannot use (the message says why), 2 bad usage.");
    return options;
}

const double kDeg = CV_PI / 180.0;

struct Case
{
    std::string name;
    RollingShutter shutter;
    int window = 0;
};

Ptr<CameraModel> defaultCamera()
{
    return CameraModel::create(1230.0, 1230.0, 639.5, 479.5, 1280, 960);
}

/* The kernels of a bank as a grid laid out like the frame: at most maxRows × maxCols nodes, evenly
   picked, each kernel at its node's place, all at one zoom (so their sizes compare), each scaled to
   its own peak, with its shift; node x and y on the axes, in pixels, and a title. */
Mat psfMontage(const PsfBank& bank, int maxRows, int maxCols)
{
    const auto pick = [](size_t count, int most) {
        std::vector<size_t> chosen;
        const size_t n = std::min(count, size_t(most));
        for (size_t i = 0; i < n; i++)
            chosen.push_back(n == 1 ? 0 : i * (count - 1) / (n - 1));
        return chosen;
    };
    const std::vector<size_t> rows = pick(bank.nodeRows.size(), maxRows), cols = pick(bank.nodeCols.size(), maxCols);
    const Size largest = bank.maxKernelSize();
    const int cell = 130, inner = cell - 34, left = 70, top = 86;
    const int zoom = std::max(1, inner / std::max(1, std::max(largest.width, largest.height)));
    const Scalar text(230, 230, 230), dim(150, 150, 150);
    Mat montage(top + int(rows.size()) * cell + 30, left + int(cols.size()) * cell + 10, CV_8UC3, Scalar(20, 20, 20));
    putText(montage, format("PSF bank (%s): the kernel at each node, x %dx zoomed, each scaled to its peak",
                            bank.model == PSF_TILES ? "tiles" : bank.model == PSF_ROWS ? "row bands" : "uniform", zoom),
            Point(10, 22), FONT_HERSHEY_SIMPLEX, 0.6, text, 1, LINE_AA);
    putText(montage, "node x (px)", Point(left, 50), FONT_HERSHEY_SIMPLEX, 0.45, dim, 1, LINE_AA);
    putText(montage, "node y (px)", Point(4, top - 4), FONT_HERSHEY_SIMPLEX, 0.45, dim, 1, LINE_AA);
    putText(montage, "under each kernel: its size and the shift of its centre (dx, dy), px", Point(left, montage.rows - 10),
            FONT_HERSHEY_SIMPLEX, 0.45, dim, 1, LINE_AA);
    for (size_t c = 0; c < cols.size(); c++)
        putText(montage, format("%.0f", bank.nodeCols[cols[c]]), Point(left + int(c) * cell + cell / 2 - 14, top - 6),
                FONT_HERSHEY_SIMPLEX, 0.45, text, 1, LINE_AA);
    for (size_t r = 0; r < rows.size(); r++)
    {
        putText(montage, format("%.0f", bank.nodeRows[rows[r]]), Point(8, top + int(r) * cell + cell / 2),
                FONT_HERSHEY_SIMPLEX, 0.45, text, 1, LINE_AA);
        for (size_t c = 0; c < cols.size(); c++)
        {
            const size_t n = rows[r] * bank.nodeCols.size() + cols[c];
            const Mat& kernel = bank.kernels[n];
            Mat shown;
            double peak = 0;
            minMaxLoc(kernel, nullptr, &peak);
            kernel.convertTo(shown, CV_8U, 255.0 / std::max(peak, 1e-12));
            resize(shown, shown, Size(), zoom, zoom, INTER_NEAREST);
            applyColorMap(shown, shown, COLORMAP_INFERNO);
            const Rect box(left + int(c) * cell + 4, top + int(r) * cell + 4, cell - 8, inner);
            Mat tile = montage(box);
            tile.setTo(Scalar(45, 45, 45));
            const Rect fit((box.width - std::min(shown.cols, box.width)) / 2, (box.height - std::min(shown.rows, box.height)) / 2,
                           std::min(shown.cols, box.width), std::min(shown.rows, box.height));
            shown(Rect(0, 0, fit.width, fit.height)).copyTo(tile(fit));
            const Point shift = bank.shifts[n];
            putText(montage, format("%dx%d (%d, %d)", kernel.cols, kernel.rows, shift.x, shift.y),
                    Point(box.x, box.y + box.height + 16), FONT_HERSHEY_SIMPLEX, 0.4, dim, 1, LINE_AA);
        }
    }
    return montage;
}

double maxShutterRows(const std::vector<Case>& cases)
{
    int rows = 1;
    for (const Case& c : cases)
        rows = std::max(rows, c.shutter.rows);
    return rows;
}

// θ(t) of the saccade, and below it each frame's row exposure intervals (a rolling shutter's
// parallelogram, a global shutter's rectangle), on one time axis.
void writeTrajectoryPlot(const std::string& path, const Ptr<Plant>& plant, const SwitchSchedule& schedule,
                         const std::vector<Case>& cases)
{
    double tMin = schedule.times.front() - 0.01, tMax = schedule.times.back() + 0.04;
    for (const Case& c : cases)
    {
        const Vec2d readout = c.shutter.readoutInterval();
        tMin = std::min(tMin, readout[0] - 0.005);
        tMax = std::max(tMax, readout[1] + 0.005);
    }
    const int samples = 1200;
    Mat t(1, samples, CV_64F), theta, omega;
    for (int i = 0; i < samples; ++i)
        t.at<double>(i) = tMin + (tMax - tMin) * i / (samples - 1);
    plant->response(schedule, t, theta);
    plant->velocity(schedule, t, omega);
    std::vector<double> ms(samples), deg(samples), degPerSec(samples);
    for (int i = 0; i < samples; ++i)
    {
        ms[i] = 1e3 * t.at<double>(i);
        deg[i] = theta.at<double>(i) / kDeg;
        degPerSec[i] = omega.at<double>(i) / kDeg;
    }
    dynblur_plot::Figure figure(1100, "10 deg saccade and the frames' row exposure intervals", 240);
    const double target = plant->restingAngle(schedule.finalLevel()) / kDeg;
    figure.addPanel("angle", "theta (deg)").yBand(target * 0.98, target * 1.02, "+-2% band").line(ms, deg, "theta(t)");
    figure.addPanel("velocity", "dtheta/dt (deg/s)").hLine(0.0).line(ms, degPerSec, "dtheta/dt");
    dynblur_plot::Panel& rows = figure.addPanel("row exposure intervals (every 60th row)", "row");
    for (size_t k = 0; k < cases.size(); ++k)
    {
        const RollingShutter& shutter = cases[k].shutter;
        const cv::Scalar color = dynblur_plot::paletteColor(static_cast<int>(k) + 2);
        for (int r = 0; r < shutter.rows; r += 60)
        {
            const Vec2d interval = shutter.rowInterval(r);
            rows.hBar(1e3 * interval[0], 1e3 * interval[1], -r + 0.15 * 60 * static_cast<double>(k),
                      r == 0 ? cases[k].name : "", color, 3);
        }
    }
    rows.yLimits(-maxShutterRows(cases), 60);
    figure.xLabel("time (ms)");
    if (!figure.save(path))
        CV_Error(Error::StsError, "cannot write " + path);
}

/* The rates of a hand-held shake about each camera axis, rad/s: two sinusoids per axis between 2.3
   and 16.5 Hz whose rates peak together at `peakDegPerSec`. */
Vec3d shakeRate(double t, double peakDegPerSec)
{
    static const double hz[3][2] = {{3.1, 11.0}, {2.3, 7.7}, {4.4, 16.5}}, phase[3][2] = {{0.4, 2.0}, {1.3, 0.2}, {2.9, 1.1}};
    Vec3d w;
    for (int i = 0; i < 3; ++i)
        w[i] = 0.5 * peakDegPerSec * kDeg *
               (std::cos(2 * CV_PI * hz[i][0] * t + phase[i][0]) + std::cos(2 * CV_PI * hz[i][1] * t + phase[i][1]));
    return w;
}

/* Samples of shakeRate every `step` seconds over [0, duration], plus Gaussian noise of `noiseDegPerSec`
   per axis: what a gyroscope rigidly fixed to the camera logs. */
void sampleGyro(double step, double duration, double peakDegPerSec, double noiseDegPerSec, std::vector<double>& times,
                Mat& rates)
{
    const int n = static_cast<int>(std::round(duration / step)) + 1;
    times.resize(size_t(n));
    rates.create(n, 3, CV_64F);
    RNG rng(0x6e70);
    for (int k = 0; k < n; ++k)
    {
        times[size_t(k)] = k * step;
        const Vec3d w = shakeRate(times[size_t(k)], peakDegPerSec);
        for (int i = 0; i < 3; ++i)
            rates.at<double>(k, i) = w[i] + rng.gaussian(noiseDegPerSec * kDeg);
    }
}

/* A hand-held frame: the camera shaken about all three axes (60 deg/s, 20 ms exposure, the rolling
   readout of the other frames), rendered from the true motion and restored from a 200 Hz gyroscope
   log of it (noise 0.1 deg/s), with no plant: the seed's single PSF against the spatially variant
   restoration. Appends a panel row and a table row; writes handheld_trajectory.png. */
void runHandHeld(const Ptr<CameraModel>& camera, const Mat& scene, double lineDelay, const RLParams& params,
                 const std::string& outDir, std::vector<Mat>& panelRows, std::vector<std::string>& tableRows)
{
    const Size frameSize = camera->getImageSize();
    const int margin = 96;  // the shake turns the view by up to ~1.9 deg: 41 px at f = 1230 px
    Mat wide, wideLinear;
    resize(scene, wide, Size(frameSize.width + 2 * margin, frameSize.height + 2 * margin), 0, 0, INTER_AREA);
    srgbToLinear(wide, wideLinear);
    const Mat truth = wide(Rect(margin, margin, frameSize.width, frameSize.height));
    const RollingShutter shutter(0.30, 0.020, lineDelay, frameSize.height);
    std::printf("[demo] hand-held frame (3-axis shake, 20 ms exposure): rendering from the true motion, restoring from "
                "a 200 Hz gyro log...\n");
    std::fflush(stdout);

    std::vector<double> trueTimes, gyroTimes;
    Mat trueRates, gyroRates;
    sampleGyro(0.0005, 0.6, 60, 0.0, trueTimes, trueRates);
    sampleGyro(0.005, 0.6, 60, 0.1, gyroTimes, gyroRates);
    const Ptr<CameraMotion> truth3d = CameraMotion::fromAngularVelocity(trueTimes, trueRates);
    const Ptr<CameraMotion> gyro = CameraMotion::fromAngularVelocity(gyroTimes, gyroRates);

    Mat blurred, noisy, frame;
    renderBlurred(wideLinear, truth3d, camera, shutter, blurred);
    addSensorNoise(blurred, noisy, 4000.0, 8.0, 5.0, 77);
    linearToSrgb(noisy, frame, CV_8U);

    const BothRestorations r = restoreBothWays(frame, gyro, camera, shutter, params);
    tableRows.push_back(tableRow("hand-held, gyro log", r.window, truth, frame, r.uniform, r.variant,
                                 judgedPixels(r.valid), r.uniformMs, r.variantMs));
    const int cellWidth = 400;
    std::vector<Mat> cells{labelled(frame, "hand-held (3-axis shake): blurred", cellWidth),
                           labelled(shadeUnobserved(r.uniform, r.valid), "single PSF (seed)", cellWidth),
                           labelled(shadeUnobserved(r.variant, r.valid), "restored from the gyro log", cellWidth),
                           labelled(truth, "truth (view at mid-exposure)", cellWidth)};
    Mat row;
    hconcat(cells, row);
    panelRows.push_back(row);

    // The motion: the orientation's rotation vector (relative to the frame's reference) and the rates.
    const Matx33d reference = gyro->referenceOrientation(std::numeric_limits<double>::quiet_NaN(), shutter);
    std::vector<double> ms, angle[3], rate[3];
    for (double t = 0.25; t <= 0.40; t += 0.0005)
    {
        Vec3d r;
        Rodrigues(Mat(gyro->relativeRotation(t, reference)), r);
        const Vec3d w = gyro->angularVelocity(t);
        ms.push_back(1e3 * t);
        for (int i = 0; i < 3; ++i)
        {
            angle[i].push_back(r[i] / kDeg);
            rate[i].push_back(w[i] / kDeg);
        }
    }
    const Vec2d readout = shutter.readoutInterval();
    dynblur_plot::Figure figure(1100, "hand-held shake from the 200 Hz gyro log; the frame's readout shaded", 240);
    const char* axes[3] = {"x (tilt)", "y (pan)", "z (roll)"};
    dynblur_plot::Panel& angles = figure.addPanel("orientation relative to the reference view", "angle (deg)");
    dynblur_plot::Panel& rates = figure.addPanel("body rates", "rate (deg/s)");
    angles.xSpan(1e3 * readout[0], 1e3 * readout[1], "readout");
    rates.xSpan(1e3 * readout[0], 1e3 * readout[1], "readout");
    for (int i = 0; i < 3; ++i)
    {
        angles.line(ms, angle[i], axes[i]);
        rates.line(ms, rate[i], axes[i]);
    }
    figure.xLabel("time (ms)");
    if (!figure.save(outDir + "/handheld_trajectory.png"))
        CV_Error(Error::StsError, "cannot write " + outDir + "/handheld_trajectory.png");
}

/* The same move on hardware that is not the model: the camera's clock 1.2 ms late, the line delay
   7 % short, the plant 3.5 % stiffer and 15 % more damped. The deblurrer is told the nominal model;
   refined against the still frame taken after the move, it finds the truth back. Prints the
   restorations' PSNR (nominal, refined, told the truth) and the recovered parameters, and writes
   drift_panel.png and drift_objective.png (the refinement's objective over the offset and ωn). */
void runDriftedHardware(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera, const SwitchSchedule& schedule,
                        const Mat& sceneLinear, const Mat& truth, double exposure, double lineDelay,
                        const RLParams& params, int model, const std::string& outDir)
{
    MotionCorrection drift;
    drift.timeOffset = 1.2e-3;
    drift.lineDelayScale = 0.93;
    drift.naturalFreqScale = 1.035;
    drift.dampingScale = 1.15;
    RollingShutter told(0, exposure, lineDelay, camera->getImageSize().height);
    if (lineDelay <= 0 || !frameStartInWindow(plant, schedule, told, EXPOSURE_III, told.frameStart))
    {
        std::printf("[demo] drifted hardware: no rolling window III frame for this shutter; skipped\n");
        return;
    }
    std::printf("\n[demo] drifted hardware: rendering a window III frame with the clock %+.1f ms off, line delay "
                "x%.3f, wn x%.3f, zeta x%.3f; restoring it told the nominal model, refined, and told the truth...\n",
                drift.timeOffset * 1e3, drift.lineDelayScale, drift.naturalFreqScale, drift.dampingScale);
    std::fflush(stdout);
    const Ptr<Plant> truePlant = drift.correctPlant(plant);
    const RollingShutter happened = drift.correctShutter(told);
    Mat blurredLinear, noisy, frame, still;
    renderBlurred(sceneLinear, truePlant, schedule, camera, happened, blurredLinear);
    addSensorNoise(blurredLinear, noisy, 4000.0, 8.0, 5.0, 2001);
    linearToSrgb(noisy, frame, CV_8U);
    // The still frame after the move: it saw what the moving rows of a window III frame see.
    renderBlurred(sceneLinear, truePlant, schedule, camera, RollingShutter(1.0, exposure, lineDelay, told.rows),
                  blurredLinear);
    addSensorNoise(blurredLinear, noisy, 4000.0, 8.0, 5.0, 2002);
    linearToSrgb(noisy, still, CV_8U);
    const double stillAngle = plant->restingAngle(schedule.finalLevel());

    const auto restore = [&](const Ptr<Plant>& told_plant, const RollingShutter& shutter, bool refine, Mat& out,
                             Mat& valid, MotionCorrection* found) {
        Ptr<DynamicDeblurrer> d = DynamicDeblurrer::create(told_plant, camera);
        d->setRLParams(params);
        d->setPsfModel(model);
        if (refine)
            d->setReferenceFrame(still, stillAngle);
        TickMeter timer;
        timer.start();
        d->deblur(frame, schedule, shutter, out, std::numeric_limits<double>::quiet_NaN(), valid);
        timer.stop();
        if (found)
            *found = d->getLastCorrection();
        return timer.getTimeMilli();
    };
    Mat nominal, refined, knowing, valid, unused;
    MotionCorrection found;
    restore(plant, told, false, nominal, unused, nullptr);
    const double refineMs = restore(plant, told, true, refined, unused, &found);
    restore(truePlant, happened, false, knowing, valid, nullptr);
    const Mat judged = judgedPixels(valid);
    std::printf("%-22s | %-17s | %-17s | %-17s | %-17s\n", "drifted hardware", "blurred PSNR/SSIM",
                "nominal PSNR/SSIM", "refined PSNR/SSIM", "truth PSNR/SSIM");
    std::printf("%-22s | %7.2f dB %6.3f | %7.2f dB %6.3f | %7.2f dB %6.3f | %7.2f dB %6.3f\n", "rolling, window III",
                maskedPsnr(truth, frame, judged, 255), maskedSsim(truth, frame, judged),
                maskedPsnr(truth, nominal, judged, 255), maskedSsim(truth, nominal, judged),
                maskedPsnr(truth, refined, judged, 255), maskedSsim(truth, refined, judged),
                maskedPsnr(truth, knowing, judged, 255), maskedSsim(truth, knowing, judged));
    std::printf("recovered: clock %+.3f ms (true %+.3f), line delay x%.4f (%.4f), wn x%.4f (%.4f), zeta x%.3f "
                "(%.3f); consistency %.2f; refinement and restoration %.0f ms\n",
                found.timeOffset * 1e3, drift.timeOffset * 1e3, found.lineDelayScale, drift.lineDelayScale,
                found.naturalFreqScale, drift.naturalFreqScale, found.dampingScale, drift.dampingScale,
                found.consistency, refineMs);

    const int cellWidth = 400;
    const auto db = [&](const Mat& image) { return format(", %.2f dB", maskedPsnr(truth, image, judged, 255)); };
    std::vector<Mat> cells{labelled(frame, "drifted hardware: blurred" + db(frame), cellWidth),
                           labelled(nominal, "told the nominal model" + db(nominal), cellWidth),
                           labelled(refined, "refined against the still" + db(refined), cellWidth),
                           labelled(knowing, "told the truth" + db(knowing), cellWidth)};
    Mat row;
    hconcat(cells, row);
    imwrite(outDir + "/drift_panel.png", row);

    // The objective the refinement minimised, over the offset and over wn, the rest at the truth.
    std::vector<MotionCorrection> overOffset, overFrequency;
    std::vector<double> offsetsMs, frequencyScales;
    for (int k = -30; k <= 30; k++)
    {
        MotionCorrection c = drift;
        c.timeOffset = drift.timeOffset + k * 1e-4;
        overOffset.push_back(c);
        offsetsMs.push_back(c.timeOffset * 1e3);
        c = drift;
        c.naturalFreqScale = drift.naturalFreqScale + k * 0.002;
        overFrequency.push_back(c);
        frequencyScales.push_back(c.naturalFreqScale);
    }
    const std::vector<double> byOffset =
        motionConsistency(plant, camera, still, frame, schedule, told, overOffset, stillAngle);
    const std::vector<double> byFrequency =
        motionConsistency(plant, camera, still, frame, schedule, told, overFrequency, stillAngle);
    dynblur_plot::Figure offsetFigure(900, "Refinement objective (consistency, noise units), the rest at the truth");
    offsetFigure.addPanel("over the clock offset", "consistency")
        .line(offsetsMs, byOffset, "consistency")
        .xSpan(drift.timeOffset * 1e3 - 0.01, drift.timeOffset * 1e3 + 0.01, "truth")
        .xSpan(found.timeOffset * 1e3 - 0.01, found.timeOffset * 1e3 + 0.01, "found", Scalar(80, 80, 220));
    offsetFigure.xLabel("clock offset (ms)");
    dynblur_plot::Figure frequencyFigure(900, "");
    frequencyFigure.addPanel("over the natural frequency", "consistency")
        .line(frequencyScales, byFrequency, "consistency")
        .xSpan(drift.naturalFreqScale - 0.0005, drift.naturalFreqScale + 0.0005, "truth")
        .xSpan(found.naturalFreqScale - 0.0005, found.naturalFreqScale + 0.0005, "found", Scalar(80, 80, 220));
    frequencyFigure.xLabel("natural frequency scale");
    Mat objective;
    vconcat(offsetFigure.render(), frequencyFigure.render(), objective);
    imwrite(outDir + "/drift_objective.png", objective);
}

int runSynthetic(const CliArgs& args)
{
    const std::string outDir = args.str("out");
    utils::fs::createDirectories(outDir);
    const int iterations = args.integer("iterations");
    const int model = psfModelFromName(args.str("model"));
    const double exposure = args.num("exposure"), lineDelay = args.num("line-delay");

    PlantFile plantFile;
    plantFile.plant = Plant::create(14.4, 0.12, kDeg);
    if (args.has("plant"))
        plantFile = loadPlantFile(args.str("plant"));
    const Ptr<Plant> plant = plantFile.plant;
    const Ptr<CameraModel> camera = args.has("camera") ? CameraModel::load(args.str("camera")) : defaultCamera();
    const Size frameSize = camera->getImageSize();

    const std::string modeName = args.str("mode");
    if (modeName != "robust" && modeName != "fast")
        CV_Error(Error::StsBadArg, "--mode must be robust or fast (got '" + modeName + "')");
    std::printf("[demo] planning a 10 deg saccade, %s mode (plant %.1f Hz, zeta %.2f, %.2f deg/level, max level %d)\n",
                modeName.c_str(), plant->getNaturalFreqHz(), plant->getDampingRatio(), plant->getGain() / kDeg,
                plantFile.maxLevel);
    const int mode = modeName == "fast" ? PLAN_FAST : PLAN_ROBUST;
    const SwitchSchedule schedule = SwitchPlanner::create(plant, plantFile.maxLevel, mode)->plan(0.0, 10 * kDeg, 0.0);
    std::printf("[demo]   %zu switches, settles in %.1f ms, peak %.0f deg/s, residual vibration %.3f%%\n",
                schedule.times.size(), 1e3 * schedule.settleTime, schedule.peakVelocity / kDeg,
                100 * schedule.residualVibration);
    schedule.save(outDir + "/schedule.yml");

    // A view wider than the frame, so rows exposed before the move see real scene content.
    const double moveDisplacementPx = camera->getFy() * std::tan(10 * kDeg);
    const int marginY = static_cast<int>(std::ceil(moveDisplacementPx)) + 40, marginX = 40;
    const Size sceneSize(frameSize.width + 2 * marginX, frameSize.height + 2 * marginY);
    Mat scene;
    if (args.has("image"))
    {
        const std::string imagePath = args.str("image");
        Mat image = imread(imagePath, IMREAD_COLOR);
        if (image.empty())
            CV_Error(Error::StsError, "cannot read --image '" + imagePath + "'");
        resize(image, scene, sceneSize, 0, 0, INTER_CUBIC);
    }
    else
    {
        scene = makeScene(sceneSize);
    }
    Mat sceneLinear;
    srgbToLinear(scene, sceneLinear);
    const Mat truth = scene(Rect(marginX, marginY, frameSize.width, frameSize.height)).clone();
    imwrite(outDir + "/truth.png", truth);

    std::vector<Case> cases;
    for (int window : {EXPOSURE_I, EXPOSURE_II, EXPOSURE_III})
    {
        Case c{std::string("rolling, window ") + exposureWindowName(window), RollingShutter(0, exposure, lineDelay, frameSize.height),
               window};
        if (frameStartInWindow(plant, schedule, c.shutter, window, c.shutter.frameStart))
            cases.push_back(c);
        else
            std::printf("[demo] no frame start gives window %s for this move and shutter; skipped\n", exposureWindowName(window));
    }
    Case global{"global, window III", RollingShutter(0, exposure, 0.0, frameSize.height), EXPOSURE_III};
    if (frameStartInWindow(plant, schedule, global.shutter, EXPOSURE_III, global.shutter.frameStart))
        cases.push_back(global);

    Ptr<DynamicDeblurrer> variant = DynamicDeblurrer::create(plant, camera);
    Ptr<DynamicDeblurrer> uniform = DynamicDeblurrer::create(plant, camera);
    RLParams params = variant->getRLParams();
    params.iterations = iterations;
    variant->setRLParams(params);
    uniform->setRLParams(params);
    variant->setPsfModel(model);
    uniform->setPsfModel(PSF_UNIFORM);

    std::vector<Mat> panelRows;
    std::vector<std::string> tableRows;
    for (size_t i = 0; i < cases.size(); ++i)
    {
        const Case& c = cases[i];
        std::printf("[demo] frame %zu/%zu (%s, starts %.1f ms): rendering, restoring...\n", i + 1, cases.size(),
                    c.name.c_str(), 1e3 * c.shutter.frameStart);
        std::fflush(stdout);
        Mat blurredLinear, noisy, frame;
        renderBlurred(sceneLinear, plant, schedule, camera, c.shutter, blurredLinear);
        addSensorNoise(blurredLinear, noisy, 4000.0, 8.0, 5.0, 1000 + i);
        linearToSrgb(noisy, frame, CV_8U);

        Mat restoredUniform, restoredVariant, valid;
        TickMeter uniformTimer, variantTimer;
        uniformTimer.start();
        uniform->deblur(frame, schedule, c.shutter, restoredUniform);
        uniformTimer.stop();
        variantTimer.start();
        variant->deblur(frame, schedule, c.shutter, restoredVariant, std::numeric_limits<double>::quiet_NaN(), valid);
        variantTimer.stop();

        // All three are judged on the same pixels: those the frame observed, away from the frame edge.
        tableRows.push_back(tableRow(c.name, variant->getLastExposureWindow(), truth, frame, restoredUniform,
                                     restoredVariant, judgedPixels(valid), uniformTimer.getTimeMilli(),
                                     variantTimer.getTimeMilli()));

        const std::string stem = outDir + format("/frame%zu", i + 1);
        imwrite(stem + "_blurred.png", frame);
        imwrite(stem + "_uniform.png", restoredUniform);
        imwrite(stem + "_variant.png", restoredVariant);
        const int cellWidth = 400;
        std::vector<Mat> cells{labelled(frame, c.name + ": blurred", cellWidth),
                               labelled(shadeUnobserved(restoredUniform, valid), "uniform PSF (seed)", cellWidth),
                               labelled(shadeUnobserved(restoredVariant, valid),
                                        std::string("spatially variant (") + args.str("model") + ")", cellWidth),
                               labelled(truth, "truth (view at theta_ref)", cellWidth)};
        Mat row;
        hconcat(cells, row);
        panelRows.push_back(row);
        if (c.window == EXPOSURE_III && c.shutter.lineDelay > 0)
            imwrite(outDir + "/psf_bank.png", psfMontage(variant->getLastPsfBank(), 6, 8));
    }
    runHandHeld(camera, scene, lineDelay, params, outDir, panelRows, tableRows);
    runPanTilt(camera, scene, exposure, lineDelay, params, panelRows, tableRows);
    if (!panelRows.empty())
    {
        Mat panel;
        vconcat(panelRows, panel);
        imwrite(outDir + "/panel.png", panel);
    }
    std::printf("\nPSNR and SSIM against the truth over the pixels the frame observed; restoration times:\n");
    std::printf("%-22s %6s | %-17s | %-17s | %-17s | %9s %9s\n", "frame", "window", "blurred PSNR/SSIM",
                "uniform PSNR/SSIM", "variant PSNR/SSIM", "uniform", "variant");
    for (const std::string& row : tableRows)
        std::printf("%s\n", row.c_str());
    writeTrajectoryPlot(outDir + "/trajectory.png", plant, schedule, cases);
    runDriftedHardware(plant, camera, schedule, sceneLinear, truth, exposure, lineDelay, params, model, outDir);
    std::printf("\n[demo] wrote %s/panel.png (blurred | uniform | variant | truth; the last rows hand-held and pan-tilt), psf_bank.png, "
                "trajectory.png, handheld_trajectory.png, drift_panel.png (blurred | nominal | refined | truth-told), "
                "drift_objective.png\n",
                outDir.c_str());
    return 0;
}

int runRealFrame(const CliArgs& args)
{
    for (const char* required : {"schedule", "frame-start"})
        if (!args.has(required))
            throw std::runtime_error(std::string("--frame needs --") + required);
    const std::string framePath = args.str("frame");
    Mat frame = imread(framePath, IMREAD_UNCHANGED);
    if (frame.empty())
        CV_Error(Error::StsError, "cannot read --frame '" + framePath + "'");
    const SwitchSchedule schedule = SwitchSchedule::load(args.str("schedule"));
    // A default is said aloud: a frame restored with another camera's or plant's model comes out wrong.
    if (!args.has("camera"))
        std::fprintf(stderr, "note: no --camera: using the nominal C270 at 1280x960 (fx 1230 px)\n");
    if (!args.has("plant"))
        std::fprintf(stderr, "note: no --plant: using the seed's plant (14.4 Hz, zeta 0.12, 1 deg per level)\n");
    const Ptr<CameraModel> camera = args.has("camera") ? CameraModel::load(args.str("camera")) : defaultCamera();
    const Ptr<Plant> plant = args.has("plant") ? loadPlantFile(args.str("plant")).plant : Plant::create(14.4, 0.12, kDeg);
    const RollingShutter shutter(args.num("frame-start", NAN), args.num("exposure"),
                                 args.num("line-delay"), frame.rows);
    const double thetaRef = args.num("theta-ref", NAN);  // NaN: the schedule's final angle

    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(plant, camera);
    if (args.has("timing"))  // a single frame has no still to refine against: the calibration as told
        deblurrer->setCalibration(TimingCalibration::load(args.str("timing")).correction);
    deblurrer->setPsfModel(psfModelFromName(args.str("model")));
    RLParams params = deblurrer->getRLParams();
    params.iterations = args.integer("iterations");
    deblurrer->setRLParams(params);
    std::printf("[demo] restoring %s (%dx%d, %d channels)...\n", framePath.c_str(), frame.cols, frame.rows, frame.channels());
    Mat restored, valid;
    TickMeter timer;
    timer.start();
    deblurrer->deblur(frame, schedule, shutter, restored, thetaRef, valid);
    timer.stop();
    const std::string outDir = args.str("out");
    utils::fs::createDirectories(outDir);
    imwrite(outDir + "/restored.png", restored);
    imwrite(outDir + "/valid_mask.png", valid);
    Mat panel;
    hconcat(std::vector<Mat>{labelled(frame, "frame", 640), labelled(restored, "restored", 640)}, panel);
    imwrite(outDir + "/panel.png", panel);
    std::printf("[demo] exposure window %s, restored in %.0f ms; wrote %s/restored.png, valid_mask.png, panel.png\n",
                exposureWindowName(deblurrer->getLastExposureWindow()), timer.getTimeMilli(), outDir.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv)
{
    try
    {
        const CliOptions options = demoOptions();
        const CliArgs args = options.parse(argc, argv);
        if (options.printHelp(args))
            return 0;
        if (!args.has("frame"))
            for (const char* realOnly : {"schedule", "frame-start", "timing", "theta-ref"})
                if (args.has(realOnly))
                    throw std::runtime_error(std::string("--") + realOnly + " belongs to the real-frame mode: give --frame");
        return args.has("frame") ? runRealFrame(args) : runSynthetic(args);
    }
    catch (const std::runtime_error& e)
    {
        std::fprintf(stderr, "dynblur_demo: error: %s\n(see dynblur_demo --help)\n", e.what());
        return 2;
    }
    catch (const cv::Exception& e)
    {
        std::fprintf(stderr, "dynblur_demo: error: %s\n", e.err.c_str());
        return 1;
    }
}
