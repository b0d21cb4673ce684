// SPDX-License-Identifier: Apache-2.0
// The motion a recording's command log commands: one plant's response to its levels, or a mount's
// (one schedule per axis, Mount::motion), as a correction (a calibration) makes it. What the
// pairing of frames with stills, the restorer and the timing calibration ask of a frame's commands.
#ifndef DYNBLUR_SAMPLES_COMMANDED_MOTION_HPP
#define DYNBLUR_SAMPLES_COMMANDED_MOTION_HPP

#include <opencv2/dynblur.hpp>

#include <string>
#include <vector>

namespace dynblur_samples {

class CommandedMotion
{
public:
    /** @param plant the nominal plant of a one-axis recording (unused with a mount).
    @param mount the nominal mount of a mount's recording; empty: one axis, `plant`'s.
    @param correction the model's correction (MotionCorrection() for none). */
    CommandedMotion(const cv::Ptr<cv::dynblur::Plant>& plant, const cv::Ptr<cv::dynblur::Mount>& mount,
                    const cv::dynblur::MotionCorrection& correction = cv::dynblur::MotionCorrection());

    bool isMount() const { return !mount_.empty(); }
    //! The number of axes a command log must carry: the mount's, or 1.
    int axisCount() const { return mount_.empty() ? 1 : mount_->getAxisCount(); }
    //! A copy with another correction.
    CommandedMotion corrected(const cv::dynblur::MotionCorrection& correction) const;

    /** The exposure window of the frame read out as `shutter` (already corrected) under the corrected
    motion of `schedules` (one per axis): classifyExposure of the plant, or of the mount's motion. */
    int classify(const std::vector<cv::dynblur::SwitchSchedule>& schedules, const cv::dynblur::RollingShutter& shutter,
                 double angleTol = 2e-4, double velocityTol = 0.02) const;
    //! The mount's motion under `schedules`, as told (uncorrected); mount recordings only.
    cv::Ptr<cv::dynblur::CameraMotion> motion(const std::vector<cv::dynblur::SwitchSchedule>& schedules) const;
    //! The mount's orientation at joint angles `angles` (radians, one per axis); mount recordings only.
    cv::Matx33d mountOrientation(const std::vector<double>& angles) const { return mount_->orientation(angles); }
    //! The nominal plant of a one-axis recording (axis 0's for a mount).
    const cv::Ptr<cv::dynblur::Plant>& plant() const { return plant_; }
    /** The largest angle the corrected motion turns during one row's exposure, radians, over nine rows
    of `shutter` (already corrected): what ranks frames by blur. */
    double largestRowTurn(const std::vector<cv::dynblur::SwitchSchedule>& schedules,
                          const cv::dynblur::RollingShutter& shutter) const;

private:
    cv::Ptr<cv::dynblur::Plant> plant_, correctedPlant_;
    cv::Ptr<cv::dynblur::Mount> mount_;
    cv::dynblur::MotionCorrection correction_;
};

}  // namespace dynblur_samples

#endif
