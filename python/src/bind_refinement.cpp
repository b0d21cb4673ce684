// SPDX-License-Identifier: Apache-2.0
// Bindings of refinement.hpp: RefinementParameter, refinementParameters, refinementFlags, MotionCorrection,
// TimingCalibration, calibrateTiming, motionConsistency, blindMotionConsistency.
#include "bindings.hpp"

#include <opencv2/dynblur/refinement.hpp>

#include <limits>
#include <memory>
#include <sstream>

namespace dynblur_py {

using namespace cv::dynblur;

namespace {

std::string repr(const MotionCorrection& c)
{
    std::ostringstream o;
    o << "MotionCorrection(timeOffset=" << c.timeOffset << ", lineDelayScale=" << c.lineDelayScale
      << ", naturalFreqScale=" << c.naturalFreqScale << ", dampingScale=" << c.dampingScale
      << ", axisNaturalFreqScales=(" << c.axisNaturalFreqScales[0] << ", " << c.axisNaturalFreqScales[1] << ")"
      << ", axisDampingScales=(" << c.axisDampingScales[0] << ", " << c.axisDampingScales[1] << ")"
      << ", gyroBias=(" << c.gyroBias[0] << ", " << c.gyroBias[1] << ", " << c.gyroBias[2] << ")"
      << ", rateScale=" << c.rateScale
      << ", consistency=" << c.consistency << ", held=" << c.held << ", stillGain=" << c.stillGain << ", applied=" << (c.applied ? "True" : "False") << ", reason='"
      << c.reason << "')";
    return o.str();
}


}  // namespace

void bindRefinement(py::module_& m)
{
    // The flags from the refinement's table of parameters: one constant per flag it names.
    m.attr("REFINE_NONE") = int(REFINE_NONE);
    m.attr("REFINE_ALL") = int(REFINE_ALL);
    for (const RefinementParameter& p : refinementParameters())
        m.attr(p.flagName.c_str()) = p.flag;

    py::class_<RefinementParameter>(m, "RefinementParameter", R"doc(One parameter the refinement estimates (refinementParameters):
the MotionCorrection field it sets, the MotionRefinement flag that turns it on, and where it applies.)doc")
        .def_readonly("name", &RefinementParameter::name, "what it is: 'time offset', 'natural frequency', 'gyro bias x'")
        .def_readonly("group", &RefinementParameter::group, "its flag's name in messages: 'time offset', 'plant'")
        .def_readonly("key", &RefinementParameter::key, "its flag's short name in command lines: 'offset', 'plant'")
        .def_readonly("flagName", &RefinementParameter::flagName, "'REFINE_TIME_OFFSET'")
        .def_readonly("flag", &RefinementParameter::flag, "the MotionRefinement flag (parameters may share one)")
        .def_readonly("unit", &RefinementParameter::unit, "the field's unit: 's', '' (a scale) or 'rad/s'")
        .def_readonly("searchHalfWidth", &RefinementParameter::searchHalfWidth,
                      "how far from its value as told it is searched, in unit (0 for the time offset: the "
                      "caller's maxTimeOffset)")
        .def_readonly("plantMotion", &RefinementParameter::plantMotion, "it corrects a plant's motion")
        .def_readonly("mountMotion", &RefinementParameter::mountMotion, "it corrects a mount's motion (Mount.motion)")
        .def_readonly("measuredMotion", &RefinementParameter::measuredMotion, "it corrects a measured motion")
        .def_readonly("mountAxis", &RefinementParameter::mountAxis,
                      "the mount axis (0 = base) whose plant it scales; -1: it scales no plant")
        .def_readonly("rollingShutterOnly", &RefinementParameter::rollingShutterOnly,
                      "only a rolling shutter observes it")
        .def_readonly("inRefineAll", &RefinementParameter::inRefineAll, "REFINE_ALL includes its flag")
        .def("__repr__", [](const RefinementParameter& p) {
            return "RefinementParameter(name='" + p.name + "', flagName='" + p.flagName + "', key='" + p.key + "')";
        });
    m.def("refinementParameters", &refinementParameters,
          "The parameters the refinement estimates, in the order it fits them: the table setRefinement, "
          "calibrateTiming and their reports read.");
    m.def("refinementFlags", &refinementFlags, py::arg("names"),
          "MotionRefinement flags from a comma-separated list of RefinementParameter.key values, 'all' and 'none' "
          "('offset,line-delay' gives REFINE_TIME_OFFSET | REFINE_LINE_DELAY); raises dynblur.error naming an "
          "unknown item.");

    py::class_<MotionCorrection>(m, "MotionCorrection", R"doc(A correction of the predicted motion: the shutter
starts timeOffset seconds later and reads its rows with lineDelayScale times the line delay; the
plant has naturalFreqScale times ωn and dampingScale times ζ.)doc")
        .def(py::init([](double timeOffset, double lineDelayScale, double naturalFreqScale, double dampingScale) {
                 MotionCorrection c;
                 c.timeOffset = timeOffset;
                 c.lineDelayScale = lineDelayScale;
                 c.naturalFreqScale = naturalFreqScale;
                 c.dampingScale = dampingScale;
                 return c;
             }),
             py::arg("timeOffset") = 0.0, py::arg("lineDelayScale") = 1.0, py::arg("naturalFreqScale") = 1.0,
             py::arg("dampingScale") = 1.0)
        .def_readwrite("timeOffset", &MotionCorrection::timeOffset, "seconds, added to the shutter's frameStart")
        .def_readwrite("lineDelayScale", &MotionCorrection::lineDelayScale, "x the shutter's lineDelay")
        .def_readwrite("naturalFreqScale", &MotionCorrection::naturalFreqScale, "x the plant's natural frequency")
        .def_readwrite("dampingScale", &MotionCorrection::dampingScale, "x the plant's damping ratio")
        .def_readwrite("axisNaturalFreqScales", &MotionCorrection::axisNaturalFreqScales,
                       "x the natural frequency of a mount's axes 1 and 2 (the base takes naturalFreqScale)")
        .def_readwrite("axisDampingScales", &MotionCorrection::axisDampingScales,
                       "x the damping ratio of a mount's axes 1 and 2 (the base takes dampingScale)")
        .def_readwrite("gyroBias", &MotionCorrection::gyroBias,
                       "a measured motion's gyro bias, rad/s, camera axes, removed from its rates")
        .def_readwrite("rateScale", &MotionCorrection::rateScale,
                       "a measured motion's rates x this (1: the rotation as measured; more when the camera "
                       "also translates)")
        .def_readwrite("consistency", &MotionCorrection::consistency,
                       "RMS of the frame minus the reference carried through the corrected blur, in noise standard "
                       "deviations (about 1 when the model is right; NaN: not measured)")
        .def_readwrite("held", &MotionCorrection::held,
                       "MotionRefinement flags of the parameters the frames did not determine (unobserved, or "
                       "trading against another along a ridge), kept at their prior")
        .def_readwrite("heldParameters", &MotionCorrection::heldParameters,
                       "the held parameters one by one: bit j set when refinementParameters()[j] was held")
        .def_readwrite("stillGain", &MotionCorrection::stillGain,
                       "the frame's brightness over its still's (automatic exposure, lighting); 1 without a still")
        .def_readwrite("applied", &MotionCorrection::applied, "False: the frame was returned unrestored (see reason)")
        .def_readwrite("reason", &MotionCorrection::reason, "why it was not applied, or how it was found")
        .def("correctShutter", &MotionCorrection::correctShutter, py::arg("shutter"),
             "The shutter as corrected: frameStart + timeOffset, lineDelay x lineDelayScale.")
        .def("correctPlant",
             [](const MotionCorrection& c, const std::shared_ptr<Plant>& plant) {
                 return std::shared_ptr<Plant>(c.correctPlant(required(plant, "plant")));
             },
             py::arg("plant"), "The plant as corrected (itself when both scales are 1).")
        .def("correctMotion",
             [](const MotionCorrection& c, const std::shared_ptr<CameraMotion>& motion) {
                 return shared(c.correctMotion(required(motion, "motion")));
             },
             py::arg("motion"),
             "A mount's motion with each axis's plant scaled (a plant's motion: its plant); any other motion as "
             "given.")
        .def("validate", &MotionCorrection::validate)
        .def("__repr__", &repr);

    py::class_<TimingCalibration>(m, "TimingCalibration",
                                  "The clock offset, line delay and plant of a recording (calibrateTiming).")
        .def(py::init<>())
        .def_readwrite("correction", &TimingCalibration::correction, "the common MotionCorrection")
        .def_readwrite("timeOffsetStd", &TimingCalibration::timeOffsetStd,
                       "standard deviation of timeOffset, seconds (independent pixel noise: a lower bound)")
        .def_readwrite("lineDelayScaleStd", &TimingCalibration::lineDelayScaleStd)
        .def_readwrite("naturalFreqScaleStd", &TimingCalibration::naturalFreqScaleStd)
        .def_readwrite("dampingScaleStd", &TimingCalibration::dampingScaleStd)
        .def_readwrite("axisNaturalFreqScaleStd", &TimingCalibration::axisNaturalFreqScaleStd, "a mount's axes 1 and 2")
        .def_readwrite("axisDampingScaleStd", &TimingCalibration::axisDampingScaleStd, "a mount's axes 1 and 2")
        .def_readwrite("gyroBiasStd", &TimingCalibration::gyroBiasStd, "rad/s (a measured motion's bias)")
        .def_readwrite("rateScaleStd", &TimingCalibration::rateScaleStd, "a measured motion's rate scale")
        .def_readwrite("axisCorrection", &TimingCalibration::axisCorrection,
                       "the rotation from the log's camera axes to the camera's the images showed (3x3; identity: as "
                       "read); GyroLog.withAxisCorrection applies it")
        .def_readwrite("explainedMotion", &TimingCalibration::explainedMotion,
                       "share of the image's turn between frames the log explains at the offset found (NaN: not "
                       "measured)")
        .def_readwrite("trackResidualPx", &TimingCalibration::trackResidualPx,
                       "RMS reprojection error of the tracked features, pixels (NaN: not measured)")
        .def_readwrite("frameUsed", &TimingCalibration::frameUsed, "1 for each frame in the fit, else 0")
        .def_readwrite("frameConsistency", &TimingCalibration::frameConsistency,
                       "each frame's consistency at the result (NaN: a still frame)")
        .def_readwrite("scanTimeOffsets", &TimingCalibration::scanTimeOffsets,
                       "offsets scanned around the result, seconds")
        .def_readwrite("scanObjective", &TimingCalibration::scanObjective,
                       "mean squared residual (noise units) at each scanned offset")
        .def("save", &TimingCalibration::save, py::arg("filename"),
             "Writes the calibration (YAML/XML/JSON by extension), atomically.")
        .def_static("load", &TimingCalibration::load, py::arg("filename"));

    m.def("calibrateTiming",
        [](const std::shared_ptr<Plant>& plant, const std::shared_ptr<CameraModel>& camera, py::handle references,
           py::handle frames, const std::vector<SwitchSchedule>& schedules, const std::vector<RollingShutter>& shutters,
           int flags, const std::vector<double>& referenceAngles, double maxTimeOffset, double maxConsistency) {
            const std::vector<cv::Mat> stills = toMats(references, "references"), blurred = toMats(frames, "frames");
            py::gil_scoped_release release;
            return calibrateTiming(required(plant, "plant"), required(camera, "camera"), stills, blurred, schedules,
                                   shutters, flags, referenceAngles, maxTimeOffset, maxConsistency);
        },
        py::arg("plant"), py::arg("camera"), py::arg("references"), py::arg("frames"), py::arg("schedules"),
        py::arg("shutters"), py::arg("flags") = int(REFINE_TIME_OFFSET | REFINE_LINE_DELAY),
        py::arg("referenceAngles") = std::vector<double>(), py::arg("maxTimeOffset") = 0.02,
        py::arg("maxConsistency") = 3.0,
        R"doc(One clock offset, line delay (and, with REFINE_PLANT, scales of wn and zeta) for a whole recording,
from several frames each paired with a still frame (before the move for a frame that starts at rest,
after it for one that ends at rest). referenceAngles: radians, empty = each schedule's initial
resting angle. Returns a TimingCalibration.)doc");

    m.def("calibrateTiming",
        [](const std::shared_ptr<CameraMotion>& motion, const std::shared_ptr<CameraModel>& camera,
           py::handle references, py::handle frames, const std::vector<RollingShutter>& shutters,
           const std::vector<RollingShutter>& referenceShutters, int flags, double maxTimeOffset,
           double maxConsistency) {
            const std::vector<cv::Mat> stills = toMats(references, "references"), blurred = toMats(frames, "frames");
            py::gil_scoped_release release;
            return calibrateTiming(required(motion, "motion"), required(camera, "camera"), stills, blurred, shutters,
                                   referenceShutters, flags, maxTimeOffset, maxConsistency);
        },
        py::arg("motion"), py::arg("camera"), py::arg("references"), py::arg("frames"), py::arg("shutters"),
        py::arg("referenceShutters"), py::arg("flags") = int(REFINE_TIME_OFFSET | REFINE_LINE_DELAY),
        py::arg("maxTimeOffset") = 0.02, py::arg("maxConsistency") = 3.0,
        R"doc(The clock offset, line delay (and, with REFINE_GYRO_BIAS, the gyro bias) of a recording whose
motion was measured (a gyro log's CameraMotion), from frames each paired with a still placed by its
capture time (the mid-exposure of its shutter in referenceShutters). Returns a TimingCalibration.)doc");

    m.def("calibrateTiming",
        [](const std::vector<std::shared_ptr<CameraMotion>>& motions, const std::shared_ptr<CameraModel>& camera,
           py::handle references, py::handle frames, const std::vector<RollingShutter>& shutters, int flags,
           const std::vector<int>& referencesAfter, double maxTimeOffset, double maxConsistency) {
            const std::vector<cv::Mat> stills = toMats(references, "references"), blurred = toMats(frames, "frames");
            std::vector<cv::Ptr<CameraMotion>> moves;
            for (const std::shared_ptr<CameraMotion>& motion : motions)
                moves.push_back(required(motion, "motions"));
            py::gil_scoped_release release;
            return calibrateTiming(moves, required(camera, "camera"), stills, blurred, shutters, flags,
                                   referencesAfter, maxTimeOffset, maxConsistency);
        },
        py::arg("motions"), py::arg("camera"), py::arg("references"), py::arg("frames"), py::arg("shutters"),
        py::arg("flags") = int(REFINE_TIME_OFFSET | REFINE_LINE_DELAY), py::arg("referencesAfter") = std::vector<int>(),
        py::arg("maxTimeOffset") = 0.02, py::arg("maxConsistency") = 3.0,
        R"doc(The clock offset, line delay (and, with REFINE_PLANT, each axis's wn and zeta scales) of a
recording made with a mount: one Mount.motion per frame, each frame paired with a still at rest before
its move (or after it, where referencesAfter is non-zero). Returns a TimingCalibration.)doc");

    m.def("motionConsistency",
        [](const std::shared_ptr<Plant>& plant, const std::shared_ptr<CameraModel>& camera, py::handle reference,
           py::handle frame, const SwitchSchedule& schedule, const RollingShutter& shutter,
           const std::vector<MotionCorrection>& candidates, double referenceAngle, int maxWidth) {
            MatIn still = toFrame(reference, "reference"), blurred = toFrame(frame, "frame");
            py::gil_scoped_release release;
            return motionConsistency(required(plant, "plant"), required(camera, "camera"), still.mat, blurred.mat,
                                     schedule, shutter, candidates, referenceAngle, maxWidth);
        },
        py::arg("plant"), py::arg("camera"), py::arg("reference"), py::arg("frame"), py::arg("schedule"),
        py::arg("shutter"), py::arg("candidates"), py::arg("referenceAngle") = std::numeric_limits<double>::quiet_NaN(),
        py::arg("maxWidth") = 320,
        "The consistency of each candidate MotionCorrection with one frame (for plots and diagnostics).");

    m.def("blindMotionConsistency",
        [](const std::shared_ptr<Plant>& plant, const std::shared_ptr<CameraModel>& camera, py::handle frame,
           const SwitchSchedule& schedule, const RollingShutter& shutter,
           const std::vector<MotionCorrection>& candidates, int maxWidth) {
            MatIn blurred = toFrame(frame, "frame");
            py::gil_scoped_release release;
            return blindMotionConsistency(required(plant, "plant"), required(camera, "camera"), blurred.mat, schedule,
                                          shutter, candidates, maxWidth);
        },
        py::arg("plant"), py::arg("camera"), py::arg("frame"), py::arg("schedule"), py::arg("shutter"),
        py::arg("candidates"), py::arg("maxWidth") = 320,
        "The blind criterion of each candidate MotionCorrection for one frame without a reference (NaN: the "
        "frame has too few still rows).");
}

}  // namespace dynblur_py
