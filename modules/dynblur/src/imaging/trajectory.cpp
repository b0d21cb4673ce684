// SPDX-License-Identifier: Apache-2.0
// The plant's trajectory over a frame's readout: exact samples at knots, Hermite cubics between.
#include "precomp.hpp"

#include "imaging/trajectory.hpp"
#include "motion/axis_rotation.hpp"

namespace cv {
namespace dynblur {
namespace detail {

namespace {

//! Knots per natural period of the plant: the trajectory is sampled exactly at these instants (and
//! at every switch) and interpolated in between by cubic Hermite polynomials, whose error is
//! ≈ (ωn·h)⁴/384 of the move: < 1e-7 of it (< 1e-5 px for a 10° move at fx = 1230 px). Kernels
//! stay within L1 1e-4 of a dense computation (test PsfGenerator.KernelsMatchADenseReference);
//! half as many knots let a path that comes to rest at a switch reach 4e-4.
const double kKnotsPerPeriod = 100;
//! Largest angle step between two knots, radians (a plant moving faster than its nominal
//! frequency suggests gets denser knots).
const double kMaxKnotAngleStep = 0.02;
/* Any rotation: knots at most this far apart, seconds. A gyroscope's rates are linear between its
   samples, so a pixel's path bends at each sample; a knot interval that holds such a bend is still
   a cubic to h²·Δd''/16: for a 20 Hz, 30 °/s shake at f = 1230 px, under 1e-3 px. */
const double kMaxKnotStepSec = 2.5e-4;
//! ... and turned by at most this much from one knot to the next, radians (2.5 px at f = 1230 px).
const double kMaxKnotRotation = 0.002;

//! The angle of a rotation matrix, radians, in [0, π].
double rotationAngle(const Matx33d& R)
{
    return std::acos(std::min(1.0, std::max(-1.0, 0.5 * (R(0, 0) + R(1, 1) + R(2, 2) - 1.0))));
}

}  // namespace

Matx33d Trajectory::rotation(double a) const
{
    return axisRotation(axis, a);
}

Trajectory sampleTrajectory(const Plant& plant, const SwitchSchedule& schedule, const Vec2d& readout,
                            double thetaRef, const Vec3d& axis)
{
    const double T0 = readout[0], T1 = readout[1];
    Trajectory tr;
    tr.axis = axis;
    if (!(T1 > T0))
        tr.t.assign(1, T0);
    const double fn = plant.getNaturalFreqHz();
    double step = std::isfinite(fn) && fn > 0 ? 1.0 / (kKnotsPerPeriod * fn) : (T1 - T0) / 64;
    for (int refinement = 0;; refinement++)
    {
        if (T1 > T0)
        {
            // Uniform knots, then every switch strictly inside the readout; a uniform knot closer
            // than a tenth of a step to a switch gives way to it.
            const int n = (int)std::min(1.0e6, std::max(4.0, std::ceil((T1 - T0) / step)));
            const double h = (T1 - T0) / n;
            std::vector<std::pair<double, bool>> knots;  // time, is a switch
            for (int i = 0; i <= n; i++)
                knots.emplace_back(i == n ? T1 : T0 + h * i, false);
            for (double s : schedule.times)
                if (s > T0 && s < T1)
                    knots.emplace_back(s, true);
            std::sort(knots.begin(), knots.end());
            tr.t.clear();
            for (size_t i = 0; i < knots.size(); i++)
            {
                const double ti = knots[i].first;
                const bool end = ti == T0 || ti == T1;
                const bool yields = !knots[i].second && !end &&
                                    ((i > 0 && knots[i - 1].second && ti - knots[i - 1].first < 0.1 * h) ||
                                     (i + 1 < knots.size() && knots[i + 1].second && knots[i + 1].first - ti < 0.1 * h));
                if (!yields && (tr.t.empty() || ti > tr.t.back()))
                    tr.t.push_back(ti);
            }
        }
        const int nk = (int)tr.t.size();
        Mat tk(1, nk, CV_64F, tr.t.data()), th, om;
        plant.response(schedule, tk, th);
        plant.velocity(schedule, tk, om);
        tr.angle.resize(nk);
        tr.rate.resize(nk);
        double largestStep = 0;
        for (int i = 0; i < nk; i++)
        {
            tr.angle[i] = th.at<double>(i) - thetaRef;
            tr.rate[i] = om.at<double>(i);
            if (i > 0)
                largestStep = std::max(largestStep, std::abs(tr.angle[i] - tr.angle[i - 1]));
        }
        if (nk < 2 || largestStep <= kMaxKnotAngleStep || refinement >= 8 || nk > 500000)
            break;
        step *= 0.5 * kMaxKnotAngleStep / largestStep;
    }
    tr.rot.resize(tr.t.size());
    tr.invStep.resize(tr.t.size());
    for (size_t i = 0; i < tr.t.size(); i++)
    {
        tr.rot[i] = tr.rotation(tr.angle[i]);
        tr.invStep[i] = i + 1 < tr.t.size() ? 1 / (tr.t[i + 1] - tr.t[i]) : 0.0;
    }
    return tr;
}

Trajectory sampleTrajectory(const ViewMotion& motion, const Vec2d& readout)
{
    if (motion.oneAxis())
        return sampleTrajectory(*motion.plant, motion.schedule, readout, motion.thetaRef, motion.axis);
    const double T0 = readout[0], T1 = readout[1];
    Trajectory tr;
    tr.motion = motion.motion;
    tr.reference = motion.reference;
    int n = T1 > T0 ? (int)std::max(4.0, std::ceil((T1 - T0) / kMaxKnotStepSec)) : 0;
    for (int refinement = 0;; refinement++)
    {
        tr.t.resize(size_t(n) + 1);
        tr.rot.resize(tr.t.size());
        tr.spin.resize(tr.t.size());
        double largestTurn = 0;
        for (int i = 0; i <= n; i++)
        {
            tr.t[size_t(i)] = i == n ? T1 : T0 + (T1 - T0) * i / n;
            tr.rot[size_t(i)] = tr.reference.t() * tr.motion->orientation(tr.t[size_t(i)]);
            tr.spin[size_t(i)] = tr.rot[size_t(i)] * tr.motion->angularVelocity(tr.t[size_t(i)]);
            if (i > 0)
                largestTurn = std::max(largestTurn, rotationAngle(tr.rot[size_t(i) - 1].t() * tr.rot[size_t(i)]));
        }
        if (largestTurn <= kMaxKnotRotation || refinement >= 8 || n > 500000)
            break;
        n = (int)std::min(1.0e6, std::ceil(n * 1.5 * largestTurn / kMaxKnotRotation));
    }
    tr.invStep.resize(tr.t.size());
    for (size_t i = 0; i < tr.t.size(); i++)
        tr.invStep[i] = i + 1 < tr.t.size() ? 1 / (tr.t[i + 1] - tr.t[i]) : 0.0;
    return tr;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
