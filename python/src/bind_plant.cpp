// SPDX-License-Identifier: Apache-2.0
// Bindings of plant.hpp: Plant, OdePlant, residualVibration.
#include "bindings.hpp"

#include <opencv2/dynblur/plant.hpp>

#include <exception>
#include <limits>
#include <memory>

namespace dynblur_py {

using namespace cv::dynblur;

namespace {

//! Plant.response / Plant.velocity: t of any shape → float64 array of the same shape.
py::array evaluate(const Plant& plant, const SwitchSchedule& schedule, py::handle t, bool velocity)
{
    auto times = toDoubleArray(t, "t");
    std::vector<py::ssize_t> shape(times.shape(), times.shape() + times.ndim());
    cv::Mat tm(int(times.size()), 1, CV_64F, const_cast<double*>(times.data()));
    cv::Mat out;
    const SwitchSchedule s = schedule;
    pendingCallbackError = nullptr;
    try
    {
        py::gil_scoped_release release;
        if (velocity)
            plant.velocity(s, tm, out);
        else
            plant.response(s, tm, out);
    }
    catch (...)
    {
        rethrowCallbackError();  // a Python rhs that raised surfaces as itself, not as a CVODE failure
        throw;
    }
    py::array_t<double> result(shape);
    CV_Assert(out.total() == size_t(result.size()) && out.type() == CV_64F && out.isContinuous());
    std::copy(out.ptr<double>(), out.ptr<double>() + out.total(), result.mutable_data());
    return result;
}

//! State shared by the CVODE callbacks of an OdePlant made from Python callables.
struct PyCallbacks
{
    py::object rhs, restState;
    int stateSize = 0;
    ~PyCallbacks()
    {
        py::gil_scoped_acquire gil;
        rhs = py::object();
        restState = py::object();
    }
};

}  // namespace

void bindPlant(py::module_& m)
{
    // ---------------------------------------------------------------- Plant
    py::class_<Plant, std::shared_ptr<Plant>>(m, "Plant", R"doc(The camera-positioning mechanism: one rotational degree of freedom (tilt) driven by
cellular piezoelectric actuators. The linear model is
θ'' + 2ζωn θ' + ωn² θ = ωn² g u(t), with u the staircase of a SwitchSchedule. create() gives the
exact closed form; OdePlant integrates user-supplied dynamics with SUNDIALS CVODE.)doc")
        .def_static("create", [](double f, double z, double g) { return std::shared_ptr<Plant>(Plant::create(f, z, g)); },
                    py::arg("naturalFreqHz") = 14.4, py::arg("dampingRatio") = 0.12, py::arg("gain") = CV_PI / 180.0,
                    R"doc(The linear second-order plant, evaluated in closed form.

naturalFreqHz: natural frequency ωn/2π, Hz, > 0 (seed: 14.4); dampingRatio: ζ in (0, 1)
(seed: 0.12); gain: static gain, radians per level, non-zero (seed: 1° = π/180).)doc")
        .def("response", [](const Plant& p, const SwitchSchedule& s, py::handle t) { return evaluate(p, s, t, false); },
             py::arg("schedule"), py::arg("t"),
             "Angle θ(t), radians, for each time in t (seconds, any shape); float64 array of t's shape.")
        .def("velocity", [](const Plant& p, const SwitchSchedule& s, py::handle t) { return evaluate(p, s, t, true); },
             py::arg("schedule"), py::arg("t"),
             "Angular velocity dθ/dt, rad/s, for each time in t (seconds); float64 array of t's shape.")
        .def("getNaturalFreqHz", &Plant::getNaturalFreqHz, "Natural frequency of the (nominal, linear) model, Hz.")
        .def("getDampingRatio", &Plant::getDampingRatio, "Damping ratio of the (nominal, linear) model.")
        .def("getGain", &Plant::getGain, "Static gain, radians per level.")
        .def("restingAngle", &Plant::restingAngle, py::arg("level"),
             "Resting angle for a held level, radians (gain * level for the linear plant).")
        .def_static("identify",
            [](py::handle t, py::handle theta, const SwitchSchedule& schedule, bool estimateDelay) {
                MatIn tm = toMat(toDoubleArray(t, "t").attr("ravel")(), "t");
                MatIn th = toMat(toDoubleArray(theta, "theta").attr("ravel")(), "theta");
                const SwitchSchedule s = schedule;
                double rms = 0, delay = 0;
                cv::Ptr<Plant> plant;
                {
                    py::gil_scoped_release release;
                    plant = Plant::identify(tm.mat, th.mat, s, estimateDelay, &rms, &delay);
                }
                return py::make_tuple(std::shared_ptr<Plant>(plant), rms, delay);
            },
            py::arg("t"), py::arg("theta"), py::arg("schedule"), py::arg("estimateDelay") = false,
            R"doc(Identifies ωn, ζ and gain of the linear model from a logged response.

A first guess from the logarithmic decrement and the final value is refined by a
Levenberg–Marquardt fit of the closed-form response.
t: sample times, seconds, strictly increasing, ≥ 8 samples; theta: measured angle, radians;
schedule: command applied during the log (same clock as t); estimateDelay: also fit a constant
delay between command and motion.
Returns (plant, rmsResidual [rad], delaySec [s, 0 unless estimateDelay]).)doc");

    // ---------------------------------------------------------------- OdePlant
    py::class_<OdePlant, Plant, std::shared_ptr<OdePlant>>(m, "OdePlant", R"doc(A plant whose dynamics are integrated with SUNDIALS CVODE (BDF, dense Newton).
The state x has x[0] = θ (rad) and x[1] = dθ/dt (rad/s); more components are allowed. The input is
the commanded level u (cells) as a float; CVODE restarts at each switching instant.)doc")
        .def_static("createLinear",
                    [](double f, double z, double g) { return std::shared_ptr<OdePlant>(OdePlant::createLinear(f, z, g)); },
                    py::arg("naturalFreqHz") = 14.4, py::arg("dampingRatio") = 0.12, py::arg("gain") = CV_PI / 180.0,
                    "The linear second-order plant of Plant.create, integrated by CVODE.")
        .def_static("create",
            [](py::function rhs, int stateSize, py::function restState, double f, double z, double g,
               double relTol, double absTol) {
                auto cb = std::make_shared<PyCallbacks>();
                cb->rhs = rhs;
                cb->restState = restState;
                cb->stateSize = stateSize;
                OdePlant::RightHandSide f_rhs = [cb](double t, const double* x, double u, double* dxdt) {
                    py::gil_scoped_acquire gil;
                    try
                    {
                        py::array_t<double> xs(cb->stateSize);
                        std::copy(x, x + cb->stateSize, xs.mutable_data());
                        auto d = toDoubleArray(cb->rhs(t, xs, u), "rhs result");
                        if (d.size() != cb->stateSize)
                            throw py::value_error("OdePlant rhs returned " + std::to_string(d.size()) +
                                                  " values, expected stateSize = " + std::to_string(cb->stateSize));
                        std::copy(d.data(), d.data() + d.size(), dxdt);
                    }
                    catch (...)
                    {
                        if (!pendingCallbackError)
                            pendingCallbackError = std::current_exception();
                        std::fill(dxdt, dxdt + cb->stateSize, std::numeric_limits<double>::quiet_NaN());
                    }
                };
                auto f_rest = [cb](int level) {
                    py::gil_scoped_acquire gil;
                    auto r = toDoubleArray(cb->restState(level), "restState result");
                    return std::vector<double>(r.data(), r.data() + r.size());
                };
                return std::shared_ptr<OdePlant>(OdePlant::create(f_rhs, stateSize, f_rest, f, z, g, relTol, absTol));
            },
            py::arg("rhs"), py::arg("stateSize"), py::arg("restState"), py::arg("nominalFreqHz"),
            py::arg("nominalDamping"), py::arg("nominalGain"), py::arg("relTol") = 1e-10, py::arg("absTol") = 1e-12,
            R"doc(A plant with user-supplied dynamics (the callables run with the GIL held).

rhs(t, x, u) -> dx/dt: t seconds, x float64 array of stateSize, u the level (float); returns a
sequence of stateSize floats. stateSize ≥ 2. restState(level) -> equilibrium state for a held level
(the state before the schedule's first switch). nominalFreqHz, nominalDamping, nominalGain: the
linear model a planner should use. relTol, absTol: CVODE tolerances.)doc");

    m.def("residualVibration", &residualVibration, py::arg("schedule"), py::arg("naturalFreqHz"),
          py::arg("dampingRatio"), R"doc(Residual vibration of a schedule on a linear plant (Singer & Seering), as a fraction
of the move: V = e^(−σ t_last) |Σ aᵢ e^(σ tᵢ) e^(j ωd tᵢ)| / |Σ aᵢ|; 0 when the schedule makes no net move.)doc");
}

}  // namespace dynblur_py
