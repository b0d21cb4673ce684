// SPDX-License-Identifier: Apache-2.0
// CameraMotion from samples: gyroscope rates integrated on SO(3) (fromAngularVelocity) and
// orientations interpolated by a C¹ cubic on SO(3) (fromOrientations).
#include "precomp.hpp"

#include "motion/sampled_motion.hpp"
#include "motion/so3.hpp"

namespace cv {
namespace dynblur {
namespace detail {

size_t findLongGap(const std::vector<double>& times, double& median)
{
    std::vector<double> steps(times.size() - 1);
    for (size_t k = 1; k < times.size(); ++k)
        steps[k - 1] = times[k] - times[k - 1];
    std::vector<double> sorted = steps;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    median = sorted[sorted.size() / 2];
    for (size_t k = 0; k < steps.size(); ++k)
        if (steps[k] > kMaxGapInMedianIntervals * median * (1 + 1e-9))  // timestamps' rounding is no gap
            return k + 1;
    return 0;
}

namespace {

const char* const kAngularVelocity = "CameraMotion::fromAngularVelocity";
const char* const kOrientations = "CameraMotion::fromOrientations";

//! Sample times: a finite, strictly increasing vector of ≥ 2 seconds without long gaps.
std::vector<double> readSampleTimes(InputArray times, const char* function)
{
    const Mat m = times.getMat();
    if (m.empty() || m.channels() != 1 || (m.depth() != CV_64F && m.depth() != CV_32F) ||
        (m.rows != 1 && m.cols != 1))
        CV_Error_(Error::StsBadArg, ("%s: 'times' must be an N×1 or 1×N one-channel CV_64F or CV_32F vector of "
                                     "sample times (seconds), got %d×%d with %d channel(s) of depth %d",
                                     function, m.rows, m.cols, m.channels(), m.depth()));
    Mat asDouble;
    m.reshape(1, 1).convertTo(asDouble, CV_64F);
    std::vector<double> t(asDouble.begin<double>(), asDouble.end<double>());
    if (t.size() < 2)
        CV_Error_(Error::StsBadArg, ("%s: 'times' has %zu sample(s); a sampled motion needs at least 2", function,
                                     t.size()));
    for (size_t k = 0; k < t.size(); ++k)
    {
        if (!std::isfinite(t[k]))
            CV_Error_(Error::StsBadArg, ("%s: times[%zu] = %g is not finite (seconds)", function, k, t[k]));
        if (k > 0 && !(t[k] > t[k - 1]))
            CV_Error_(Error::StsBadArg, ("%s: 'times' must be strictly increasing (no repeated or unsorted samples), "
                                         "but times[%zu] = %.9g s <= times[%zu] = %.9g s",
                                         function, k, t[k], k - 1, t[k - 1]));
    }
    double median = 0;
    if (const size_t k = findLongGap(t, median))
        CV_Error_(Error::StsBadArg, ("%s: 'times' has a gap of %.6g s between times[%zu] = %.9g s and times[%zu] = "
                                     "%.9g s, longer than %g median sample intervals (%.6g s): samples are missing",
                                     function, t[k] - t[k - 1], k - 1, t[k - 1], k, t[k],
                                     kMaxGapInMedianIntervals, median));
    return t;
}

/** One row of `columns` finite values per sample, as N×columns CV_64F: a one-channel N×C array or
    an N×1 C-channel one, CV_64F or CV_32F, with C one of `allowed` (a zero-terminated list). */
Mat readSampleRows(InputArray values, size_t samples, const int* allowed, const char* function, const char* name,
                   const char* what)
{
    const Mat m = values.getMat();
    const int columns = m.channels() == 1 ? m.cols : (m.cols == 1 ? m.channels() : 0);
    bool columnsAllowed = false;
    for (const int* c = allowed; *c; ++c)
        columnsAllowed = columnsAllowed || columns == *c;
    if (m.empty() || !columnsAllowed || (m.depth() != CV_64F && m.depth() != CV_32F))
        CV_Error_(Error::StsBadArg, ("%s: '%s' must be %s, CV_64F or CV_32F (N×C one-channel or N×1 C-channel); "
                                     "got %d×%d with %d channel(s) of depth %d",
                                     function, name, what, m.rows, m.cols, m.channels(), m.depth()));
    if (size_t(m.rows) != samples)
        CV_Error_(Error::StsBadArg, ("%s: '%s' has %d rows but 'times' has %zu samples; one row per sample",
                                     function, name, m.rows, samples));
    Mat rows;
    m.reshape(1, m.rows).convertTo(rows, CV_64F);
    for (int i = 0; i < rows.rows; ++i)
        for (int j = 0; j < rows.cols; ++j)
            if (!std::isfinite(rows.at<double>(i, j)))
                CV_Error_(Error::StsBadArg, ("%s: %s[%d][%d] = %g is not finite", function, name, i, j,
                                             rows.at<double>(i, j)));
    return rows;
}

Vec4d quatFromRotation(const Matx33d& R, const char* function, const char* name)
{
    const double defect = so3::rotationDefect(R);
    if (!(defect <= 1e-3))
        CV_Error_(Error::StsBadArg, ("%s: %s is not a rotation: det = %.6g and RᵀR differs from I by up to %.3g; "
                                     "a proper rotation (orthonormal, det = +1, within 1e-3) is required",
                                     function, name, determinant(R), defect));
    return so3::quatFromMatrix(R);
}

/** The derivative at every sample of the curve whose difference quotient over [t_k, t_{k+1}] is d_k:
    the three-point (quadratic) derivative, second order on any grid, with
    (h_k·d_{k−1} + h_{k−1}·d_k)/(h_{k−1} + h_k) inside and the one-sided quadratic's at the ends
    (d_0 for both ends of a single interval). */
std::vector<Vec3d> threePointDerivative(const std::vector<double>& t, const std::vector<Vec3d>& d)
{
    const size_t n = t.size();
    auto h = [&t](size_t k) { return t[k + 1] - t[k]; };
    std::vector<Vec3d> m(n, d[0]);
    if (n == 2)
        return m;
    for (size_t k = 1; k + 1 < n; ++k)
        m[k] = (d[k - 1] * h(k) + d[k] * h(k - 1)) * (1.0 / (h(k - 1) + h(k)));
    m[0] = d[0] + (d[0] - d[1]) * (h(0) / (h(0) + h(1)));
    m[n - 1] = d[n - 2] + (d[n - 2] - d[n - 3]) * (h(n - 2) / (h(n - 2) + h(n - 3)));
    return m;
}

//! The cubic Hermite curve of values y0, y1 and derivatives m0, m1 (per second) over an interval of h seconds, at s ∈ [0, 1].
inline Vec3d hermite(const Vec3d& y0, const Vec3d& y1, const Vec3d& m0, const Vec3d& m1, double h, double s)
{
    const double s2 = s * s, s3 = s2 * s;
    return y0 * (2 * s3 - 3 * s2 + 1) + y1 * (3 * s2 - 2 * s3) + (m0 * (s3 - 2 * s2 + s) + m1 * (s3 - s2)) * h;
}

//! What the sampled motions share: the span, the segment lookup and the default reference.
class SampledMotion : public CameraMotion
{
public:
    explicit SampledMotion(std::vector<double> times) : t_(std::move(times)) {}

