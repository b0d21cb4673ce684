// SPDX-License-Identifier: Apache-2.0
#include "commanded_motion.hpp"

#include <opencv2/calib3d.hpp>

#include <algorithm>

namespace dynblur_samples {

using namespace cv;
using namespace cv::dynblur;

CommandedMotion::CommandedMotion(const Ptr<Plant>& plant, const Ptr<Mount>& mount, const MotionCorrection& correction)
    : plant_(mount.empty() ? plant : mount->getPlant(0)), correctedPlant_(correction.correctPlant(plant_)),
      mount_(mount), correction_(correction)
{
}

CommandedMotion CommandedMotion::corrected(const MotionCorrection& correction) const
{
    return CommandedMotion(plant_, mount_, correction);
}

Ptr<CameraMotion> CommandedMotion::motion(const std::vector<SwitchSchedule>& schedules) const
{
    CV_Assert(isMount() && int(schedules.size()) == axisCount());
    return mount_->motion(schedules);
}

int CommandedMotion::classify(const std::vector<SwitchSchedule>& schedules, const RollingShutter& shutter,
                              double angleTol, double velocityTol) const
{
    if (!isMount())
        return classifyExposure(correctedPlant_, schedules[0], shutter, angleTol, velocityTol);
    return classifyExposure(correction_.correctMotion(motion(schedules)), shutter, angleTol, velocityTol);
}

/* The angle's sweep over a row's interval for one plant; for a mount, the largest turn from the row's
   first instant (the sweep of a move that does not come back within one exposure). */
double CommandedMotion::largestRowTurn(const std::vector<SwitchSchedule>& schedules, const RollingShutter& shutter) const
{
    const Ptr<CameraMotion> moved = isMount() ? correction_.correctMotion(motion(schedules)) : Ptr<CameraMotion>();
    double largest = 0;
    for (int k = 0; k <= 8; k++)
    {
        const Vec2d interval = shutter.rowInterval((shutter.rows - 1) * k / 8);
        Mat t(1, 33, CV_64F);
        for (int i = 0; i < t.cols; i++)
            t.at<double>(i) = interval[0] + (interval[1] - interval[0]) * i / (t.cols - 1);
        if (moved.empty())
        {
            Mat theta;
            correctedPlant_->response(schedules[0], t, theta);
            double low, high;
            minMaxLoc(theta, &low, &high);
            largest = std::max(largest, high - low);
            continue;
        }
        const Matx33d start = moved->orientation(interval[0]);
        for (int i = 1; i < t.cols; i++)
        {
            Vec3d turn;
            Rodrigues(Mat(start.t() * moved->orientation(t.at<double>(i))), turn);
            largest = std::max(largest, norm(turn));
        }
    }
    return largest;
}

}  // namespace dynblur_samples
