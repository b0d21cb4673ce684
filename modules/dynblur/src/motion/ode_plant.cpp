// SPDX-License-Identifier: Apache-2.0
#include "precomp.hpp"
#include "motion/time_vector.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cstdlib>
#include <mutex>
#include <numeric>

namespace cv {
namespace dynblur {

namespace {

void checkCvode(int flag, const char* call)
{
    if (flag >= 0)
        return;
    // CVodeGetReturnFlagName returns a malloc'ed copy that the caller frees (found by LeakSanitizer).
    char* name = CVodeGetReturnFlagName(flag);
    const String message = format("OdePlant: CVODE call %s failed with flag %d (%s)", call, flag, name ? name : "?");
    std::free(name);
    CV_Error(Error::StsError, message);
}

}  // namespace

/** CVODE state for one plant. CVODE memory is not re-entrant, so calls are serialised. */
class OdePlantImpl CV_FINAL : public OdePlant
{
public:
    OdePlantImpl(const RightHandSide& rhs, int stateSize, const std::function<std::vector<double>(int)>& restState,
                 double nominalFreqHz, double nominalDamping, double nominalGain, double relTol, double absTol)
        : rhs_(rhs), stateSize_(stateSize), restState_(restState), nominalFreqHz_(nominalFreqHz),
          nominalDamping_(nominalDamping), nominalGain_(nominalGain), relTol_(relTol), absTol_(absTol)
    {
        checkCvode(SUNContext_Create(nullptr, &context_), "SUNContext_Create");
        state_ = N_VNew_Serial(stateSize_, context_);
        jacobian_ = SUNDenseMatrix(stateSize_, stateSize_, context_);
        linearSolver_ = SUNLinSol_Dense(state_, jacobian_, context_);
        cvode_ = CVodeCreate(CV_BDF, context_);
        if (!state_ || !jacobian_ || !linearSolver_ || !cvode_)
        {
            release();
            CV_Error(Error::StsNoMem, "OdePlant: cannot allocate CVODE memory");
        }
        N_VConst(0.0, state_);
        checkCvode(CVodeInit(cvode_, &OdePlantImpl::rhsTrampoline, 0.0, state_), "CVodeInit");
        checkCvode(CVodeSStolerances(cvode_, relTol_, absTol_), "CVodeSStolerances");
        checkCvode(CVodeSetLinearSolver(cvode_, linearSolver_, jacobian_), "CVodeSetLinearSolver");
        checkCvode(CVodeSetUserData(cvode_, this), "CVodeSetUserData");
        checkCvode(CVodeSetMaxNumSteps(cvode_, 200000), "CVodeSetMaxNumSteps");
    }

    ~OdePlantImpl() CV_OVERRIDE { release(); }

    void response(const SwitchSchedule& schedule, InputArray t, OutputArray theta) const CV_OVERRIDE
    {
        integrate(schedule, t, theta, 0);
    }

    void velocity(const SwitchSchedule& schedule, InputArray t, OutputArray omega) const CV_OVERRIDE
    {
        integrate(schedule, t, omega, 1);
    }

    double getNaturalFreqHz() const CV_OVERRIDE { return nominalFreqHz_; }
    double getDampingRatio() const CV_OVERRIDE { return nominalDamping_; }
    double getGain() const CV_OVERRIDE { return nominalGain_; }
    String getDefaultName() const CV_OVERRIDE { return "dynblur.OdePlant"; }

private:
    static int rhsTrampoline(sunrealtype t, N_Vector y, N_Vector ydot, void* userData)
    {
        auto* self = static_cast<OdePlantImpl*>(userData);
        try
        {
            self->rhs_(t, N_VGetArrayPointer(y), self->currentLevel_, N_VGetArrayPointer(ydot));
        }
        catch (...)
        {
            return -1;  // unrecoverable: CVODE stops and reports CV_RHSFUNC_FAIL
        }
        return 0;
    }

    std::vector<double> restStateChecked(int level) const
    {
        std::vector<double> rest = restState_(level);
        if (static_cast<int>(rest.size()) != stateSize_)
            CV_Error(Error::StsBadArg, format("OdePlant: restState(%d) returned %zu values; stateSize is %d", level,
                                              rest.size(), stateSize_));
        return rest;
    }

    void integrate(const SwitchSchedule& schedule, InputArray t, OutputArray out, int component) const
    {
        if (!(schedule.times.empty() && schedule.levels.empty()))
            schedule.validate();
        std::vector<double> times;
        double* dst = allocateTimeOutput(t, out, times);
        if (!dst)
            return;

        // Outputs are produced in time order, integrating forward once through the schedule.
        std::vector<size_t> order(times.size());
        std::iota(order.begin(), order.end(), size_t(0));
        std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return times[a] < times[b]; });

