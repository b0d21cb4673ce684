// SPDX-License-Identifier: Apache-2.0
#include "precomp.hpp"

#include "restore/arguments.hpp"
#include "restore/operators/bank_geometry.hpp"
#include "restore/fft_kernel.hpp"
#include "restore/rl/fill_unobserved.hpp"
#include "restore/rl/restored_planes.hpp"

namespace cv {
namespace dynblur {

using detail::writeOutput;

void wienerDeconvolve(InputArray blurred, const PsfBank& bank, OutputArray latent, double noiseToSignal)
{
    const char* fn = "wienerDeconvolve";
    checkImage(blurred, "blurred", fn, false);
    checkBank(bank, blurred.size(), fn);
    if (!(noiseToSignal > 0) || !std::isfinite(noiseToSignal))
        CV_Error(Error::StsOutOfRange,
                 format("%s: noiseToSignal = %g must be finite and > 0", fn, noiseToSignal));

    const Size size = blurred.size();
    std::vector<Mat> planes;
    split(blurred.getMat(), planes);
    std::vector<Mat> numerator(planes.size());
    for (Mat& n : numerator)
        n = Mat::zeros(size, CV_32F);
    Mat denominator = Mat::zeros(size, CV_32F);

    // Each node's share of the frame's rows and columns where it has one: the forward operator's blend.
    const int nx = int(bank.nodeCols.size()), ny = int(bank.nodeRows.size());
    const std::vector<detail::AxisWeight> rowAxis = detail::nodeRowWeights(bank, size.height);
    const std::vector<detail::AxisWeight> colAxis = detail::nodeColumnWeights(bank, size.width);
    const std::vector<Range> rowSupport = detail::supports(rowAxis, ny), colSupport = detail::supports(colAxis, nx);
    const std::vector<std::vector<float>> rowWeight = detail::supportWeights(rowAxis, rowSupport);
    const std::vector<std::vector<float>> colWeight = detail::supportWeights(colAxis, colSupport);
    for (int j = 0; j < ny; j++)
    {
        const Range rows = rowSupport[size_t(j)];
        const std::vector<float>& wy = rowWeight[size_t(j)];  // over rows
        for (int i = 0; i < nx; i++)
        {
            const Range cols = colSupport[size_t(i)];
            const std::vector<float>& wx = colWeight[size_t(i)];  // over cols
            if (rows.empty() || cols.empty())
                continue;
            const size_t n = size_t(j * nx + i);
            Mat kernel;
            bank.kernels[n].convertTo(kernel, CV_32F);
            const Point shift = bank.shifts[n];

            /* The node's region plus a margin for the kernel's reach and the inverse filter's
               tails, mirrored where it leaves the frame, then faded to its mean over an outer
               band so the FFT's periodic wrap meets no step (no ringing from the wrap). */
            const int marginX = kernel.cols + 16, marginY = kernel.rows + 16;
            const Rect region(cols.start - marginX, rows.start - marginY, cols.size() + 2 * marginX,
                              rows.size() + 2 * marginY);
            const Size grid(getOptimalDFTSize(region.width + 2 * marginX), getOptimalDFTSize(region.height + 2 * marginY));
            const Rect inside = region & Rect(Point(), size);
            const Point gridOrigin = region.tl() - Point(marginX, marginY);  // frame coords of grid (0,0)
            detail::FftKernel fft(grid, kernel);
            Mat taper(grid, CV_32F);
            for (int y = 0; y < grid.height; y++)
                for (int x = 0; x < grid.width; x++)
                {
                    const int dx = std::min(x, grid.width - 1 - x), dy = std::min(y, grid.height - 1 - y);
                    const float fx = std::min(1.f, float(dx) / float(marginX));
                    const float fy = std::min(1.f, float(dy) / float(marginY));
                    taper.at<float>(y, x) = (0.5f - 0.5f * std::cos(float(CV_PI) * fx)) *
                                            (0.5f - 0.5f * std::cos(float(CV_PI) * fy));
                }

            for (size_t c = 0; c < planes.size(); c++)
            {
                Mat padded;
                const Point at = inside.tl() - gridOrigin;
                copyMakeBorder(planes[c](inside), padded, at.y, grid.height - at.y - inside.height, at.x,
                               grid.width - at.x - inside.width, BORDER_REFLECT_101);
                const float level = float(mean(planes[c](inside))[0]);
                padded = (padded - level).mul(taper) + level;
                Mat restored;
                fft.wiener(padded, restored, float(noiseToSignal));
                // restored(p) is the latent at p − shift (grid p ↔ frame p + gridOrigin).
                for (int y = rows.start; y < rows.end; y++)
                {
                    const int qy = y - shift.y;
                    if (qy < 0 || qy >= size.height)
                        continue;
                    const float* src = restored.ptr<float>(y - gridOrigin.y);
                    float* num = numerator[c].ptr<float>(qy);
                    float* den = denominator.ptr<float>(qy);
                    for (int x = cols.start; x < cols.end; x++)
                    {
                        const int qx = x - shift.x;
                        if (qx < 0 || qx >= size.width)
                            continue;
                        const float w = wy[size_t(y - rows.start)] * wx[size_t(x - cols.start)];
                        num[qx] += w * src[x - gridOrigin.x];
                        if (c == 0)
                            den[qx] += w;
                    }
                }
            }
        }
    }
    Mat valid = denominator > 1e-3f;
    std::vector<Mat> out(planes.size());
    for (size_t c = 0; c < planes.size(); c++)
        out[c] = numerator[c] / max(denominator, 1e-3f);
    writeOutput(out, latent);
    Mat output = latent.getMat();
    detail::fillFromNearest(output, valid);
}

}  // namespace dynblur
}  // namespace cv
