// SPDX-License-Identifier: Apache-2.0
#include "restore/rl/frame_planes.hpp"

#include "restore/rl/rl_rows.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cmath>

namespace cv {
namespace dynblur {
namespace detail {

ImageLevel foldLevel(const std::vector<double>& sums, const std::vector<double>& peaks, double count)
{
    ImageLevel level;
    level.peak = -DBL_MAX;
    for (size_t k = 0; k < sums.size(); k++)
    {
        level.mean += sums[k];
        level.peak = std::max(level.peak, peaks[k]);
    }
    level.mean /= count;
    return level;
}

ObservedFrame observeFrame(const Mat& frame, std::vector<Mat>& pool, bool estimateNoise)
{
    const int channels = frame.channels(), width = frame.cols;
    ObservedFrame observed;
    if (channels == 1)
        observed.planes = {frame};
    else
    {
        pool.resize(std::max(pool.size(), size_t(channels)));
        for (int c = 0; c < channels; c++)
        {
            pool[size_t(c)].create(frame.size(), CV_32FC1);
            observed.planes.push_back(pool[size_t(c)]);
        }
    }
    /* Each row's statistics are taken from its planes' rows while they are in L1, and Immerkær's
       mask reads the frame's rows around it, which the pass has just brought into the caches. */
    const bool noise = estimateNoise && frame.rows >= 3 && width >= 3;
    const size_t cells = size_t(frame.rows) * size_t(channels);
    std::vector<double> rowSum(cells), rowPeak(cells), rowNoise(size_t(frame.rows), 0.0);
    parallel_for_(Range(0, frame.rows), [&](const Range& rows) {
        for (int y = rows.start; y < rows.end; y++)
        {
            const float* row = frame.ptr<float>(y);
            for (int c = 0; c < channels; c++)
            {
                const size_t cell = size_t(y) * size_t(channels) + size_t(c);
                const float* plane = row;
                if (channels > 1)
                {
                    float* out = observed.planes[size_t(c)].ptr<float>(y);
                    channelRow(row, channels, c, width, out);
                    plane = out;
                }
                rowSum[cell] = rowSumAndPeak(plane, width, rowPeak[cell]);
            }
            if (noise && y > 0 && y + 1 < frame.rows)
                rowNoise[size_t(y)] =
                    noiseMaskSumRow(frame.ptr<float>(y - 1), row, frame.ptr<float>(y + 1), (width - 2) * channels,
                                    channels);
        }
    });
    const double pixels = double(frame.rows) * width;
    for (size_t cell = 0; cell < cells; cell++)
        observed.channelMean[int(cell % size_t(channels))] += rowSum[cell] / pixels;
    observed.level = foldLevel(rowSum, rowPeak, pixels * channels);
    if (noise)
    {
        double noiseTotal = 0;
        for (double v : rowNoise)
            noiseTotal += v;
        // A Gaussian's mean absolute value is σ √(2/π); the mask's norm is √36 = 6.
        observed.noiseSigma =
            std::sqrt(CV_PI / 2) * noiseTotal / (6.0 * (frame.rows - 2) * double((width - 2) * channels));
    }
    return observed;
}

bool finiteRange(const Mat& image, float& low, float& high)
{
    const int n = image.cols * image.channels();
    std::vector<uchar> rowFinite(size_t(image.rows), 0);
    std::vector<float> rowLow(size_t(image.rows)), rowHigh(size_t(image.rows));
    parallel_for_(Range(0, image.rows), [&](const Range& rows) {
        for (int y = rows.start; y < rows.end; y++)
            rowFinite[size_t(y)] = finiteRow(image.ptr<float>(y), n, rowLow[size_t(y)], rowHigh[size_t(y)]);
    });
    if (!std::all_of(rowFinite.begin(), rowFinite.end(), [](uchar f) { return f != 0; }))
        return false;
    low = *std::min_element(rowLow.begin(), rowLow.end());
    high = *std::max_element(rowHigh.begin(), rowHigh.end());
    return true;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
