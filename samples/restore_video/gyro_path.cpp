// SPDX-License-Identifier: Apache-2.0
// dynblur_restore_video --gyro: every frame restored with the gyro log's motion, on the clock, line
// delay and bias of --timing; the video and a CSV of each frame's window and correction.
#include "restore_video.hpp"
#include "restored_video.hpp"

#include "atomic_file.hpp"  // samples/support
#include "frame_timing.hpp"  // samples/simulation
#include "gyro_recording.hpp"

#include <cstdio>

namespace dynblur_samples {

using namespace cv;
using namespace cv::dynblur;

int restoreGyroRecording(const CliArgs& args, const RestorationSettings& settings)
{
    GyroRecording recording;
    GyroRecording::open(args, defaultCameraPath(), recording);
    if (args.has("refine") && args.str("refine") != "none")
        throw std::runtime_error("--refine: a gyro recording is restored with --timing's calibration (per-frame "
                                 "refinement needs stills: DynamicDeblurrer::setReferenceFrame(still, stillShutter))");
    const std::string videoOut = args.str("out");
    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(recording.camera);
    settings.apply(*deblurrer);
    MotionCorrection calibration;
    if (!recording.timingPath.empty())
        calibration = TimingCalibration::load(recording.timingPath).correction, deblurrer->setCalibration(calibration);
    const std::vector<FrameRecord>& log = recording.log;
    RestoredVideo video(videoOut, args.str("csv", pathStem(videoOut) + ".csv"), log, recording.camera->getImageSize(),
                        "frame,window,restored,time_offset,line_delay_scale,bias_x,bias_y,bias_z\n");
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
        deblurrer->deblur(recording.read(f), recording.motion, shutter, restored);
        const MotionCorrection c = deblurrer->getLastCorrection();
        video.write(restored);
        video.csv() << format("%d,%s,%d,%.9f,%.6f,%.6g,%.6g,%.6g\n", f.frame,
                              exposureWindowName(deblurrer->getLastExposureWindow()),
                              int(deblurrer->getLastExposureWindow() != EXPOSURE_IV && c.applied), c.timeOffset,
                              c.lineDelayScale, c.gyroBias[0], c.gyroBias[1], c.gyroBias[2]);
        std::printf("\rframe %d of %zu", f.frame + 1, log.size());
        std::fflush(stdout);
    }
    video.close();
    video.commit();
    std::printf("\nwrote %s, %s\n", video.videoPath().c_str(), video.csvPath().c_str());
    return 0;
}

}  // namespace dynblur_samples
