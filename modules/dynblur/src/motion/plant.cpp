// SPDX-License-Identifier: Apache-2.0
#include "precomp.hpp"
#include "motion/time_vector.hpp"

#include <Eigen/Core>
#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>

#include <complex>

namespace cv {
namespace dynblur {

// ---------------------------------------------------------------------------------------------
// Shared helpers

std::vector<double> readTimeVector(InputArray t, const char* argName)
{
    Mat m = t.getMat();
    if (m.empty())
        return {};
    if (m.channels() != 1 || (m.depth() != CV_64F && m.depth() != CV_32F))
        CV_Error(Error::StsBadArg,
                 format("'%s' must be a one-channel CV_64F or CV_32F array of times (seconds)", argName));
    Mat asDouble;
    m.reshape(1, 1).convertTo(asDouble, CV_64F);
    std::vector<double> values(asDouble.begin<double>(), asDouble.end<double>());
    for (size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i]))
            CV_Error(Error::StsBadArg, format("'%s'[%zu] is not finite", argName, i));
    return values;
}

double* allocateTimeOutput(InputArray t, OutputArray out, std::vector<double>& times)
{
    times = readTimeVector(t, "t");
    if (times.empty())
    {
        out.release();
        return nullptr;
    }
    out.create(t.size(), CV_64F);
    Mat result = out.getMat();
    CV_Assert(result.isContinuous());
    return result.ptr<double>();
}

static const double kMaxNaturalFreqHz = 1000.0;
static const double kMaxGainRadPerLevel = CV_PI / 12;

static void checkFrequencyAndDamping(double naturalFreqHz, double dampingRatio)
{
    if (!(std::isfinite(naturalFreqHz) && naturalFreqHz > 0))
        CV_Error(Error::StsOutOfRange,
                 format("naturalFreqHz = %g must be finite and > 0 (Hz)", naturalFreqHz));
    // A camera positioner resonates at Hz to hundreds of Hz, and turns by a fraction of a degree to a
    // few degrees per level; values far outside are unit mistakes (kHz, rad/s, degrees as radians).
    if (naturalFreqHz > kMaxNaturalFreqHz)
        CV_Error(Error::StsOutOfRange,
                 format("naturalFreqHz = %g Hz is implausible for a camera positioner (at most %g Hz): ωn/2π in Hz "
                        "expected (the seed's is 14.4)", naturalFreqHz, kMaxNaturalFreqHz));
    if (!(std::isfinite(dampingRatio) && dampingRatio > 0 && dampingRatio < 1))
        CV_Error(Error::StsOutOfRange,
                 format("dampingRatio = %g must lie in the open interval (0, 1)", dampingRatio));
}

static void checkLinearParameters(double naturalFreqHz, double dampingRatio, double gain)
{
    checkFrequencyAndDamping(naturalFreqHz, dampingRatio);
    if (!(std::isfinite(gain) && gain != 0))
        CV_Error(Error::StsOutOfRange, format("gain = %g must be finite and non-zero (radians per level)", gain));
    if (std::abs(gain) > kMaxGainRadPerLevel)
        CV_Error(Error::StsOutOfRange,
                 format("gain = %g rad per level (%.1f deg) is implausible (at most %.4f rad = 15 deg per level): "
                        "radians per level expected (is it in degrees? 1 deg is 0.01745)",
                        gain, gain * 180 / CV_PI, kMaxGainRadPerLevel));
}

// Unit-step response of the normalised second-order plant and its derivative, for a step at
// tau = 0 (tau >= 0): 1 - e^{-σ τ}(cos ωd τ + σ/ωd sin ωd τ) and (ωn²/ωd) e^{-σ τ} sin ωd τ.
struct SecondOrder
{
    double naturalRadPerSec, sigma, dampedRadPerSec;

    SecondOrder(double naturalFreqHz, double dampingRatio)
        : naturalRadPerSec(2 * CV_PI * naturalFreqHz),
          sigma(dampingRatio * naturalRadPerSec),
          dampedRadPerSec(naturalRadPerSec * std::sqrt(1 - dampingRatio * dampingRatio))
    {
    }

