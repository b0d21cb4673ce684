// SPDX-License-Identifier: Apache-2.0
#include "mount_recording.hpp"

#include "atomic_file.hpp"  // samples/support
#include "recording.hpp"
#include "scene.hpp"

#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <cmath>
#include <cstdio>

namespace dynblur_samples {

using namespace cv;
using namespace cv::dynblur;

namespace {

const double kFps = 30.0, kExposure = 0.008;

//! Saccades from every axis at 0 to the targets and back, one every 0.6 s (each 7 ms later in the frame period).
CommandLog plannedSaccades(const MountRecordingSpec& spec)
{
    const int axes = spec.mount->getAxisCount();
    CommandLog commands;
    commands.times = {0.0};
    commands.levels.assign(size_t(axes), std::vector<int>{0});
    const Ptr<MountPlanner> planner = MountPlanner::create(spec.mount);
    const std::vector<double> rest(size_t(axes), 0.0);
    for (int k = 0; k < spec.saccades; k++)
    {
        const bool out = k % 2 == 0;
        const MountMove move = planner->plan(out ? rest : spec.targetAngles, out ? spec.targetAngles : rest,
                                             0.5 + 0.6 * k + 0.007 * k);
        commands.appendMove(move.schedules, 0.0);
    }
    return commands;
}

//! The whole log as one schedule per axis (each axis resting at its first level before it).
std::vector<SwitchSchedule> wholeLog(const CommandLog& commands)
{
    std::vector<SwitchSchedule> schedules;
    for (const std::vector<int>& levels : commands.levels)
        schedules.push_back(SwitchSchedule(commands.times, levels, levels[0]));
    return schedules;
}

void writeFrame(const std::string& dir, int k, const Mat& frame, VideoWriter& writer)
{
    if (writer.isOpened())
        return writer.write(frame);
    const std::string path = format("%s/frame_%04d.png", dir.c_str(), k);
    if (!imwrite(path, frame))
        CV_Error(Error::StsError, "cannot write '" + path + "'");
}

/* What dynblur_restore_video --truth reads (RecordingTruth): the scene's joint angles and the correction
   from the nominal model to the motion that rendered the frames. */
void writeTruth(const std::string& path, const std::vector<double>& sceneAngles, const MotionCorrection& drift)
{
    FileStorage fs(path, FileStorage::WRITE);
    if (!fs.isOpened())
        CV_Error(Error::StsError, "cannot write '" + path + "'");
    fs.writeComment("the truth of a rendered mount recording: scene.png is the view at sceneAngles (radians, one "
                    "per axis); the frames were rendered with the nominal mount and frame log corrected by the rest");
    fs << "sceneAngles" << sceneAngles << "timeOffset" << drift.timeOffset << "lineDelayScale" << drift.lineDelayScale
       << "naturalFreqScale" << drift.naturalFreqScale << "dampingScale" << drift.dampingScale
       << "axisNaturalFreqScales" << drift.axisNaturalFreqScales << "axisDampingScales" << drift.axisDampingScales;
}

}  // namespace

int renderMountRecording(const std::string& dir, const MountRecordingSpec& spec)
{
    CV_Assert(!spec.mount.empty() && int(spec.targetAngles.size()) == spec.mount->getAxisCount());
    utils::fs::createDirectories(dir + "/truth");
    const Ptr<CameraModel> camera = CameraModel::create(615.0, 615.0, 319.5, 239.5, 640, 480);
    const double lineDelay = 1.0 / kFps / 480;
    const CommandLog commands = plannedSaccades(spec);
    const Ptr<CameraMotion> truth = spec.drift.correctMotion(spec.mount->motion(wholeLog(commands)));

    // The scene is the view with every axis at 0 (the log's start), wide enough for the far end.
    double reach = 0;
    for (double a : spec.targetAngles)
        reach = std::max(reach, std::abs(a));
    const int margin = int(std::ceil(615.0 * std::tan(reach + 1 * CV_PI / 180))) + 24;
    Mat scene;
    srgbToLinear(makeScene(Size(640 + 2 * margin, 480 + 2 * margin)), scene);
    GaussianBlur(scene, scene, Size(0, 0), 1.0);  // a webcam's lens is softer than the drawn stripes

    const int count = int(std::ceil((0.5 + 0.6 * spec.saccades + 0.3) * kFps));
    VideoWriter writer;
    if (spec.asVideo && !writer.open(dir + "/frames.avi", VideoWriter::fourcc('M', 'J', 'P', 'G'), kFps, Size(640, 480)))
        CV_Error(Error::StsError, "cannot write '" + dir + "/frames.avi'");
    std::vector<FrameRecord> frames;
    for (int k = 0; k < count; k++)
    {
        const FrameRecord f{k, k / kFps, kExposure, lineDelay};
        const RollingShutter happened = spec.drift.correctShutter(RollingShutter(f.frameStart, kExposure, lineDelay, 480));
        Mat blurred, noisy, frame;
        renderBlurred(scene, truth, camera, happened, blurred, 0.0);
        addSensorNoise(blurred, noisy, 4000.0, 8.0, 5.0, 1000 + uint64(k));
        linearToSrgb(noisy, frame, CV_8U);
        writeFrame(dir, k, frame, writer);
        frames.push_back(f);
        std::printf("\rrendering frame %d of %d", k + 1, count);
        std::fflush(stdout);
    }
    std::printf("\n");
    writer.release();
    writeFrameLog(dir + "/frames.csv", frames);
    writeCommandLog(dir + "/commands.csv", commands);
    camera->save(dir + "/camera.xml");
    spec.mount->save(dir + "/mount.yml");
    Mat srgb;
    linearToSrgb(scene, srgb, CV_8U);
    if (!imwrite(dir + "/truth/scene.png", srgb))
        CV_Error(Error::StsError, "cannot write '" + dir + "/truth/scene.png'");
    writeTruth(dir + "/truth/truth.yml", std::vector<double>(spec.targetAngles.size(), 0.0), spec.drift);
    return count;
}

Mat viewOfScene(const Mat& scene, const Matx33d& sceneOrientation, const Matx33d& orientation,
                const Ptr<CameraModel>& camera)
{
    const Size size = camera->getImageSize();
    const Matx33d K(camera->getFx(), 0, camera->getCx(), 0, camera->getFy(), camera->getCy(), 0, 0, 1);
    Matx33d Ks = K;  // the scene's principal point: the same margin on each side
    Ks(0, 2) += (scene.cols - size.width) / 2.0;
    Ks(1, 2) += (scene.rows - size.height) / 2.0;
    const Matx33d toScene = Ks * (sceneOrientation.t() * orientation) * K.inv();  // I(p) = scene(K_s R K⁻¹ p)
    Mat view;
    warpPerspective(scene, view, Mat(toScene), size, INTER_LINEAR | WARP_INVERSE_MAP, BORDER_REFLECT_101);
    return view;
}

}  // namespace dynblur_samples
