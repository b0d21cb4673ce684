// SPDX-License-Identifier: Apache-2.0
// dynblur_restore_video --truth: a rendered recording's truth (dynblur_calibrate_timing --simulate
// writes it), each moving frame measured against the sharp view it is restored to, and the summary.
#ifndef DYNBLUR_SAMPLES_RESTORE_TRUTH_HPP
#define DYNBLUR_SAMPLES_RESTORE_TRUTH_HPP

#include "frame_restorer.hpp"
#include "reference_pairing.hpp"

#include <opencv2/dynblur.hpp>

#include <string>
#include <vector>

namespace dynblur_samples {

/* The sharp scene (the view at sceneAngle, or at a mount's sceneAngles) and the correction from the
   nominal model to the motion that rendered the frames. */
struct RecordingTruth
{
    cv::Mat scene;  //!< 8-bit sRGB, wider than a frame by the same margin on each side
    double sceneAngle = 0;  //!< radians
    std::vector<double> sceneAngles;  //!< a mount's recording: radians per axis (empty: one axis)
    cv::dynblur::MotionCorrection motion;

    /** Reads DIR/scene.png and DIR/truth.yml (sceneAngle, or sceneAngles and each axis's scales for a
    mount); throws cv::Exception naming --truth and the file. */
    static RecordingTruth load(const std::string& dir);
    //! The sharp view at `angle` (radians): the scene turned by angle - sceneAngle, as the renderer turns it.
    cv::Mat viewAt(double angle, const cv::Ptr<cv::dynblur::Plant>& plant,
                   const cv::Ptr<cv::dynblur::CameraModel>& camera) const;
};

//! Each moving frame's PSNR against its truth, as recorded and restored, and the recording's summary.
class TruthComparison
{
public:
    /** Throws cv::Exception naming --truth and --mount when the truth is a mount's and the recording
    not, or the other way round. */
    TruthComparison(const std::string& dir, const CommandedMotion& motion,
                    const cv::Ptr<cv::dynblur::CameraModel>& camera);

    /** A moving frame restored (to the view at r.thetaRef or r.orientation): its CSV columns
    window_true, psnr_recorded_db, psnr_restored_db, gain_db, and the gain as the contact sheet labels it. */
    void measure(const ReferencePairing::Item& item, const RestoredFrame& r, std::string& columns,
                 std::string& gainText);
    //! "truth: gain over the recording, ..." once a frame was measured.
    void printSummary(int mostBlurred, int refused) const;

private:
    struct Measured
    {
        int frame;
        double gain;  //!< dB
    };
    RecordingTruth truth_;
    CommandedMotion motion_;
    cv::Ptr<cv::dynblur::Plant> plant_;
    cv::Ptr<cv::dynblur::CameraModel> camera_;
    std::vector<Measured> measured_;
};

}  // namespace dynblur_samples

#endif