    double step(double tau) const
    {
        const double decay = std::exp(-sigma * tau);
        return 1 - decay * (std::cos(dampedRadPerSec * tau) + sigma / dampedRadPerSec * std::sin(dampedRadPerSec * tau));
    }

    double stepRate(double tau) const
    {
        return naturalRadPerSec * naturalRadPerSec / dampedRadPerSec * std::exp(-sigma * tau)
               * std::sin(dampedRadPerSec * tau);
    }
};

// θ(t)/gain (or θ'(t)/gain) of the linear plant: the initial rest level plus one step per switch.
static double linearResponseInLevels(const SecondOrder& model, const SwitchSchedule& schedule, double t, bool rate)
{
    double sum = rate ? 0.0 : static_cast<double>(schedule.initialLevel);
    int previousLevel = schedule.initialLevel;
    for (size_t i = 0; i < schedule.times.size() && schedule.times[i] <= t; ++i)
    {
        const int stepSize = schedule.levels[i] - previousLevel;
        previousLevel = schedule.levels[i];
        if (stepSize == 0)
            continue;
        const double tau = t - schedule.times[i];
        sum += stepSize * (rate ? model.stepRate(tau) : model.step(tau));
    }
    return sum;
}

static void checkScheduleArgument(const SwitchSchedule& schedule)
{
    // An empty schedule is legal here: the plant rests at the initial level throughout.
    if (schedule.times.empty() && schedule.levels.empty())
        return;
    schedule.validate();
}

// ---------------------------------------------------------------------------------------------
// Closed-form linear plant

class LinearPlantImpl CV_FINAL : public Plant
{
public:
    LinearPlantImpl(double naturalFreqHz, double dampingRatio, double gain)
        : naturalFreqHz_(naturalFreqHz), dampingRatio_(dampingRatio), gain_(gain),
          model_(naturalFreqHz, dampingRatio)
    {
    }

    void response(const SwitchSchedule& schedule, InputArray t, OutputArray theta) const CV_OVERRIDE
    {
        evaluate(schedule, t, theta, false);
    }

    void velocity(const SwitchSchedule& schedule, InputArray t, OutputArray omega) const CV_OVERRIDE
    {
        evaluate(schedule, t, omega, true);
    }

    double getNaturalFreqHz() const CV_OVERRIDE { return naturalFreqHz_; }
    double getDampingRatio() const CV_OVERRIDE { return dampingRatio_; }
    double getGain() const CV_OVERRIDE { return gain_; }
    String getDefaultName() const CV_OVERRIDE { return "dynblur.Plant"; }

private:
    void evaluate(const SwitchSchedule& schedule, InputArray t, OutputArray out, bool rate) const
    {
        checkScheduleArgument(schedule);
        std::vector<double> times;
        double* dst = allocateTimeOutput(t, out, times);
        for (size_t i = 0; i < times.size(); ++i)
            dst[i] = gain_ * linearResponseInLevels(model_, schedule, times[i], rate);
    }

    double naturalFreqHz_, dampingRatio_, gain_;
    SecondOrder model_;
};

Ptr<Plant> Plant::create(double naturalFreqHz, double dampingRatio, double gain)
{
    checkLinearParameters(naturalFreqHz, dampingRatio, gain);
    return makePtr<LinearPlantImpl>(naturalFreqHz, dampingRatio, gain);
}

// ---------------------------------------------------------------------------------------------
// Residual vibration (DESIGN §2)

