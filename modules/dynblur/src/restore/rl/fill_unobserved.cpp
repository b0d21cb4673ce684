// SPDX-License-Identifier: Apache-2.0
#include "restore/rl/fill_unobserved.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <climits>
#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

/* Rows per strip in fillFromNearest: a band of invalid rows reaches its valid pixels through tens
   of rows, so narrower strips would each transform the band's reach again. */
constexpr int kFillStripRows = 128;

namespace {

/* fillFromNearest where every row is wholly valid or wholly invalid (`rowReach` -1 or INT_MAX), as
   a row-wise bank leaves a frame (the rows beyond the motion at one edge): an invalid row's nearest
   valid pixels are straight up or down in the nearest valid row, which the distance transform finds
   too (its 5×5 mask measures every other path as longer), so that row is copied, a copy instead of
   a transform over every such row of a row-wise frame. Returns false, doing nothing,
   for any other mask, or when a row lies as far from a valid row above as below (the transform's
   choice between them is its own) or has none. */
bool fillWholeRows(Mat& image, const std::vector<int>& rowReach)
{
    const int height = image.rows;
    std::vector<int> source(size_t(height), -1);
    for (int y = 0, above = -1; y < height; y++)
    {
        if (rowReach[size_t(y)] == -1)
            above = y;
        else if (rowReach[size_t(y)] != INT_MAX)
            return false;
        else
            source[size_t(y)] = above;
    }
    for (int y = height - 1, below = -1; y >= 0; y--)
    {
        if (rowReach[size_t(y)] == -1)
        {
            below = y;
            continue;
        }
        const int above = source[size_t(y)];
        if (above < 0 && below < 0)
            return false;
        if (above >= 0 && below >= 0 && y - above == below - y)
            return false;
        source[size_t(y)] = above < 0 || (below >= 0 && below - y < y - above) ? below : above;
    }
    for (int y = 0; y < height; y++)
        if (rowReach[size_t(y)] == INT_MAX)
            image.row(source[size_t(y)]).copyTo(image.row(y));
    return true;
}

}  // namespace

/* The distance transform runs on boxes around the invalid pixels, not on the box of their rows:
   every run of invalid pixels along a row has a valid pixel within a known reach (along its row
   or, when the row has none, straight up or down to the nearest row that has one and then along
   it), so the nearest valid pixel lies in the run's box grown by that reach. The invalid pixels
   are the frame's edges across the motion: a band of rows, and slivers down the sides whose common
   box was most of the frame. Runs are grouped by strips of rows; a strip's runs whose grown boxes
   share columns share one transform, and the groups run in parallel. */
