// SPDX-License-Identifier: Apache-2.0
// dynblur_restore_video: restores a recording (frames, frame log, command log; docs/recording-format.md)
// frame by frame, streaming: each frame taken during a move is refined against the stills on both
// sides of its move (the deblurrer chooses the one that saw its moving rows) and restored; still
// frames pass through. A frame that ends its move at rest waits for the still after the move.
// Writes the restored video, a CSV of each frame's window, correction and consistency, and a contact
// sheet of the most blurred frames. With --truth (a rendered recording's sharp scene) each moving
// frame's gain over the recording is measured.
//
//     dynblur_restore_video --video rec/frame_%04d.png --frames rec/frames.csv --commands rec/commands.csv
//                           --camera rec/camera.xml --plant rec/plant.yml --timing rec/timing.yml
#include "atomic_file.hpp"  // samples/support
#include "cli_args.hpp"
#include "frame_timing.hpp"
#include "gyro_recording.hpp"
#include "image_metrics.hpp"
#include "plant_file.hpp"
#include "recording.hpp"
#include "restoration_options.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

using namespace cv;
using namespace cv::dynblur;
using namespace dynblur_samples;
using namespace dynblur_test;

static CliOptions restoreVideoOptions()
{
    CliOptions options("dynblur_restore_video");
    options.synopsis("--video V --frames FRAMES.csv --commands COMMANDS.csv [options]")
        .synopsis("--recording DIR [options]")
        .synopsis("--gyro LOG --video V --frames FRAMES.csv [options]")
        .description("Restores the frames of a recording that a move blurred, with the blur predicted from the plant "
                     "and the commands, corrected per frame against the still frame before the move (a frame that "
                     "starts at rest) or after it (one that ends at rest), in units of the noise measured from the "
                     "last two consecutive still frames. A frame no correction explains is written unchanged.")
        .description("Each frame is restored to the view at the angle of its middle row's mid-exposure. A frame that "
                     "needs the still after its move is held until that still arrives (the rest of the move and one "
                     "frame; the progress line shows how many frames wait).")
        .group(recordingOptions())
        .option("timing", "FILE.yml", "",
                "the recording's calibration (dynblur_calibrate_timing); each frame then refines its clock's jitter "
                "only, unless --refine says otherwise")
        .option("refine", "LIST", "",
                "offset, line-delay, plant, all or none, comma-separated (default: offset with --timing, all without)")
        .group(restorationOptions())
        .option("no-still-after", "WHAT", "as-told",
                "a frame that ends its move at rest (window III) but has no still after it (the recording ends, or "
                "another move starts) cannot be refined: as-told restores it with the model as told (and --timing), "
                "unchanged writes it as recorded; the tool lists those frames either way")
        .option("unobserved", "WHAT", "recorded",
                "where a frame never saw the restored view (content beyond its edges): recorded keeps the frame's "
                "pixels, marked paints them black, nearest repeats the nearest observed pixel (streaks across a wide "
                "band)")
        .option("truth", "DIR", "",
                "a rendered recording's truth (scene.png, truth.yml: dynblur_calibrate_timing --simulate writes "
                "them): each moving frame's PSNR against the view it is restored to, as recorded and restored, its "
                "true window, and a summary")
        .option("out", "FILE", "restored.avi",
                "restored video (MJPG at the frame log's rate); beside it OUT_frames.png, the most blurred moving "
                "frames as recorded and restored")
        .option("csv", "FILE", "",
                "per-frame log (default: OUT's name with .csv); window is the frame's exposure window under the "
                "motion it was restored with, window_as_told under the model as given, blur_px the largest image "
                "motion during one row's exposure")
        .group(gyroLogOptions(
            "Gyro mode (--gyro):",
            "A recording whose motion is a gyro log: every frame is restored with the log's motion, on the clock, line "
            "delay and bias of --timing (dynblur_calibrate_timing --gyro; without it, as the logs tell), to the view "
            "at its middle row's mid-exposure. --camera, --timing, --exposure, --line-delay, --preset, --model, --out "
            "and --csv as above; frames the log shows still pass through."))
        .footer("Output is written to temporary files and renamed into place only when the whole recording is done.")
        .footer("Exit status: 0 restored, 1 bad or unusable recording (the message says why), 2 bad usage.");
    return options;
}

