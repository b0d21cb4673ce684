// SPDX-License-Identifier: Apache-2.0
// Switching schedules as phasors in normalised time τ = ωn t (DESIGN §2, "Residual vibration of a
// schedule"): the step response, the Newton solve of the switching instants that close the phasor
// polygon, the settle time and the worst vibration over an ωn error. Shared by SwitchPlanner (one
// axis) and MountPlanner (an axis coordinated with another); planner.cpp explains the method.
#ifndef OPENCV_DYNBLUR_SWITCH_PHASORS_HPP
#define OPENCV_DYNBLUR_SWITCH_PHASORS_HPP

#include <opencv2/core.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <complex>
#include <vector>

namespace cv {
namespace dynblur {
namespace phasors {

typedef std::complex<double> Complex;

//! The plant's pole in normalised time τ = ωn t.
struct NormalisedPole
{
    double zeta;          //!< damping ratio
    double dampedFactor;  //!< √(1−ζ²): damped frequency over ωn
    Complex s;            //!< ζ + j√(1−ζ²)

    explicit NormalisedPole(double dampingRatio)
        : zeta(dampingRatio), dampedFactor(std::sqrt(1 - dampingRatio * dampingRatio)),
          s(dampingRatio, std::sqrt(1 - dampingRatio * dampingRatio))
    {
    }

    //! Unit-step response at normalised age τ ≥ 0.
    double step(double tau) const
    {
        return 1 - std::exp(-zeta * tau)
                       * (std::cos(dampedFactor * tau) + zeta / dampedFactor * std::sin(dampedFactor * tau));
    }

