// SPDX-License-Identifier: Apache-2.0
// Test support of the test_deconv_*.cpp files: test images, noise, kernels and banks, and direct
// (convolution-by-definition) references of the restorations.
#ifndef DYNBLUR_TEST_DECONV_FIXTURES_HPP
#define DYNBLUR_TEST_DECONV_FIXTURES_HPP

#include "test_common.hpp"

#include "restore/deconv_rl.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace deconv_test {

using namespace cv;
using namespace cv::dynblur;

// ---------------------------------------------------------------------------------------------
// Helpers

//! A test image as linear CV_32F in [0, 1], resized to `size`.
inline Mat loadImage(const std::string& path, Size size, bool color)
{
    Mat image = imread(path, color ? IMREAD_COLOR : IMREAD_GRAYSCALE);
    CV_Assert(!image.empty());
    resize(image, image, size, 0, 0, INTER_AREA);
    image.convertTo(image, CV_32F, 1.0 / 255);
    return image;
}

inline double psnr(const Mat& a, const Mat& b, const Mat& mask = Mat())
{
    Mat diff;
    absdiff(a, b, diff);
    diff = diff.mul(diff);
    const Scalar m = mean(diff, mask);
    double mse = 0;
    for (int c = 0; c < a.channels(); c++)
        mse += m[c];
    mse /= a.channels();
    return 10 * std::log10(1.0 / std::max(mse, 1e-20));
}

//! Gaussian read noise, clipped at 0 as a sensor does (Richardson–Lucy refuses negative data).
inline Mat addGaussianNoise(const Mat& image, double sigma, uint64 seed)
{
    Mat noise(image.size(), image.type());
    RNG rng(seed);
    rng.fill(noise, RNG::NORMAL, 0, sigma);
    Mat noisy = image + noise;
    return max(noisy, 0.0);
}

//! Webcam-like noise: shot noise of `fullWell` electrons at intensity 1 plus Gaussian read noise,
//! clipped at 0 (the black level).
inline Mat addSensorNoise(const Mat& image, double fullWell, double readNoise, unsigned seed)
{
    std::mt19937 gen(seed);
    std::normal_distribution<double> read(0.0, readNoise);
    Mat out = image.clone();
    float* p = out.ptr<float>();
    for (size_t i = 0; i < out.total() * out.channels(); i++)
    {
        std::poisson_distribution<int> shot(std::max(0.0, double(p[i]) * fullWell));
        p[i] = float(std::max(0.0, (shot(gen) + read(gen)) / fullWell));
    }
    return out;
}

//! A motion-path kernel: a line from −half to +half (pixels), splatted bilinearly, sum 1.
inline Mat pathKernel(Point2d half, int rows, int cols)
{
    Mat k = Mat::zeros(rows, cols, CV_32F);
    const Point2d c((cols - 1) / 2.0, (rows - 1) / 2.0);
    const int samples = 200;
    for (int i = 0; i < samples; i++)
    {
        const double t = -1 + 2.0 * (i + 0.5) / samples;
        const Point2d p = c + t * half;
        const int x0 = int(std::floor(p.x)), y0 = int(std::floor(p.y));
        const double fx = p.x - x0, fy = p.y - y0;
        for (int dy = 0; dy < 2; dy++)
            for (int dx = 0; dx < 2; dx++)
            {
                const int x = x0 + dx, y = y0 + dy;
                if (x >= 0 && y >= 0 && x < cols && y < rows)
                    k.at<float>(y, x) += float((dx ? fx : 1 - fx) * (dy ? fy : 1 - fy));
            }
    }
    return k / sum(k)[0];
}

inline PsfBank oneNodeBank(Size size, const Mat& kernel, Point shift)
{
    PsfBank bank;
    bank.model = PSF_UNIFORM;
    bank.imageSize = size;
    bank.nodeRows = {size.height / 2.0};
    bank.nodeCols = {size.width / 2.0};
    bank.kernels = {kernel};
    bank.shifts = {shift};
    return bank;
}

/* Rolling-shutter-like row bank: a node every `band` rows, horizontal-ish motion whose length
   varies down the frame, and a vertical displacement falling from `maxShift` (top) to 0. */
inline PsfBank rowBank(Size size, int band, int maxShift)
{
    PsfBank bank;
    bank.model = PSF_ROWS;
    bank.imageSize = size;
    bank.nodeCols = {size.width / 2.0};
    for (double y = band / 2.0; y < size.height; y += band)
    {
        const double f = y / size.height;
        bank.nodeRows.push_back(y);
        bank.kernels.push_back(pathKernel(Point2d(3 + 6 * f, 1.5 * (1 - f)), 5, 21));
        bank.shifts.push_back(Point(0, cvRound(maxShift * (1 - f))));
    }
    return bank;
}

//! Tile bank: nx × ny nodes, each with its own motion direction and a small shift.
inline PsfBank tileBank(Size size, int nx, int ny, int maxShift)
{
    PsfBank bank;
    bank.model = PSF_TILES;
    bank.imageSize = size;
    for (int i = 0; i < nx; i++)
        bank.nodeCols.push_back((i + 0.5) * size.width / nx);
    for (int j = 0; j < ny; j++)
        bank.nodeRows.push_back((j + 0.5) * size.height / ny);
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++)
        {
            const double angle = 0.4 * i + 0.7 * j;
            const double length = 4 + i + j;
            bank.kernels.push_back(pathKernel(Point2d(length * std::cos(angle), length * std::sin(angle)), 17, 17));
            bank.shifts.push_back(Point((i - nx / 2) * maxShift / nx, (j - ny / 2) * maxShift / ny));
        }
    return bank;
}