static int usageError(const std::string& message)
{
    std::cerr << "error: " << message << "\n(see dynblur_restore_video --help)\n";
    return 2;
}

const size_t kSheetRows = 6;

//! --preset and --model, read before any file is opened (a usage error comes first).
struct RestorationSettings
{
    int preset, psfModel;

    explicit RestorationSettings(const CliArgs& args)
        : preset(deblurPresetFromName(args.str("preset"))),
          psfModel(psfModelFromName(args.str("model")))
    {
    }
    //! The preset, then the model over the preset's PSF_AUTO.
    void apply(DynamicDeblurrer& deblurrer) const
    {
        deblurrer.setPreset(preset);
        deblurrer.setPsfModel(psfModel);
    }
};

/* --gyro: each frame restored with the gyro log's motion as --timing corrects it; the video and a CSV
   of each frame's window, written whole. */
static int restoreGyroRecording(const CliArgs& args, const RestorationSettings& settings)
{
    GyroRecording recording;
    GyroRecording::open(args, std::string(DYNBLUR_CALIB_DIR) + "/c270_nominal.xml", recording);
    if (args.has("refine") && args.str("refine") != "none")
        return usageError("--refine: a gyro recording is restored with --timing's calibration (per-frame "
                          "refinement needs stills: DynamicDeblurrer::setReferenceFrame(still, stillShutter))");
    const std::string videoOut = args.str("out"), csvOut = args.str("csv", pathStem(videoOut) + ".csv");
    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(recording.camera);
    settings.apply(*deblurrer);
    MotionCorrection calibration;
    if (!recording.timingPath.empty())
        calibration = TimingCalibration::load(recording.timingPath).correction, deblurrer->setCalibration(calibration);
    const std::vector<FrameRecord>& log = recording.log;
    const double fps = log.size() > 1 ? (log.size() - 1) / (log.back().frameStart - log.front().frameStart) : 30.0;
    const std::string videoTemporary = temporaryPathFor(videoOut), csvTemporary = temporaryPathFor(csvOut);
    try
    {
        VideoWriter writer(videoTemporary, VideoWriter::fourcc('M', 'J', 'P', 'G'), fps,
                           recording.camera->getImageSize(), true);
        if (!writer.isOpened())
            CV_Error(Error::StsError, "--out: cannot write a video to '" + videoOut + "'");
        std::ofstream csv(csvTemporary);
        csv << "frame,window,restored,time_offset,line_delay_scale,bias_x,bias_y,bias_z\n";
        const Vec2d span = recording.motion->getTimeSpan();
        Mat restored;
        for (const FrameRecord& f : log)
        {
            const RollingShutter shutter = GyroRecording::shutterOf(f, recording.camera->getImageSize().height);
            const Vec2d readout = calibration.correctShutter(shutter).readoutInterval();
            if (!(readout[0] >= span[0] && readout[1] <= span[1]))
                CV_Error(Error::StsOutOfRange,
                         format("--timing: with its clock offset %+.6f s, frame %d is read outside the gyro log's "
                                "time span [%.6f, %.6f] s",
                                calibration.timeOffset, f.frame, span[0], span[1]));
            const Mat image = recording.read(f);
            deblurrer->deblur(image, recording.motion, shutter, restored);
            const MotionCorrection c = deblurrer->getLastCorrection();
            Mat color = restored;
            if (restored.channels() == 1)
                cvtColor(restored, color, COLOR_GRAY2BGR);
            writer.write(color);
            csv << format("%d,%s,%d,%.9f,%.6f,%.6g,%.6g,%.6g\n", f.frame,
                          exposureWindowName(deblurrer->getLastExposureWindow()),
                          int(deblurrer->getLastExposureWindow() != EXPOSURE_IV && c.applied), c.timeOffset,
                          c.lineDelayScale, c.gyroBias[0], c.gyroBias[1], c.gyroBias[2]);
            std::printf("\rframe %d of %zu", f.frame + 1, log.size());
            std::fflush(stdout);
        }
        writer.release();
        csv.close();
        if (!csv)
            CV_Error(Error::StsError, "--csv: cannot write '" + csvOut + "'");
        renameIntoPlace(videoTemporary, videoOut);
        renameIntoPlace(csvTemporary, csvOut);
    }
    catch (...)
    {
        std::remove(videoTemporary.c_str());
        std::remove(csvTemporary.c_str());
        throw;
    }
    std::printf("\nwrote %s, %s\n", videoOut.c_str(), csvOut.c_str());
    return 0;
}

