// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_CAMERA_HPP
#define OPENCV_DYNBLUR_CAMERA_HPP

#include <opencv2/core.hpp>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_imaging
//! @{

/** @brief Pinhole camera with ViSP's one-term radial distortion, mounted on the positioner.

Intrinsics follow ViSP's perspective model with distortion @cite Marchand2005Visp:
a normalised undistorted point (x, y) projects to u = cx + fx·x·(1 + kud·r²),
v = cy + fy·y·(1 + kud·r²); a distorted pixel is undistorted with kdu. Camera frame: x right,
y down, z forward. The camera rotates about `mountAxis` (unit vector in the camera frame,
default +x: tilt). The view at angle θ relative to θ_ref is
I_θ(p) = I_ref(K·R_axis(θ − θ_ref)·K⁻¹·p) (DESIGN §2).
*/
class CV_EXPORTS_W CameraModel : public Algorithm
{
public:
    /** @param fx, fy focal lengths, pixels, > 0.
        @param cx, cy principal point, pixels.
        @param width, height image size, pixels, > 0.
        @param kud undistorted-to-distorted radial coefficient (ViSP), dimensionless.
        @param kdu distorted-to-undistorted radial coefficient (ViSP), dimensionless. */
    CV_WRAP static Ptr<CameraModel> create(double fx, double fy, double cx, double cy, int width, int height,
                                           double kud = 0.0, double kdu = 0.0);

    /** @brief Reads a ViSP camera XML file (vpXmlParserCamera format).
    @param filename path of the XML file.
    @param cameraName camera name in the file; empty takes the first one.
    @param width, height image size to select in the file (0: any); the file's size is used. */
    CV_WRAP static Ptr<CameraModel> load(const String& filename, const String& cameraName = String(),
                                         int width = 0, int height = 0);
    /** @brief Writes a ViSP camera XML file, with distortion when kud or kdu is non-zero.
    @param filename path of the XML file; an existing file is replaced.
    @param cameraName camera name in the file. */
    CV_WRAP virtual void save(const String& filename, const String& cameraName) const = 0;
    /** @brief Writes a ViSP camera XML file with the camera named "Camera" (so Algorithm::save also
    writes the ViSP format). */
    CV_WRAP void save(const String& filename) const CV_OVERRIDE { save(filename, "Camera"); }

    CV_WRAP virtual double getFx() const = 0;  //!< focal length along x, pixels
    CV_WRAP virtual double getFy() const = 0;  //!< focal length along y, pixels
    CV_WRAP virtual double getCx() const = 0;  //!< principal point x, pixels
    CV_WRAP virtual double getCy() const = 0;  //!< principal point y, pixels
    CV_WRAP virtual double getKud() const = 0; //!< undistorted→distorted radial coefficient
    CV_WRAP virtual double getKdu() const = 0; //!< distorted→undistorted radial coefficient
    CV_WRAP virtual Size getImageSize() const = 0; //!< image size, pixels
    /** @brief Rotation axis of the mount in the camera frame (unit vector). */
    CV_WRAP virtual Vec3d getMountAxis() const = 0;
    /** @param axis rotation axis in the camera frame, non-zero; it is normalised. */
    CV_WRAP virtual void setMountAxis(const Vec3d& axis) = 0;
    /** @brief The 3×3 intrinsic matrix K. */
    CV_WRAP virtual Matx33d cameraMatrix() const = 0;

    /** @brief Undistorted normalised coordinates of a (distorted) pixel, ViSP's
    vpPixelMeterConversion formula: x = (u − cx)/fx · (1 + kdu·r²), r² from the distorted pixel.
    @param pixel pixel coordinates, pixels. @return normalised coordinates (x, y), dimensionless. */
    CV_WRAP virtual Point2d pixelToNormalized(const Point2d& pixel) const = 0;
    /** @brief (Distorted) pixel of undistorted normalised coordinates, ViSP's vpMeterPixelConversion
    formula: u = cx + fx·x·(1 + kud·(x² + y²)).
    @param normalized normalised coordinates (x, y), dimensionless. @return pixel coordinates, pixels. */
    CV_WRAP virtual Point2d normalizedToPixel(const Point2d& normalized) const = 0;

    /** @brief Where a pixel of the view at θ = θ_ref + angle sees the reference view:
    q = distort(K·R_axis(angle)·K⁻¹·undistort(p)).

    With distortion, ViSP's kud and kdu are only approximate inverses of each other; so that a zero
    angle maps every pixel exactly onto itself, the mapping is computed as
    q = p + distort(R·undistort(p)) − distort(undistort(p)) (identical to the formula above when
    the distortion pair is exactly inverse, and within ViSP's approximation otherwise). A ray that
    turns behind the reference camera gives NaN.
    @param points Nx2 or 1xN 2-channel pixel coordinates in the rotated view, pixels.
    @param angle θ − θ_ref, radians.
    @param refPoints output, same layout, pixel coordinates in the reference view (CV_64F). */
    CV_WRAP virtual void viewToReference(InputArray points, double angle, OutputArray refPoints) const = 0;
    /** @brief Scalar form of viewToReference for one pixel. */
    virtual Point2d viewToReference(const Point2d& pixel, double angle) const = 0;
    /** @brief Where a pixel of the view turned by any rotation R relative to the reference sees the
    reference view: q = distort(K·R·K⁻¹·undistort(p)), computed as the angle form is (DESIGN §2,
    Rotation: R = Q_refᵀ·Q(t), CameraMotion::relativeRotation).
    @param points Nx2 or 1xN 2-channel pixel coordinates in the rotated view, pixels.
    @param rotation R, a rotation matrix (orthonormal to 1e-6, det = +1).
    @param refPoints output, same layout, pixel coordinates in the reference view (CV_64F). */
    CV_WRAP virtual void viewToReference(InputArray points, const Matx33d& rotation, OutputArray refPoints) const = 0;
    /** @brief Scalar form of the rotation form of viewToReference for one pixel. */
    virtual Point2d viewToReference(const Point2d& pixel, const Matx33d& rotation) const = 0;
};

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
