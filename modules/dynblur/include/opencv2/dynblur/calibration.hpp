// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_CALIBRATION_HPP
#define OPENCV_DYNBLUR_CALIBRATION_HPP

#include <opencv2/core.hpp>

#include "opencv2/dynblur/camera.hpp"

#include <vector>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_imaging
//! @{

/** @brief Result of a chessboard calibration of the camera intrinsics (calibrateCameraViSP).

Intrinsics are in ViSP's perspective model with one radial term @cite Marchand2005Visp
(see CameraModel): a normalised undistorted point (x, y) projects to
u = u0 + px·x·(1 + kud·r²), v = v0 + py·y·(1 + kud·r²), r² = x² + y². This is exactly OpenCV's
model with k1 = kud and k2 = p1 = p2 = k3 = 0 (openCVDistortion()); kdu, ViSP's separate
distorted-to-undistorted coefficient, has no OpenCV counterpart (OpenCV inverts numerically).

Every input view has one entry in the per-view vectors, in input order, whether it was used or not:
`viewUsed[i]` is 1 when the view took part in the final fit, and `viewStatus[i]` says why not
("image unreadable", "chessboard not found", "image size differs", "outlier: ...").
*/
struct CV_EXPORTS_W_SIMPLE CameraCalibration
{
    CV_WRAP CameraCalibration();

    CV_PROP_RW double px;        //!< focal length along x, pixels
    CV_PROP_RW double py;        //!< focal length along y, pixels
    CV_PROP_RW double u0;        //!< principal point x, pixels
    CV_PROP_RW double v0;        //!< principal point y, pixels
    CV_PROP_RW double kud;       //!< undistorted→distorted radial coefficient (ViSP), dimensionless
    CV_PROP_RW double kdu;       //!< distorted→undistorted radial coefficient (ViSP), dimensionless
    CV_PROP_RW Size imageSize;   //!< size of the calibrated images, pixels

    /** @brief RMS reprojection residual over all corners of the used views, pixels: the corners of
    the board projected with the fitted poses and the forward (kud) model against the detected
    corners, sqrt(Σ|Δ|²/N) — the same definition as the value cv::calibrateCamera returns. */
    CV_PROP_RW double globalResidual;
    /** @brief The global residual ViSP's vpCalibration::computeCalibrationMulti reports, pixels
    (it averages the kud and the kdu directions of its model). */
    CV_PROP_RW double vispGlobalResidual;

    CV_PROP_RW std::vector<String> viewNames;       //!< name of each input view (file path or given name)
    CV_PROP_RW std::vector<int> viewUsed;           //!< 1 when the view is in the final fit, else 0
    CV_PROP_RW std::vector<String> viewStatus;      //!< "used", or why the view was left out
    CV_PROP_RW std::vector<double> viewResiduals;   //!< RMS reprojection residual of each view, pixels (NaN without corners)
    /** @brief Detected inner corners of each view (row by row, cornerSubPix-refined), pixels;
    empty when the board was not found. */
    CV_PROP_RW std::vector<std::vector<Point2f> > imagePoints;

    /** @brief The calibrated camera (CameraModel::create with kud, kdu and imageSize). */
    CV_WRAP Ptr<CameraModel> cameraModel() const;
    /** @brief OpenCV's 3×3 camera matrix [px 0 u0; 0 py v0; 0 0 1]. */
    CV_WRAP Matx33d cameraMatrix() const;
    /** @brief OpenCV distortion coefficients (k1, k2, p1, p2, k3) = (kud, 0, 0, 0, 0): exact for the
    projection of 3D points; OpenCV inverts it iteratively where ViSP uses kdu. */
    CV_WRAP Mat openCVDistortion() const;
    /** @brief Number of views in the final fit. */
    CV_WRAP int usedViews() const;
};

/** @brief Finds the inner corners of a chessboard with OpenCV (findChessboardCorners, then
cornerSubPix on an 11×11 window).
@param image 8-bit grey or BGR image.
@param boardSize inner corners per row and per column (e.g. 9×6), each ≥ 2.
@param corners output, boardSize.area() corners row by row (CV_32FC2), pixels; empty if not found.
@return true when the whole board was found. */
CV_EXPORTS_W bool detectChessboardCorners(InputArray image, Size boardSize, OutputArray corners);

/** @brief Calibrates the camera intrinsics from chessboard images with ViSP @cite Marchand2005Visp
(planar-target calibration, @cite Zhang2000Flexible).

Steps: read each image (an unreadable one is reported and left out); detect its corners with
detectChessboardCorners (a view without the whole board is reported and left out); calibrate
each view alone with vpCalibration::computeCalibration(CALIB_VIRTUAL_VS) to get its pose;
then all views together with vpCalibration::computeCalibrationMulti(CALIB_VIRTUAL_VS_DIST),
starting from the per-view median intrinsics. Outlier rule: a view whose RMS residual exceeds
`outlierFactor` × the median of the used views' residuals (and 0.5 px) is marked
"outlier" and the fit is redone without it, until no view is rejected.
@param imagePaths image files, any format cv::imread reads; all must have the same size.
@param boardSize inner corners per row and per column (OpenCV's convention, e.g. 9×6), each ≥ 2.
@param squareSize side of one chessboard square, metres, > 0.
@param outlierFactor residual rejection factor (see above), > 1; 0 disables the rejection.
@return intrinsics, residuals and the fate of every view.
@throws cv::Exception when fewer than 3 views are usable (the message lists each view and why),
or when an argument is out of range.
@note Not to be called from several threads at once: ViSP's calibration gain is process-wide (it
is raised to 1 during the fit and restored after). */
CV_EXPORTS_W CameraCalibration calibrateCameraViSP(const std::vector<String>& imagePaths, Size boardSize,
                                                   double squareSize, double outlierFactor = 3.0);

/** @brief calibrateCameraViSP on images already in memory.
@param images 8-bit grey or BGR images, all the same size (an empty one counts as unreadable).
@param viewNames a name per image for the report (empty: "view 0", "view 1", ...).
@param boardSize inner corners per row and per column, each ≥ 2.
@param squareSize side of one chessboard square, metres, > 0.
@param outlierFactor residual rejection factor, > 1; 0 disables the rejection. */
CV_EXPORTS_W CameraCalibration calibrateCameraViSPImages(InputArrayOfArrays images,
                                                         const std::vector<String>& viewNames, Size boardSize,
                                                         double squareSize, double outlierFactor = 3.0);

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