/* The largest image motion during one row's exposure, pixels (the angle's sweep over the row's
   interval times the larger focal length: a bound for a pan or a tilt), over nine rows: what ranks
   frames by blur. */
static double blurPixels(const Ptr<Plant>& plant, const SwitchSchedule& schedule, const RollingShutter& shutter,
                         double focalPx)
{
    double largest = 0;
    for (int k = 0; k <= 8; k++)
    {
        const Vec2d interval = shutter.rowInterval((shutter.rows - 1) * k / 8);
        Mat t(1, 33, CV_64F), theta;
        for (int i = 0; i < t.cols; i++)
            t.at<double>(i) = interval[0] + (interval[1] - interval[0]) * i / (t.cols - 1);
        plant->response(schedule, t, theta);
        double low, high;
        minMaxLoc(theta, &low, &high);
        largest = std::max(largest, (high - low) * focalPx);
    }
    return largest;
}

/* A rendered recording's truth (dynblur_calibrate_timing --simulate writes it): the sharp scene, the
   view at sceneAngle, and the correction from the nominal model to the motion that rendered the frames. */
struct RecordingTruth
{
    Mat scene;  //!< 8-bit sRGB, wider than a frame by the same margin on each side
    double sceneAngle = 0;  //!< radians
    MotionCorrection motion;

    static RecordingTruth load(const std::string& dir)
    {
        RecordingTruth truth;
        truth.scene = imread(dir + "/scene.png", IMREAD_COLOR);
        if (truth.scene.empty())
            CV_Error(Error::StsError, "--truth: cannot read '" + dir + "/scene.png'");
        FileStorage fs(dir + "/truth.yml", FileStorage::READ);
        if (!fs.isOpened() || fs["sceneAngle"].empty())
            CV_Error(Error::StsError, "--truth: cannot read sceneAngle from '" + dir + "/truth.yml'");
        fs["sceneAngle"] >> truth.sceneAngle;
        fs["timeOffset"] >> truth.motion.timeOffset;
        fs["lineDelayScale"] >> truth.motion.lineDelayScale;
        fs["naturalFreqScale"] >> truth.motion.naturalFreqScale;
        fs["dampingScale"] >> truth.motion.dampingScale;
        return truth;
    }

    //! The sharp view at `angle` (radians): the scene turned by angle - sceneAngle, as the renderer turns it.
    Mat viewAt(double angle, const Ptr<Plant>& plant, const Ptr<CameraModel>& camera) const
    {
        // A plant resting at 0 sees the scene given as the view at sceneAngle - angle.
        Mat view;
        renderBlurred(scene, plant, SwitchSchedule({0.0}, {0}, 0), camera,
                      RollingShutter(0.0, 1e-3, 0.0, camera->getImageSize().height), view, sceneAngle - angle);
        return view;
    }
};

//! A moving frame's row of the contact sheet, and what ranks it.
struct SheetRow
{
    int frame = 0;
    double blurPx = 0;
    Mat image;
};

/* One row of the contact sheet: the frame and its restoration, 480 px wide each, labelled with the
   frame's window, blur, correction, and whether it was restored or refused (and why). */
