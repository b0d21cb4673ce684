// SPDX-License-Identifier: Apache-2.0
// Private: the pinhole projection with ViSP's one-term radial distortion and the mapping of a
// camera rotated about its mount axis, shared by CameraModel and the PSF generator.
#ifndef OPENCV_DYNBLUR_IMAGING_PINHOLE_HPP
#define OPENCV_DYNBLUR_IMAGING_PINHOLE_HPP

#include <opencv2/core.hpp>

#include <limits>

namespace cv {
namespace dynblur {

class CameraModel;

namespace detail {

/** @brief Intrinsics (pixels), ViSP's radial distortion and the mount axis: the one place a ray is
projected. Inline because the PSF generator projects once per knot and node. */
struct Pinhole
{
    double fx, fy, cx, cy;  //!< focal lengths and principal point, pixels
    double kud, kdu;        //!< ViSP's undistorted-to-distorted and distorted-to-undistorted terms
    Vec3d axis;             //!< unit mount axis in the camera frame

    //! R·(m.x, m.y, 1): the ray m turned by R.
    static Vec3d turn(const Point2d& m, const Matx33d& R)
    {
        return Vec3d(R(0, 0) * m.x + R(0, 1) * m.y + R(0, 2), R(1, 0) * m.x + R(1, 1) * m.y + R(1, 2),
                     R(2, 0) * m.x + R(2, 1) * m.y + R(2, 2));
    }
    //! Normalised ray (z = 1) of a pixel: ViSP's vpPixelMeterConversion with kdu.
    Point2d undistort(const Point2d& p) const
    {
        const double xd = (p.x - cx) / fx, yd = (p.y - cy) / fy;
        const double f = 1.0 + kdu * (xd * xd + yd * yd);
        return Point2d(xd * f, yd * f);
    }
    //! Pixel of the normalised ray (x, y, 1): ViSP's vpMeterPixelConversion with kud.
    Point2d distort(double x, double y) const
    {
        const double f = 1.0 + kud * (x * x + y * y);
        return Point2d(cx + fx * x * f, cy + fy * y * f);
    }
    /** Pixel q of the ray m (z = 1) turned by R; false (q untouched) when the turned ray leaves the
    reference camera's front half-space. */
    bool project(const Point2d& m, const Matx33d& R, Point2d& q) const
    {
        const Vec3d P = turn(m, R);
        if (!(P[2] > 1e-12))
            return false;
        q = distort(P[0] / P[2], P[1] / P[2]);
        return true;
    }
    /** p + distort(R·undistort(p)) − distort(undistort(p)), NaN behind the camera: corrected so
    that R = I maps p exactly onto itself (CameraModel::viewToReference). */
    Point2d map(const Point2d& p, const Matx33d& R) const
    {
        const Point2d m = undistort(p);
        Point2d q;
        if (!project(m, R, q))
            return nan();
        if (kud == 0.0 && kdu == 0.0)
            return q;
        return p + (q - distort(m.x, m.y));
    }
    //! d = dm − q with q the projection of R·m (the path of a pixel whose ray is m, dm = distort(m)).
    Point2d displacement(const Point2d& m, const Point2d& dm, const Matx33d& R) const
    {
        Point2d q;
        return project(m, R, q) ? dm - q : nan();
    }
    /** d as above and its time derivative for an angle changing at `rate` rad/s: the ray turns as
    dP/dθ = axis × P. Returns false when the ray turns behind the reference camera. */
    bool displacementAndRate(const Point2d& m, const Point2d& dm, const Matx33d& R, double rate, Point2d& d,
                             Point2d& dd) const
    {
        const Vec3d P = turn(m, R);
        const double X = P[0], Y = P[1], Z = P[2];
        if (!(Z > 1e-12))
            return false;
        projectWithRate(dm, P, rate * (axis[1] * Z - axis[2] * Y), rate * (axis[2] * X - axis[0] * Z),
                        rate * (axis[0] * Y - axis[1] * X), d, dd);
        return true;
    }
    /** d as above and its time derivative for a view turning at the spatial rate `spin` (rad/s, in
    the reference camera's frame: R·ω for body rates ω): the ray turns as dP/dt = spin × P. Returns
    false when the ray turns behind the reference camera. */
    bool displacementAndRate(const Point2d& m, const Point2d& dm, const Matx33d& R, const Vec3d& spin, Point2d& d,
                             Point2d& dd) const
    {
        const Vec3d P = turn(m, R);
        const double X = P[0], Y = P[1], Z = P[2];
        if (!(Z > 1e-12))
            return false;
        projectWithRate(dm, P, spin[1] * Z - spin[2] * Y, spin[2] * X - spin[0] * Z, spin[0] * Y - spin[1] * X, d,
                        dd);
        return true;
    }
    /** d = dm − distort(P) and its derivative for the ray P (in front of the camera) moving at
    (dX, dY, dZ); projected with one reciprocal of Z, which the rate needs again. */
    void projectWithRate(const Point2d& dm, const Vec3d& P, double dX, double dY, double dZ, Point2d& d,
                         Point2d& dd) const
    {
        const double iz = 1.0 / P[2], x = P[0] * iz, y = P[1] * iz;
        const double dx = (dX - x * dZ) * iz, dy = (dY - y * dZ) * iz;
        const double f = 1.0 + kud * (x * x + y * y), df = 2 * kud * (x * dx + y * dy);
        d = dm - distort(x, y);
        dd = Point2d(-fx * (dx * f + x * df), -fy * (dy * f + y * df));
    }
    //! Rotation of `angle` radians about the mount axis.
    Matx33d rotation(double angle) const;

    static Point2d nan()
    {
        return Point2d(std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN());
    }
};

//! The pinhole of a camera model (its intrinsics, distortion and mount axis).
Pinhole pinholeOf(const CameraModel& camera);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