    Vec2d getTimeSpan() const CV_OVERRIDE { return Vec2d(t_.front(), t_.back()); }
    bool isPlantMotion() const CV_OVERRIDE { return false; }

    Matx33d referenceOrientation(double tRef, const RollingShutter& shutter) const CV_OVERRIDE
    {
        if (std::isinf(tRef))
            CV_Error(Error::StsBadArg, "CameraMotion::referenceOrientation: tRef must be finite (seconds) or NaN "
                                       "(the middle of the frame's exposure)");
        if (std::isnan(tRef))
        {
            shutter.validate();
            // The middle row's mid-exposure instant (DESIGN §2 Rotation).
            tRef = shutter.frameStart + 0.5 * (shutter.rows - 1) * shutter.lineDelay + 0.5 * shutter.exposure;
        }
        return so3::matrixFromQuat(quatAt(tRef, "CameraMotion::referenceOrientation"));
    }

    Matx33d orientation(double t) const CV_OVERRIDE
    {
        return so3::matrixFromQuat(quatAt(t, "CameraMotion::orientation"));
    }

protected:
    //! The segment [t_k, t_{k+1}] holding t (the last one for t at the end); throws outside the span.
    size_t segment(double t, const char* function) const
    {
        if (!(t >= t_.front() && t <= t_.back()))
            CV_Error_(Error::StsOutOfRange, ("%s: t = %.9g s lies outside the motion's time span [%.9g, %.9g] s "
                                             "(its first and last sample, same clock as the shutter's frameStart)",
                                             function, t, t_.front(), t_.back()));
        const size_t after = size_t(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin());
        return std::min(after, t_.size() - 1) - 1;
    }
    virtual Vec4d quatAt(double t, const char* function) const = 0;