static Mat sheetRow(const Mat& blurred, const Mat& restored, int frame, const std::string& window, double blurPx,
                    const MotionCorrection& c, const std::string& gain)
{
    const auto cell = [](const Mat& image, const std::string& line1, const std::string& line2) {
        Mat small, color;
        resize(image, small, Size(480, image.rows * 480 / image.cols), 0, 0, INTER_AREA);
        color = small;
        if (small.channels() == 1)
            cvtColor(small, color, COLOR_GRAY2BGR);
        rectangle(color, Rect(0, 0, color.cols, 38), Scalar(0, 0, 0), FILLED);
        putText(color, line1, Point(5, 15), FONT_HERSHEY_SIMPLEX, 0.45, Scalar(255, 255, 255), 1, LINE_AA);
        putText(color, line2, Point(5, 32), FONT_HERSHEY_SIMPLEX, 0.45, Scalar(255, 255, 255), 1, LINE_AA);
        return color;
    };
    const std::string correction =
        format("clock %+.2f ms, line delay x%.3f, wn x%.3f", c.timeOffset * 1e3, c.lineDelayScale, c.naturalFreqScale);
    Mat row;
    hconcat(cell(blurred, format("frame %d: as recorded", frame),
                 format("window %s, blur %.0f px", window.c_str(), blurPx)),
            cell(restored,
                 c.applied ? format("RESTORED, consistency %.2f%s", c.consistency, gain.c_str())
                           : format("REFUSED (written as recorded), consistency %.2f", c.consistency),
                 correction),
            row);
    return row;
}