double residualVibration(const SwitchSchedule& schedule, double naturalFreqHz, double dampingRatio)
{
    checkFrequencyAndDamping(naturalFreqHz, dampingRatio);
    schedule.validate();
    const SecondOrder model(naturalFreqHz, dampingRatio);
    const double lastTime = schedule.times.back();
    std::complex<double> phasorSum(0, 0);
    int previousLevel = schedule.initialLevel, netMove = 0;
    for (size_t i = 0; i < schedule.times.size(); ++i)
    {
        const int stepSize = schedule.levels[i] - previousLevel;
        previousLevel = schedule.levels[i];
        netMove += stepSize;
        // e^{σ t_i} e^{-σ t_last} folded into one exponent so long clocks cannot overflow.
        const double age = schedule.times[i] - lastTime;
        phasorSum += static_cast<double>(stepSize) * std::exp(model.sigma * age)
                     * std::polar(1.0, model.dampedRadPerSec * schedule.times[i]);
    }
    return std::abs(phasorSum) / std::max(1, std::abs(netMove));
}

// ---------------------------------------------------------------------------------------------
// Identification

namespace {

// Unit-gain response of the schedule delayed by `delay`, in levels.
void unitGainResponse(const SecondOrder& model, const SwitchSchedule& schedule, const std::vector<double>& t,
                      double delay, Eigen::VectorXd& f)
{
    f.resize(static_cast<Eigen::Index>(t.size()));
    for (size_t i = 0; i < t.size(); ++i)
        f[static_cast<Eigen::Index>(i)] = linearResponseInLevels(model, schedule, t[i] - delay, false);
}

// Given the nonlinear parameters, gain and a constant sensor offset enter linearly: solve them by
// least squares (variable projection) and return the residual.
struct ProjectedFit
{
    const std::vector<double>& t;
    const Eigen::VectorXd& theta;
    const SwitchSchedule& schedule;

    double gain = 0, offset = 0;

    void residual(double naturalFreqHz, double dampingRatio, double delay, Eigen::VectorXd& r)
    {
        const SecondOrder model(naturalFreqHz, dampingRatio);
        Eigen::VectorXd f;
        unitGainResponse(model, schedule, t, delay, f);
        const double n = static_cast<double>(f.size());
        const double meanF = f.mean(), meanTheta = theta.mean();
        const double varF = (f.array() - meanF).square().sum();
        const double cov = ((f.array() - meanF) * (theta.array() - meanTheta)).sum();
        gain = varF > 0 ? cov / varF : 0.0;
        offset = meanTheta - gain * meanF;
        r = theta - (gain * f).array().matrix() - Eigen::VectorXd::Constant(static_cast<Eigen::Index>(n), offset);
    }
};

struct IdentifyFunctor
{
    typedef double Scalar;
    enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
    typedef Eigen::VectorXd InputType;
    typedef Eigen::VectorXd ValueType;
    typedef Eigen::MatrixXd JacobianType;

    ProjectedFit* fit;
    bool withDelay;
    int samples;

    int inputs() const { return withDelay ? 3 : 2; }
    int values() const { return samples; }

    // Parameters: log(ωn/2π), atanh-like map of ζ, delay. The maps keep ωn > 0 and 0 < ζ < 1.
    static double toDamping(double x) { return 0.5 * (std::tanh(x) + 1.0); }

    int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& r) const
    {
        fit->residual(std::exp(x[0]), toDamping(x[1]), withDelay ? x[2] : 0.0, r);
        return 0;
    }
};