        std::lock_guard<std::mutex> lock(mutex_);
        const std::vector<double> rest = restStateChecked(schedule.initialLevel);
        size_t next = 0;
        // Before the first switch the plant rests at the initial level's equilibrium.
        const double firstSwitch = schedule.times.empty() ? std::numeric_limits<double>::infinity() : schedule.times[0];
        while (next < order.size() && times[order[next]] < firstSwitch)
            dst[order[next++]] = rest[static_cast<size_t>(component)];
        if (next == order.size())
            return;

        std::copy(rest.begin(), rest.end(), N_VGetArrayPointer(state_));
        double now = firstSwitch;
        for (size_t segment = 0; segment < schedule.times.size() && next < order.size(); ++segment)
        {
            // The input jumps at each switch: restart CVODE there instead of stepping across it.
            currentLevel_ = schedule.levels[segment];
            const double segmentEnd = segment + 1 < schedule.times.size() ? schedule.times[segment + 1]
                                                                           : std::numeric_limits<double>::infinity();
            checkCvode(CVodeReInit(cvode_, now, state_), "CVodeReInit");
            // The last segment still gets a stop time (past the last output): CVODE 6.4 cannot
            // clear one left over from an earlier segment.
            const double stopTime = std::isfinite(segmentEnd) ? segmentEnd : times[order.back()] + 1.0;
            checkCvode(CVodeSetStopTime(cvode_, stopTime), "CVodeSetStopTime");
            sunrealtype reached = now;
            while (next < order.size() && times[order[next]] < segmentEnd)
            {
                const double target = times[order[next]];
                // CVODE refuses an output time within roundoff of the current one (CV_TOO_CLOSE);
                // 1 ns moves the plant by nanoradians, far below its accuracy.
                if (target > reached + 1e-9)
                    checkCvode(CVode(cvode_, target, state_, &reached, CV_NORMAL), "CVode");
                dst[order[next++]] = N_VGetArrayPointer(state_)[component];
            }
            if (std::isfinite(segmentEnd) && next < order.size())
            {
                if (segmentEnd > reached + 1e-9)
                    checkCvode(CVode(cvode_, segmentEnd, state_, &reached, CV_NORMAL), "CVode");
                now = segmentEnd;
            }
        }
    }

    void release()
    {
        if (cvode_)
            CVodeFree(&cvode_);
        if (linearSolver_)
            SUNLinSolFree(linearSolver_);
        if (jacobian_)
            SUNMatDestroy(jacobian_);
        if (state_)
            N_VDestroy(state_);
        if (context_)
            SUNContext_Free(&context_);
        linearSolver_ = nullptr;
        jacobian_ = nullptr;
        state_ = nullptr;
    }

    RightHandSide rhs_;
    int stateSize_;
    std::function<std::vector<double>(int)> restState_;
    double nominalFreqHz_, nominalDamping_, nominalGain_, relTol_, absTol_;

    SUNContext context_ = nullptr;
    N_Vector state_ = nullptr;
    SUNMatrix jacobian_ = nullptr;
    SUNLinearSolver linearSolver_ = nullptr;
    void* cvode_ = nullptr;
    mutable double currentLevel_ = 0;
    mutable std::mutex mutex_;
};

Ptr<OdePlant> OdePlant::create(const RightHandSide& rhs, int stateSize,
                               const std::function<std::vector<double>(int level)>& restState, double nominalFreqHz,
                               double nominalDamping, double nominalGain, double relTol, double absTol)
{
    CV_Assert(rhs && "OdePlant::create: 'rhs' must be callable");
    CV_Assert(restState && "OdePlant::create: 'restState' must be callable");
    if (stateSize < 2)
        CV_Error(Error::StsOutOfRange, format("OdePlant::create: stateSize = %d must be >= 2 (theta, dtheta/dt)", stateSize));
    if (!(relTol > 0 && relTol < 1) || !(absTol > 0 && std::isfinite(absTol)))
        CV_Error(Error::StsOutOfRange, format("OdePlant::create: relTol = %g must lie in (0, 1) and absTol = %g must be > 0",
                                              relTol, absTol));
    Plant::create(nominalFreqHz, nominalDamping, nominalGain);  // validates the nominal model
    return makePtr<OdePlantImpl>(rhs, stateSize, restState, nominalFreqHz, nominalDamping, nominalGain, relTol, absTol);
}

Ptr<OdePlant> OdePlant::createLinear(double naturalFreqHz, double dampingRatio, double gain)
{
    Plant::create(naturalFreqHz, dampingRatio, gain);  // validates
    const double omega = 2 * CV_PI * naturalFreqHz;
    RightHandSide rhs = [omega, dampingRatio, gain](double, const double* x, double u, double* dxdt) {
        dxdt[0] = x[1];
        dxdt[1] = omega * omega * (gain * u - x[0]) - 2 * dampingRatio * omega * x[1];
    };
    auto rest = [gain](int level) { return std::vector<double>{gain * level, 0.0}; };
    return create(rhs, 2, rest, naturalFreqHz, dampingRatio, gain);
}

}  // namespace dynblur
}  // namespace cv