void fillFromNearest(Mat& image, const Mat& valid)
{
    struct Run
    {
        int y, begin, end, reach;
    };
    const int height = valid.rows, width = valid.cols;
    std::vector<std::vector<Run>> rowRuns(static_cast<size_t>(height));
    std::vector<int> rowReach(size_t(height), -1);  // -1: every pixel valid; INT_MAX: none
    parallel_for_(Range(0, height), [&](const Range& rows) {
        for (int y = rows.start; y < rows.end; y++)
        {
            const uchar *v = valid.ptr<uchar>(y), *end = v + width;
            const uchar* x = static_cast<const uchar*>(std::memchr(v, 0, size_t(width)));
            if (!x)
                continue;
            std::vector<Run>& runs = rowRuns[size_t(y)];
            while (x)
            {
                const uchar* stop = std::find_if(x, end, [](uchar m) { return m != 0; });
                runs.push_back({y, int(x - v), int(stop - v), 0});
                x = stop < end ? static_cast<const uchar*>(std::memchr(stop, 0, size_t(end - stop))) : nullptr;
            }
            int& reach = rowReach[size_t(y)];
            if (runs.size() == 1 && runs[0].begin == 0 && runs[0].end == width)
            {
                reach = INT_MAX;
                continue;
            }
            for (Run& r : runs)
            {
                const int length = r.end - r.begin;
                r.reach = r.begin > 0 && r.end < width ? (length + 1) / 2 : length;  // one valid end or two
                reach = std::max(reach, r.reach);
            }
        }
    });
    if (fillWholeRows(image, rowReach))
        return;
    // Rows with no valid pixel reach down or up to the nearest row with one, then along it.
    std::vector<int> fromAbove(size_t(height), INT_MAX);
    for (int y = 0, last = -1; y < height; y++)
        if (rowReach[size_t(y)] != INT_MAX)
            last = y;
        else if (last >= 0)
            fromAbove[size_t(y)] = y - last + std::max(rowReach[size_t(last)], 0);
    bool anyValid = false;
    for (int y = height - 1, last = -1; y >= 0; y--)
    {
        if (rowReach[size_t(y)] != INT_MAX)
        {
            last = y;
            anyValid = true;
        }
        else
        {
            const int below = last >= 0 ? last - y + std::max(rowReach[size_t(last)], 0) : INT_MAX;
            rowReach[size_t(y)] = std::min(fromAbove[size_t(y)], below);
            rowRuns[size_t(y)][0].reach = rowReach[size_t(y)];
        }
    }
    if (!anyValid)
        return;

    struct Group
    {
        Rect box;
        std::vector<Run> runs;
    };
    std::vector<Group> groups;
    const Rect imageRect(Point(), valid.size());
    for (int strip = 0; strip < height; strip += kFillStripRows)
    {
        std::vector<Run> runs;
        for (int y = strip; y < std::min(height, strip + kFillStripRows); y++)
            runs.insert(runs.end(), rowRuns[size_t(y)].begin(), rowRuns[size_t(y)].end());
        const auto grown = [&](const Run& r) {
            return Rect(Point(r.begin - r.reach, r.y - r.reach), Point(r.end + r.reach, r.y + r.reach + 1)) & imageRect;
        };
        std::sort(runs.begin(), runs.end(), [&](const Run& a, const Run& b) { return grown(a).x < grown(b).x; });
        for (size_t i = 0; i < runs.size(); i++)
        {
            const Rect box = grown(runs[i]);
            if (i == 0 || box.x >= groups.back().box.br().x)
                groups.push_back({box, {}});
            groups.back().box |= box;
            groups.back().runs.push_back(runs[i]);
        }
    }
    const size_t channels = size_t(image.channels());
    parallel_for_(Range(0, int(groups.size())), [&](const Range& range) {
        for (int g = range.start; g < range.end; g++)
        {
            const Rect roi = groups[size_t(g)].box;
            const Mat validRoi = valid(roi);
            Mat distance, labels;
            distanceTransform(validRoi == 0, distance, labels, DIST_L2, DIST_MASK_5, DIST_LABEL_PIXEL);
            // Each valid pixel carries its own label: map labels back to their positions.
            std::vector<Point> where(size_t(roi.area()) + 1, Point(-1, -1));
            for (int y = 0; y < roi.height; y++)
            {
                const uchar* v = validRoi.ptr<uchar>(y);
                const int* label = labels.ptr<int>(y);
                for (int x = 0; x < roi.width; x++)
                    if (v[x])
                        where[size_t(label[x])] = Point(x + roi.x, y + roi.y);
            }
            for (const Run& run : groups[size_t(g)].runs)
            {
                const int* label = labels.ptr<int>(run.y - roi.y) - roi.x;
                float* out = image.ptr<float>(run.y);
                for (int x = run.begin; x < run.end; x++)
                {
                    const Point source = where[size_t(label[x])];
                    if (source.x < 0)
                        continue;  // cannot happen: each run's grown box holds a valid pixel
                    const float* from = image.ptr<float>(source.y) + size_t(source.x) * channels;
                    std::copy(from, from + channels, out + size_t(x) * channels);
                }
            }
        }
    });
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