    std::vector<double> t_;
};

/** Gyroscope rates integrated by the fourth-order Magnus step with two Gauss points
    @cite Iserles2000Lie. Between samples the rate is the C¹ cubic Hermite curve through them whose
    slopes are the three-point derivative (threePointDerivative): a rate that is smooth between
    samples is followed to O(h⁴) where a linear one errs by O(h²) (a plant's 14 Hz ringing sampled at
    1 kHz: 2e-4 rad linear). For Q' = Q·[ω]× over [t_k, t_k + τ] with the rate's values ω₁, ω₂ at
    t_k + (1/2 ∓ √3/6)·τ,
        φ = τ/2·(ω₁ + ω₂) + (√3/12)·τ²·(ω₁ × ω₂),   Q(t_k + τ) = Q(t_k)·exp([φ]×).
    The commutator's sign is that of right multiplication by the body rate; the test against a dense
    RK4 solution holds it. */
class AngularVelocityMotion CV_FINAL : public SampledMotion
{
public:
    AngularVelocityMotion(std::vector<double> times, const Mat& rates, const Vec4d& initial)
        : SampledMotion(std::move(times)), w_(t_.size()), q_(t_.size())
    {
        const size_t n = t_.size();
        for (size_t k = 0; k < n; ++k)
            w_[k] = Vec3d(rates.ptr<double>(int(k)));
        std::vector<Vec3d> d(n - 1);
        for (size_t k = 0; k + 1 < n; ++k)
            d[k] = (w_[k + 1] - w_[k]) * (1.0 / (t_[k + 1] - t_[k]));
        m_ = threePointDerivative(t_, d);
        q_[0] = initial;
        for (size_t k = 0; k + 1 < n; ++k)
        {
            // Half a turn or more between two samples cannot be told from a slower turn the other
            // way: the log undersamples the motion, or its rates are in the wrong unit.
            const double angle = norm(w_[k] + w_[k + 1]) * 0.5 * (t_[k + 1] - t_[k]);
            if (!(angle < CV_PI) || !std::isfinite(norm(m_[k])))
                CV_Error_(Error::StsBadArg, ("CameraMotion::fromAngularVelocity: between times[%zu] and times[%zu] "
                                             "the rates turn the camera by %.3g rad, not less than π per sample "
                                             "interval; check the rates' unit (rad/s) and the sampling",
                                             k, k + 1, angle));
            q_[k + 1] = stepFrom(k, t_[k + 1] - t_[k]);
        }
    }