// First guess of ωn and ζ from the free oscillation after the last switch: the period between
// successive extrema and the logarithmic decrement of their amplitudes.
bool logDecrementGuess(const std::vector<double>& t, const Eigen::VectorXd& theta, double settleStart,
                       double& naturalFreqHz, double& dampingRatio)
{
    std::vector<size_t> idx;
    for (size_t i = 0; i < t.size(); ++i)
        if (t[i] >= settleStart)
            idx.push_back(i);
    if (idx.size() < 16)
        return false;
    // Final value from the last quarter, and a light moving average against noise.
    const size_t tail = idx.size() / 4;
    double finalValue = 0;
    for (size_t k = idx.size() - tail; k < idx.size(); ++k)
        finalValue += theta[static_cast<Eigen::Index>(idx[k])];
    finalValue /= static_cast<double>(tail);
    const int half = 2;
    std::vector<double> dev(idx.size());
    for (size_t k = 0; k < idx.size(); ++k)
    {
        double s = 0;
        int n = 0;
        for (int d = -half; d <= half; ++d)
        {
            const long j = static_cast<long>(k) + d;
            if (j >= 0 && j < static_cast<long>(idx.size()))
            {
                s += theta[static_cast<Eigen::Index>(idx[static_cast<size_t>(j)])];
                ++n;
            }
        }
        dev[k] = s / n - finalValue;
    }
    // Extrema: the largest |dev| between consecutive zero crossings.
    std::vector<std::pair<double, double>> extrema;  // (time, |amplitude|)
    size_t start = 0;
    for (size_t k = 1; k <= dev.size(); ++k)
    {
        if (k == dev.size() || (dev[k] > 0) != (dev[start] > 0))
        {
            size_t best = start;
            for (size_t j = start; j < k; ++j)
                if (std::abs(dev[j]) > std::abs(dev[best]))
                    best = j;
            if (k - start >= 2)
                extrema.emplace_back(t[idx[best]], std::abs(dev[best]));
            start = k;
        }
    }
    if (extrema.size() < 3)
        return false;
    const double halfPeriod = (extrema[2].first - extrema[0].first) / 2.0;
    const double decrement = std::log(extrema[0].second / extrema[2].second);
    if (!(halfPeriod > 0) || !(decrement > 0))
        return false;
    dampingRatio = decrement / std::sqrt(4 * CV_PI * CV_PI + decrement * decrement);
    naturalFreqHz = 1.0 / (2 * halfPeriod * std::sqrt(1 - dampingRatio * dampingRatio));
    return std::isfinite(naturalFreqHz) && dampingRatio > 0 && dampingRatio < 1;
}

}  // namespace

