// SPDX-License-Identifier: Apache-2.0
// Private: rotations as unit quaternions (w, x, y, z) and rotation vectors, the exponential and
// logarithm of SO(3) and its right Jacobian, for the sampled motions (sampled_motion.cpp).
//
// Orientations are kept as quaternions between samples because a product of many rotation
// matrices drifts away from SO(3); a quaternion is renormalised by one division.
#ifndef OPENCV_DYNBLUR_MOTION_SO3_HPP
#define OPENCV_DYNBLUR_MOTION_SO3_HPP

#include <opencv2/core.hpp>

#include <cmath>

namespace cv {
namespace dynblur {
namespace so3 {

//! [v]×, the cross-product matrix: skew(v)·u = v × u.
inline Matx33d skew(const Vec3d& v)
{
    return Matx33d(0, -v[2], v[1], v[2], 0, -v[0], -v[1], v[0], 0);
}

//! The Hamilton product a ⊗ b (the rotation b first, then a, as for matrices A·B).
inline Vec4d multiply(const Vec4d& a, const Vec4d& b)
{
    return Vec4d(a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
                 a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
                 a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
                 a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]);
}

inline Vec4d conjugate(const Vec4d& q)
{
    return Vec4d(q[0], -q[1], -q[2], -q[3]);
}

inline Vec4d normalized(const Vec4d& q)
{
    return q * (1.0 / std::sqrt(q.dot(q)));
}

//! exp of the rotation vector φ (radians) as a unit quaternion.
inline Vec4d quatFromRotationVector(const Vec3d& phi)
{
    const double theta = std::sqrt(phi.dot(phi));
    // sin(θ/2)/θ by its series below 1e-4 rad, where the quotient loses digits.
    const double k = theta < 1e-4 ? 0.5 - theta * theta / 48.0 : std::sin(0.5 * theta) / theta;
    return Vec4d(std::cos(0.5 * theta), k * phi[0], k * phi[1], k * phi[2]);
}

//! log of a unit quaternion: the rotation vector (radians, angle in [0, π]) of the shorter rotation.
inline Vec3d rotationVectorFromQuat(Vec4d q)
{
    if (q[0] < 0)
        q = -q;
    const double n = std::sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    // angle/n = 2·atan2(n, w)/n → 2/w as n → 0 (w → 1).
    const double k = n < 1e-12 ? 2.0 / q[0] : 2.0 * std::atan2(n, q[0]) / n;
    return Vec3d(k * q[1], k * q[2], k * q[3]);
}

inline Matx33d matrixFromQuat(const Vec4d& q)
{
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    return Matx33d(1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                   2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                   2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y));
}

//! The unit quaternion of a rotation matrix (Shepperd's method: the largest of the four squares
//! first, so no branch divides by a small number).
inline Vec4d quatFromMatrix(const Matx33d& R)
{
    const double tr = R(0, 0) + R(1, 1) + R(2, 2);
    Vec4d q;
    if (tr >= R(0, 0) && tr >= R(1, 1) && tr >= R(2, 2))
    {
        const double s = 2.0 * std::sqrt(std::max(1.0 + tr, 1e-300));
        q = Vec4d(0.25 * s, (R(2, 1) - R(1, 2)) / s, (R(0, 2) - R(2, 0)) / s, (R(1, 0) - R(0, 1)) / s);
    }
    else if (R(0, 0) >= R(1, 1) && R(0, 0) >= R(2, 2))
    {
        const double s = 2.0 * std::sqrt(std::max(1.0 + R(0, 0) - R(1, 1) - R(2, 2), 1e-300));
        q = Vec4d((R(2, 1) - R(1, 2)) / s, 0.25 * s, (R(0, 1) + R(1, 0)) / s, (R(0, 2) + R(2, 0)) / s);
    }
    else if (R(1, 1) >= R(2, 2))
    {
        const double s = 2.0 * std::sqrt(std::max(1.0 + R(1, 1) - R(0, 0) - R(2, 2), 1e-300));
        q = Vec4d((R(0, 2) - R(2, 0)) / s, (R(0, 1) + R(1, 0)) / s, 0.25 * s, (R(1, 2) + R(2, 1)) / s);
    }
    else
    {
        const double s = 2.0 * std::sqrt(std::max(1.0 + R(2, 2) - R(0, 0) - R(1, 1), 1e-300));
        q = Vec4d((R(1, 0) - R(0, 1)) / s, (R(0, 2) + R(2, 0)) / s, (R(1, 2) + R(2, 1)) / s, 0.25 * s);
    }
    return normalized(q);
}

/** The right Jacobian J_r(v) of SO(3): for Q(t) = Q₀·exp([v(t)]×) the body rate is ω = J_r(v)·v̇.
    J_r = I − (1 − cos θ)/θ²·[v]× + (θ − sin θ)/θ³·[v]×², θ = |v| @cite Iserles2000Lie. */
inline Matx33d rightJacobian(const Vec3d& v)
{
    const double t2 = v.dot(v), theta = std::sqrt(t2);
    const double a = theta < 1e-4 ? 0.5 - t2 / 24.0 : (1.0 - std::cos(theta)) / t2;
    const double b = theta < 1e-4 ? 1.0 / 6.0 - t2 / 120.0 : (theta - std::sin(theta)) / (t2 * theta);
    const Matx33d S = skew(v);
    return Matx33d::eye() - a * S + b * (S * S);
}

/** J_r(v)⁻¹ = I + ½[v]× + (1/θ² − cot(θ/2)/(2θ))·[v]×², θ = |v| ≤ π (written with cot(θ/2) rather
    than (1 + cos θ)/sin θ, which is 0/0 at θ = π). */
inline Matx33d rightJacobianInverse(const Vec3d& v)
{
    const double t2 = v.dot(v), theta = std::sqrt(t2);
    const double c = theta < 1e-4 ? 1.0 / 12.0 + t2 / 720.0 : 1.0 / t2 - 0.5 / (theta * std::tan(0.5 * theta));
    const Matx33d S = skew(v);
    return Matx33d::eye() + 0.5 * S + c * (S * S);
}

/** How far a 3×3 matrix is from a rotation: max(|RᵀR − I| entrywise, |det R − 1|). Rotations
    given by callers are accepted within 1e-3 of SO(3) and projected onto it (quatFromMatrix). */
inline double rotationDefect(const Matx33d& R)
{
    const Matx33d E = R.t() * R - Matx33d::eye();
    double worst = std::abs(determinant(R) - 1.0);
    for (int i = 0; i < 9; ++i)
        worst = std::max(worst, std::abs(E.val[i]));
    return worst;
}

}  // namespace so3
}  // namespace dynblur
}  // namespace cv

#endif
