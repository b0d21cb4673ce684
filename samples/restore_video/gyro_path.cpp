// SPDX-License-Identifier: Apache-2.0
// dynblur_restore_video --gyro: a clip whose motion is a gyro log, streamed frame by frame (its frame
// times from a frame log or the video's own timestamps), each frame restored with the log's motion as
// --timing corrects it (clock offset, line delay, bias, rate scale, axes) and checked against its
// neighbour (a frame whose motion the log does not explain comes back unchanged); the video at the
// input's size and rate, the CSV of each frame's window, outcome and blur, the contact sheet of the
// most blurred frames and the summary. A failure midway keeps the frames written so far.
#include "restore_video.hpp"

#include "atomic_file.hpp"  // samples/support
#include "contact_sheet.hpp"
#include "frame_timing.hpp"  // samples/simulation
#include "gyro_recording.hpp"
#include "hand_motion.hpp"
#include "restored_video.hpp"

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace dynblur_samples {

using namespace cv;
using namespace cv::dynblur;

namespace {

const size_t kSheetRows = 6;

// After the columns every mode writes: the frame's start on the video's clock and the calibration's bias.
const char* const kGyroCsvColumns = ",frame_start_s,gyro_bias_x,gyro_bias_y,gyro_bias_z,rate_scale";

//! The frames by outcome, and the most blurred.
struct ClipSummary
{
    int frames = 0, restored = 0, skipped = 0, refused = 0, mostBlurred = -1;
    double mostBlurPx = -1;

    void add(int frame, bool deconvolved, bool applied, double blurPx)
    {
        frames++;
        restored += deconvolved;
        skipped += applied && !deconvolved;
        refused += !applied;
        if (blurPx > mostBlurPx)
            mostBlurPx = blurPx, mostBlurred = frame;
    }

    void print() const
    {
        std::printf("%d frame(s): %d restored, %d skipped (still or sharp), %d refused (written as recorded); the most "
                    "blurred is frame %d (%.1f px)\n",
                    frames, restored, skipped, refused, mostBlurred, mostBlurPx);
    }
};

//! A frame of the stream and its timing.
struct StreamFrame
{
    Mat image;
    FrameRecord record;
};

/* The largest extent of a point's path during its row's exposure, pixels, under the motion as
   calibrated: what ranks frames by blur (the rate scale scales it). */
double blurPixels(const Ptr<CameraMotion>& motion, const Ptr<CameraModel>& camera, const RollingShutter& corrected,
                  double rateScale)
{
    CameraPath path;
    path.rotation = motion;
    return rateScale * frameBlurPx(path, camera->cameraMatrix(), camera->getImageSize(), corrected, true);
}

//! The calibration of --timing, or none; its axes applied to the log.
MotionCorrection calibrationOf(GyroRecording& recording)
{
    if (recording.timingPath.empty())
        return MotionCorrection();
    const TimingCalibration t = TimingCalibration::load(recording.timingPath);
    recording.gyro = recording.gyro.withAxisCorrection(t.axisCorrection);
    return t.correction;
}

//! Throws naming --gyro when the frame's readout, as calibrated, lies outside the log.
void checkCovered(const GyroRecording& recording, const FrameRecord& f, const RollingShutter& corrected,
                  const Vec2d& span, const MotionCorrection& calibration)
{
    const Vec2d readout = corrected.readoutInterval();
    if (readout[0] >= span[0] && readout[1] <= span[1])
        return;
    CV_Error(Error::StsOutOfRange,
             format("--gyro: frame %d (at %.6f s on the video's clock) is read over [%.6f, %.6f] s on the log's clock "
                    "(with the clock offset %+.6f s%s), outside the span of '%s', [%.6f, %.6f] s: the log is shorter "
                    "than the clip, or on another clock (calibrate it: dynblur_calibrate_timing --gyro)",
                    f.frame, f.frameStart, readout[0], readout[1], calibration.timeOffset,
                    recording.timingPath.empty() ? ": no --timing" : (" of --timing " + recording.timingPath).c_str(),
                    recording.gyroPath.c_str(), span[0], span[1]));
}

}  // namespace

int restoreGyroRecording(const CliArgs& args, const RestorationSettings& settings)
{
    if (args.has("refine") && args.str("refine") != "none")
        throw std::runtime_error("--refine: a gyro recording is restored with --timing's calibration (per-frame "
                                 "refinement needs stills: DynamicDeblurrer::setReferenceFrame(still, stillShutter))");
    GyroRecording recording;
    GyroRecording::open(args, defaultCameraPath(), UntoldReadout::Refuse, recording);
    const MotionCorrection calibration = calibrationOf(recording);
    const Ptr<CameraMotion> motion = recording.gyro.toMotion();
    const Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(recording.camera);
    settings.apply(*deblurrer);
    if (!recording.timingPath.empty())
        deblurrer->setCalibration(calibration);
    std::printf("%s; clock offset %+.4f s, line delay x%.4f (%s)\n", recording.toldText().c_str(),
                calibration.timeOffset, calibration.lineDelayScale,
                recording.timingPath.empty() ? "no --timing: the log's clock taken as the video's"
                                             : ("--timing " + recording.timingPath).c_str());

    const std::string videoOut = args.str("out"), csvOut = args.str("csv", pathStem(videoOut) + ".csv");
    RestoredVideo video(videoOut, csvOut, recording.fps, recording.camera->getImageSize(),
                        std::string(kFrameCsvHeader) + kGyroCsvColumns + "\n");
    ContactSheet sheet(kSheetRows);  // the most blurred frames, recorded beside restored, for a look
    ClipSummary summary;
    const Vec2d span = motion->getTimeSpan();
    // Each frame is checked against its neighbour: the frame before, or for the first the one after it.
    StreamFrame previous, current, after;
    bool more = recording.next(current.image, current.record);
    bool moreAfter = more && recording.next(after.image, after.record);
    Mat restored;
    try
    {
        while (more)
        {
            const FrameRecord& f = current.record;
            const RollingShutter shutter = recording.shutterOf(f);
            const RollingShutter corrected = calibration.correctShutter(shutter);
            checkCovered(recording, f, corrected, span, calibration);
            const StreamFrame& neighbour = previous.image.empty() && moreAfter ? after : previous;
            deblurrer->setNeighbourFrame(neighbour.image, neighbour.image.empty() ? RollingShutter()
                                                                                   : recording.shutterOf(neighbour.record));
            deblurrer->deblur(current.image, motion, shutter, restored);
            const MotionCorrection c = deblurrer->getLastCorrection();
            const int window = deblurrer->getLastExposureWindow();
            const double blurPx = blurPixels(motion, recording.camera, corrected, calibration.rateScale);
            const bool still = window == EXPOSURE_IV;
            // A sharp frame is not deconvolved (at most its rows are moved back): its correction stands.
            const bool deconvolved = !still && c.applied && c.reason.rfind("sharp:", 0) != 0;
            video.write(restored);
            video.csv() << frameCsvColumns(f.frame, still ? "still" : exposureWindowName(window), deconvolved, c,
                                           still ? std::string("still") : c.reason,
                                           exposureWindowName(classifyExposure(motion, corrected)), blurPx)
                        << format(",,,,,%.9f,%.6g,%.6g,%.6g,%.6f\n", f.frameStart, c.gyroBias[0], c.gyroBias[1],
                                  c.gyroBias[2], c.rateScale);
            summary.add(f.frame, deconvolved, c.applied, blurPx);
            if (!still)
                sheet.offer(current.image, restored, f.frame, exposureWindowName(window), blurPx, c, "");
            std::printf("\rframe %d (%.2f s) written: %d restored, %d skipped, %d refused", f.frame, f.frameStart,
                        summary.restored, summary.skipped, summary.refused);
            std::fflush(stdout);
            previous = current;
            current = after;  // next() reads into a buffer of its own: `current` keeps this frame
            more = moreAfter;
            moreAfter = more && recording.next(after.image, after.record);
        }
    }
    catch (const cv::Exception& e)
    {
        if (video.framesWritten() == 0)
            throw;
        // Copied rather than raised anew: cv::error would quote a message of two lines.
        cv::Exception failure = e;
        failure.err = e.err + "\n" + video.keepWritten();
        throw failure;
    }
    std::printf("\n");
    summary.print();
    video.close();
    const std::string sheetPath = pathStem(videoOut) + "_frames.png";
    if (!sheet.empty() && !imwrite(video.temporaryFor(sheetPath), sheet.render()))
        CV_Error(Error::StsError, "cannot write '" + sheetPath + "'");
    video.commit();
    const std::string sheetNote =
        sheet.empty() ? "" : " and " + sheetPath + " (the most blurred frames: recorded | restored)";
    std::printf("wrote %s (%d frames at %.6g fps), %s%s\n", videoOut.c_str(), video.framesWritten(), recording.fps,
                csvOut.c_str(), sheetNote.c_str());
    return 0;
}

}  // namespace dynblur_samples
