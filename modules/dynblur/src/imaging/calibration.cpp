// SPDX-License-Identifier: Apache-2.0
// Chessboard calibration of the camera intrinsics: OpenCV finds the corners, ViSP's vpCalibration
// solves (per-view virtual visual servoing, then all views with the one-term radial distortion).
#include "precomp.hpp"

#include "imaging/pinhole.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImagePoint.h>
#include <visp3/vision/vpCalibration.h>

#include <exception>
#include <sstream>

namespace cv {
namespace dynblur {

CameraCalibration::CameraCalibration()
    : px(0), py(0), u0(0), v0(0), kud(0), kdu(0), imageSize(), globalResidual(0), vispGlobalResidual(0)
{
}

Ptr<CameraModel> CameraCalibration::cameraModel() const
{
    return CameraModel::create(px, py, u0, v0, imageSize.width, imageSize.height, kud, kdu);
}

Matx33d CameraCalibration::cameraMatrix() const
{
    return Matx33d(px, 0, u0, 0, py, v0, 0, 0, 1);
}

Mat CameraCalibration::openCVDistortion() const
{
    return (Mat_<double>(1, 5) << kud, 0.0, 0.0, 0.0, 0.0);
}

int CameraCalibration::usedViews() const
{
    int n = 0;
    for (int used : viewUsed)
        n += used ? 1 : 0;
    return n;
}

bool detectChessboardCorners(InputArray image, Size boardSize, OutputArray corners)
{
    if (boardSize.width < 2 || boardSize.height < 2)
        CV_Error_(Error::StsBadArg, ("detectChessboardCorners: boardSize=%dx%d must count >= 2 inner corners "
                                     "per row and per column", boardSize.width, boardSize.height));
    Mat src = image.getMat();
    if (src.empty())
        CV_Error(Error::StsBadArg, "detectChessboardCorners: 'image' is empty");
    CV_CheckDepthEQ(src.depth(), CV_8U, "detectChessboardCorners: 'image' must be 8-bit");
    Mat gray;
    if (src.channels() == 3)
        cvtColor(src, gray, COLOR_BGR2GRAY);
    else if (src.channels() == 4)
        cvtColor(src, gray, COLOR_BGRA2GRAY);
    else if (src.channels() == 1)
        gray = src;
    else
        CV_Error_(Error::StsBadArg, ("detectChessboardCorners: 'image' has %d channels; 1, 3 or 4 expected",
                                     src.channels()));
    std::vector<Point2f> found;
    const bool ok = findChessboardCorners(gray, boardSize, found,
                                          CALIB_CB_ADAPTIVE_THRESH | CALIB_CB_NORMALIZE_IMAGE | CALIB_CB_FAST_CHECK);
    if (!ok || found.size() != static_cast<size_t>(boardSize.area()))
    {
        corners.release();
        return false;
    }
    cornerSubPix(gray, found, Size(11, 11), Size(-1, -1),
                 TermCriteria(TermCriteria::EPS + TermCriteria::COUNT, 30, 0.01));
    Mat(found).copyTo(corners);
    return true;
}

namespace {

//! One view's board as ViSP calibration data: the board points (metres, Z = 0) and their corners.
vpCalibration makeViewData(const std::vector<Point2f>& corners, Size boardSize, double squareSize)
{
    vpCalibration data;
    data.clearPoint();
    for (int i = 0; i < boardSize.height; ++i)
        for (int j = 0; j < boardSize.width; ++j)
        {
            const Point2f& c = corners[static_cast<size_t>(i * boardSize.width + j)];
            vpImagePoint ip;
            ip.set_u(c.x);
            ip.set_v(c.y);
            data.addPoint(j * squareSize, i * squareSize, 0.0, ip);
        }
    return data;
}

//! RMS distance, pixels, between the detected corners and the board projected with the forward model.
double forwardResidual(const std::vector<Point2f>& corners, Size boardSize, double squareSize,
                       const vpHomogeneousMatrix& cMo, const vpCameraParameters& cam, double* sumSquares)
{
    const detail::Pinhole pinhole{cam.get_px(), cam.get_py(), cam.get_u0(), cam.get_v0(), cam.get_kud(), cam.get_kdu(),
                                  Vec3d(1, 0, 0)};
    double sum = 0;
    for (int i = 0; i < boardSize.height; ++i)
        for (int j = 0; j < boardSize.width; ++j)
        {
            const double X = j * squareSize, Y = i * squareSize;
            const double cX = cMo[0][0] * X + cMo[0][1] * Y + cMo[0][3];
            const double cY = cMo[1][0] * X + cMo[1][1] * Y + cMo[1][3];
            const double cZ = cMo[2][0] * X + cMo[2][1] * Y + cMo[2][3];
            const Point2d q = pinhole.distort(cX / cZ, cY / cZ);
            const Point2f& c = corners[static_cast<size_t>(i * boardSize.width + j)];
            sum += (q.x - c.x) * (q.x - c.x) + (q.y - c.y) * (q.y - c.y);
        }
    if (sumSquares)
        *sumSquares = sum;
    return std::sqrt(sum / boardSize.area());
}

double median(std::vector<double> values)
{
    CV_Assert(!values.empty());
    const size_t mid = values.size() / 2;
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
    double m = values[mid];
    if (values.size() % 2 == 0)
        m = 0.5 * (m + *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid)));
    return m;
}

struct MultiFit
{
    vpCameraParameters cam;
    double vispGlobal = 0;
    double global = 0;
    std::vector<double> residuals;  // per fitted view
};

//! Sets ViSP's (process-wide) virtual-visual-servoing gain for a scope and restores it after.
class LambdaScope
{
public:
    explicit LambdaScope(double lambda) : saved_(vpCalibration::getLambda()) { vpCalibration::setLambda(lambda); }
    ~LambdaScope() { vpCalibration::setLambda(saved_); }
    LambdaScope(const LambdaScope&) = delete;
    LambdaScope& operator=(const LambdaScope&) = delete;

private:
    double saved_;
};

//! ViSP calibration of the given views (indices into `corners`).
MultiFit fitViewsOnce(const std::vector<std::vector<Point2f> >& corners, const std::vector<int>& views, Size imageSize,
                  Size boardSize, double squareSize)
{
    std::vector<vpCalibration> table;
    std::vector<double> pxs, pys, u0s, v0s;
    // A first guess about a 50-60 degree field of view; each view's virtual visual servoing refines
    // it together with the view's pose.
    const double f0 = std::max(imageSize.width, imageSize.height);
    for (int v : views)
    {
        table.push_back(makeViewData(corners[static_cast<size_t>(v)], boardSize, squareSize));
        vpCameraParameters cam;
        cam.initPersProjWithoutDistortion(f0, f0, 0.5 * (imageSize.width - 1), 0.5 * (imageSize.height - 1));
        vpHomogeneousMatrix cMo;
        table.back().computeCalibration(vpCalibration::CALIB_VIRTUAL_VS, cMo, cam, false);
        pxs.push_back(cam.get_px());
        pys.push_back(cam.get_py());
        u0s.push_back(cam.get_u0());
        v0s.push_back(cam.get_v0());
    }
    MultiFit fit;
    // One view alone pins the intrinsics poorly; the median over the views is a robust start.
    fit.cam.initPersProjWithoutDistortion(median(pxs), median(pys), median(u0s), median(v0s));
    vpCalibration::computeCalibrationMulti(vpCalibration::CALIB_VIRTUAL_VS_DIST, table, fit.cam, fit.vispGlobal,
                                           false);
    double total = 0;
    for (size_t k = 0; k < views.size(); ++k)
    {
        double sum = 0;
        fit.residuals.push_back(forwardResidual(corners[static_cast<size_t>(views[k])], boardSize, squareSize,
                                                table[k].cMo_dist, fit.cam, &sum));
        total += sum;
    }
    fit.global = std::sqrt(total / (static_cast<double>(views.size()) * boardSize.area()));
    return fit;
}

/** ViSP's default gain (0.25) converges in small steps; a full Gauss-Newton step (gain 1) reaches the
same intrinsics (checked on OpenCV's left01..14 to 0.01 px) in about a third of the time. When
the full step fails to converge, the fit is redone with ViSP's own gain. */
MultiFit fitViews(const std::vector<std::vector<Point2f> >& corners, const std::vector<int>& views, Size imageSize,
                  Size boardSize, double squareSize)
{
    try
    {
        LambdaScope fast(1.0);
        MultiFit fit = fitViewsOnce(corners, views, imageSize, boardSize, squareSize);
        if (std::isfinite(fit.global) && fit.cam.get_px() > 0 && fit.cam.get_py() > 0)
            return fit;
    }
    catch (const std::exception&)
    {
    }
    return fitViewsOnce(corners, views, imageSize, boardSize, squareSize);
}

std::string describeViews(const CameraCalibration& result)
{
    std::ostringstream out;
    for (size_t i = 0; i < result.viewNames.size(); ++i)
        out << "\n  " << result.viewNames[i] << ": " << result.viewStatus[i];
    return out.str();
}

void checkArguments(Size boardSize, double squareSize, double outlierFactor, const char* function)
{
    if (boardSize.width < 2 || boardSize.height < 2)
        CV_Error_(Error::StsBadArg, ("%s: boardSize=%dx%d must count >= 2 inner corners per row and per column",
                                     function, boardSize.width, boardSize.height));
    if (!(squareSize > 0) || !std::isfinite(squareSize))
        CV_Error_(Error::StsBadArg, ("%s: squareSize=%g must be > 0 (metres)", function, squareSize));
    if (!(outlierFactor == 0 || (outlierFactor > 1 && std::isfinite(outlierFactor))))
        CV_Error_(Error::StsBadArg, ("%s: outlierFactor=%g must be > 1 (or 0 to keep every view)", function,
                                     outlierFactor));
}

//! The common path: `load(i)` gives view i's image (empty when it cannot be read).
template <typename Loader>
CameraCalibration calibrate(size_t count, const std::vector<String>& names, Loader load, Size boardSize,
                            double squareSize, double outlierFactor, const char* function)
{
    CameraCalibration result;
    std::vector<int> candidates;
    const String boardText = format("%dx%d", boardSize.width, boardSize.height);
    for (size_t i = 0; i < count; ++i)
    {
        result.viewNames.push_back(i < names.size() && !names[i].empty() ? names[i] : format("view %zu", i));
        result.viewUsed.push_back(0);
        result.viewResiduals.push_back(std::numeric_limits<double>::quiet_NaN());
        result.imagePoints.emplace_back();
        const Mat image = load(i);
        if (image.empty())
        {
            result.viewStatus.push_back("image unreadable");
            continue;
        }
        if (image.depth() != CV_8U)
        {
            result.viewStatus.push_back("image is not 8-bit");
            continue;
        }
        if (result.imageSize.area() == 0)
            result.imageSize = image.size();
        if (image.size() != result.imageSize)
        {
            result.viewStatus.push_back(format("image size %dx%d differs from the first view's %dx%d", image.cols,
                                               image.rows, result.imageSize.width, result.imageSize.height));
            continue;
        }
        std::vector<Point2f> corners;
        if (!detectChessboardCorners(image, boardSize, corners))
        {
            result.viewStatus.push_back("chessboard " + boardText + " not found");
            continue;
        }
        result.imagePoints.back() = corners;
        result.viewStatus.push_back("used");
        candidates.push_back(static_cast<int>(i));
    }

    auto tooFew = [&](const std::string& why) {
        std::string hint;
        bool anyBoard = false;
        for (const auto& pts : result.imagePoints)
            anyBoard = anyBoard || !pts.empty();
        if (!anyBoard && count > 0)
            hint = "\nNo view shows a " + boardText + " chessboard: boardSize counts the INNER corners per row and "
                   "per column (a board of 10x7 squares has 9x6).";
        CV_Error(Error::StsError, std::string(function) + ": " + why + " (at least 3 are needed):" +
                                      describeViews(result) + hint);
    };
    if (candidates.size() < 3)
        tooFew(format("only %zu of %zu views are usable", candidates.size(), count));

    MultiFit fit;
    for (;;)
    {
        try
        {
            fit = fitViews(result.imagePoints, candidates, result.imageSize, boardSize, squareSize);
        }
        catch (const cv::Exception&)
        {
            throw;
        }
        catch (const std::exception& e)
        {
            CV_Error(Error::StsNoConv, std::string(function) + ": ViSP's calibration failed: " + e.what());
        }
        for (size_t k = 0; k < candidates.size(); ++k)
            result.viewResiduals[static_cast<size_t>(candidates[k])] = fit.residuals[k];
        if (outlierFactor == 0)
            break;
        const double typical = median(fit.residuals);
        const double limit = std::max(outlierFactor * typical, 0.5);
        std::vector<int> kept;
        for (size_t k = 0; k < candidates.size(); ++k)
        {
            if (fit.residuals[k] > limit)
                result.viewStatus[static_cast<size_t>(candidates[k])] =
                    format("outlier: residual %.3f px > %g x median %.3f px", fit.residuals[k], outlierFactor, typical);
            else
                kept.push_back(candidates[k]);
        }
        if (kept.size() == candidates.size())
            break;
        candidates = kept;
        if (candidates.size() < 3)
            tooFew(format("only %zu views are left after rejecting outliers", candidates.size()));
    }
    for (int v : candidates)
        result.viewUsed[static_cast<size_t>(v)] = 1;
    result.px = fit.cam.get_px();
    result.py = fit.cam.get_py();
    result.u0 = fit.cam.get_u0();
    result.v0 = fit.cam.get_v0();
    result.kud = fit.cam.get_kud();
    result.kdu = fit.cam.get_kdu();
    result.globalResidual = fit.global;
    result.vispGlobalResidual = fit.vispGlobal;
    if (!(result.px > 0 && result.py > 0 && std::isfinite(result.u0) && std::isfinite(result.v0)))
        CV_Error_(Error::StsNoConv, ("%s: the calibration diverged (px=%g, py=%g)", function, result.px, result.py));
    return result;
}

}  // namespace

