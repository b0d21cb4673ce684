// SPDX-License-Identifier: Apache-2.0
// Bindings of clip_timing.hpp: ClipTimingOptions, ClipTimingCalibrator and calibrateTiming of a clip.
#include "bindings.hpp"

#include <opencv2/dynblur/clip_timing.hpp>

namespace dynblur_py {

using namespace cv::dynblur;

void bindClipTiming(py::module_& m)
{
    py::class_<ClipTimingOptions>(m, "ClipTimingOptions", R"doc(Settings of ClipTimingCalibrator: the calibration of a
clip against its gyro log from the frames alone, with no still frame.)doc")
        .def(py::init<>())
        .def_readwrite("maxTimeOffset", &ClipTimingOptions::maxTimeOffset,
                       "half-width of the clock offset's search, seconds, in (0, 60] (default 2)")
        .def_readwrite("flags", &ClipTimingOptions::flags,
                       "MotionRefinement flags of the fine stage: REFINE_TIME_OFFSET, and REFINE_LINE_DELAY, "
                       "REFINE_GYRO_BIAS, REFINE_RATE_SCALE (default the first three)")
        .def_readwrite("scanReadout", &ClipTimingOptions::scanReadout,
                       "search the readout from a quarter to twice the shutters' (default True)")
        .def_readwrite("detectAxes", &ClipTimingOptions::detectAxes,
                       "adopt the signed mapping of the log's axes the images show (default True); False: refuse a "
                       "log whose axes the images contradict")
        .def_readwrite("analysisWidth", &ClipTimingOptions::analysisWidth,
                       "the frames are measured at this width, pixels, in [160, 4096] (default 640)");

    py::class_<ClipTimingCalibrator, std::shared_ptr<ClipTimingCalibrator>>(m, "ClipTimingCalibrator", R"doc(Calibrates a
clip in continuous motion against its gyro log, with no still frame: the clock offset (seconds apart),
the line delay, the gyro bias, optionally a rate scale, and the log's axes. Frames are added one at a
time, in order (addFrame); calibrate() returns a TimingCalibration or raises dynblur.error naming
what the images contradict (the units, the axes, another clip's log).)doc")
        .def_static(
            "create",
            [](const std::shared_ptr<CameraModel>& camera, const GyroLog& log, const ClipTimingOptions& options) {
                return std::shared_ptr<ClipTimingCalibrator>(
                    ClipTimingCalibrator::create(required(camera, "camera"), log, options));
            },
            py::arg("camera"), py::arg("log"), py::arg("options") = ClipTimingOptions())
        .def(
            "addFrame",
            [](ClipTimingCalibrator& c, py::handle frame, const RollingShutter& shutter) {
                MatIn f = toFrame(frame, "frame");
                py::gil_scoped_release release;
                c.addFrame(f.mat, shutter);
            },
            py::arg("frame"), py::arg("shutter"),
            "Adds the clip's next frame (uint8 sRGB or float32 linear) with its timing on the video's clock.")
        .def("getFrameCount", &ClipTimingCalibrator::getFrameCount)
        .def("calibrate", &ClipTimingCalibrator::calibrate, py::call_guard<py::gil_scoped_release>(),
             "The calibration of the frames added (a TimingCalibration).");

    m.def(
        "calibrateTiming",
        [](const GyroLog& log, const std::shared_ptr<CameraModel>& camera, py::handle frames,
           const std::vector<RollingShutter>& shutters, const ClipTimingOptions& options) {
            const std::vector<cv::Mat> images = toMats(frames, "frames");
            py::gil_scoped_release release;
            return calibrateTiming(log, required(camera, "camera"), images, shutters, options);
        },
        py::arg("log"), py::arg("camera"), py::arg("frames"), py::arg("shutters"),
        py::arg("options") = ClipTimingOptions(),
        R"doc(A clip's calibration against its gyro log from frames in memory (ClipTimingCalibrator over them).)doc");
}

}  // namespace dynblur_py
