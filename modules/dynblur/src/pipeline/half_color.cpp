// SPDX-License-Identifier: Apache-2.0
#include "precomp.hpp"

#include "restore/deconv_rl.hpp"
#include "pipeline/half_color.hpp"
#include "restore/simd_clones.hpp"
#include "imaging/srgb.hpp"

namespace cv {
namespace dynblur {
namespace detail {

namespace {

/* Row of the frame halved from its rows 2y (`top`) and 2y + 1 of 3-channel pixels: each 2×2
   block's mean, its four values added in cv::resize's order, so the result is INTER_AREA's to the bit. */
DYNBLUR_SIMD_CLONES
void halveRows(const float* __restrict top, const float* __restrict bottom, int halfWidth, float* __restrict out)
{
    for (int x = 0; x < halfWidth; x++)
        for (int c = 0; c < 3; c++)
            out[3 * x + c] = (top[6 * x + c] + top[6 * x + 3 + c] + bottom[6 * x + c] + bottom[6 * x + 3 + c]) * 0.25f;
}

/* Row y of a factor-2 linear upsampling reads rows y/2 and y/2 ∓ 1 (cv::resize's source
   coordinate is (y + 0.5) / 2 − 0.5): out = 3/4 · near + 1/4 · far, `far` clamped to the image. */
DYNBLUR_SIMD_CLONES
void blendRows(const float* __restrict near, const float* __restrict far, int n, float* __restrict out)
{
    for (int x = 0; x < n; x++)
        out[x] = 0.75f * near[x] + 0.25f * far[x];
}

/* The same along a row of 3-channel pixels, written as three planes' rows of 2·halfWidth pixels:
   output pixel 2j reads pixels j and j − 1, pixel 2j + 1 reads j and j + 1. */
DYNBLUR_SIMD_CLONES
void upsampleRow(const float* __restrict interleaved, int halfWidth, float* __restrict* planes)
{
    for (int c = 0; c < 3; c++)
    {
        const float* p = interleaved + c;
        float* out = planes[c];
        out[0] = p[0];
        for (int j = 1; j < halfWidth; j++)
        {
            const float left = p[3 * (j - 1)], right = p[3 * j];
            out[2 * j - 1] = 0.75f * left + 0.25f * right;
            out[2 * j] = 0.25f * left + 0.75f * right;
        }
        out[2 * halfWidth - 1] = p[3 * (halfWidth - 1)];
    }
}

/* Row of the restored frame from the upsampled color's three plane rows and the luminance
   (luminanceChanged, within [0, 1]): one gain per pixel, the three channels written interleaved. */
DYNBLUR_SIMD_CLONES
void scaleToLuminanceRow(const float* __restrict blue, const float* __restrict green, const float* __restrict red,
                         const float* __restrict luminance, float black, int n, float* __restrict out)
{
    for (int x = 0; x < n; x++)
    {
        const float before = (blue[x] + green[x] + red[x]) * (1.f / 3.f), after = luminance[x];
        const bool lit = before > black;
        const float gain = after / (lit ? before : 1.f);  // the divisor made safe
        out[3 * x] = luminanceChanged(blue[x], lit, gain, after, before, 1.f);
        out[3 * x + 1] = luminanceChanged(green[x], lit, gain, after, before, 1.f);
        out[3 * x + 2] = luminanceChanged(red[x], lit, gain, after, before, 1.f);
    }
}

}  // namespace

void halveAndAverageChannels(const Mat& frame, Mat& halfColor, Mat& luminance)
{
    CV_Assert((frame.type() == CV_32FC3 || frame.type() == CV_8UC3) && frame.cols % 2 == 0 && frame.rows % 2 == 0);
    halfColor.create(frame.rows / 2, frame.cols / 2, CV_32FC3);
    luminance.create(frame.size(), CV_32FC1);
    const bool srgb = frame.depth() == CV_8U;
    const float* decode = detail::srgbDecodingTable();
    const int n = 3 * frame.cols;
    parallel_for_(Range(0, halfColor.rows), [&](const Range& rows) {
        std::vector<float> decoded(srgb ? size_t(2 * n) : 0);  // an 8-bit frame's two rows, linear
        for (int y = rows.start; y < rows.end; y++)
        {
            const float *top, *bottom;
            if (srgb)
            {
                const uchar *codesTop = frame.ptr<uchar>(2 * y), *codesBottom = frame.ptr<uchar>(2 * y + 1);
                for (int x = 0; x < n; x++)
                {
                    decoded[size_t(x)] = decode[codesTop[x]];
                    decoded[size_t(n + x)] = decode[codesBottom[x]];
                }
                top = decoded.data();
                bottom = top + n;
            }
            else
            {
                top = frame.ptr<float>(2 * y);
                bottom = frame.ptr<float>(2 * y + 1);
            }
            channelMeanRow(top, 3, frame.cols, luminance.ptr<float>(2 * y));
            channelMeanRow(bottom, 3, frame.cols, luminance.ptr<float>(2 * y + 1));
            halveRows(top, bottom, halfColor.cols, halfColor.ptr<float>(y));
        }
    });
}

void combineLuminanceAndHalfColor(const Mat& luminance, const Mat& halfColor, float black, int depth,
                                   const _OutputArray& restored)
{
    CV_Assert(luminance.type() == CV_32FC1 && halfColor.type() == CV_32FC3 &&
              luminance.size() == Size(2 * halfColor.cols, 2 * halfColor.rows) &&
              (depth == CV_32F || depth == CV_8U));
    const int width = luminance.cols, halfWidth = halfColor.cols, halfHeight = halfColor.rows;
    restored.create(luminance.size(), CV_MAKETYPE(depth, 3));
    Mat out = restored.getMat();
    parallel_for_(Range(0, luminance.rows), [&](const Range& rows) {
        // Scratch: the blended half row, the upsampled planes' rows, and an 8-bit frame's linear row.
        std::vector<float> scratch(size_t(3 * halfWidth) + size_t(3 * width) + (depth == CV_8U ? size_t(3 * width) : 0));
        float* blended = scratch.data();
        float* upsampled[3] = {blended + 3 * halfWidth, blended + 3 * halfWidth + width,
                               blended + 3 * halfWidth + 2 * width};
        float* linearRow = upsampled[2] + width;
        for (int y = rows.start; y < rows.end; y++)
        {
            const int near = y / 2, far = std::min(std::max(y % 2 ? near + 1 : near - 1, 0), halfHeight - 1);
            blendRows(halfColor.ptr<float>(near), halfColor.ptr<float>(far), 3 * halfWidth, blended);
            upsampleRow(blended, halfWidth, upsampled);
            scaleToLuminanceRow(upsampled[0], upsampled[1], upsampled[2], luminance.ptr<float>(y), black, width,
                                depth == CV_8U ? linearRow : out.ptr<float>(y));
            if (depth == CV_8U)
                encodeSrgbRow(linearRow, 3 * width, out.ptr<uchar>(y));
        }
    });
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
