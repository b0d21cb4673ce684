// SPDX-License-Identifier: Apache-2.0
// Test support: camera motions known in closed form, for the tests of rotation blur.
#ifndef DYNBLUR_TEST_ROTATION_MOTION_HPP
#define DYNBLUR_TEST_ROTATION_MOTION_HPP

#include <opencv2/dynblur.hpp>

#include <cmath>
#include <vector>

namespace dynblur_test {

//! One sinusoid of an angle: amplitude (radians), frequency (Hz), phase (radians).
struct Wave
{
    double amplitude, frequencyHz, phase;
};

/** A 3-axis motion in closed form: Q(t) = R_z(γ(t))·R_y(β(t))·R_x(α(t)), each angle a sum of
sinusoids, with its exact body rates ω = γ'·R_xᵀR_yᵀe_z + β'·R_xᵀe_y + α'·e_x. The reference of a
NaN tRef is the middle row's mid-exposure, as for any sampled motion. */
class WaveMotion CV_FINAL : public cv::dynblur::CameraMotion
{
public:
    WaveMotion(const std::vector<Wave>& aboutX, const std::vector<Wave>& aboutY, const std::vector<Wave>& aboutZ)
    {
        waves_[0] = aboutX;
        waves_[1] = aboutY;
        waves_[2] = aboutZ;
    }

    cv::Matx33d orientation(double t) const CV_OVERRIDE
    {
        return rotation(2, angle(2, t)) * rotation(1, angle(1, t)) * rotation(0, angle(0, t));
    }
    cv::Vec3d angularVelocity(double t) const CV_OVERRIDE
    {
        const cv::Matx33d Rx = rotation(0, angle(0, t)), Ry = rotation(1, angle(1, t));
        return rate(2, t) * (Rx.t() * (Ry.t() * cv::Vec3d(0, 0, 1))) + rate(1, t) * (Rx.t() * cv::Vec3d(0, 1, 0)) +
               rate(0, t) * cv::Vec3d(1, 0, 0);
    }
    cv::Vec2d getTimeSpan() const CV_OVERRIDE { return cv::Vec2d(-1.0, 1.0); }
    cv::Matx33d referenceOrientation(double tRef, const cv::dynblur::RollingShutter& shutter) const CV_OVERRIDE
    {
        if (std::isnan(tRef))
            tRef = shutter.frameStart + 0.5 * (shutter.rows - 1) * shutter.lineDelay + 0.5 * shutter.exposure;
        return orientation(tRef);
    }
    bool isPlantMotion() const CV_OVERRIDE { return false; }

    //! The angle about camera axis `i` at t, radians.
    double angle(int i, double t) const
    {
        double a = 0;
        for (const Wave& w : waves_[i])
            a += w.amplitude * std::sin(2 * CV_PI * w.frequencyHz * t + w.phase);
        return a;
    }
    //! Its derivative, rad/s.
    double rate(int i, double t) const
    {
        double r = 0;
        for (const Wave& w : waves_[i])
            r += w.amplitude * 2 * CV_PI * w.frequencyHz * std::cos(2 * CV_PI * w.frequencyHz * t + w.phase);
        return r;
    }

private:
    static cv::Matx33d rotation(int axis, double a)
    {
        const double c = std::cos(a), s = std::sin(a);
        if (axis == 0)
            return cv::Matx33d(1, 0, 0, 0, c, -s, 0, s, c);
        if (axis == 1)
            return cv::Matx33d(c, 0, s, 0, 1, 0, -s, 0, c);
        return cv::Matx33d(c, -s, 0, s, c, 0, 0, 0, 1);
    }
    std::vector<Wave> waves_[3];
};

/** A hand-held shake: on each axis two sinusoids between 2 and 17 Hz whose rates peak at about
`peakRateDegPerSec` together (°/s), phases fixed per axis so every test sees the same motion. */
inline cv::Ptr<WaveMotion> handShake(double peakRateDegPerSec)
{
    const double r = peakRateDegPerSec * CV_PI / 180 / 2;  // each of the two waves' peak rate, rad/s
    auto wave = [r](double hz, double phase) { return Wave{r / (2 * CV_PI * hz), hz, phase}; };
    return cv::makePtr<WaveMotion>(std::vector<Wave>{wave(3.1, 0.4), wave(11.0, 2.0)},
                                   std::vector<Wave>{wave(2.3, 1.3), wave(7.7, 0.2)},
                                   std::vector<Wave>{wave(4.4, 2.9), wave(16.5, 1.1)});
}

}  // namespace dynblur_test

#endif
