// SPDX-License-Identifier: Apache-2.0
// A hand's motion for the hand-held clip simulator (handheld_clip.hpp): band-limited noise for the
// camera's rotation and, optionally, its translation, with still and shaky stretches, and the blur it
// puts into a frame.
#ifndef DYNBLUR_SAMPLES_HAND_MOTION_HPP
#define DYNBLUR_SAMPLES_HAND_MOTION_HPP

#include <opencv2/dynblur.hpp>

namespace dynblur_samples {

/** @brief Still and shaky stretches of a hand, on the camera's clock: from t = 0, `stillSeconds`
held still, then `shakySeconds` of shake (raised-cosine ramps of `rampSeconds` at both ends, inside
the shaky stretch), repeated. `stillSeconds` = 0: shaky throughout, no still frame. */
struct ShakeStretches
{
    double stillSeconds = 0;    //!< s, ≥ 0; 0: no still stretch
    double shakySeconds = 1;    //!< s, > 0 (read only when stillSeconds > 0)
    double rampSeconds = 0.05;  //!< s, in [0, shakySeconds / 2]

    //! The shake's amplitude at camera time t (seconds), in [0, 1]: 0 still, 1 shaky.
    double envelope(double t) const;
};

/** @brief The camera's true motion on the camera's clock: the rotation Q(t) (camera frame in the home
frame, the identity at the motion's first instant) and the position c(t) of the camera centre
(metres, home frame) in front of a plane at `planeDepth` metres facing the home view (normal +z).
The view at t sees home-view pixel homeFromView(t)·p at its pixel p. */
struct CameraPath
{
    cv::Ptr<cv::dynblur::CameraMotion> rotation;  //!< Q(t), sampled densely (exact for its band)
    cv::Mat positions;         //!< N×3 CV_64F camera centres, metres, every 1/sampleRateHz from `start`; empty: none
    double start = 0;          //!< s, camera clock: the first sample, where Q = I and c = 0 (the home view)
    double sampleRateHz = 0;   //!< Hz, of `positions`
    double planeDepth = 0;     //!< m, > 0 when `positions` is set

    //! The camera centre at t (seconds), metres, home frame: linear between samples; 0 without translation.
    cv::Vec3d position(double t) const;
    /** The homography from view pixels at t to home-view pixels: K·(I + c·nᵀ/(d − c_z))·Q(t)·K⁻¹ with
    n = (0, 0, 1) and d = planeDepth; K·Q(t)·K⁻¹ (DESIGN §2, Rotation) when `rotationOnly` or without
    translation. @param t seconds, camera clock. @param K camera matrix, pixels. */
    cv::Matx33d homeFromView(double t, const cv::Matx33d& K, bool rotationOnly = false) const;
};

/** @brief The largest extent of a point's path during its row's exposure, pixels: over probe pixels
(three columns, five rows), the largest distance between two positions in the home view that the
pixel sees during [rowInterval]. 0 for a zero exposure.
@param path the motion. @param K camera matrix. @param size frame size, pixels.
@param shutter the frame's timing (camera clock). @param rotationOnly leave the translation out. */
double frameBlurPx(const CameraPath& path, const cv::Matx33d& K, const cv::Size& size,
                   const cv::dynblur::RollingShutter& shutter, bool rotationOnly = false);

/** @brief How far the view strays from the home view over [from, to] (seconds): the largest distance,
pixels, of a border pixel of the frame from the home-view pixel it sees, sampled every millisecond. */
double viewStrayPx(const CameraPath& path, const cv::Matx33d& K, const cv::Size& size, double from, double to);

/** @brief Shapes of band-limited noise, scaled later: for each of rotation and translation, three
axes of a signal whose spectrum is flat in its derivative (rate or speed) between lowHz and highHz
and zero elsewhere (no drift below lowHz), its derivative of unit RMS per axis, times the stretches'
envelope and a 0.1 s fade-in from the home view at `start`. Sampled at kSampleRateHz. */
class HandShake
{
public:
    static constexpr double kSampleRateHz = 2000;  //!< 100 samples per period at 20 Hz

    /** @param start first instant, seconds (the home view). @param end last instant, seconds.
    @param stretches still and shaky stretches. @param seed random seed. */
    HandShake(double start, double end, const ShakeStretches& stretches, uint64 seed);

    /** The rotation vectors φ (radians, N×3) of a rotation band [lowHz, highHz] (Hz) with per-axis
    weights, scaled by `scale` (the RMS rate of a weight-1 axis while shaking, rad/s). */
    cv::Mat rotationVectors(double lowHz, double highHz, const cv::Vec3d& weights, double scale) const;
    //! The positions (metres, N×3) of a translation band, `scale` the RMS speed of a weight-1 axis, m/s.
    cv::Mat positions(double lowHz, double highHz, const cv::Vec3d& weights, double scale) const;
    //! The path for the rotation vectors and positions above (positions empty: rotation only).
    CameraPath path(const cv::Mat& rotationVectors, const cv::Mat& positions, double planeDepth) const;

    double start() const { return start_; }
    int samples() const { return samples_; }

private:
    cv::Mat shape(double lowHz, double highHz, const cv::Vec3d& weights, double scale, uint64 stream) const;

    double start_;
    int samples_;
    uint64 seed_;
    std::vector<double> envelope_;
};

}  // namespace dynblur_samples

#endif
