// SPDX-License-Identifier: Apache-2.0
#include "truth.hpp"

#include "frame_timing.hpp"  // samples/simulation
#include "image_metrics.hpp"

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
    if (!fs.isOpened() || fs["sceneAngle"].empty())
        CV_Error(Error::StsError, "--truth: cannot read sceneAngle from '" + dir + "/truth.yml'");
    fs["sceneAngle"] >> truth.sceneAngle;
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

TruthComparison::TruthComparison(const std::string& dir, const Ptr<Plant>& plant, const Ptr<CameraModel>& camera)
    : truth_(RecordingTruth::load(dir)), plant_(plant), truePlant_(truth_.motion.correctPlant(plant)), camera_(camera)
{
}

void TruthComparison::measure(const ReferencePairing::Item& item, const Mat& restored, double thetaRef,
                              std::string& columns, std::string& gainText)
{
    // The truth of a restoration is the sharp view at the angle it restores to.
    const Mat view = truth_.viewAt(thetaRef, plant_, camera_);
    const double before = maskedPsnr(view, item.image, Mat(), 255.0);
    const double after = maskedPsnr(view, restored, Mat(), 255.0);
    measured_.push_back({item.record.frame, after - before});
    const int trueWindow = classifyExposure(truePlant_, item.schedule, truth_.motion.correctShutter(item.shutter));
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
