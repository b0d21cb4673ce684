// SPDX-License-Identifier: Apache-2.0
// Bindings of calibration.hpp: the ViSP chessboard calibration as a library call from Python.
#include "bindings.hpp"

#include <opencv2/dynblur/calibration.hpp>

#include <memory>

namespace dynblur_py {

using namespace cv::dynblur;

void bindCalibration(py::module_& m)
{
    py::class_<CameraCalibration>(m, "CameraCalibration", R"doc(Result of calibrateCameraViSP: ViSP intrinsics
(px, py, u0, v0 in pixels; kud, kdu dimensionless), the global and per-view RMS reprojection
residuals (pixels), and the fate of every input view (viewUsed, viewStatus). List fields are copies.)doc")
        .def(py::init<>())
        .def_readwrite("px", &CameraCalibration::px, "focal length along x, pixels")
        .def_readwrite("py", &CameraCalibration::py, "focal length along y, pixels")
        .def_readwrite("u0", &CameraCalibration::u0, "principal point x, pixels")
        .def_readwrite("v0", &CameraCalibration::v0, "principal point y, pixels")
        .def_readwrite("kud", &CameraCalibration::kud, "undistorted-to-distorted radial coefficient (ViSP)")
        .def_readwrite("kdu", &CameraCalibration::kdu, "distorted-to-undistorted radial coefficient (ViSP)")
        .def_readwrite("imageSize", &CameraCalibration::imageSize, "size (width, height) of the images, pixels")
        .def_readwrite("globalResidual", &CameraCalibration::globalResidual,
                       "RMS reprojection residual over the used views' corners, pixels")
        .def_readwrite("vispGlobalResidual", &CameraCalibration::vispGlobalResidual,
                       "the residual ViSP's computeCalibrationMulti reports, pixels")
        .def_readwrite("viewNames", &CameraCalibration::viewNames, "name of each input view")
        .def_readwrite("viewUsed", &CameraCalibration::viewUsed, "1 when the view is in the final fit, else 0")
        .def_readwrite("viewStatus", &CameraCalibration::viewStatus, "'used', or why the view was left out")
        .def_readwrite("viewResiduals", &CameraCalibration::viewResiduals,
                       "RMS reprojection residual of each view, pixels (NaN without corners)")
        .def_property_readonly("imagePoints",
            [](const CameraCalibration& c) {
                py::list views;
                for (const auto& corners : c.imagePoints)
                    views.append(fromMat(cv::Mat(corners, true).reshape(1)));
                return views;
            },
            "detected corners of each view, an (N, 2) float32 array each (empty when not found), pixels")
        .def("cameraModel", [](const CameraCalibration& c) { return std::shared_ptr<CameraModel>(c.cameraModel()); },
             "The calibrated CameraModel (kud, kdu, image size).")
        .def("cameraMatrix", [](const CameraCalibration& c) { return fromMat(cv::Mat(c.cameraMatrix())); },
             "OpenCV's 3x3 camera matrix [px 0 u0; 0 py v0; 0 0 1].")
        .def("openCVDistortion", [](const CameraCalibration& c) { return fromMat(c.openCVDistortion()); },
             "OpenCV distortion coefficients (k1, k2, p1, p2, k3) = (kud, 0, 0, 0, 0).")
        .def("usedViews", &CameraCalibration::usedViews, "Number of views in the final fit.");

    m.def("detectChessboardCorners",
        [](py::handle image, cv::Size boardSize) {
            MatIn in = toMat(image, "image");
            cv::Mat corners;
            bool found;
            {
                py::gil_scoped_release release;
                found = detectChessboardCorners(in.mat, boardSize, corners);
            }
            return py::make_tuple(found, found ? py::object(fromMat(corners.reshape(1))) : py::object(py::none()));
        },
        py::arg("image"), py::arg("boardSize"),
        R"doc(Finds the inner corners of a chessboard (findChessboardCorners + cornerSubPix).
image: 8-bit grey or BGR; boardSize: inner corners (columns, rows), each >= 2.
Returns (found, corners) with corners an (N, 2) float32 array in pixels, or None.)doc");

    m.def("calibrateCameraViSP",
        [](const std::vector<cv::String>& imagePaths, cv::Size boardSize, double squareSize, double outlierFactor) {
            py::gil_scoped_release release;
            return calibrateCameraViSP(imagePaths, boardSize, squareSize, outlierFactor);
        },
        py::arg("imagePaths"), py::arg("boardSize"), py::arg("squareSize"), py::arg("outlierFactor") = 3.0,
        R"doc(Calibrates the camera intrinsics from chessboard image files with ViSP (per view CALIB_VIRTUAL_VS,
then computeCalibrationMulti with CALIB_VIRTUAL_VS_DIST). boardSize: inner corners (columns, rows);
squareSize: metres; views above outlierFactor x the median residual (and 0.5 px) are left out
and reported. Raises dynblur.error with fewer than 3 usable views. Not thread safe (ViSP's
calibration gain is process-wide).)doc");

    m.def("calibrateCameraViSPImages",
        [](py::iterable images, const std::vector<cv::String>& viewNames, cv::Size boardSize, double squareSize,
           double outlierFactor) {
            std::vector<MatIn> held;
            std::vector<cv::Mat> mats;
            int i = 0;
            for (auto image : images)
            {
                const std::string name = "images[" + std::to_string(i++) + "]";
                held.push_back(toMat(image, name.c_str()));
                mats.push_back(held.back().mat);
            }
            py::gil_scoped_release release;
            return calibrateCameraViSPImages(mats, viewNames, boardSize, squareSize, outlierFactor);
        },
        py::arg("images"), py::arg("viewNames"), py::arg("boardSize"),
        py::arg("squareSize"), py::arg("outlierFactor") = 3.0,
        "calibrateCameraViSP on 8-bit images already in memory; viewNames names them in the report.");
}

}  // namespace dynblur_py