    Vec3d angularVelocity(double t) const CV_OVERRIDE
    {
        const size_t k = segment(t, "CameraMotion::angularVelocity");
        return rateAt(k, t - t_[k]);
    }
    String getDefaultName() const CV_OVERRIDE { return "dynblur.CameraMotion.AngularVelocity"; }

private:
    Vec4d quatAt(double t, const char* function) const CV_OVERRIDE
    {
        const size_t k = segment(t, function);
        return stepFrom(k, t - t_[k]);
    }

    //! ω(t_k + tau), 0 ≤ tau ≤ t_{k+1} − t_k.
    Vec3d rateAt(size_t k, double tau) const
    {
        const double h = t_[k + 1] - t_[k];
        return hermite(w_[k], w_[k + 1], m_[k], m_[k + 1], h, tau / h);
    }

    //! Q(t_k + tau) for 0 ≤ tau ≤ t_{k+1} − t_k: one Magnus step over the partial interval.
    Vec4d stepFrom(size_t k, double tau) const
    {
        static const double g = std::sqrt(3.0) / 6.0;
        const Vec3d w1 = rateAt(k, (0.5 - g) * tau), w2 = rateAt(k, (0.5 + g) * tau);
        const Vec3d phi = (w1 + w2) * (0.5 * tau) + w1.cross(w2) * (0.5 * g * tau * tau);
        return so3::normalized(so3::multiply(q_[k], so3::quatFromRotationVector(phi)));
    }

    std::vector<Vec3d> w_;  //!< rates at the samples, rad/s, camera frame
    std::vector<Vec3d> m_;  //!< their time derivatives, rad/s²
    std::vector<Vec4d> q_;  //!< Q at the samples
};

/** Orientations joined by a C¹ cubic on SO(3) @cite Kim1995General. On [t_k, t_{k+1}], h = t_{k+1} − t_k,
    s = (t − t_k)/h: Q(t) = Q_k·exp([v(s)]×), v the cubic Hermite curve with v(0) = 0, v(1) = r_k =
    log(Q_kᵀQ_{k+1}) (the shorter rotation), v'(0) = h·ω_k and v'(1) = h·J_r(r_k)⁻¹·ω_{k+1}, so the body
    rate ω = J_r(v)·v'(s)/h equals the sample rate ω_k at both ends of every segment. The sample
    rates are the three-point derivative (threePointDerivative) of the rotations' quotients
    d_k = r_k/h_k (d_k is the same vector in frames k and k+1: it is r_k's axis). */
class OrientationSplineMotion CV_FINAL : public SampledMotion
{
public:
    OrientationSplineMotion(std::vector<double> times, std::vector<Vec4d> q)
        : SampledMotion(std::move(times)), q_(std::move(q)), r_(t_.size() - 1), m1_(t_.size() - 1), w_(t_.size())
    {
        const size_t n = t_.size();
        std::vector<Vec3d> d(n - 1);
        for (size_t k = 0; k + 1 < n; ++k)
        {
            r_[k] = so3::rotationVectorFromQuat(so3::multiply(so3::conjugate(q_[k]), q_[k + 1]));
            d[k] = r_[k] * (1.0 / (t_[k + 1] - t_[k]));
        }
        w_ = threePointDerivative(t_, d);
        for (size_t k = 0; k + 1 < n; ++k)
        {
            m1_[k] = so3::rightJacobianInverse(r_[k]) * w_[k + 1] * (t_[k + 1] - t_[k]);
            if (!std::isfinite(norm(w_[k])) || !std::isfinite(norm(m1_[k])))
                CV_Error_(Error::StsBadArg, ("CameraMotion::fromOrientations: the rate near times[%zu] = %.9g s "
                                             "overflows: the sample interval is too short for the rotation",
                                             k, t_[k]));
        }
    }

