// SPDX-License-Identifier: Apache-2.0
// The plane renderer (plane_render.hpp): time cells of equal image motion, each a warped view added
// to the rows it overlaps.
#include "plane_render.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace dynblur_samples {

using namespace cv;
using namespace cv::dynblur;

namespace {

//! The inverse map of warpPerspective for rows [firstRow, …) of the view at t: band pixel → scene pixel.
Matx33d sceneFromBand(const CameraPath& path, const Matx33d& K, double t, int margin, int firstRow, bool rotationOnly)
{
    const Matx33d toScene(1, 0, margin, 0, 1, margin, 0, 0, 1), fromBand(1, 0, 0, 0, 1, firstRow, 0, 0, 1);
    return toScene * path.homeFromView(t, K, rotationOnly) * fromBand;
}

Mat warpRows(const Mat& scene, int margin, const CameraPath& path, const Matx33d& K, int width, int firstRow,
             int rows, double t, bool rotationOnly)
{
    Mat band;
    warpPerspective(scene, band, sceneFromBand(path, K, t, margin, firstRow, rotationOnly), Size(width, rows),
                    INTER_LINEAR | WARP_INVERSE_MAP, BORDER_REFLECT_101);
    return band;
}

/** Cumulative image motion over `times`, pixels: at each step the largest displacement of a border
pixel (corners, edge midpoints) between the homographies, +25 % for pixels between them. */
std::vector<double> pathLength(const CameraPath& path, const Matx33d& K, const Size& size,
                               const std::vector<double>& times, bool rotationOnly, double& largestStep)
{
    std::vector<Point2d> border;
    for (double y : {0.0, 0.5 * (size.height - 1), size.height - 1.0})
        for (double x : {0.0, 0.5 * (size.width - 1), size.width - 1.0})
            border.emplace_back(x, y);
    std::vector<double> length(times.size(), 0.0);
    std::vector<Point2d> previous(border.size());
    largestStep = 0;
    for (size_t k = 0; k < times.size(); k++)
    {
        const Matx33d H = path.homeFromView(times[k], K, rotationOnly);
        double step = 0;
        for (size_t i = 0; i < border.size(); i++)
        {
            const Vec3d q = H * Vec3d(border[i].x, border[i].y, 1);
            const Point2d p(q[0] / q[2], q[1] / q[2]);
            if (k > 0)
                step = std::max(step, 1.25 * norm(p - previous[i]));
            previous[i] = p;
        }
        if (k > 0)
            length[k] = length[k - 1] + step;
        largestStep = std::max(largestStep, step);
    }
    return length;
}

std::vector<double> uniformTimes(double from, double to, int n)
{
    std::vector<double> t(static_cast<size_t>(n));
    for (int k = 0; k < n; k++)
        t[size_t(k)] = from + (to - from) * k / (n - 1);
    return t;
}

/** The edges of time cells over [from, to] in each of which the image moves by at most maxStepPx:
equal steps of the path's length, on a grid fine enough that one grid step moves a quarter of that. */
std::vector<double> cellEdges(const CameraPath& path, const Matx33d& K, const Size& size, double from, double to,
                              double maxStepPx, bool rotationOnly)
{
    double largest = 0;
    std::vector<double> grid = uniformTimes(from, to, 2001);
    std::vector<double> length = pathLength(path, K, size, grid, rotationOnly, largest);
    const int fine = int(std::min(4.0e6, std::ceil(2000 * largest * 4 / maxStepPx) + 1));
    if (fine > int(grid.size()))
    {
        grid = uniformTimes(from, to, fine);
        length = pathLength(path, K, size, grid, rotationOnly, largest);
    }
    const int cells = std::max(1, int(std::ceil(length.back() / maxStepPx)));
    std::vector<double> edges{from};
    size_t k = 1;
    for (int c = 1; c < cells; c++)
    {
        const double s = length.back() * c / cells;
        while (length[k] < s)
            k++;
        const double a = (s - length[k - 1]) / (length[k] - length[k - 1]);
        edges.push_back(grid[k - 1] + a * (grid[k] - grid[k - 1]));
    }
    edges.push_back(to);
    return edges;
}

}  // namespace

Mat viewAt(const Mat& sceneLinear, int margin, const CameraPath& path, const Matx33d& K, const Size& size, double t,
           bool rotationOnly)
{
    return warpRows(sceneLinear, margin, path, K, size.width, 0, size.height, t, rotationOnly);
}

Mat renderPlaneBlurred(const Mat& sceneLinear, int margin, const CameraPath& path, const Matx33d& K, const Size& size,
                       const RollingShutter& shutter, double maxStepPx, bool rotationOnly)
{
    CV_Assert(sceneLinear.depth() == CV_32F && margin >= 0 && sceneLinear.cols == size.width + 2 * margin &&
              sceneLinear.rows == size.height + 2 * margin && shutter.rows == size.height && maxStepPx > 0);
    const int H = size.height, W = size.width;
    Mat frame = Mat::zeros(size, sceneLinear.type());
    if (shutter.exposure <= 0)
    {
        for (int r = 0; r < H; r++)
        {
            const double start = shutter.rowInterval(r)[0];
            warpRows(sceneLinear, margin, path, K, W, r, 1, start, rotationOnly).copyTo(frame.row(r));
        }
        return frame;
    }
    const Vec2d readout = shutter.readoutInterval();
    const std::vector<double> edges = cellEdges(path, K, size, readout[0], readout[1], maxStepPx, rotationOnly);
    std::vector<double> exposed(size_t(H), 0.0);
    for (size_t c = 0; c + 1 < edges.size(); c++)
    {
        const double c0 = edges[c], c1 = edges[c + 1];
        const Range rows = shutter.rowsOverlapping(c0, c1);
        if (rows.empty())
            continue;
        const Mat band = warpRows(sceneLinear, margin, path, K, W, rows.start, rows.size(), 0.5 * (c0 + c1),
                                  rotationOnly);
        for (int r = rows.start; r < rows.end; r++)
        {
            const Vec2d interval = shutter.rowInterval(r);
            const double w = std::min(c1, interval[1]) - std::max(c0, interval[0]);
            if (w <= 0)
                continue;
            scaleAdd(band.row(r - rows.start), w, frame.row(r), frame.row(r));
            exposed[size_t(r)] += w;
        }
    }
    for (int r = 0; r < H; r++)
        frame.row(r) *= 1.0 / exposed[size_t(r)];
    return frame;
}

}  // namespace dynblur_samples