//! The same bank seen on a bigger canvas whose crop at `offset` is the frame.
inline PsfBank onCanvas(PsfBank bank, Size canvas, Point offset)
{
    bank.imageSize = canvas;
    for (double& y : bank.nodeRows)
        y += offset.y;
    for (double& x : bank.nodeCols)
        x += offset.x;
    return bank;
}

//! Zero-padded "same" convolution written out directly: dst(p) = Σ_u k(u) src(p − (u − c)).
inline Mat directConvolve(const Mat& src, const Mat& k, bool flipped)
{
    Mat dst = Mat::zeros(src.size(), CV_32F);
    const int cx = (k.cols - 1) / 2, cy = (k.rows - 1) / 2;
    for (int y = 0; y < src.rows; y++)
        for (int x = 0; x < src.cols; x++)
        {
            double acc = 0;
            for (int v = 0; v < k.rows; v++)
                for (int u = 0; u < k.cols; u++)
                {
                    const int sy = flipped ? y + (v - cy) : y - (v - cy);
                    const int sx = flipped ? x + (u - cx) : x - (u - cx);
                    if (sy >= 0 && sx >= 0 && sy < src.rows && sx < src.cols)
                        acc += k.at<float>(v, u) * src.at<float>(sy, sx);
                }
            dst.at<float>(y, x) = float(acc);
        }
    return dst;
}

//! Textbook RL (scikit-image's form, zero boundary): x ← x ⊙ (k★(b / (k⊛x))).
inline Mat directRichardsonLucy(const Mat& blurred, const Mat& k, const Mat& start, int iterations)
{
    Mat x = start.clone();
    for (int i = 0; i < iterations; i++)
    {
        Mat reblurred = directConvolve(x, k, false);
        Mat ratio = blurred / (reblurred + 1e-12f);
        x = x.mul(directConvolve(ratio, k, true));
    }
    return x;
}

/* RL with TV (Dey et al.) for a blur A given by `forward` and `adjoint`:
   x ← x ⊙ Aᵀ(b / A x) / (Aᵀ1 − λ div(∇x/|∇x|)), the divisor kept ≥ 0.1 Aᵀ1, pixels whose Aᵀ1
   (`normalizer`) is ≤ kUnobserved kept. ∇ by forward differences (0 across the last column and
   row), div by backward ones, |∇x| on x / mean(b) regularised at 1e-3: the library's definition,
   written out pixel by pixel. */
inline Mat directRichardsonLucyTV(const Mat& blurred, const std::function<Mat(const Mat&)>& forward,
                           const std::function<Mat(const Mat&)>& adjoint, const Mat& normalizer, const Mat& start,
                           int iterations, double lambda)
{
    const double scale = 1.0 / mean(blurred)[0], eps2 = 1e-6;
    Mat x = start.clone();
    for (int i = 0; i < iterations; i++)
    {
        Mat nx(x.size(), CV_64F), ny(x.size(), CV_64F);
        for (int r = 0; r < x.rows; r++)
            for (int c = 0; c < x.cols; c++)
            {
                const double gx = c + 1 < x.cols ? (x.at<float>(r, c + 1) - x.at<float>(r, c)) * scale : 0.0;
                const double gy = r + 1 < x.rows ? (x.at<float>(r + 1, c) - x.at<float>(r, c)) * scale : 0.0;
                const double length = std::sqrt(gx * gx + gy * gy + eps2);
                nx.at<double>(r, c) = gx / length;
                ny.at<double>(r, c) = gy / length;
            }
        const Mat correction = adjoint(blurred / (forward(x) + 1e-12f));
        for (int r = 0; r < x.rows; r++)
            for (int c = 0; c < x.cols; c++)
            {
                const double n = normalizer.at<float>(r, c);
                if (n <= cv::dynblur::detail::kUnobserved)
                    continue;
                const double curvature = nx.at<double>(r, c) - (c > 0 ? nx.at<double>(r, c - 1) : 0.0) +
                                         ny.at<double>(r, c) - (r > 0 ? ny.at<double>(r - 1, c) : 0.0);
                const double divisor = std::max(n - lambda * curvature, 0.1 * n);
                x.at<float>(r, c) = float(x.at<float>(r, c) * correction.at<float>(r, c) / divisor);
            }
    }
    return x;
}

//! The same for one kernel, zero boundary, where the update divides by 1 − λ div(∇x/|∇x|).
inline Mat directRichardsonLucyTV(const Mat& blurred, const Mat& k, const Mat& start, int iterations, double lambda)
{
    return directRichardsonLucyTV(
        blurred, [&](const Mat& x) { return directConvolve(x, k, false); },
        [&](const Mat& ratio) { return directConvolve(ratio, k, true); }, Mat(start.size(), CV_32F, Scalar(1)), start,
        iterations, lambda);
}

inline RLParams plainParams(int boundary, int iterations)
{
    RLParams p;
    p.iterations = iterations;
    p.boundary = boundary;
    p.accelerate = false;
    p.tvWeight = 0;
    p.damping = 0;
    p.tolerance = 0;
    return p;
}

//! Mean absolute error of each row over the masked pixels.
inline std::vector<double> rowErrors(const Mat& a, const Mat& b, const Mat& mask)
{
    Mat diff;
    absdiff(a, b, diff);
    if (diff.channels() > 1)
        cvtColor(diff, diff, COLOR_BGR2GRAY);
    std::vector<double> e(size_t(a.rows), -1);
    for (int y = 0; y < a.rows; y++)
        if (countNonZero(mask.row(y)) > 0)
            e[size_t(y)] = mean(diff.row(y), mask.row(y))[0];
    return e;
}


}  // namespace deconv_test

#endif
