// SPDX-License-Identifier: Apache-2.0
// A rendered recording of a mount at work (dynblur_calibrate_timing --simulate DIR --mount FILE):
// diagonal saccades of every axis, planned together by MountPlanner, seen by a 640x480 rolling-shutter
// webcam, written in the recording format (docs/recording-format.md) with its truth.
#ifndef DYNBLUR_SAMPLES_MOUNT_RECORDING_HPP
#define DYNBLUR_SAMPLES_MOUNT_RECORDING_HPP

#include <opencv2/dynblur.hpp>

#include <string>
#include <vector>

namespace dynblur_samples {

struct MountRecordingSpec
{
    cv::Ptr<cv::dynblur::Mount> mount;  //!< the nominal mount the moves are planned on (two axes at least)
    std::vector<double> targetAngles;   //!< the far end of the saccades, radians per axis (the near end: 0)
    /** the truth that moved the camera, as the correction from the nominal model to it (the clock, the
        line delay, each axis's plant: MotionCorrection::correctMotion) */
    cv::dynblur::MotionCorrection drift;
    int saccades = 4;                   //!< moves there and back, in [1, 20]
    bool asVideo = false;               //!< frames.avi (MJPG) instead of frame_%04d.png
};

/** @brief Renders the recording into `dir`: the frames, frames.csv, commands.csv (one level column per
axis), camera.xml, mount.yml (the nominal mount) and truth/ (scene.png, the sharp view with every axis
at 0 and wider than a frame; truth.yml, the drift). Returns the number of frames written. Throws
cv::Exception naming the file it cannot write. */
int renderMountRecording(const std::string& dir, const MountRecordingSpec& spec);

/** @brief The sharp view at orientation `orientation` (camera frame in the mount's base frame) of a scene
taken at `sceneOrientation` and wider than the camera's image by the same margin on each side, as
renderBlurred turns it: I(p) = scene(K_s · R · K⁻¹ · p) with R = sceneOrientationᵀ · orientation and K_s the
camera's matrix with the principal point moved by the margin. */
cv::Mat viewOfScene(const cv::Mat& scene, const cv::Matx33d& sceneOrientation, const cv::Matx33d& orientation,
                    const cv::Ptr<cv::dynblur::CameraModel>& camera);

}  // namespace dynblur_samples

#endif
