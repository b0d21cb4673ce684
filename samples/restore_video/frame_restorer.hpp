// SPDX-License-Identifier: Apache-2.0
// dynblur_restore_video on a commanded recording: one paired frame restored (a moving frame refined
// against the stills of its move, in units of the noise of the last two consecutive stills; a still
// frame passed through), and the progress line that times it.
#ifndef DYNBLUR_SAMPLES_FRAME_RESTORER_HPP
#define DYNBLUR_SAMPLES_FRAME_RESTORER_HPP

#include "reference_pairing.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/dynblur.hpp>

namespace dynblur_samples {

/* "N of M frames written, K moving frame(s) left, ETA ..., P held for the still after their move".
   The ETA counts the moving frames still to restore at the time a moving frame has taken so far (a
   still frame costs next to nothing), and the line is shown before each restoration, so a slow frame
   never leaves a stale estimate on the screen. */
class ProgressLine
{
public:
    ProgressLine(const ReferencePairing& pairing, size_t frames, int moving)
        : pairing_(pairing), frames_(frames), movingLeft_(moving)
    {
    }
    void show(const char* doing) const;
    void frameWritten() { written_++; }
    //! Shows the line, then times the restoration until restored().
    void restoring();
    void restored();

private:
    const ReferencePairing& pairing_;
    size_t frames_;
    int written_ = 0, movingDone_ = 0, movingLeft_;
    cv::TickMeter clock_;
};

//! A frame as it goes out.
struct RestoredFrame
{
    cv::Mat image;                             //!< restored, or as recorded
    cv::dynblur::MotionCorrection correction;  //!< of a moving frame; default for a still one
    int window = 0;                            //!< under the motion it was restored with
    double thetaRef = 0;                       //!< the angle restored to, radians (moving frames of one axis)
    cv::Matx33d orientation = cv::Matx33d::eye();  //!< the orientation restored to (moving frames of a mount)
    double blurPx = 0;                         //!< largest image motion during one row's exposure (moving frames)
    bool noStillAfter = false;                 //!< ends its move at rest with no still after it: not refined
};

class FrameRestorer
{
public:
    /** @param calibration the recording's (--timing; MotionCorrection() without). @param unrefinedUnchanged
    --no-still-after unchanged: a frame that could not be refined is written as recorded. */
    FrameRestorer(const cv::Ptr<cv::dynblur::DynamicDeblurrer>& deblurrer, const CommandedMotion& motion,
                  const cv::Ptr<cv::dynblur::CameraModel>& camera, const cv::dynblur::MotionCorrection& calibration,
                  bool unrefinedUnchanged);

    RestoredFrame restore(const ReferencePairing::Item& item, ProgressLine& progress);

private:
    //! A mount's frame restored to the view at its middle row's mid-exposure (r.orientation set).
    void deblurMount(const ReferencePairing::Item& item, RestoredFrame& r);
    //! The stills the deblurrer refines against, set only when they change.
    void useReferences(const ReferencePairing::Item& item, bool noStillAfter);
    //! The noise of the last two consecutive stills at one level, once both are known.
    void useNoise();
    void observeStill(const ReferencePairing::Item& item);

    cv::Ptr<cv::dynblur::DynamicDeblurrer> deblurrer_;
    CommandedMotion motion_;  //!< as calibrated
    cv::Ptr<cv::dynblur::Plant> correctedPlant_;
    double focalPx_;
    cv::dynblur::MotionCorrection calibration_;
    bool unrefinedUnchanged_;
    cv::Mat lastBefore_, lastAfter_, restored_;
    cv::Mat noiseA_, noiseB_;
    int lastStillFrame_ = -2;
    std::vector<int> lastStillLevels_;
    bool noisePending_ = false;
};

}  // namespace dynblur_samples

#endif