int main(int argc, char** argv)
{
    std::string videoOut, csvOut, videoTemporary, csvTemporary, sheetTemporary;
    try
    {
        const CliOptions options = restoreVideoOptions();
        const CliArgs args = options.parse(argc, argv);
        if (options.printHelp(args))
            return 0;
        const RestorationSettings settings(args);
        if (args.has("gyro"))
        {
            if (args.has("truth"))
                return usageError("--truth belongs to a recording with a command log, not to --gyro");
            return restoreGyroRecording(args, settings);
        }
        if (!OpenedRecording::named(args))
            return usageError("--recording DIR, or --video, --frames and --commands, are required");
        const std::string noStillAfterMode = args.str("no-still-after");
        if (noStillAfterMode != "as-told" && noStillAfterMode != "unchanged")
            return usageError("--no-still-after must be as-told or unchanged");
        const std::string unobservedName = args.str("unobserved");
        const int unobserved = unobservedName == "recorded" ? UNOBSERVED_RECORDED
                               : unobservedName == "marked" ? UNOBSERVED_MARKED
                               : unobservedName == "nearest" ? UNOBSERVED_NEAREST : -1;
        if (unobserved < 0)
            return usageError("--unobserved must be recorded, marked or nearest");
        videoOut = args.str("out");
        csvOut = args.str("csv", pathStem(videoOut) + ".csv");

        OpenedRecording recording;
        OpenedRecording::open(args, std::string(DYNBLUR_CALIB_DIR) + "/c270_nominal.xml", recording);
        const std::vector<FrameRecord>& log = recording.log;
        const Ptr<Plant>& plant = recording.plant;
        const Ptr<CameraModel>& camera = recording.camera;
        const std::string& timingPath = recording.timingPath;
        int flags = 0;
        if (!parseRefinementList(args.str("refine", timingPath.empty() ? "all" : "offset"), flags))
            return usageError("--refine takes offset, line-delay, plant, all or none, comma-separated");
        const MotionCorrection calibration =
            timingPath.empty() ? MotionCorrection() : TimingCalibration::load(timingPath).correction;

        const Ptr<Plant> correctedPlant = calibration.correctPlant(plant);
        const bool hasTruth = args.has("truth");
        const RecordingTruth truth = hasTruth ? RecordingTruth::load(args.str("truth")) : RecordingTruth();
        const Ptr<Plant> truePlant = truth.motion.correctPlant(plant);
        Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(plant, camera);
        settings.apply(*deblurrer);
        deblurrer->setRefinement(flags);
        deblurrer->setUnobservedFill(unobserved);
        if (!timingPath.empty())
            deblurrer->setCalibration(calibration);

        const Size size = camera->getImageSize();
        const double fps = log.size() > 1 ? (log.size() - 1) / (log.back().frameStart - log.front().frameStart) : 30.0;
        videoTemporary = temporaryPathFor(videoOut);
        csvTemporary = temporaryPathFor(csvOut);
        VideoWriter writer(videoTemporary, VideoWriter::fourcc('M', 'J', 'P', 'G'), fps, size, true);
        if (!writer.isOpened())
            CV_Error(Error::StsError, "--out: cannot write a video to '" + videoOut + "'");
        std::ofstream csv(csvTemporary);
        if (!csv)
            CV_Error(Error::StsError, "--csv: cannot write '" + csvOut + "'");
        csv << "frame,window,restored,time_offset_s,line_delay_scale,natural_freq_scale,damping_scale,consistency,"
               "reason,window_as_told,blur_px,window_true,psnr_recorded_db,psnr_restored_db,gain_db\n";

        ReferencePairing pairing(plant, camera, recording.commands, calibration, 0.005);
        std::vector<SheetRow> sheetRows;  // the most blurred moving frames, blurred beside restored, for a look
        struct Measured { int frame; double gain; };
        std::vector<Measured> measured;  // --truth: each moving frame's gain over the recording, dB
        int movingSeen = 0, refused = 0;
        double mostBlurPx = -1;
        int mostBlurred = -1;
        Mat lastBefore, lastAfter, restored;
        std::vector<int> unrefined;  // frames that needed the still after their move and had none
        /* The last two consecutive still frames at one resting level: the noise refinement weighs its
           residuals by is measured from their difference (setNoiseFrames), compression included. */
        Mat noiseA, noiseB;
        int lastStillFrame = -2, lastStillLevel = 0;
        bool noisePending = false;
        /* The ETA counts the moving frames still to restore at the time a moving frame has taken so far
           (a still frame costs next to nothing), and the line is shown before each restoration, so a
           slow frame never leaves a stale estimate on the screen. */
        int written = 0, movingDone = 0;
        int movingLeft = int(std::count_if(log.begin(), log.end(),
                                           [&](const FrameRecord& f) { return !pairing.isStill(f, size.height); }));
        TickMeter clock;
        const auto progress = [&](const char* doing) {
            const double perMoving = movingDone ? clock.getTimeSec() / movingDone : NAN;
            std::printf("\r%d of %zu frames written%s, %d moving frame(s) left, ETA %s, %zu held for the still after "
                        "their move   ",
                        written, log.size(), doing, movingLeft,
                        std::isnan(perMoving) ? "after the first moving frame" : format("%.0f s", movingLeft * perMoving).c_str(),
                        pairing.pending());
            std::fflush(stdout);
        };
        const auto restoreAndWrite = [&](const std::vector<ReferencePairing::Item>& ready) {
            for (const ReferencePairing::Item& item : ready)
            {
                MotionCorrection c;
                Mat out = item.image;
                int window = item.window;
                double blurPx = 0, thetaRef = 0;
                if (!item.still)
                {
                    /* Each frame is restored to the view the camera had at its middle row's mid-exposure
                       (the video does not jump to where a move will end, and the frame saw most of
                       that view), on the calibrated clock and plant. */
                    const Vec2d middle = calibration.correctShutter(item.shutter).rowInterval(item.shutter.rows / 2);
                    Mat t(1, 1, CV_64F, Scalar((middle[0] + middle[1]) / 2)), theta;
                    correctedPlant->response(item.schedule, t, theta);
                    thetaRef = theta.at<double>(0);
                }
                // A frame that ends its move at rest is refined against the still after it.
                const bool noStillAfter = !item.still && item.after.empty() && item.window == EXPOSURE_III;
                if (noStillAfter)
                    unrefined.push_back(item.record.frame);
                if (noStillAfter && noStillAfterMode == "unchanged")
                {
                    c.applied = false;
                    c.reason = "no still after the move: not refined; written as recorded (--no-still-after unchanged)";
                }
                else if (!item.still)
                {
                    if (noStillAfter || (item.before.empty() && item.after.empty()))
                        deblurrer->clearReferenceFrame(), lastBefore = lastAfter = Mat();
                    else if (item.before.data != lastBefore.data || item.after.data != lastAfter.data)
                        deblurrer->setReferenceFrames(item.before, item.after, item.angleBefore, item.angleAfter);
                    if (!noStillAfter)
                        lastBefore = item.before, lastAfter = item.after;
                    if (noisePending)
                    {
                        noisePending = false;
                        try
                        {
                            deblurrer->setNoiseFrames(noiseA, noiseB);
                        }
                        catch (const cv::Exception& e)
                        {
                            std::fprintf(stderr, "\nnote: the noise stays as measured before (or Immerkaer's estimate "
                                                 "on each still): %s\n",
                                         e.err.c_str());
                        }
                    }
                    progress(": restoring");
                    clock.start();
                    deblurrer->deblur(item.image, item.schedule, item.shutter, restored, thetaRef);
                    clock.stop();
                    movingDone++;
                    movingLeft = std::max(0, movingLeft - 1);
                    c = deblurrer->getLastCorrection();
                    window = deblurrer->getLastExposureWindow();
                    if (noStillAfter)
                        c.reason = "no still after the move: not refined; restored as told (--no-still-after as-told)";
                    out = restored;
                }
                if (item.still)
                {
                    const int level = item.schedule.levelAt(item.shutter.frameStart);
                    if (item.record.frame == lastStillFrame + 1 && level == lastStillLevel)
                    {
                        noiseA = noiseB, noiseB = item.image;
                        noisePending = !noiseA.empty();
                    }
                    else
                        noiseA = Mat(), noiseB = item.image;
                    lastStillFrame = item.record.frame, lastStillLevel = level;
                }
                std::string truthColumns = ",,,";
                if (!item.still)
                {
                    blurPx = blurPixels(correctedPlant, item.schedule, calibration.correctShutter(item.shutter),
                                        std::max(camera->getFx(), camera->getFy()));
                    movingSeen++;
                    refused += !c.applied;
                    if (blurPx > mostBlurPx)
                        mostBlurPx = blurPx, mostBlurred = item.record.frame;
                }
                std::string gainText;
                if (!item.still && hasTruth)
                {
                    // The truth of a restoration is the sharp view at the angle it restores to.
                    const Mat view = truth.viewAt(thetaRef, plant, camera);
                    const double before = maskedPsnr(view, item.image, Mat(), 255.0), after = maskedPsnr(view, out, Mat(), 255.0);
                    measured.push_back({item.record.frame, after - before});
                    const int trueWindow = classifyExposure(truePlant, item.schedule, truth.motion.correctShutter(item.shutter));
                    truthColumns = format("%s,%.3f,%.3f,%+.3f", exposureWindowName(trueWindow), before, after, after - before);
                    gainText = format(", %+.2f dB", after - before);
                }
                if (!item.still && window != EXPOSURE_IV)
                {
                    SheetRow row{item.record.frame, blurPx,
                                 sheetRow(item.image, out, item.record.frame,
                                          window == item.window ? std::string(exposureWindowName(window))
                                                                : format("%s (as told %s)", exposureWindowName(window),
                                                                         exposureWindowName(item.window)),
                                          blurPx, c, gainText)};
                    sheetRows.push_back(row);
                    // Keep the most blurred ones.
                    if (sheetRows.size() > kSheetRows)
                        sheetRows.erase(std::min_element(sheetRows.begin(), sheetRows.end(),
                                                         [](const SheetRow& a, const SheetRow& b) { return a.blurPx < b.blurPx; }));
                }
                Mat color = out;
                if (out.channels() == 1)
                    cvtColor(out, color, COLOR_GRAY2BGR);
                writer.write(color);
                std::string reason = item.still ? std::string("still") : c.reason;
                for (char& ch : reason)
                    ch = ch == ',' || ch == '"' ? ';' : ch;
                csv << format("%d,%s,%d,%.9f,%.6f,%.6f,%.6f,%.4f,%s,%s,%.2f,%s\n", item.record.frame,
                              item.still ? "still" : exposureWindowName(window),
                              int(!item.still && c.applied), c.timeOffset, c.lineDelayScale, c.naturalFreqScale,
                              c.dampingScale, c.consistency, reason.c_str(),
                              item.still ? "still" : exposureWindowName(item.window), blurPx, truthColumns.c_str());
                written++;
            }
            progress("");
        };

        for (const FrameRecord& f : log)
            restoreAndWrite(pairing.push(f, recording.read(f).clone()));
        restoreAndWrite(pairing.finish());
        std::printf("\n");
        if (!unrefined.empty())
        {
            std::string list;
            for (int frame : unrefined)
                list += (list.empty() ? "" : ", ") + std::to_string(frame);
            std::printf("could not refine %zu frame(s) with no still after their move: %s; %s (--no-still-after)\n",
                        unrefined.size(), list.c_str(),
                        noStillAfterMode == "unchanged" ? "written as recorded" : "restored as told");
        }
        std::printf("%d moving frame(s): %d restored, %d refused (%.0f %%); the most blurred is frame %d (%.1f px)\n",
                    movingSeen, movingSeen - refused, refused, movingSeen ? 100.0 * refused / movingSeen : 0.0,
                    mostBlurred, mostBlurPx);
        if (!measured.empty())
        {
            double sum = 0;
            const Measured* worst = &measured.front();
            const Measured* blurred = nullptr;
            for (const Measured& m : measured)
            {
                sum += m.gain;
                worst = m.gain < worst->gain ? &m : worst;
                blurred = m.frame == mostBlurred ? &m : blurred;
            }
            std::printf("truth: gain over the recording, mean %+.2f dB, worst %+.2f dB (frame %d), most blurred frame %d "
                        "%+.2f dB; %d of %zu moving frames refused (%.0f %%)\n",
                        sum / measured.size(), worst->gain, worst->frame, mostBlurred, blurred ? blurred->gain : NAN,
                        refused, measured.size(), 100.0 * refused / measured.size());
        }
        writer.release();
        csv.close();
        if (!csv)
            CV_Error(Error::StsError, "--csv: cannot write '" + csvOut + "'");
        const std::string sheetPath = pathStem(videoOut) + "_frames.png";
        if (!sheetRows.empty())
        {
            std::sort(sheetRows.begin(), sheetRows.end(), [](const SheetRow& a, const SheetRow& b) { return a.frame < b.frame; });
            std::vector<Mat> images;
            for (const SheetRow& row : sheetRows)
                images.push_back(row.image);
            Mat sheet;
            vconcat(images, sheet);
            sheetTemporary = temporaryPathFor(sheetPath);
            if (!imwrite(sheetTemporary, sheet))
                CV_Error(Error::StsError, "cannot write '" + sheetPath + "'");
        }
        renameIntoPlace(videoTemporary, videoOut);
        renameIntoPlace(csvTemporary, csvOut);
        if (!sheetTemporary.empty())
            renameIntoPlace(sheetTemporary, sheetPath);
        std::printf("wrote %s, %s%s\n", videoOut.c_str(), csvOut.c_str(),
                    sheetRows.empty() ? "" : (" and " + sheetPath + " (the most blurred moving frames: recorded | restored)").c_str());
        return 0;
    }
    catch (const std::runtime_error& e)
    {
        return usageError(e.what());
    }
    catch (const cv::Exception& e)
    {
        // Nothing half-written stays behind.
        if (!videoTemporary.empty())
            std::remove(videoTemporary.c_str());
        if (!csvTemporary.empty())
            std::remove(csvTemporary.c_str());
        if (!sheetTemporary.empty())
            std::remove(sheetTemporary.c_str());
        std::cerr << "\nerror: " << e.err << "\n";
        return 1;
    }
}