    //! d/dτ of step(τ).
    double stepRate(double tau) const
    {
        return std::exp(-zeta * tau) * std::sin(dampedFactor * tau) / dampedFactor;
    }
};

//! A candidate move in normalised time: level steps and the instants they happen at (τ₀ = 0).
struct Candidate
{
    std::vector<int> levels;    //!< level switched on at each instant; the last is the target
    std::vector<double> tau;    //!< normalised instants from the first switch (the leader's for a delayed follower)
    double settle = 0;          //!< normalised settle time
    double worstVibration = 0;  //!< worst residual vibration over the robust range, fraction of the move
};

//! Angle in levels at normalised time τ for the schedule startLevel → levels at tau.
inline double angleInLevels(const NormalisedPole& pole, int startLevel, const std::vector<int>& levels,
                     const std::vector<double>& tau, double t)
{
    double angle = startLevel;
    int previous = startLevel;
    for (size_t i = 0; i < levels.size() && tau[i] <= t; ++i)
    {
        angle += (levels[i] - previous) * pole.step(t - tau[i]);
        previous = levels[i];
    }
    return angle;
}

//! Angular rate in levels per normalised time unit at τ.
inline double rateInLevels(const NormalisedPole& pole, int startLevel, const std::vector<int>& levels,
                    const std::vector<double>& tau, double t)
{
    double rate = 0;
    int previous = startLevel;
    for (size_t i = 0; i < levels.size() && tau[i] <= t; ++i)
    {
        rate += (levels[i] - previous) * pole.stepRate(t - tau[i]);
        previous = levels[i];
    }
    return rate;
}

/** Solves the N free instants τ₁..τ_N (τ₀ = 0) of N+1 level steps so that F = 0 (N = 2) or
F = G = 0 (N = 4). Returns false when Newton does not converge or the result breaks the order or
the dwell. `tau` holds the starting point on entry (N+1 values, tau[0] = 0). */
template <int N>
bool solveInstants(const NormalisedPole& pole, const int* steps, double* tau, double minDwellTau, double maxTau)
{
    typedef Eigen::Matrix<double, N, N> Jacobian;
    typedef Eigen::Matrix<double, N, 1> Vector;
    double stepScale = 0;
    for (int i = 0; i <= N; ++i)
        stepScale += std::abs(steps[i]);
    const double tolerance = 1e-12 * stepScale;
    // Newton steps longer than this (a tenth of a damped period) overshoot into other roots.
    const double maxNewtonStep = 0.6;
    Vector x;
    for (int k = 0; k < N; ++k)
        x[k] = tau[k + 1];
    for (int iteration = 0; iteration < 30; ++iteration)
    {
        Complex sumF = static_cast<double>(steps[0]);  // τ₀ = 0: e^{s·0} = 1, τ₀·1 = 0
        Complex sumG(0, 0);
        Jacobian jacobian;
        for (int k = 0; k < N; ++k)
        {
            const double t = x[k];
            const Complex z = static_cast<double>(steps[k + 1]) * std::exp(pole.s * t);
            sumF += z;
            const Complex dF = pole.s * z;
            jacobian(0, k) = dF.real();
            jacobian(1, k) = dF.imag();
            if constexpr (N == 4)
            {
                sumG += t * z;
                const Complex dG = (1.0 + pole.s * t) * z;
                jacobian(2, k) = dG.real();
                jacobian(3, k) = dG.imag();
            }
        }
        Vector residual;
        residual[0] = sumF.real();
        residual[1] = sumF.imag();
        if constexpr (N == 4)
        {
            residual[2] = sumG.real();
            residual[3] = sumG.imag();
        }
        const double residualNorm = residual.norm();
        // Newton converges in a handful of steps near a root; a start still far from one after a
        // dozen steps is wandering, and giving up early is most of the search's speed.
        if (iteration >= 12 && residualNorm > 1e-3 * stepScale)
            return false;
        if (residualNorm < tolerance)
        {
            for (int k = 0; k < N; ++k)
                tau[k + 1] = x[k];
            for (int k = 1; k <= N; ++k)
                if (tau[k] - tau[k - 1] < minDwellTau * (1 - 1e-9))
                    return false;
            return true;
        }
        Vector delta = jacobian.partialPivLu().solve(residual);
        if (!delta.allFinite())
            return false;
        const double longest = delta.cwiseAbs().maxCoeff();
        if (longest > maxNewtonStep)
            delta *= maxNewtonStep / longest;
        x -= delta;
        if (x.minCoeff() < -1.0 || x.maxCoeff() > maxTau)
            return false;
    }
    return false;
}

//! Normalised starting points for N free instants, as fractions of a damped period; sorted.
inline std::vector<std::vector<double>> startingPoints(int freeInstants, double dampedPeriodTau)
{
    std::vector<std::vector<double>> starts;
    if (freeInstants == 2)
    {
        // A grid over (τ₁, τ₂ − τ₁): the 3-switch problem has few roots per level sequence.
        const double fractions[] = {0.05, 0.15, 0.3, 0.5};
        for (double first : fractions)
            for (double gap : fractions)
                starts.push_back({first * dampedPeriodTau, (first + gap) * dampedPeriodTau});
        return starts;
    }
    // Robust: low-discrepancy (Halton, bases 2, 3, 5, 7) points in [0.02, 1.2] damped periods,
    // sorted; deterministic so that plans are reproducible.
    const int bases[] = {2, 3, 5, 7};
    for (int index = 1; index <= 8; ++index)
    {
        std::vector<double> point;
        for (int b = 0; b < freeInstants; ++b)
        {
            double value = 0, weight = 1.0 / bases[b];
            for (int i = index; i > 0; i /= bases[b], weight /= bases[b])
                value += (i % bases[b]) * weight;
            point.push_back((0.02 + 1.18 * value) * dampedPeriodTau);
        }
        std::sort(point.begin(), point.end());
        starts.push_back(point);
    }
    return starts;
}

//! Worst residual vibration over ωn·(1+e), |e| ≤ robustRange, fraction of the move; stops early
//! once it exceeds robustTolerance.
inline double worstVibration(const NormalisedPole& pole, int startLevel, const Candidate& candidate, double move,
                             double robustRange, double robustTolerance)
{
    const int samples = 41;
    const double lastTau = candidate.tau.back();
    double worst = 0;
    // The ends of the range first: V grows away from the nominal ωn, so they usually decide,
    // and a candidate that fails there needs no more samples.
    for (int n = 0; n < samples; ++n)
    {
        const int k = n == 0 ? 0 : n == 1 ? samples - 1 : n - 1;
        if (n >= 2 && worst > robustTolerance)
            break;
        const double scale = 1 + robustRange * (2.0 * k / (samples - 1) - 1);
        // A true ωn scaled by `scale` sees every normalised instant scaled by it too.
        Complex sum(0, 0);
        int previous = startLevel;
        for (size_t i = 0; i < candidate.levels.size(); ++i)
        {
            sum += static_cast<double>(candidate.levels[i] - previous)
                   * std::exp(pole.s * (scale * candidate.tau[i]) - pole.zeta * scale * lastTau);
            previous = candidate.levels[i];
        }
        worst = std::max(worst, std::abs(sum) / move);
    }
    return worst;
}

/** Normalised time after which |θ − target| ≤ tolerance (levels) for good. The candidate's
vibration after the last switch is (near) zero, so the search goes backwards from the last instant. */
inline double settleTime(const NormalisedPole& pole, int startLevel, const Candidate& candidate, double tolerance)
{
    const int target = candidate.levels.back();
    auto outside = [&](double t) {
        return std::abs(angleInLevels(pole, startLevel, candidate.levels, candidate.tau, t) - target) > tolerance;
    };
    // Steps of 1/200 of a damped period: the error cannot leave and re-enter the band between
    // two samples (it moves on the time scale of the oscillation).
    const double step = 2 * CV_PI / pole.dampedFactor / 200;
    // Candidates are roots of F = 0: from the last switch on the angle is exactly the target.
    double inside = candidate.tau.back();
    double t = inside - step;
    while (t > 0 && !outside(t))
    {
        inside = t;
        t -= step;
    }
    if (t <= 0)
        return 0;
    double out = t;
    for (int i = 0; i < 30; ++i)
    {
        const double middle = 0.5 * (out + inside);
        (outside(middle) ? out : inside) = middle;
    }
    return inside;
}

}  // namespace phasors
}  // namespace dynblur
}  // namespace cv

#endif
