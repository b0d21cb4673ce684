// SPDX-License-Identifier: Apache-2.0
// Bindings of plant.hpp, planner.hpp and shutter.hpp.
#include "bindings.hpp"

#include <opencv2/dynblur/camera_motion.hpp>

#include <opencv2/dynblur/planner.hpp>
#include <opencv2/dynblur/plant.hpp>
#include <opencv2/dynblur/shutter.hpp>

#include <exception>
#include <limits>
#include <memory>
#include <sstream>

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

std::string repr(const SwitchSchedule& s)
{
    std::ostringstream o;
    o << "SwitchSchedule(times=[";
    for (size_t i = 0; i < s.times.size(); ++i)
        o << (i ? ", " : "") << s.times[i];
    o << "], levels=[";
    for (size_t i = 0; i < s.levels.size(); ++i)
        o << (i ? ", " : "") << s.levels[i];
    o << "], initialLevel=" << s.initialLevel << ")";
    return o.str();
}

}  // namespace

void bindMotion(py::module_& m)
{
    // ---------------------------------------------------------------- SwitchSchedule
    py::class_<SwitchSchedule>(m, "SwitchSchedule", R"doc(A staircase command: integer actuator levels switched at chosen instants.

The level ``levels[i]`` is held from ``times[i]`` to ``times[i+1]`` (the last one forever). Before
``times[0]`` the level ``initialLevel`` is in force and the plant rests at ``gain * initialLevel``.
The planner fills settleTime, peakVelocity and residualVibration; they are NaN for a hand-made
schedule. The list fields are copies: assign a new list to change them.)doc")
        .def(py::init<>())
        .def(py::init<const std::vector<double>&, const std::vector<int>&, int>(), py::arg("times"),
             py::arg("levels"), py::arg("initialLevel") = 0,
             R"doc(times: switching instants, seconds, strictly increasing; levels: level switched on at
each instant (cells), same length; initialLevel: level before times[0] (cells).)doc")
        .def_readwrite("times", &SwitchSchedule::times, "switching instants, seconds, strictly increasing")
        .def_readwrite("levels", &SwitchSchedule::levels, "level from each instant on, cells")
        .def_readwrite("initialLevel", &SwitchSchedule::initialLevel, "level before times[0], cells")
        .def_readwrite("settleTime", &SwitchSchedule::settleTime,
                       "predicted time from times[0] until the angle stays in the settle band, seconds")
        .def_readwrite("peakVelocity", &SwitchSchedule::peakVelocity, "predicted peak |dθ/dt|, rad/s")
        .def_readwrite("residualVibration", &SwitchSchedule::residualVibration,
                       "vibration left after the last switch, fraction of the move")
        .def("finalLevel", &SwitchSchedule::finalLevel,
             "Level in force after the last switch (initialLevel when the schedule is empty).")
        .def("levelAt", &SwitchSchedule::levelAt, py::arg("t"), "Level in force at time t, seconds.")
        .def("validate", &SwitchSchedule::validate, py::arg("maxLevel") = 1 << 20,
             R"doc(Raises dynblur.error naming the offending field when the schedule is malformed: empty,
lengths differ, non-finite or non-increasing times, or a level outside [-maxLevel, maxLevel].)doc")
        .def("save", &SwitchSchedule::save, py::arg("filename"),
             "Writes the schedule to a cv::FileStorage file (YAML, XML or JSON by extension).")
        .def_static("load", &SwitchSchedule::load, py::arg("filename"),
                    "Reads a schedule written by save(); checks it with validate().")
        .def("__repr__", &repr);

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

    // ---------------------------------------------------------------- SwitchPlanner
    m.attr("PLAN_FAST") = int(PLAN_FAST);
    m.attr("PLAN_ROBUST") = int(PLAN_ROBUST);
    py::class_<SwitchPlanner, std::shared_ptr<SwitchPlanner>>(m, "SwitchPlanner", R"doc(Plans point-to-point moves as integer-level switching schedules that leave no residual vibration.
The switching instants are solved so that the steps' phasors close into a polygon; robust mode
also zeroes the derivative with respect to ωn. A minimum dwell between switches and the level
limits are hard constraints.)doc")
        .def_static("create",
            [](const std::shared_ptr<Plant>& plant, int maxLevel, int mode, double minDwell) {
                return std::shared_ptr<SwitchPlanner>(SwitchPlanner::create(cv::Ptr<Plant>(plant), maxLevel, mode, minDwell));
            },
            py::arg("plant"), py::arg("maxLevel") = 16, py::arg("mode") = int(PLAN_FAST), py::arg("minDwell") = 0.002,
            R"doc(plant: the plant to plan for (its nominal ωn, ζ and gain are used); maxLevel: largest |level|,
cells, ≥ 1; mode: PLAN_FAST or PLAN_ROBUST; minDwell: shortest time between two switches, seconds.)doc")
        .def("plan",
            [](const SwitchPlanner& p, double from, double to, double start) {
                py::gil_scoped_release release;
                return p.plan(from, to, start);
            },
            py::arg("fromAngle"), py::arg("toAngle"), py::arg("startTime") = 0.0,
            R"doc(Plans a move from fromAngle to toAngle (radians, rounded to the nearest level in
[-maxLevel, maxLevel]) whose first switch is at startTime (seconds). Returns the SwitchSchedule
with settleTime, peakVelocity and residualVibration filled in; a zero move returns an empty
schedule at the start level.)doc")
        .def("getMaxLevel", &SwitchPlanner::getMaxLevel)
        .def("setMaxLevel", &SwitchPlanner::setMaxLevel, py::arg("maxLevel"))
        .def("getMode", &SwitchPlanner::getMode)
        .def("setMode", &SwitchPlanner::setMode, py::arg("mode"))
        .def("getMinDwell", &SwitchPlanner::getMinDwell, "Minimum dwell between switches, seconds.")
        .def("setMinDwell", &SwitchPlanner::setMinDwell, py::arg("minDwell"))
        .def("getSettleBand", &SwitchPlanner::getSettleBand,
             "Half-width of the band that defines the settle time, fraction of the move (default 0.02).")
        .def("setSettleBand", &SwitchPlanner::setSettleBand, py::arg("band"))
        .def("getRobustRange", &SwitchPlanner::getRobustRange,
             "Relative ωn error robust mode is designed for (default 0.10 = ±10%).")
        .def("setRobustRange", &SwitchPlanner::setRobustRange, py::arg("range"))
        .def("getRobustTolerance", &SwitchPlanner::getRobustTolerance,
             "Largest residual vibration, fraction of the move, a robust plan may leave in the robust range.")
        .def("setRobustTolerance", &SwitchPlanner::setRobustTolerance, py::arg("tolerance"))
        .def("getPlant", [](const SwitchPlanner& p) { return std::shared_ptr<Plant>(p.getPlant()); });

    // ---------------------------------------------------------------- RollingShutter
    py::class_<RollingShutter>(m, "RollingShutter", R"doc(When each sensor row integrates light: row r over
[frameStart + r·lineDelay, frameStart + r·lineDelay + exposure] (seconds, the schedule's clock).
lineDelay = 0 is a global shutter.)doc")
        .def(py::init<double, double, double, int>(), py::arg("frameStart") = 0.0, py::arg("exposure") = 0.008,
             py::arg("lineDelay") = 0.0, py::arg("rows") = 1,
             R"doc(frameStart: start of row 0's exposure, s; exposure: of each row, s, ≥ 0; lineDelay: delay
between the starts of consecutive rows, s, ≥ 0; rows: number of sensor rows, > 0.)doc")
        .def_readwrite("frameStart", &RollingShutter::frameStart, "start of row 0's exposure, seconds")
        .def_readwrite("exposure", &RollingShutter::exposure, "exposure of one row, seconds")
        .def_readwrite("lineDelay", &RollingShutter::lineDelay, "row-to-row readout delay, seconds (0: global shutter)")
        .def_readwrite("rows", &RollingShutter::rows, "number of sensor rows")
        .def("rowInterval", &RollingShutter::rowInterval, py::arg("row"),
             "Exposure interval of row r as (start, end), seconds; 0 ≤ row < rows.")
        .def("intervalAt", &RollingShutter::intervalAt, py::arg("row"),
             "Exposure interval (start, end), seconds, of a possibly fractional row position; checks nothing.")
        .def("readoutInterval", &RollingShutter::readoutInterval,
             "Start of the first row's exposure and end of the last one's, seconds.")
        .def("validate", &RollingShutter::validate, "Raises dynblur.error naming the field when a value is out of range.")
        .def("__repr__", [](const RollingShutter& s) {
            std::ostringstream o;
            o << "RollingShutter(frameStart=" << s.frameStart << ", exposure=" << s.exposure
              << ", lineDelay=" << s.lineDelay << ", rows=" << s.rows << ")";
            return o.str();
        });

    m.attr("EXPOSURE_I") = int(EXPOSURE_I);
    m.attr("EXPOSURE_II") = int(EXPOSURE_II);
    m.attr("EXPOSURE_III") = int(EXPOSURE_III);
    m.attr("EXPOSURE_IV") = int(EXPOSURE_IV);
    m.def("classifyExposure",
          [](const std::shared_ptr<Plant>& plant, const SwitchSchedule& s, const RollingShutter& sh, double a, double v) {
              if (!plant)
                  throw py::value_error("argument 'plant' is None");
              return classifyExposure(cv::Ptr<Plant>(plant), s, sh, a, v);
          },
          py::arg("plant"), py::arg("schedule"), py::arg("shutter"), py::arg("angleTol") = 2e-4,
          py::arg("velocityTol") = 0.02,
          R"doc(Which exposure window (EXPOSURE_I .. EXPOSURE_IV) a frame falls in. "Moving" at t means t is at
or after the first switch and |dθ/dt| > velocityTol (rad/s), or θ(t) is farther than angleTol (rad) from both
θ_final and θ_rest(t), the resting angle of the level in force at t (a schedule holding several moves rests
between them).
I: still at the start, moving later; II: moving throughout; III: moving at the start, still before
the end; IV: still throughout. A move that starts and ends inside one readout is window I.)doc");
    m.def("classifyExposure",
          [](const std::shared_ptr<CameraMotion>& motion, const RollingShutter& sh, double a, double v) {
              if (!motion)
                  throw py::value_error("argument 'motion' is None");
              return classifyExposure(cv::Ptr<CameraMotion>(motion), sh, a, v);
          },
          py::arg("motion"), py::arg("shutter"), py::arg("angleTol") = 2e-4, py::arg("velocityTol") = 0.02,
          R"doc(The exposure window of a frame for any camera motion: a plant's motion as the plant form; any
other is "moving" where its rate |ω| exceeds velocityTol (rad/s), sampled every 0.25 ms.)doc");
}

}  // namespace dynblur_py
