// SPDX-License-Identifier: Apache-2.0
// CameraModel: pinhole intrinsics with ViSP's one-term radial distortion, ViSP XML I/O and the
// view-to-reference mapping of a camera rotating about a fixed mount axis (DESIGN §2).
#include "precomp.hpp"

#include "imaging/half_camera.hpp"
#include "imaging/pinhole.hpp"

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpXmlParserCamera.h>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace cv {
namespace dynblur {

namespace {

void checkIntrinsics(double fx, double fy, double cx, double cy, int width, int height, double kud, double kdu,
                     const char* where)
{
    if (!(std::isfinite(fx) && fx > 0) || !(std::isfinite(fy) && fy > 0))
        CV_Error_(Error::StsBadArg, ("%s: focal lengths fx=%g, fy=%g must be finite and > 0 (pixels)", where, fx, fy));
    if (!std::isfinite(cx) || !std::isfinite(cy))
        CV_Error_(Error::StsBadArg, ("%s: principal point cx=%g, cy=%g must be finite (pixels)", where, cx, cy));
    if (width <= 0 || height <= 0)
        CV_Error_(Error::StsBadArg, ("%s: image size width=%d, height=%d must be > 0 (pixels)", where, width, height));
    if (!std::isfinite(kud) || !std::isfinite(kdu))
        CV_Error_(Error::StsBadArg, ("%s: distortion kud=%g, kdu=%g must be finite", where, kud, kdu));
}

//! Name of the first <camera> of a ViSP XML file ("" when it has none or no name).
std::string firstCameraName(const std::string& filename)
{
    std::ifstream in(filename.c_str());
    if (!in)
        return std::string();
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    const size_t cam = text.find("<camera>");
    if (cam == std::string::npos)
        return std::string();
    const size_t camEnd = text.find("</camera>", cam);
    const size_t name = text.find("<name>", cam);
    if (name == std::string::npos || (camEnd != std::string::npos && name > camEnd))
        return std::string();
    const size_t b = name + 6, e = text.find("</name>", b);
    if (e == std::string::npos)
        return std::string();
    std::string s = text.substr(b, e - b);
    const size_t f = s.find_first_not_of(" \t\r\n"), l = s.find_last_not_of(" \t\r\n");
    return f == std::string::npos ? std::string() : s.substr(f, l - f + 1);
}

class CameraModelImpl CV_FINAL : public CameraModel
{
public:
    CameraModelImpl(double fx, double fy, double cx, double cy, int width, int height, double kud, double kdu)
        : pin_{fx, fy, cx, cy, kud, kdu, Vec3d(1, 0, 0)}, size_(width, height)
    {
    }

    using CameraModel::save;  // save(filename): the camera named "Camera"
    void save(const String& filename, const String& cameraName) const CV_OVERRIDE
    {
        CV_Assert(!filename.empty());
        vpCameraParameters cam;
        if (pin_.kud != 0.0 || pin_.kdu != 0.0)
            cam.initPersProjWithDistortion(pin_.fx, pin_.fy, pin_.cx, pin_.cy, pin_.kud, pin_.kdu);
        else
            cam.initPersProjWithoutDistortion(pin_.fx, pin_.fy, pin_.cx, pin_.cy);
        // vpXmlParserCamera appends to an existing file and refuses a duplicate camera:
        // CameraModel::save overwrites, like every OpenCV writer. It also reports success when it
        // cannot write the file at all (a missing folder): check that it can be created first.
        std::remove(filename.c_str());
        if (!std::ofstream(filename))
            CV_Error(Error::StsError, "CameraModel::save: cannot write '" + filename + "'");
        std::remove(filename.c_str());
        vpXmlParserCamera parser;
        if (parser.save(cam, filename, cameraName, (unsigned)size_.width, (unsigned)size_.height) !=
                vpXmlParserCamera::SEQUENCE_OK ||
            !std::ifstream(filename))
            CV_Error(Error::StsError, "CameraModel::save: ViSP could not write camera '" + cameraName + "' to '" +
                                          filename + "'");
    }

    double getFx() const CV_OVERRIDE { return pin_.fx; }
    double getFy() const CV_OVERRIDE { return pin_.fy; }
    double getCx() const CV_OVERRIDE { return pin_.cx; }
    double getCy() const CV_OVERRIDE { return pin_.cy; }
    double getKud() const CV_OVERRIDE { return pin_.kud; }
    double getKdu() const CV_OVERRIDE { return pin_.kdu; }
    Size getImageSize() const CV_OVERRIDE { return size_; }
    Vec3d getMountAxis() const CV_OVERRIDE { return pin_.axis; }

    void setMountAxis(const Vec3d& axis) CV_OVERRIDE
    {
        const double n = norm(axis);
        if (!(std::isfinite(n) && n > 1e-12))
            CV_Error_(Error::StsBadArg, ("CameraModel::setMountAxis: axis (%g, %g, %g) must be finite and non-zero",
                                         axis[0], axis[1], axis[2]));
        pin_.axis = axis * (1.0 / n);
    }

    Matx33d cameraMatrix() const CV_OVERRIDE { return Matx33d(pin_.fx, 0, pin_.cx, 0, pin_.fy, pin_.cy, 0, 0, 1); }

    void viewToReference(InputArray points, double angle, OutputArray refPoints) const CV_OVERRIDE
    {
        if (!std::isfinite(angle))
            CV_Error(Error::StsBadArg, "CameraModel::viewToReference: angle must be finite (radians)");
        mapPoints(points, pin_.rotation(angle), refPoints);
    }

    void viewToReference(InputArray points, const Matx33d& rotation, OutputArray refPoints) const CV_OVERRIDE
    {
        const double det = determinant(rotation);
        if (!(std::abs(det - 1) <= 1e-6) || !(norm(rotation * rotation.t() - Matx33d::eye(), NORM_INF) <= 1e-6))
            CV_Error_(Error::StsBadArg, ("CameraModel::viewToReference: rotation must be a rotation matrix (orthonormal "
                                         "to 1e-6, det = +1; its det is %g)",
                                         det));
        mapPoints(points, rotation, refPoints);
    }

    Point2d viewToReference(const Point2d& pixel, const Matx33d& rotation) const CV_OVERRIDE
    {
        return pin_.map(pixel, rotation);
    }

private:
    //! Every point of `points` mapped by pin_.map with the rotation M.
    void mapPoints(InputArray points, const Matx33d& M, OutputArray refPoints) const
    {
        Mat src = points.getMat();
        if (src.empty())
        {
            refPoints.release();
            return;
        }
        const int depth = src.depth();
        CV_CheckType(src.type(), depth == CV_32F || depth == CV_64F,
                     "CameraModel::viewToReference: points must be CV_32F or CV_64F");
        Mat pts;
        int outRows, outCols, outType;
        if (src.channels() == 2)
        {
            CV_CheckEQ(src.cols == 1 || src.rows == 1, true,
                       "CameraModel::viewToReference: 2-channel points must be 1xN or Nx1");
            if (depth == CV_64F && src.isContinuous())
                pts = src.reshape(2, 1);  // no copy
            else
                src.convertTo(pts, CV_64F);
            pts = pts.reshape(2, 1);
            outRows = src.rows;
            outCols = src.cols;
            outType = CV_64FC2;
        }
        else
        {
            CV_CheckEQ(src.channels(), 1, "CameraModel::viewToReference: points must be Nx2 (1 channel) or 2-channel");
            CV_CheckEQ(src.cols, 2, "CameraModel::viewToReference: 1-channel points must be Nx2");
            if (depth == CV_64F && src.isContinuous())
                pts = src;
            else
                src.convertTo(pts, CV_64F);
            pts = pts.reshape(2, 1);
            outRows = src.rows;
            outCols = 2;
            outType = CV_64FC1;
        }
        if (!pts.isContinuous())
            pts = pts.clone();
        if (refPoints.isMat() && refPoints.getMat().data == pts.data)
            pts = pts.clone();  // in-place call: keep the input
        refPoints.create(outRows, outCols, outType);
        Mat dst = refPoints.getMat();
        CV_Assert(dst.isContinuous());
        const Point2d* in = pts.ptr<Point2d>();
        Point2d* out = reinterpret_cast<Point2d*>(dst.data);
        const int n = (int)pts.total();
        parallel_for_(Range(0, n),
                      [&](const Range& r) {
                          for (int i = r.start; i < r.end; i++)
                              out[i] = pin_.map(in[i], M);
                      },
                      n / 16384.0);
    }

public:
    Point2d pixelToNormalized(const Point2d& p) const CV_OVERRIDE { return pin_.undistort(p); }

    Point2d normalizedToPixel(const Point2d& m) const CV_OVERRIDE { return pin_.distort(m.x, m.y); }

    Point2d viewToReference(const Point2d& pixel, double angle) const CV_OVERRIDE
    {
        return pin_.map(pixel, pin_.rotation(angle));
    }

private:
    detail::Pinhole pin_;  // intrinsics, distortion and mount axis
    Size size_;
};

}  // namespace

Ptr<CameraModel> CameraModel::create(double fx, double fy, double cx, double cy, int width, int height, double kud,
                                     double kdu)
{
    checkIntrinsics(fx, fy, cx, cy, width, height, kud, kdu, "CameraModel::create");
    return makePtr<CameraModelImpl>(fx, fy, cx, cy, width, height, kud, kdu);
}

Ptr<CameraModel> CameraModel::load(const String& filename, const String& cameraName, int width, int height)
{
    if (width < 0 || height < 0)
        CV_Error_(Error::StsBadArg,
                  ("CameraModel::load: width=%d, height=%d must be >= 0 (0: any size in the file)", width, height));
    {
        std::ifstream probe(filename.c_str());
        if (!probe)
            CV_Error(Error::StsError, "CameraModel::load: cannot open '" + filename + "'");
    }
    const std::string name = cameraName.empty() ? firstCameraName(filename) : std::string(cameraName);
    // Prefer the model with distortion when the file holds both (it is the more accurate one).
    const vpCameraParameters::vpCameraParametersProjType models[2] = {
        vpCameraParameters::perspectiveProjWithDistortion, vpCameraParameters::perspectiveProjWithoutDistortion};
    for (int m = 0; m < 2; m++)
    {
        vpXmlParserCamera parser;
        vpCameraParameters cam;
        int rc = vpXmlParserCamera::SEQUENCE_ERROR;
        try
        {
            rc = parser.parse(cam, filename, name, models[m], (unsigned)width, (unsigned)height);
        }
        catch (const std::exception& e)
        {
            CV_Error(Error::StsParseError, "CameraModel::load: ViSP could not parse '" + filename + "': " + e.what());
        }
        if (rc != vpXmlParserCamera::SEQUENCE_OK)
            continue;
        int w = (int)parser.getWidth(), h = (int)parser.getHeight();
        if (w <= 0)
            w = width;
        if (h <= 0)
            h = height;
        if (w <= 0 || h <= 0)
            CV_Error(Error::StsBadArg, "CameraModel::load: camera '" + name + "' in '" + filename +
                                           "' has no image_width/image_height; pass width and height");
        const bool dist = m == 0;
        const double kud = dist ? cam.get_kud() : 0.0, kdu = dist ? cam.get_kdu() : 0.0;
        checkIntrinsics(cam.get_px(), cam.get_py(), cam.get_u0(), cam.get_v0(), w, h, kud, kdu, "CameraModel::load");
        return makePtr<CameraModelImpl>(cam.get_px(), cam.get_py(), cam.get_u0(), cam.get_v0(), w, h, kud, kdu);
    }
    std::ostringstream msg;
    msg << "CameraModel::load: no camera named '" << name << "'";
    if (width > 0 || height > 0)
        msg << " with image size " << width << "x" << height;
    msg << " (perspective model with or without distortion) in ViSP camera file '" << filename << "'";
    CV_Error(Error::StsParseError, msg.str());
}

namespace detail {

Ptr<CameraModel> halfResolutionCamera(const CameraModel& camera)
{
    const Size size = camera.getImageSize();
    CV_Assert(size.width % 2 == 0 && size.height % 2 == 0);
    Ptr<CameraModel> half = CameraModel::create(camera.getFx() / 2, camera.getFy() / 2, (camera.getCx() - 0.5) / 2,
                                                (camera.getCy() - 0.5) / 2, size.width / 2, size.height / 2,
                                                camera.getKud(), camera.getKdu());
    half->setMountAxis(camera.getMountAxis());
    return half;
}

}  // namespace detail

}  // namespace dynblur
}  // namespace cv
