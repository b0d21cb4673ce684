// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_PLANT_HPP
#define OPENCV_DYNBLUR_PLANT_HPP

#include <opencv2/core.hpp>
#include <opencv2/dynblur/schedule.hpp>

#include <functional>
#include <string>
#include <vector>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_motion
//! @{

/** @brief The camera-positioning mechanism: one rotational degree of freedom (tilt) driven by
cellular piezoelectric actuators.

The linear model (DESIGN §2) is
\f[\ddot\theta + 2\zeta\omega_n\dot\theta + \omega_n^2\theta = \omega_n^2\, g\, u(t)\f]
with \f$u\f$ the staircase of a SwitchSchedule @cite DynblurSeed. create() gives the
exact closed form; OdePlant integrates any user-supplied dynamics with SUNDIALS CVODE
@cite Hindmarsh2005Sundials.
*/
class CV_EXPORTS_W Plant : public Algorithm
{
public:
    /** @brief The linear second-order plant, evaluated in closed form.
    @param naturalFreqHz natural frequency ωn/2π, Hz, in (0, 1000] (seed: 14.4).
    @param dampingRatio damping ratio ζ, in (0, 1) (seed: 0.12).
    @param gain static gain, radians per level, non-zero, |gain| ≤ π/12 (15° per level; seed: 1° = π/180). */
    CV_WRAP static Ptr<Plant> create(double naturalFreqHz = 14.4, double dampingRatio = 0.12,
                                     double gain = CV_PI / 180.0);

    /** @brief Angle θ(t), radians, for each time in t (seconds, any order, CV_64F or CV_32F);
    the output has t's shape and is CV_64F. */
    CV_WRAP virtual void response(const SwitchSchedule& schedule, InputArray t, OutputArray theta) const = 0;
    /** @brief Angular velocity dθ/dt, rad/s, for each time in t (seconds). */
    CV_WRAP virtual void velocity(const SwitchSchedule& schedule, InputArray t, OutputArray omega) const = 0;

    /** @brief Natural frequency of the (nominal, linear) model, Hz. */
    CV_WRAP virtual double getNaturalFreqHz() const = 0;
    /** @brief Damping ratio of the (nominal, linear) model. */
    CV_WRAP virtual double getDampingRatio() const = 0;
    /** @brief Static gain, radians per level. */
    CV_WRAP virtual double getGain() const = 0;

    /** @brief Resting angle for a held level, radians (gain * level for the linear plant). */
    CV_WRAP double restingAngle(int level) const { return getGain() * level; }

    /** @brief Identifies ωn, ζ and gain of the linear model from a logged response.

    A first guess comes from the logarithmic decrement of the oscillation and the final value;
    a Levenberg–Marquardt least-squares fit (Eigen) of the closed-form response refines it.
    @param t sample times, seconds, strictly increasing, ≥ 8 samples.
    @param theta measured angle at each sample, radians.
    @param schedule command applied during the log (same clock as t).
    @param estimateDelay also fit a constant delay between command and motion (a log whose
           start time is unknown), seconds, reported in delaySec.
    @param rmsResidual if not null, receives the RMS fit residual, radians.
    @param delaySec if not null, receives the fitted delay, seconds (0 unless estimateDelay). */
    CV_WRAP static Ptr<Plant> identify(InputArray t, InputArray theta, const SwitchSchedule& schedule,
                                       bool estimateDelay = false,
                                       CV_OUT double* rmsResidual = nullptr,
                                       CV_OUT double* delaySec = nullptr);
};

/** @brief A plant whose dynamics are integrated with SUNDIALS CVODE (BDF, dense Newton).

The state is a vector x with x[0] = θ (rad) and x[1] = dθ/dt (rad/s); more components are
allowed (actuator states, hysteresis). The input is the commanded level u (cells) as a double.
The level is discontinuous at switching instants, so CVODE is restarted at each one.
*/
class CV_EXPORTS_W OdePlant : public Plant
{
public:
    /** @brief Right-hand side: writes dx/dt for time t (seconds), state x and level u. */
    typedef std::function<void(double t, const double* x, double u, double* dxdt)> RightHandSide;

    /** @brief A plant with user-supplied dynamics.
    @param rhs the right-hand side dx/dt = f(t, x, u).
    @param stateSize number of state components, ≥ 2.
    @param restState function giving the equilibrium state for a held level; it is the state
           before the schedule's first switch.
    @param nominalFreqHz, nominalDamping, nominalGain the linear model a planner should use,
           Hz, dimensionless, radians per level.
    @param relTol, absTol CVODE tolerances (dimensionless, radians). */
    static Ptr<OdePlant> create(const RightHandSide& rhs, int stateSize,
                                const std::function<std::vector<double>(int level)>& restState,
                                double nominalFreqHz, double nominalDamping, double nominalGain,
                                double relTol = 1e-10, double absTol = 1e-12);

    /** @brief The linear second-order plant of Plant::create, integrated by CVODE. */
    CV_WRAP static Ptr<OdePlant> createLinear(double naturalFreqHz = 14.4, double dampingRatio = 0.12,
                                              double gain = CV_PI / 180.0);
};

/** @brief Residual vibration of a schedule on a linear plant (Singer & Seering
@cite Singer1990Preshaping; DESIGN §2), as a fraction of the move:
\f[V = e^{-\sigma t_{last}}\,\frac{|\sum_i a_i e^{\sigma t_i} e^{j\omega_d t_i}|}{|\sum_i a_i|}\f]
@param schedule the command.
@param naturalFreqHz natural frequency, Hz, > 0.
@param dampingRatio damping ratio, in (0, 1).
@return V (dimensionless); 0 when the schedule makes no net move. */
CV_EXPORTS_W double residualVibration(const SwitchSchedule& schedule, double naturalFreqHz,
                                      double dampingRatio);

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
