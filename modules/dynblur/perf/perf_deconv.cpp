// SPDX-License-Identifier: Apache-2.0
// Speed of deconv.hpp on a 1280×960 RGB CV_32F frame, 10 RL iterations: uniform FFTW RL, the
// row-variant bank (bands of 8 rows, ~31×3 kernels, displacements up to 200 px), a 4×3 tile
// bank, and a baseline RL written with cv::filter2D for scale.
#include "perf_baseline.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/imgproc.hpp>

#include <benchmark/benchmark.h>

namespace {

using namespace cv;
using namespace cv::dynblur;

const Size kFrame(1280, 960);

Mat frame()
{
    Mat image(kFrame, CV_32FC3);
    RNG(1).fill(image, RNG::UNIFORM, 0.05, 0.95);
    GaussianBlur(image, image, Size(0, 0), 2.0);
    return image;
}

//! A straight motion path from −half to +half, splatted bilinearly, sum 1.
Mat pathKernel(Point2d half, int rows, int cols)
{
    Mat k = Mat::zeros(rows, cols, CV_32F);
    const Point2d c((cols - 1) / 2.0, (rows - 1) / 2.0);
    for (int i = 0; i < 200; i++)
    {
        const Point2d p = c + (-1 + 2.0 * (i + 0.5) / 200) * half;
        const int x0 = int(std::floor(p.x)), y0 = int(std::floor(p.y));
        const double fx = p.x - x0, fy = p.y - y0;
        for (int dy = 0; dy < 2; dy++)
            for (int dx = 0; dx < 2; dx++)
                if (x0 + dx >= 0 && y0 + dy >= 0 && x0 + dx < cols && y0 + dy < rows)
                    k.at<float>(y0 + dy, x0 + dx) += float((dx ? fx : 1 - fx) * (dy ? fy : 1 - fy));
    }
    return k / sum(k)[0];
}

RLParams tenIterations()
{
    RLParams p;
    p.iterations = 10;
    return p;
}

void BM_RichardsonLucyUniformFftw(benchmark::State& state)
{
    const Mat blurred = frame();
    const Mat kernel = pathKernel(Point2d(10, 0), 1, 21);
    Mat latent;
    for (auto _ : state)
        richardsonLucy(blurred, kernel, latent, tenIterations());
}
BENCHMARK(BM_RichardsonLucyUniformFftw)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_RichardsonLucyRowBank(benchmark::State& state)
{
    const Mat blurred = frame();
    PsfBank bank;
    bank.model = PSF_ROWS;
    bank.imageSize = kFrame;
    bank.nodeCols = {kFrame.width / 2.0};
    for (double y = 4; y < kFrame.height; y += 8)
    {
        const double f = y / kFrame.height;
        bank.nodeRows.push_back(y);
        bank.kernels.push_back(pathKernel(Point2d(8 + 7 * f, 1.0), 3, 31));
        bank.shifts.push_back(Point(0, cvRound(200 * (1 - f))));
    }
    Mat latent;
    for (auto _ : state)
        richardsonLucyVariant(blurred, bank, latent, tenIterations());
}
BENCHMARK(BM_RichardsonLucyRowBank)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_RichardsonLucyTileBank(benchmark::State& state)
{
    const Mat blurred = frame();
    PsfBank bank;
    bank.model = PSF_TILES;
    bank.imageSize = kFrame;
    for (int i = 0; i < 4; i++)
        bank.nodeCols.push_back((i + 0.5) * kFrame.width / 4);
    for (int j = 0; j < 3; j++)
        bank.nodeRows.push_back((j + 0.5) * kFrame.height / 3);
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 4; i++)
        {
            const double angle = 0.3 * i + 0.5 * j;
            bank.kernels.push_back(pathKernel(Point2d(8 * std::cos(angle), 8 * std::sin(angle)), 17, 17));
            bank.shifts.push_back(Point(0, 20 * j));
        }
    Mat latent;
    for (auto _ : state)
        richardsonLucyVariant(blurred, bank, latent, tenIterations());
}
BENCHMARK(BM_RichardsonLucyTileBank)->Unit(benchmark::kMillisecond)->UseRealTime();

//! Scale reference: plain RL with cv::filter2D (spatial, OpenCV's own parallel/SIMD code).
void BM_RichardsonLucyFilter2DBaseline(benchmark::State& state)
{
    const Mat blurred = frame(), kernel = dynblur_perf::uniformKernel21x1();
    Mat estimate;
    for (auto _ : state)
    {
        dynblur_perf::filter2DRichardsonLucy(blurred, kernel, 10, estimate);
        benchmark::DoNotOptimize(estimate.data);
    }
}
BENCHMARK(BM_RichardsonLucyFilter2DBaseline)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