CameraCalibration calibrateCameraViSP(const std::vector<String>& imagePaths, Size boardSize, double squareSize,
                                      double outlierFactor)
{
    checkArguments(boardSize, squareSize, outlierFactor, "calibrateCameraViSP");
    return calibrate(
        imagePaths.size(), imagePaths,
        [&](size_t i) {
            try
            {
                return imread(imagePaths[i], IMREAD_GRAYSCALE);
            }
            catch (const cv::Exception&)
            {
                return Mat();
            }
        },
        boardSize, squareSize, outlierFactor, "calibrateCameraViSP");
}

CameraCalibration calibrateCameraViSPImages(InputArrayOfArrays images, const std::vector<String>& viewNames,
                                            Size boardSize, double squareSize, double outlierFactor)
{
    checkArguments(boardSize, squareSize, outlierFactor, "calibrateCameraViSPImages");
    std::vector<Mat> mats;
    images.getMatVector(mats);
    if (!viewNames.empty() && viewNames.size() != mats.size())
        CV_Error_(Error::StsBadArg, ("calibrateCameraViSPImages: %zu viewNames for %zu images (give one per image "
                                     "or none)", viewNames.size(), mats.size()));
    return calibrate(
        mats.size(), viewNames, [&](size_t i) { return mats[i]; }, boardSize, squareSize, outlierFactor,
        "calibrateCameraViSPImages");
}

}  // namespace dynblur
}  // namespace cv
