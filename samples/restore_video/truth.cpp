// SPDX-License-Identifier: Apache-2.0
#include "truth.hpp"

#include "frame_timing.hpp"  // samples/simulation
#include "image_metrics.hpp"
#include "mount_recording.hpp"

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdio>

namespace dynblur_samples {

using namespace cv;
using namespace cv::dynblur;

RecordingTruth RecordingTruth::load(const std::string& dir)
{
    RecordingTruth truth;
    truth.scene = imread(dir + "/scene.png", IMREAD_COLOR);
    if (truth.scene.empty())
        CV_Error(Error::StsError, "--truth: cannot read '" + dir + "/scene.png'");
    FileStorage fs(dir + "/truth.yml", FileStorage::READ);
    if (!fs.isOpened() || (fs["sceneAngle"].empty() && fs["sceneAngles"].empty()))
        CV_Error(Error::StsError, "--truth: cannot read sceneAngle (or a mount's sceneAngles) from '" + dir + "/truth.yml'");
    fs["sceneAngle"] >> truth.sceneAngle;
    fs["sceneAngles"] >> truth.sceneAngles;
    fs["axisNaturalFreqScales"] >> truth.motion.axisNaturalFreqScales;
    fs["axisDampingScales"] >> truth.motion.axisDampingScales;
    fs["timeOffset"] >> truth.motion.timeOffset;
    fs["lineDelayScale"] >> truth.motion.lineDelayScale;
    fs["naturalFreqScale"] >> truth.motion.naturalFreqScale;
    fs["dampingScale"] >> truth.motion.dampingScale;
    return truth;
}

Mat RecordingTruth::viewAt(double angle, const Ptr<Plant>& plant, const Ptr<CameraModel>& camera) const
{
    // A plant resting at 0 sees the scene given as the view at sceneAngle - angle.
    Mat view;
    renderBlurred(scene, plant, SwitchSchedule({0.0}, {0}, 0), camera,
                  RollingShutter(0.0, 1e-3, 0.0, camera->getImageSize().height), view, sceneAngle - angle);
    return view;
}

TruthComparison::TruthComparison(const std::string& dir, const CommandedMotion& motion, const Ptr<CameraModel>& camera)
    : truth_(RecordingTruth::load(dir)), motion_(motion), plant_(motion.plant()), camera_(camera)
{
    if (truth_.sceneAngles.empty() == motion.isMount() ||
        (motion.isMount() && int(truth_.sceneAngles.size()) != motion.axisCount()))
        CV_Error(Error::StsBadArg, format("--truth: '%s/truth.yml' is the truth of %s but the recording is %s (--mount)",
                                          dir.c_str(), truth_.sceneAngles.empty() ? "one axis" : "a mount's recording",
                                          motion.isMount() ? "a mount's" : "of one axis"));
}

void TruthComparison::measure(const ReferencePairing::Item& item, const RestoredFrame& r, std::string& columns,
                              std::string& gainText)
{
    // The truth of a restoration is the sharp view at the angle (or orientation) it restores to.
    const Mat view = motion_.isMount()
                         ? viewOfScene(truth_.scene, motion_.mountOrientation(truth_.sceneAngles), r.orientation, camera_)
                         : truth_.viewAt(r.thetaRef, plant_, camera_);
    const double before = maskedPsnr(view, item.image, Mat(), 255.0);
    const double after = maskedPsnr(view, r.image, Mat(), 255.0);
    measured_.push_back({item.record.frame, after - before});
    const int trueWindow = motion_.corrected(truth_.motion).classify(item.schedules, truth_.motion.correctShutter(item.shutter));
    columns = format("%s,%.3f,%.3f,%+.3f", exposureWindowName(trueWindow), before, after, after - before);
    gainText = format(", %+.2f dB", after - before);
}

void TruthComparison::printSummary(int mostBlurred, int refused) const
{
    if (measured_.empty())
        return;
    double sum = 0;
    const Measured* worst = &measured_.front();
    const Measured* blurred = nullptr;
    for (const Measured& m : measured_)
    {
        sum += m.gain;
        worst = m.gain < worst->gain ? &m : worst;
        blurred = m.frame == mostBlurred ? &m : blurred;
    }
    std::printf("truth: gain over the recording, mean %+.2f dB, worst %+.2f dB (frame %d), most blurred frame %d "
                "%+.2f dB; %d of %zu moving frames refused (%.0f %%)\n",
                sum / measured_.size(), worst->gain, worst->frame, mostBlurred, blurred ? blurred->gain : NAN, refused,
                measured_.size(), 100.0 * refused / measured_.size());
}

}  // namespace dynblur_samples