    Vec3d angularVelocity(double t) const CV_OVERRIDE
    {
        Vec3d v, dv;
        const size_t k = evaluate(t, "CameraMotion::angularVelocity", v, dv);
        return so3::rightJacobian(v) * dv * (1.0 / (t_[k + 1] - t_[k]));
    }
    String getDefaultName() const CV_OVERRIDE { return "dynblur.CameraMotion.Orientations"; }

private:
    Vec4d quatAt(double t, const char* function) const CV_OVERRIDE
    {
        Vec3d v, dv;
        const size_t k = evaluate(t, function, v, dv);
        return so3::normalized(so3::multiply(q_[k], so3::quatFromRotationVector(v)));
    }

    //! The segment of t, v(s) and dv/ds there.
    size_t evaluate(double t, const char* function, Vec3d& v, Vec3d& dv) const
    {
        const size_t k = segment(t, function);
        const double h = t_[k + 1] - t_[k], s = (t - t_[k]) / h, s2 = s * s, s3 = s2 * s;
        const Vec3d m0 = w_[k] * h;
        v = m0 * (s3 - 2 * s2 + s) + r_[k] * (3 * s2 - 2 * s3) + m1_[k] * (s3 - s2);
        dv = m0 * (3 * s2 - 4 * s + 1) + r_[k] * (6 * s - 6 * s2) + m1_[k] * (3 * s2 - 2 * s);
        return k;
    }

    std::vector<Vec4d> q_;   //!< Q at the samples
    std::vector<Vec3d> r_;   //!< log(Q_kᵀ Q_{k+1}), radians
    std::vector<Vec3d> m1_;  //!< v'(1) of each segment
    std::vector<Vec3d> w_;   //!< body rates at the samples, rad/s
};

}  // namespace
}  // namespace detail

Ptr<CameraMotion> CameraMotion::fromAngularVelocity(InputArray times, InputArray rates,
                                                    const Matx33d& initialOrientation)
{
    std::vector<double> t = detail::readSampleTimes(times, detail::kAngularVelocity);
    static const int three[] = {3, 0};
    const Mat w = detail::readSampleRows(rates, t.size(), three, detail::kAngularVelocity, "rates",
                                         "N×3 body rates (rad/s, camera axes)");
    const Vec4d q0 = detail::quatFromRotation(initialOrientation, detail::kAngularVelocity, "initialOrientation");
    return makePtr<detail::AngularVelocityMotion>(std::move(t), w, q0);
}

Ptr<CameraMotion> CameraMotion::fromOrientations(InputArray times, InputArray rotations)
{
    using namespace detail;
    std::vector<double> t = readSampleTimes(times, kOrientations);
    static const int allowed[] = {3, 4, 9, 0};
    const Mat rows = readSampleRows(rotations, t.size(), allowed, kOrientations, "rotations",
                                    "N×3 rotation vectors (radians), N×4 unit quaternions (w, x, y, z) or N×9 "
                                    "row-major rotation matrices");
    std::vector<Vec4d> q(t.size());
    for (int k = 0; k < rows.rows; ++k)
    {
        const double* r = rows.ptr<double>(k);
        if (rows.cols == 3)
            q[k] = so3::quatFromRotationVector(Vec3d(r));
        else if (rows.cols == 4)
        {
            const Vec4d raw(r);
            const double norm = std::sqrt(raw.dot(raw));
            if (!(std::abs(norm - 1.0) <= 1e-3))
                CV_Error_(Error::StsBadArg, ("%s: rotations[%d] = (%g, %g, %g, %g) has norm %.6g; unit quaternions "
                                             "(w, x, y, z) are required, with |q| within 1e-3 of 1",
                                             kOrientations, k, r[0], r[1], r[2], r[3], norm));
            q[k] = raw * (1.0 / norm);
        }
        else
            q[k] = quatFromRotation(Matx33d(r), kOrientations, format("rotations[%d]", k).c_str());
    }
    return makePtr<OrientationSplineMotion>(std::move(t), std::move(q));
}

}  // namespace dynblur
}  // namespace cv
