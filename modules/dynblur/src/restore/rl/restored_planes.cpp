// SPDX-License-Identifier: Apache-2.0
#include "restore/rl/restored_planes.hpp"

#include "restore/rl/rl_rows.hpp"

#include <opencv2/core/utility.hpp>

namespace cv {
namespace dynblur {
namespace detail {

void writeOutput(const std::vector<Mat>& planes, OutputArray out, bool clampToUnit,
                 const LuminanceChange& change, Rect roi)
{
    if (roi.empty())
        roi = Rect(Point(), planes[0].size());
    const int channels = int(planes.size());
    out.create(roi.size(), CV_32FC(channels));
    Mat image = out.getMat();
    parallel_for_(Range(0, image.rows), [&](const Range& rows) {
        const int n = roi.width;
        std::vector<const float*> sources(planes.size());
        // With a change: the planes' mean, then each plane's changed row (the sources).
        std::vector<float> changed(change.restored.empty() ? 0 : size_t(n) * (planes.size() + 1));
        std::vector<float*> changedRows(planes.size());
        if (!changed.empty())
            for (size_t c = 0; c < planes.size(); c++)
                sources[c] = changedRows[c] = changed.data() + (c + 1) * size_t(n);
        for (int y = rows.start; y < rows.end; y++)
        {
            if (changed.empty())
                for (size_t c = 0; c < planes.size(); c++)
                    sources[c] = planes[c].ptr<float>(y + roi.y) + roi.x;
            else
                change.applyRow(planes, y + roi.y, roi.x, n, changed.data(), changedRows.data());
            interleaveRow(sources.data(), channels, n, image.ptr<float>(y));
            if (clampToUnit)
                clampRowToUnit(image.ptr<float>(y), n * channels);
        }
    });
}

void LuminanceChange::applyRow(const std::vector<Mat>& planes, int y, int x0, int n, float* before,
                               float* const* out) const
{
    meanRow(planes, y, x0, n, before);
    for (size_t c = 0; c < planes.size(); c++)
        applyLuminanceRow(restored.ptr<float>(y) + x0, before, black, upper, n, planes[c].ptr<float>(y) + x0, out[c]);
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