Ptr<Plant> Plant::identify(InputArray t, InputArray theta, const SwitchSchedule& schedule, bool estimateDelay,
                           double* rmsResidual, double* delaySec)
{
    const std::vector<double> times = readTimeVector(t, "t");
    const std::vector<double> angles = readTimeVector(theta, "theta");
    if (times.size() < 8)
        CV_Error(Error::StsBadArg, format("Plant::identify: 't' has %zu samples; at least 8 are needed", times.size()));
    if (angles.size() != times.size())
        CV_Error(Error::StsBadArg,
                 format("Plant::identify: 'theta' has %zu samples but 't' has %zu", angles.size(), times.size()));
    for (size_t i = 1; i < times.size(); ++i)
        if (!(times[i] > times[i - 1]))
            CV_Error(Error::StsBadArg, format("Plant::identify: 't' must be strictly increasing (t[%zu] <= t[%zu])", i, i - 1));
    schedule.validate();
    int netMove = schedule.finalLevel() - schedule.initialLevel;
    if (netMove == 0)
        CV_Error(Error::StsBadArg, "Plant::identify: the schedule makes no net move (final level == initial level); "
                                   "a step response is needed");

    Eigen::VectorXd measured = Eigen::Map<const Eigen::VectorXd>(angles.data(), static_cast<Eigen::Index>(angles.size()));
    const double range = measured.maxCoeff() - measured.minCoeff();
    if (!(range > 0))
        CV_Error(Error::StsBadArg, "Plant::identify: 'theta' is constant: the log shows no motion");
    // A positioner's step spans a few degrees; a range beyond a quarter turn, or a gain per level
    // beyond Plant::create's, is an angle logged in degrees.
    const double perLevel = range / std::abs(netMove);
    if (range > CV_PI / 2 || perLevel > kMaxGainRadPerLevel)
        CV_Error(Error::StsOutOfRange,
                 format("Plant::identify: 'theta' spans %g over a move of %d levels (%g per level): radians expected "
                        "(is it logged in degrees? 10 deg is 0.1745)", range, std::abs(netMove), perLevel));

    // Initial delay: when the measured angle first leaves its starting value, against the first
    // switch. The noise level is estimated from the first samples' spread.
    double delay0 = 0;
    if (estimateDelay)
    {
        const size_t head = std::max<size_t>(4, times.size() / 50);
        const double startValue = measured.head(static_cast<Eigen::Index>(head)).mean();
        size_t moved = 0;
        while (moved < times.size() && std::abs(measured[static_cast<Eigen::Index>(moved)] - startValue) < 0.1 * range)
            ++moved;
        // A 10%-of-range crossing happens roughly a quarter period after the step; back off a little.
        delay0 = (moved < times.size() ? times[moved] : times.front()) - schedule.times.front();
    }

    double hz0 = 0, zeta0 = 0;
    const double settleStart = schedule.times.back() + delay0;
    if (!logDecrementGuess(times, measured, settleStart, hz0, zeta0))
    {
        hz0 = 0;
    }

    ProjectedFit fit{times, measured, schedule};
    IdentifyFunctor functor{&fit, estimateDelay, static_cast<int>(times.size())};
    Eigen::VectorXd r;
    auto cost = [&](double hz, double zeta, double delay) {
        fit.residual(hz, zeta, delay, r);
        return r.squaredNorm();
    };
    // A coarse grid guards against a failed or misleading decrement estimate (short or noisy logs).
    const double duration = times.back() - times.front();
    const double nyquistHz = 0.5 * (static_cast<double>(times.size()) - 1) / duration;
    double bestHz = hz0, bestZeta = zeta0, bestDelay = delay0;
    double bestCost = hz0 > 0 ? cost(hz0, zeta0, delay0) : std::numeric_limits<double>::infinity();
    if (estimateDelay && hz0 > 0)
    {
        // The 10% crossing lags the step by a fraction of a period; refine the delay first.
        for (int k = -20; k <= 0; ++k)
        {
            const double d = delay0 + k * 0.25 / (hz0 * 20);
            const double c = cost(hz0, zeta0, d);
            if (c < bestCost)
                bestCost = c, bestDelay = d;
        }
    }
    const double lowHz = 2.0 / duration, highHz = nyquistHz / 4;
    for (int i = 0; i < 48 && lowHz < highHz; ++i)
    {
        const double hz = lowHz * std::pow(highHz / lowHz, i / 47.0);
        for (double zeta : {0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.9})
        {
            const int delaySteps = estimateDelay ? 8 : 0;
            for (int k = -delaySteps; k <= 0; ++k)
            {
                const double d = estimateDelay ? delay0 + k * 0.25 / (hz * std::max(1, delaySteps)) : 0.0;
                const double c = cost(hz, zeta, d);
                if (c < bestCost)
                    bestCost = c, bestHz = hz, bestZeta = zeta, bestDelay = d;
            }
        }
    }

    Eigen::VectorXd x(functor.inputs());
    x[0] = std::log(bestHz);
    x[1] = std::atanh(2 * bestZeta - 1);
    if (estimateDelay)
        x[2] = bestDelay;
    Eigen::NumericalDiff<IdentifyFunctor> numeric(functor);
    Eigen::LevenbergMarquardt<Eigen::NumericalDiff<IdentifyFunctor>> solver(numeric);
    solver.parameters.xtol = 1e-12;
    solver.parameters.ftol = 1e-12;
    solver.parameters.maxfev = 4000;
    solver.minimize(x);

    const double hz = std::exp(x[0]);
    const double zeta = IdentifyFunctor::toDamping(x[1]);
    const double delay = estimateDelay ? x[2] : 0.0;
    fit.residual(hz, zeta, delay, r);
    if (!(std::isfinite(hz) && zeta > 0 && zeta < 1 && std::isfinite(fit.gain) && fit.gain != 0))
        CV_Error(Error::StsNoConv, "Plant::identify: the fit did not converge; is the log a step response of "
                                   "the given schedule?");
    if (rmsResidual)
        *rmsResidual = std::sqrt(r.squaredNorm() / static_cast<double>(r.size()));
    if (delaySec)
        *delaySec = delay;
    return Plant::create(hz, zeta, fit.gain);
}

}  // namespace dynblur
}  // namespace cv
