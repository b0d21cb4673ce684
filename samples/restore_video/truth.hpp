// SPDX-License-Identifier: Apache-2.0
// dynblur_restore_video --truth: a rendered recording's truth (dynblur_calibrate_timing --simulate
// writes it), each moving frame measured against the sharp view it is restored to, and the summary.
#ifndef DYNBLUR_SAMPLES_RESTORE_TRUTH_HPP
#define DYNBLUR_SAMPLES_RESTORE_TRUTH_HPP

#include "recording.hpp"

#include <opencv2/dynblur.hpp>

#include <string>
#include <vector>

namespace dynblur_samples {

/* The sharp scene (the view at sceneAngle) and the correction from the nominal model to the motion
   that rendered the frames. */
struct RecordingTruth
{
    cv::Mat scene;  //!< 8-bit sRGB, wider than a frame by the same margin on each side
    double sceneAngle = 0;  //!< radians
    cv::dynblur::MotionCorrection motion;

    //! Reads DIR/scene.png and DIR/truth.yml; throws cv::Exception naming --truth and the file.
    static RecordingTruth load(const std::string& dir);
    //! The sharp view at `angle` (radians): the scene turned by angle - sceneAngle, as the renderer turns it.
    cv::Mat viewAt(double angle, const cv::Ptr<cv::dynblur::Plant>& plant,
                   const cv::Ptr<cv::dynblur::CameraModel>& camera) const;
};

//! Each moving frame's PSNR against its truth, as recorded and restored, and the recording's summary.
class TruthComparison
{
public:
    TruthComparison(const std::string& dir, const cv::Ptr<cv::dynblur::Plant>& plant,
                    const cv::Ptr<cv::dynblur::CameraModel>& camera);

    /** A moving frame restored to the view at `thetaRef` (radians): its CSV columns window_true,
    psnr_recorded_db, psnr_restored_db, gain_db, and the gain as the contact sheet labels it. */
    void measure(const ReferencePairing::Item& item, const cv::Mat& restored, double thetaRef, std::string& columns,
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
    cv::Ptr<cv::dynblur::Plant> plant_, truePlant_;
    cv::Ptr<cv::dynblur::CameraModel> camera_;
    std::vector<Measured> measured_;
};

}  // namespace dynblur_samples

#endif
