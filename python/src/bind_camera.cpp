// SPDX-License-Identifier: Apache-2.0
// Bindings of camera.hpp: CameraModel.
#include "bindings.hpp"

#include <opencv2/dynblur/camera.hpp>

#include <memory>
#include <vector>

namespace dynblur_py {

using namespace cv::dynblur;

namespace {

//! Points of shape (..., 2) → N×2 CV_64F, call, and back to the input's shape.
template <typename View>
py::array viewToReference(const CameraModel& cam, py::handle points, const View& view)
{
    auto a = toDoubleArray(points, "points");
    if (a.ndim() < 1 || a.shape(a.ndim() - 1) != 2)
        throw py::value_error("argument 'points' must have shape (..., 2): pixel (x, y) pairs");
    std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim());
    cv::Mat in(int(a.size() / 2), 2, CV_64F, const_cast<double*>(a.data())), out;
    {
        py::gil_scoped_release release;
        cam.viewToReference(in, view, out);
    }
    out = out.reshape(1, int(a.size() / 2));
    py::array_t<double> result(shape);
    CV_Assert(out.total() == size_t(result.size()) && out.depth() == CV_64F && out.isContinuous());
    std::copy(out.ptr<double>(), out.ptr<double>() + out.total(), result.mutable_data());
    return result;
}

}  // namespace

void bindCamera(py::module_& m)
{
    // ---------------------------------------------------------------- CameraModel
    py::class_<CameraModel, std::shared_ptr<CameraModel>>(m, "CameraModel", R"doc(Pinhole camera with ViSP's one-term radial distortion, mounted on the positioner.
u = cx + fx·x·(1 + kud·r²), v = cy + fy·y·(1 + kud·r²); a distorted pixel is undistorted with kdu.
Camera frame: x right, y down, z forward. The camera rotates about mountAxis (default +x: tilt);
the view at θ relative to θ_ref is I_θ(p) = I_ref(K·R_axis(θ − θ_ref)·K⁻¹·p).)doc")
        .def_static("create",
            [](double fx, double fy, double cx, double cy, int w, int h, double kud, double kdu) {
                return std::shared_ptr<CameraModel>(CameraModel::create(fx, fy, cx, cy, w, h, kud, kdu));
            },
            py::arg("fx"), py::arg("fy"), py::arg("cx"), py::arg("cy"), py::arg("width"), py::arg("height"),
            py::arg("kud") = 0.0, py::arg("kdu") = 0.0,
            R"doc(fx, fy: focal lengths, pixels, > 0; cx, cy: principal point, pixels; width, height: image
size, pixels; kud, kdu: ViSP's undistorted→distorted and distorted→undistorted radial coefficients.)doc")
        .def_static("load",
            [](const std::string& f, const std::string& name, int w, int h) {
                return std::shared_ptr<CameraModel>(CameraModel::load(f, name, w, h));
            },
            py::arg("filename"), py::arg("cameraName") = "", py::arg("width") = 0, py::arg("height") = 0,
            R"doc(Reads a ViSP camera XML file (vpXmlParserCamera format). cameraName: empty takes the first
camera; width, height: image size to select (0: any).)doc")
        .def("save", py::overload_cast<const cv::String&, const cv::String&>(&CameraModel::save, py::const_),
             py::arg("filename"), py::arg("cameraName") = "Camera",
             "Writes a ViSP camera XML file, with distortion when kud or kdu is non-zero.")
        .def("getFx", &CameraModel::getFx, "focal length along x, pixels")
        .def("getFy", &CameraModel::getFy, "focal length along y, pixels")
        .def("getCx", &CameraModel::getCx, "principal point x, pixels")
        .def("getCy", &CameraModel::getCy, "principal point y, pixels")
        .def("getKud", &CameraModel::getKud, "undistorted→distorted radial coefficient")
        .def("getKdu", &CameraModel::getKdu, "distorted→undistorted radial coefficient")
        .def("getImageSize", &CameraModel::getImageSize, "image size (width, height), pixels")
        .def("getMountAxis", &CameraModel::getMountAxis, "Rotation axis of the mount in the camera frame (unit vector).")
        .def("setMountAxis", &CameraModel::setMountAxis, py::arg("axis"),
             "axis: rotation axis in the camera frame, non-zero; it is normalised.")
        .def("cameraMatrix", &CameraModel::cameraMatrix, "The 3×3 intrinsic matrix K (float64 array).")
        .def("pixelToNormalized", &CameraModel::pixelToNormalized, py::arg("pixel"),
             "Undistorted normalised coordinates (x, y) of a (distorted) pixel (u, v).")
        .def("normalizedToPixel", &CameraModel::normalizedToPixel, py::arg("normalized"),
             "(Distorted) pixel (u, v) of undistorted normalised coordinates (x, y).")
        .def("viewToReference", &viewToReference<double>, py::arg("points"), py::arg("angle"),
             R"doc(Where pixels of the view at θ = θ_ref + angle see the reference view:
q = distort(K·R_axis(angle)·K⁻¹·undistort(p)). points: array of shape (..., 2), pixels;
angle: radians. Returns float64 pixel coordinates of the same shape (NaN for a ray behind the camera).)doc")
        .def("viewToReference", &viewToReference<cv::Matx33d>, py::arg("points"), py::arg("rotation"),
             R"doc(Where pixels of the view turned by any rotation R relative to the reference see the reference
view: q = distort(K·R·K⁻¹·undistort(p)) (R = Q_refᵀ·Q(t), CameraMotion.relativeRotation).
points: array of shape (..., 2), pixels; rotation: 3×3 rotation matrix. Returns float64 pixel
coordinates of the same shape.)doc");
}

}  // namespace dynblur_py
