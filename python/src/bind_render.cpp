// SPDX-License-Identifier: Apache-2.0
// Bindings of render.hpp: the forward model (renderBlurred), sensor noise, sRGB conversions.
#include "bindings.hpp"

#include <opencv2/dynblur/render.hpp>

#include <cstdint>
#include <memory>

namespace dynblur_py {

using namespace cv::dynblur;

void bindRender(py::module_& m)
{
    // ---------------------------------------------------------------- render.hpp
    m.def("renderBlurred",
        [](py::handle sharp, const std::shared_ptr<CameraMotion>& motion, const std::shared_ptr<CameraModel>& camera,
           const RollingShutter& shutter, double tRef, double maxStepPx, int borderMode) {
            MatIn in = toMat(sharp, "sharp");
            auto m = required(motion, "motion");
            auto c = required(camera, "camera");
            cv::Mat out;
            {
                py::gil_scoped_release release;
                renderBlurred(in.mat, m, c, shutter, out, tRef, maxStepPx, borderMode);
            }
            return fromMat(out);
        },
        py::arg("sharp"), py::arg("motion"), py::arg("camera"), py::arg("shutter"), py::arg("tRef") = kNaN,
        py::arg("maxStepPx") = 0.25, py::arg("borderMode") = int(cv::BORDER_REFLECT_101),
        R"doc(The physical forward model for any camera motion (CameraMotion): each row is the time average of
the sharp view turned by R(t) = Q_refᵀ·Q(t) over its own exposure. sharp: the view at Q(tRef) (as
for the plant form); tRef: seconds, NaN = the motion's default (a plant's final rest, a sampled
motion's mid-exposure). Returns the blurred frame.)doc");
    m.def("renderBlurred",
        [](py::handle sharp, const std::shared_ptr<Plant>& plant, const SwitchSchedule& schedule,
           const std::shared_ptr<CameraModel>& camera, const RollingShutter& shutter, double thetaRef,
           double maxStepPx, int borderMode) {
            MatIn in = toMat(sharp, "sharp");
            auto p = required(plant, "plant");
            auto c = required(camera, "camera");
            const SwitchSchedule s = schedule;
            cv::Mat out;
            {
                py::gil_scoped_release release;
                renderBlurred(in.mat, p, s, c, shutter, out, thetaRef, maxStepPx, borderMode);
            }
            return fromMat(out);
        },
        py::arg("sharp"), py::arg("plant"), py::arg("schedule"), py::arg("camera"), py::arg("shutter"),
        py::arg("thetaRef") = kNaN, py::arg("maxStepPx") = 0.25, py::arg("borderMode") = int(cv::BORDER_REFLECT_101),
        R"doc(The physical forward model: the frame a rolling-shutter sensor records while the positioner
follows a schedule. Each row is the time average, in linear intensity, of the view warped to the
camera's angle over its own exposure interval (uint8 input is taken as sRGB).

sharp: the motion-free view at θ_ref, the camera's image size or larger by the same margin on each
side, 1–4 channels, uint8/float32/float64; shutter.rows must equal the image height; thetaRef:
radians, NaN = the schedule's final resting angle; maxStepPx: largest image motion between time
samples, pixels, in (0, 1]; borderMode: cv2.BORDER_* used beyond sharp.
Returns the blurred frame (camera's image size, same dtype as sharp).)doc");

    m.def("addSensorNoise",
        [](py::handle linear, double fullWell, double readNoise, double dark, std::uint64_t seed) {
            MatIn in = toMat(linear, "linear");
            cv::Mat out;
            {
                py::gil_scoped_release release;
                addSensorNoise(in.mat, out, fullWell, readNoise, dark, seed);
            }
            return fromMat(out);
        },
        py::arg("linear"), py::arg("fullWellElectrons") = 4000.0, py::arg("readNoiseElectrons") = 8.0,
        py::arg("darkElectrons") = 5.0, py::arg("seed") = std::uint64_t(0x5eed),
        R"doc(Adds webcam sensor noise to a linear-intensity float32 image in [0, 1]: Poisson shot noise
(photons and dark current) and Gaussian read noise, then clips to [0, 1]. The same seed gives the
same noise. Returns float32.)doc");

    m.def("srgbToLinear",
        [](py::handle srgb) {
            MatIn in = toMat(srgb, "srgb");
            cv::Mat out;
            srgbToLinear(in.mat, out);
            return fromMat(out);
        },
        py::arg("srgb"), "sRGB (uint8 or [0,1] float) to linear intensity in [0, 1], float32, same channels.");
    m.def("linearToSrgb",
        [](py::handle linear, int depth) {
            MatIn in = toMat(linear, "linear");
            cv::Mat out;
            linearToSrgb(in.mat, out, depth);
            return fromMat(out);
        },
        py::arg("linear"), py::arg("depth") = int(CV_8U),
        "Linear intensity (float32) to sRGB of the requested depth (cv2.CV_8U = 0 or cv2.CV_32F = 5).");
}

}  // namespace dynblur_py
