// SPDX-License-Identifier: Apache-2.0
// Whether a frame is sharp: the extent of each sampled point's path during its row's exposure and
// the distance of its mean from the reference view, from the corrected motion alone; and, from the
// same means, where the frame recorded each pixel of the reference view.
#include "precomp.hpp"

#include "imaging/pinhole.hpp"
#include "imaging/trajectory.hpp"
#include "pipeline/frame_sharpness.hpp"

namespace cv {
namespace dynblur {
namespace detail {

namespace {

// The sample grid: columns edge to edge, every kRowStep-th row and the last, instants of each row's exposure.
constexpr int kColumns = 17;
constexpr int kRowStep = 8;
constexpr int kInstants = 17;
/* recordedPositions' fixed-point iteration at each node: each step multiplies the error by d̄'s slope
   (well under 0.1 px per pixel in a frame within 1 px), so a few steps reach kMapStepPx;
   kMapConvergedPx bounds the last step for a position to count as found. */
constexpr int kMapIterations = 12;
constexpr double kMapStepPx = 1e-3;
constexpr double kMapConvergedPx = 0.01;

const double kInf = std::numeric_limits<double>::infinity();

//! Keeps `value` and where it was found when it exceeds `largest` (NaN, a ray behind the camera: +inf).
void keepLarger(double value, const Point2d& at, double& largest, Point2d& where)
{
    if (value > largest || std::isnan(value))
    {
        largest = std::isnan(value) ? kInf : value;
        where = at;
    }
}

//! Row `y`'s place between the grid's rows: the row above (index), the one below, and the weight of the latter.
void gridRowOf(const std::vector<double>& rows, double y, int& r, int& r1, double& fy)
{
    const int last = int(rows.size()) - 1;
    // The rows are kRowStep apart but for the last one.
    r = std::min(std::max(int(y / kRowStep), 0), std::max(last - 1, 0));
    r1 = std::min(r + 1, last);
    const double y0 = rows[size_t(r)], y1 = rows[size_t(r1)];
    fy = r1 > r ? std::min(std::max((y - y0) / (y1 - y0), 0.0), 1.0) : 0.0;
}

}  // namespace

FrameSharpness measureSharpness(const ViewMotion& view, const RollingShutter& shutter, const CameraModel& camera)
{
    const Size size = camera.getImageSize();
    Pinhole pinhole = pinholeOf(camera);
    if (view.oneAxis())
        pinhole.axis = view.axis;
    const Trajectory tr = sampleTrajectory(view, shutter.readoutInterval());

    FrameSharpness sharpness;
    for (int y = 0; y < size.height; y += kRowStep)
        sharpness.rows.push_back(y);
    if (sharpness.rows.back() != size.height - 1)
        sharpness.rows.push_back(size.height - 1);
    sharpness.columnStep = (size.width - 1) / double(kColumns - 1);
    sharpness.meanDisplacement.create(int(sharpness.rows.size()), kColumns, CV_64FC2);

    sharpness.rowBlurPx.assign(sharpness.rows.size(), 0.0);
    sharpness.rowShiftPx.assign(sharpness.rows.size(), 0.0);
    std::vector<Point2d> path(size_t(kColumns * kInstants));
    for (int r = 0; r < int(sharpness.rows.size()); r++)
    {
        const double y = sharpness.rows[size_t(r)];
        const Vec2d interval = shutter.intervalAt(y);
        for (int s = 0; s < kInstants; s++)
        {
            const Matx33d R = tr.rotationAt(interval[0] + (interval[1] - interval[0]) * s / (kInstants - 1));
            for (int c = 0; c < kColumns; c++)
            {
                const Point2d m = pinhole.undistort(Point2d(c * sharpness.columnStep, y));
                path[size_t(c * kInstants + s)] = pinhole.displacement(m, pinhole.distort(m.x, m.y), R);
            }
        }
        for (int c = 0; c < kColumns; c++)
        {
            const Point2d at(c * sharpness.columnStep, y);
            const Point2d* d = &path[size_t(c * kInstants)];
            // The mean over the exposure by the trapezoid rule: the instants are evenly spaced, ends included.
            Point2d sum = 0.5 * (d[0] + d[kInstants - 1]);
            double extent = 0;
            for (int s = 0; s < kInstants; s++)
            {
                if (s > 0 && s < kInstants - 1)
                    sum += d[s];
                for (int u = s + 1; u < kInstants; u++)
                    extent = std::max(extent, norm(d[s] - d[u]));
                if (std::isnan(d[s].x))
                    extent = kInf;
            }
            const Point2d mean = sum * (1.0 / (kInstants - 1));
            sharpness.meanDisplacement.at<Vec2d>(r, c) = Vec2d(mean.x, mean.y);
            Point2d unused;
            keepLarger(extent, at, sharpness.rowBlurPx[size_t(r)], unused);
            keepLarger(norm(mean), at, sharpness.rowShiftPx[size_t(r)], unused);
            keepLarger(extent, at, sharpness.blurPx, sharpness.blurAt);
            keepLarger(norm(mean), at, sharpness.shiftPx, sharpness.shiftAt);
        }
    }
    return sharpness;
}

Point2d FrameSharpness::meanDisplacementAt(const Point2d& pixel) const
{
    int r, r1;
    double fy;
    gridRowOf(rows, pixel.y, r, r1, fy);
    const double u = std::min(std::max(pixel.x / columnStep, 0.0), double(kColumns - 1));
    const int c = std::min(int(u), kColumns - 2);
    const double fx = u - c;
    const auto at = [&](int row, int column) { return meanDisplacement.at<Vec2d>(row, column); };
    const Vec2d d =
        (1 - fy) * ((1 - fx) * at(r, c) + fx * at(r, c + 1)) + fy * ((1 - fx) * at(r1, c) + fx * at(r1, c + 1));
    return Point2d(d[0], d[1]);
}

bool recordedPositions(const FrameSharpness& sharpness, Size size, Mat& mapX, Mat& mapY)
{
    /* Solved at the grid's nodes, q = p + d̄(q) by fixed-point iteration from q = p; between them the
       offset q − p is bilinear, as d̄ itself is. */
    const int nodeRows = int(sharpness.rows.size());
    Mat offset(nodeRows, kColumns, CV_64FC2);
    double step = 0;
    for (int r = 0; r < nodeRows; r++)
        for (int c = 0; c < kColumns; c++)
        {
            const Point2d p(c * sharpness.columnStep, sharpness.rows[size_t(r)]);
            Point2d q = p;
            double last = 0;
            for (int k = 0; k < kMapIterations; k++)
            {
                const Point2d next = p + sharpness.meanDisplacementAt(q);
                last = norm(next - q);
                q = next;
                if (last < kMapStepPx)
                    break;
            }
            step = std::max(step, last);
            offset.at<Vec2d>(r, c) = Vec2d(q.x - p.x, q.y - p.y);
        }
    if (!(step <= kMapConvergedPx))
        return false;
    mapX.create(size, CV_32F);
    mapY.create(size, CV_32F);
    parallel_for_(Range(0, size.height), [&](const Range& range) {
        std::vector<Vec2d> row(kColumns);
        for (int y = range.start; y < range.end; y++)
        {
            int r, r1;
            double fy;
            gridRowOf(sharpness.rows, y, r, r1, fy);
            for (int c = 0; c < kColumns; c++)
                row[size_t(c)] = (1 - fy) * offset.at<Vec2d>(r, c) + fy * offset.at<Vec2d>(r1, c);
            float* mx = mapX.ptr<float>(y);
            float* my = mapY.ptr<float>(y);
            for (int x = 0; x < size.width; x++)
            {
                const double u = std::min(x / sharpness.columnStep, double(kColumns - 1));
                const int c = std::min(int(u), kColumns - 2);
                const double fx = u - c;
                const Vec2d d = (1 - fx) * row[size_t(c)] + fx * row[size_t(c + 1)];
                mx[x] = float(x + d[0]);
                my[x] = float(y + d[1]);
            }
        }
    });
    return true;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
