// SPDX-License-Identifier: Apache-2.0
// Bindings of shutter.hpp: RollingShutter, the exposure windows, classifyExposure of a plant.
#include "bindings.hpp"

#include <opencv2/dynblur/shutter.hpp>

#include <memory>
#include <sstream>

namespace dynblur_py {

using namespace cv::dynblur;

void bindShutter(py::module_& m)
{
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
}

}  // namespace dynblur_py
