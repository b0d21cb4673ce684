// SPDX-License-Identifier: Apache-2.0
// Accuracy of deconv.hpp: the FFT RL against a direct reference, the bank operator's adjoint,
// the forward model against filter2D, spatially variant RL (rows with large shifts, tiles),
// boundary handling, Wiener, regularisation, and argument checks.
#include "rotation_motion.hpp"
#include "test_common.hpp"

#include "restore/deconv_operator.hpp"
#include "restore/deconv_rl.hpp"
#include "restore/kernels/kernel_table.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <malloc.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <iostream>
#include <random>

namespace {

using namespace cv;
using namespace cv::dynblur;

// ---------------------------------------------------------------------------------------------
// Helpers

//! A test image as linear CV_32F in [0, 1], resized to `size`.
Mat loadImage(const std::string& path, Size size, bool color)
{
    Mat image = imread(path, color ? IMREAD_COLOR : IMREAD_GRAYSCALE);
    CV_Assert(!image.empty());
    resize(image, image, size, 0, 0, INTER_AREA);
    image.convertTo(image, CV_32F, 1.0 / 255);
    return image;
}

double psnr(const Mat& a, const Mat& b, const Mat& mask = Mat())
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
Mat addGaussianNoise(const Mat& image, double sigma, uint64 seed)
{
    Mat noise(image.size(), image.type());
    RNG rng(seed);
    rng.fill(noise, RNG::NORMAL, 0, sigma);
    Mat noisy = image + noise;
    return max(noisy, 0.0);
}

//! Webcam-like noise: shot noise of `fullWell` electrons at intensity 1 plus Gaussian read noise,
//! clipped at 0 (the black level).
Mat addSensorNoise(const Mat& image, double fullWell, double readNoise, unsigned seed)
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
Mat pathKernel(Point2d half, int rows, int cols)
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

PsfBank oneNodeBank(Size size, const Mat& kernel, Point shift)
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
PsfBank rowBank(Size size, int band, int maxShift)
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
PsfBank tileBank(Size size, int nx, int ny, int maxShift)
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
PsfBank onCanvas(PsfBank bank, Size canvas, Point offset)
{
    bank.imageSize = canvas;
    for (double& y : bank.nodeRows)
        y += offset.y;
    for (double& x : bank.nodeCols)
        x += offset.x;
    return bank;
}

//! Zero-padded "same" convolution written out directly: dst(p) = Σ_u k(u) src(p − (u − c)).
Mat directConvolve(const Mat& src, const Mat& k, bool flipped)
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
Mat directRichardsonLucy(const Mat& blurred, const Mat& k, const Mat& start, int iterations)
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
Mat directRichardsonLucyTV(const Mat& blurred, const std::function<Mat(const Mat&)>& forward,
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
Mat directRichardsonLucyTV(const Mat& blurred, const Mat& k, const Mat& start, int iterations, double lambda)
{
    return directRichardsonLucyTV(
        blurred, [&](const Mat& x) { return directConvolve(x, k, false); },
        [&](const Mat& ratio) { return directConvolve(ratio, k, true); }, Mat(start.size(), CV_32F, Scalar(1)), start,
        iterations, lambda);
}

RLParams plainParams(int boundary, int iterations)
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
std::vector<double> rowErrors(const Mat& a, const Mat& b, const Mat& mask)
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

// ---------------------------------------------------------------------------------------------
// (1) FFTW RL equals a direct-convolution RL.

TEST(DeconvRichardsonLucy, FftMatchesDirectReference)
{
    Mat truth(40, 52, CV_32F);
    RNG rng(7);
    rng.fill(truth, RNG::UNIFORM, 0.05, 1.0);
    GaussianBlur(truth, truth, Size(5, 5), 1.0);
    Mat kernel = pathKernel(Point2d(4.2, 1.3), 5, 11);
    kernel.at<float>(0, 0) = 0.02f;  // asymmetric: a flip error cannot hide
    kernel /= sum(kernel)[0];
    const Mat blurred = directConvolve(truth, kernel, false);
    const Mat start(truth.size(), CV_32F, Scalar(0.5));

    Mat fast;
    richardsonLucy(blurred, kernel, fast, plainParams(RL_BOUNDARY_ZERO, 10), start);
    const Mat reference = directRichardsonLucy(blurred, kernel, start, 10);
    EXPECT_LT(norm(fast, reference, NORM_INF), 1e-4);
    EXPECT_GT(norm(reference, start, NORM_INF), 0.1);  // the iterations did move the estimate

    // Every channel is restored, independently.
    Mat blurred3, start3, fast3;
    merge(std::vector<Mat>{blurred, blurred * 0.5, blurred * 0.25}, blurred3);
    merge(std::vector<Mat>{start, start, start}, start3);
    richardsonLucy(blurred3, kernel, fast3, plainParams(RL_BOUNDARY_ZERO, 10), start3);
    ASSERT_EQ(fast3.type(), CV_32FC3);
    std::vector<Mat> channels;
    split(fast3, channels);
    EXPECT_LT(norm(channels[0], reference, NORM_INF), 1e-4);
    EXPECT_LT(norm(channels[2], directRichardsonLucy(blurred * 0.25, kernel, start, 10), NORM_INF), 1e-4);
}

/* TV's unit gradient, its curvature and the update are taken sixteen columns at a time: a row
   that ends on a whole block (48 columns) takes its last column's right neighbour from within the
   block, other rows end in a padded block (1, 7 and 15 columns). Each matches the pixel-by-pixel
   reference, with a λ strong enough that its term moves the result. */
TEST(DeconvRichardsonLucy, TotalVariationMatchesDirectReferenceForEveryRowTail)
{
    const Mat kernel = pathKernel(Point2d(3.1, 1.7), 3, 9);
    for (int width : {48, 49, 55, 63})
    {
        SCOPED_TRACE(width);
        Mat truth(21, width, CV_32F);
        RNG(width).fill(truth, RNG::UNIFORM, 0.05, 1.0);
        const Mat blurred = directConvolve(truth, kernel, false);
        const Mat start(truth.size(), CV_32F, Scalar(0.5));
        RLParams params = plainParams(RL_BOUNDARY_ZERO, 6);
        params.tvWeight = 0.05;
        Mat fast;
        richardsonLucy(blurred, kernel, fast, params, start);
        const Mat reference = directRichardsonLucyTV(blurred, kernel, start, 6, params.tvWeight);
        EXPECT_LT(norm(fast, reference, NORM_INF), 1e-4);
        EXPECT_GT(norm(reference, directRichardsonLucy(blurred, kernel, start, 6), NORM_INF), 1e-2);  // TV did act
    }
}

/* RL_BOUNDARY_PAD, written out: the latent is the frame grown by the kernel's half-size on each
   side, A its "same" convolution cropped to the frame, Aᵀ the zero-embedded ratio correlated with
   the kernel, and x ← x ⊙ Aᵀ(b / A x) / Aᵀ1 from `start` (latent-sized). */
Mat directRichardsonLucyPad(const Mat& blurred, const Mat& k, const Mat& start, int iterations)
{
    const Rect frame((k.cols - 1) / 2, (k.rows - 1) / 2, blurred.cols, blurred.rows);
    const auto adjoint = [&](const Mat& r) {
        Mat embedded = Mat::zeros(start.size(), CV_32F);
        r.copyTo(embedded(frame));
        return directConvolve(embedded, k, true);
    };
    const Mat normalizer = adjoint(Mat::ones(blurred.size(), CV_32F));
    Mat x = start.clone();
    for (int i = 0; i < iterations; i++)
    {
        const Mat reblurred = directConvolve(x, k, false)(frame);
        x = x.mul(adjoint(blurred / (reblurred + 1e-12f))) / normalizer;
    }
    return x(frame).clone();
}

/* The update divides by Aᵀ1 read from its plane or, along a row where Aᵀ1 is one value, by that
   value without reading the plane. Both match the written-out RL: the single kernel's Aᵀ1 comes
   from FFTs and varies along every row; a row bank's vertical kernel gives rows of one value each
   (their sums are taken alike in every column), below 1 on the rows the latent adds. */
TEST(DeconvRichardsonLucy, NormalisedUpdateMatchesDirectReferenceWithConstantAndVaryingRows)
{
    Mat truth(24, 37, CV_32F);
    RNG(9).fill(truth, RNG::UNIFORM, 0.05, 1.0);
    const RLParams params = plainParams(RL_BOUNDARY_PAD, 6);

    Mat slanted = pathKernel(Point2d(1.6, 3.4), 5, 5);
    slanted.at<float>(0, 4) = 0.03f;  // asymmetric: a flip error cannot hide
    slanted /= sum(slanted)[0];
    Mat blurred = directConvolve(truth, slanted, false), start, fast;
    copyMakeBorder(blurred, start, 2, 2, 2, 2, BORDER_REPLICATE);  // the single-kernel path's start
    richardsonLucy(blurred, slanted, fast, params);
    Mat reference = directRichardsonLucyPad(blurred, slanted, start, 6);
    EXPECT_LT(norm(fast, reference, NORM_INF), 1e-4);
    EXPECT_GT(norm(reference, blurred, NORM_INF), 0.05);  // the iterations did move the estimate

    // Asymmetric, its centroid on the centre: the bank's start is the frame, the added rows its mean.
    const Mat vertical = (Mat_<float>(5, 1) << 0.2f, 0.1f, 0.3f, 0.3f, 0.1f);
    PsfBank bank;
    bank.model = PSF_ROWS;
    bank.imageSize = truth.size();
    bank.nodeRows = {truth.rows / 2.0};
    bank.nodeCols = {truth.cols / 2.0};
    bank.kernels = {vertical};
    bank.shifts = {Point(0, 0)};
    blurred = directConvolve(truth, vertical, false);
    copyMakeBorder(blurred, start, 2, 2, 0, 0, BORDER_CONSTANT, Scalar::all(mean(blurred)[0]));
    richardsonLucyVariant(blurred, bank, fast, params);
    reference = directRichardsonLucyPad(blurred, vertical, start, 6);
    EXPECT_LT(norm(fast, reference, NORM_INF), 1e-4);
    EXPECT_GT(norm(reference, blurred, NORM_INF), 0.05);
}

/* A padded domain's rows that no frame pixel reads (their Aᵀ1 is 0) keep their start, and the RL
   loop skips them from its second iteration on (extrapolation, packing, adjoint blocks, update;
   TV's unit gradient still for the seen row below). Here the bank's lowest node kernel reads 11–21
   rows above each frame row and the upper ones read in place, so the 21 latent rows above the
   frame are unseen: whole adjoint blocks, and a seen row just below one in the same band. RL with
   TV matches the written-out loop on the general operator; accelerated, regularised RL in
   bfloat16 leaves the unseen rows at their start and restores the frame as the float loop does. */
TEST(DeconvRichardsonLucy, UnseenLatentRowsKeepTheirStart)
{
    using namespace cv::dynblur::detail;
    PsfBank bank;
    bank.model = PSF_ROWS;
    bank.imageSize = Size(40, 60);
    bank.nodeRows = {0.5, 30.0, 59.5};
    bank.nodeCols = {20.0};
    bank.kernels = {Mat::ones(1, 1, CV_32F), Mat::ones(1, 1, CV_32F), Mat(11, 1, CV_32F, Scalar(1.0 / 11))};
    bank.shifts = {Point(0, 0), Point(0, 0), Point(0, 16)};

    BankBlurOperator general(bank, true);
    Mat normalizer;
    general.adjoint(Mat::ones(general.frameSize(), CV_32F), normalizer);
    int unseen = 0;
    for (int r = 0; r < normalizer.rows; r++)
        unseen += norm(normalizer.row(r), NORM_INF) <= kUnobserved;
    ASSERT_EQ(normalizer.rows, 60 + 21);
    ASSERT_EQ(unseen, 21);

    Mat truth(general.latentSize(), CV_32F), blurred;
    RNG(17).fill(truth, RNG::UNIFORM, 0.1, 1.0);
    general.forward(truth, blurred);
    const Mat start(general.latentSize(), CV_32F, Scalar(0.5));
    const Range unseenRows(0, 21), frameRows(21, 81);
    const auto restore = [&](BlurOperator& op, const RLParams& params) {
        Mat ones, opNormalizer;
        op.adjointOfOnes(opNormalizer, ones);
        std::vector<Mat> pool, estimate{start.clone()};
        RLWorkspace ws;
        LuminanceChange change;
        iterateRichardsonLucy(op, blurred, observeFrame(blurred, pool, false), opNormalizer, params, estimate, ws,
                              change);
        return estimate[0];
    };

    // RL with TV on the general operator, unseen pixels kept.
    const int iterations = 5;  // odd: the planes the loop alternates between end swapped
    RLParams regularised = plainParams(RL_BOUNDARY_PAD, iterations);
    regularised.tvWeight = 0.02;
    const Mat reference = directRichardsonLucyTV(
        blurred,
        [&](const Mat& x) {
            Mat y;
            general.forward(x, y);
            return y;
        },
        [&](const Mat& ratio) {
            Mat x;
            general.adjoint(ratio, x);
            return x;
        },
        normalizer, start, iterations, regularised.tvWeight);
    RowBankOperator rows(bank, true);
    const Mat plain = restore(rows, regularised);
    /* Where Aᵀ1 is small (the frame's last rows, which only the lowest kernel reads) the TV divisor
       magnifies the update's 5e-6 approximation of 1 / |∇x|: compared where Aᵀ1 > 1/2. */
    EXPECT_LT(norm(plain, reference, NORM_INF, normalizer > 0.5), 1e-4);
    EXPECT_GT(norm(reference, start, NORM_INF), 0.1);  // the iterations did move the seen rows
    EXPECT_EQ(norm(plain.rowRange(unseenRows), start.rowRange(unseenRows), NORM_INF), 0.0);

    RLParams accelerated = plainParams(RL_BOUNDARY_PAD, 9);
    accelerated.accelerate = true;
    accelerated.tvWeight = 0.01;
    RowBankOperator packed(bank, true, true);
    const Mat fast = restore(packed, accelerated), exact = restore(rows, accelerated);
    EXPECT_EQ(norm(fast.rowRange(unseenRows), start.rowRange(unseenRows), NORM_INF), 0.0);
    EXPECT_EQ(norm(exact.rowRange(unseenRows), start.rowRange(unseenRows), NORM_INF), 0.0);
    EXPECT_LT(norm(fast.rowRange(frameRows), exact.rowRange(frameRows), NORM_L1) / (60 * 40), 0.01);
    EXPECT_GT(norm(exact, plain, NORM_INF), 0.01);  // acceleration did act
}

TEST(DeconvRichardsonLucy, ToleranceStopsEarly)
{
    Mat truth(32, 32, CV_32F);
    RNG(3).fill(truth, RNG::UNIFORM, 0.1, 1.0);
    const Mat kernel = pathKernel(Point2d(3, 0), 1, 9);
    Mat blurred = directConvolve(truth, kernel, false), once, stopped, full;
    RLParams p = plainParams(RL_BOUNDARY_ZERO, 1);
    richardsonLucy(blurred, kernel, once, p);
    p.iterations = 50;
    richardsonLucy(blurred, kernel, full, p);
    p.tolerance = 10;  // any first step is smaller than this: stop after one iteration
    richardsonLucy(blurred, kernel, stopped, p);
    EXPECT_LT(norm(stopped, once, NORM_INF), 1e-6);
    EXPECT_GT(norm(full, once, NORM_INF), 1e-3);
}

// ---------------------------------------------------------------------------------------------
// (2) The bank operator's adjoint is exact.

void expectAdjoint(cv::dynblur::detail::BlurOperator& op, bool pad)
{
    Mat x(op.latentSize(), CV_32F), y(op.frameSize(), CV_32F), ax, aty;
    RNG rng(11);
    rng.fill(x, RNG::UNIFORM, -1, 1);
    rng.fill(y, RNG::UNIFORM, -1, 1);
    op.forward(x, ax);
    op.adjoint(y, aty);
    const double lhs = ax.dot(y), rhs = x.dot(aty);
    EXPECT_LT(std::abs(lhs - rhs), 1e-5 * std::max(std::abs(lhs), 1.0)) << "pad=" << pad << " " << lhs << " vs " << rhs;
    EXPECT_GT(norm(ax), 1.0);
}

//! The bank with node `node`'s kernel a slanted 5-tap line (5×7, offsets in both axes) at `shift`.
PsfBank withSlantedKernel(PsfBank bank, size_t node, Point shift)
{
    bank.kernels[node] = Mat::zeros(5, 7, CV_32F);
    for (int i = 0; i < 5; i++)
        bank.kernels[node].at<float>(i, i + 1) = 0.2f;
    bank.shifts[node] = shift;
    return bank;
}

//! The bank with a little noise on every non-zero tap (zero taps stay zero), renormalised.
PsfBank unevenTaps(PsfBank bank, uint64 seed)
{
    RNG rng(seed);
    for (Mat& k : bank.kernels)
    {
        Mat noise(k.size(), CV_32F), used;
        rng.fill(noise, RNG::UNIFORM, 0, 0.02);
        Mat(k > 0).convertTo(used, CV_32F, 1.0 / 255);
        k = k + noise.mul(used);
        k /= sum(k)[0];
    }
    return bank;
}

TEST(DeconvOperator, AdjointIsExactForTileBankWithShifts)
{
    const PsfBank bank = unevenTaps(tileBank(Size(90, 70), 4, 3, 30), 5);
    for (bool pad : {true, false})
    {
        cv::dynblur::detail::BankBlurOperator op(bank, pad);
        expectAdjoint(op, pad);
    }
}

//! A gathering operator computes what the general (scattering) one does, both ways.
void expectSameAsGeneral(cv::dynblur::detail::BlurOperator& gather, const PsfBank& bank, bool pad)
{
    cv::dynblur::detail::BankBlurOperator general(bank, pad);
    ASSERT_EQ(gather.latentSize(), general.latentSize());
    ASSERT_EQ(gather.origin(), general.origin());
    Mat x(gather.latentSize(), CV_32F), y(gather.frameSize(), CV_32F), a, b;
    RNG(3).fill(x, RNG::UNIFORM, 0, 1);
    RNG(4).fill(y, RNG::UNIFORM, 0, 1);
    general.forward(x, a);
    gather.forward(x, b);
    EXPECT_LT(norm(a, b, NORM_INF), 1e-5) << "forward, pad=" << pad;
    general.adjoint(y, a);
    gather.adjoint(y, b);
    EXPECT_LT(norm(a, b, NORM_INF), 1e-5) << "adjoint, pad=" << pad;
}

/* The tile gather has an exact adjoint and agrees with the general operator, slanted kernels and
   both boundaries included, with this CPU's gather kernels and with those of a CPU without AVX-512
   (narrow node column supports: the 512-bit kernel's masked partial blocks). */
TEST(DeconvOperator, TileGatherAgreesWithTheGeneralOperator)
{
    // The second bank is three columns wide, and its second node column lies far beside it: no support.
    PsfBank thin = tileBank(Size(3, 300), 2, 3, 6);
    thin.nodeCols = {0.0, 20.0};
    const PsfBank banks[] = {withSlantedKernel(unevenTaps(tileBank(Size(150, 110), 5, 4, 40), 6), 7, Point(-6, 3)),
                             thin};
    for (const PsfBank& bank : banks)
        for (cv::dynblur::kernels::KernelIsa isa : cv::dynblur::kernels::availableKernelIsas())
            for (bool pad : {true, false})
            {
                SCOPED_TRACE(cv::format("%dx%d bank, %s, %s", bank.imageSize.width, bank.imageSize.height,
                                        cv::dynblur::kernels::kernelIsaName(isa), pad ? "pad" : "zero"));
                cv::dynblur::kernels::forceKernelIsa(isa);
                cv::dynblur::detail::TileBankOperator tiles(bank, pad);
                expectAdjoint(tiles, pad);
                expectSameAsGeneral(tiles, bank, pad);
            }
    cv::dynblur::kernels::forceKernelIsa(cv::dynblur::kernels::KERNELS_ISA_COUNT);
}

// Both operators of a row bank (the general one and the row gather) have exact adjoints and agree.
TEST(DeconvOperator, AdjointIsExactForRowBankWithLargeShifts)
{
    // Slanted kernels too: taps with column offsets exercise the gather's edge columns.
    const PsfBank bank = withSlantedKernel(rowBank(Size(150, 160), 8, 120), 3, Point(-4, 2));
    for (cv::dynblur::kernels::KernelIsa isa : cv::dynblur::kernels::availableKernelIsas())
        for (bool pad : {true, false})
        {
            SCOPED_TRACE(cv::dynblur::kernels::kernelIsaName(isa));
            cv::dynblur::kernels::forceKernelIsa(isa);
            cv::dynblur::detail::BankBlurOperator general(bank, pad);
            cv::dynblur::detail::RowBankOperator rows(bank, pad);
            expectAdjoint(general, pad);
            expectAdjoint(rows, pad);
            expectSameAsGeneral(rows, bank, pad);
        }
    cv::dynblur::kernels::forceKernelIsa(cv::dynblur::kernels::KERNELS_ISA_COUNT);
}

/* A row bank's normaliser, gathered only near the edges and filled in between, is the adjoint of a
   frame of ones to the bit: float and bfloat16 gathers, every instruction set's kernels, both
   boundaries, a bank of slanted kernels (safe spans that differ from row to row), one of 1-column
   kernels, and one too narrow for the fill (the whole rows gathered). */
TEST(DeconvOperator, RowNormaliserIsTheAdjointOfOnes)
{
    const PsfBank banks[] = {withSlantedKernel(unevenTaps(rowBank(Size(150, 161), 8, 120), 7), 3, Point(-4, 2)),
                             rowBank(Size(200, 90), 5, 40),
                             withSlantedKernel(rowBank(Size(40, 60), 3, 20), 1, Point(9, 0))};
    for (const PsfBank& bank : banks)
        for (bool packed : {false, true})
            for (cv::dynblur::kernels::KernelIsa isa : cv::dynblur::kernels::availableKernelIsas())
                for (bool pad : {true, false})
                {
                    SCOPED_TRACE(cv::format("%dx%d bank, %s, %s, %s", bank.imageSize.width, bank.imageSize.height,
                                            packed ? "bfloat16" : "float", cv::dynblur::kernels::kernelIsaName(isa),
                                            pad ? "pad" : "zero"));
                    cv::dynblur::kernels::forceKernelIsa(isa);
                    cv::dynblur::detail::RowBankOperator rows(bank, pad, packed);
                    Mat normaliser, scratch, ofOnes;
                    rows.adjointOfOnes(normaliser, scratch);
                    rows.adjoint(Mat::ones(rows.frameSize(), CV_32F), ofOnes);
                    ASSERT_EQ(normaliser.size(), ofOnes.size());
                    EXPECT_EQ(norm(normaliser, ofOnes, NORM_INF), 0.0);
                    EXPECT_GT(norm(ofOnes, NORM_L1), 0.5 * double(rows.frameSize().area()));
                }
    cv::dynblur::kernels::forceKernelIsa(cv::dynblur::kernels::KERNELS_ISA_COUNT);
}

/* The restoration's start, the displacement-only blur's adjoint for several planes and a plane of
   ones at once, equals that blur's operator's adjoint placed in the full blur's latent domain:
   rows and tiles, both boundaries, kernels whose centroids sit off their centres. */
TEST(DeconvOperator, DisplacementAdjointEqualsTheOperatorsAdjoint)
{
    using namespace cv::dynblur::detail;
    const PsfBank banks[] = {withSlantedKernel(rowBank(Size(150, 160), 8, 120), 3, Point(-4, 2)),
                             withSlantedKernel(unevenTaps(tileBank(Size(150, 110), 5, 4, 40), 6), 7, Point(-6, 3))};
    for (const PsfBank& bank : banks)
        for (bool pad : {true, false})
        {
            SCOPED_TRACE(format("%d node columns, pad=%d", int(bank.nodeCols.size()), int(pad)));
            // The displacement as a bank of its own: one tap of 1 per node, at the shifts.
            PsfBank moved = bank;
            moved.shifts = displacementShifts(bank);
            for (Mat& kernel : moved.kernels)
                kernel = Mat::ones(1, 1, CV_32F);
            const std::unique_ptr<BlurOperator> blur = createBankOperator(bank, pad),
                                                move = createBankOperator(moved, pad);
            std::vector<Mat> frames, adjoints;
            for (int seed : {11, 12})
            {
                frames.emplace_back(bank.imageSize, CV_32F);
                RNG(uint64(seed)).fill(frames.back(), RNG::UNIFORM, 0, 1);
                adjoints.emplace_back(blur->latentSize(), CV_32F, Scalar(-1));
            }
            // The rows handed over, put together.
            Mat weight(blur->latentSize(), CV_32F, Scalar(-1));
            displacementAdjoint(bank, moved.shifts, blur->latentSize(), blur->origin(), frames,
                                [&](int row, const float* w, const float* const* a) {
                                    std::copy(w, w + weight.cols, weight.ptr<float>(row));
                                    for (size_t p = 0; p < frames.size(); p++)
                                        std::copy(a[p], a[p] + weight.cols, adjoints[p].ptr<float>(row));
                                });
            // The move's own domain inside the blur's (pad: the displacements reach less far than the kernels).
            const Rect inBlur(blur->origin() - move->origin(), move->latentSize());
            ASSERT_EQ(inBlur & Rect(Point(), blur->latentSize()), inBlur);
            const auto expectEqual = [&](const Mat& frame, const Mat& got, const char* what) {
                Mat own, expected = Mat::zeros(blur->latentSize(), CV_32F);
                move->adjoint(frame, own);
                own.copyTo(expected(inBlur));
                ASSERT_EQ(got.size(), expected.size()) << what;
                EXPECT_LT(norm(got, expected, NORM_INF), 1e-5) << what;
                EXPECT_GT(norm(expected, NORM_INF), 0.5) << what;
            };
            expectEqual(Mat::ones(bank.imageSize, CV_32F), weight, "plane of ones");
            expectEqual(frames[0], adjoints[0], "first plane");
            expectEqual(frames[1], adjoints[1], "second plane");
        }
}

//! `m` with every element rounded to the nearest bfloat16, so packing it loses nothing.
Mat bfloat16Exact(const Mat& m)
{
    Mat rounded = m.clone();
    for (int y = 0; y < rounded.rows; y++)
    {
        std::vector<uint32_t> packed(size_t(rounded.cols));
        cv::dynblur::detail::packRowPair(rounded.ptr<float>(y), nullptr, 0.f, rounded.cols, packed.data());
        for (int x = 0; x < rounded.cols; x++)
        {
            const uint32_t bits = packed[size_t(x)] << 16;
            std::memcpy(rounded.ptr<float>(y) + x, &bits, sizeof bits);
        }
    }
    return rounded;
}

/* A packed (bfloat16) operator agrees with the float one within bfloat16's rounding (weights and
   data each to 2^-9, so sums of positive terms to ~2^-8), is the exact transpose of itself on data
   that packs exactly (tiles: to the re-rounding of the column-weighted copies), and gives the same
   with every instruction set's kernels (the reference ones included). */
void expectPackedAgrees(cv::dynblur::detail::BlurOperator& packed, cv::dynblur::detail::BlurOperator& exact,
                        double adjointTolerance, const std::string& what)
{
    ASSERT_TRUE(packed.gathersPackedRows());
    ASSERT_FALSE(packed.gathersRows());
    ASSERT_EQ(packed.latentSize(), exact.latentSize());
    Mat x(packed.latentSize(), CV_32F), y(packed.frameSize(), CV_32F);
    RNG(7).fill(x, RNG::UNIFORM, 0.1, 1);
    RNG(8).fill(y, RNG::UNIFORM, 0.1, 1);
    x = bfloat16Exact(x);
    y = bfloat16Exact(y);
    // Packed result, compared with the float one and with every instruction set's kernels'.
    const auto compare = [&](const std::function<void(cv::dynblur::detail::BlurOperator&, Mat&)>& apply,
                             const char* direction) {
        Mat a, b, widened;
        apply(exact, a);
        apply(packed, b);
        EXPECT_LT(norm(a, b, NORM_INF), 4e-3 * norm(a, NORM_INF)) << what << ": " << direction;
        for (cv::dynblur::kernels::KernelIsa isa : cv::dynblur::kernels::availableKernelIsas())
        {
            cv::dynblur::kernels::forceKernelIsa(isa);
            apply(packed, widened);
            EXPECT_LT(norm(b, widened, NORM_INF), 1e-5 * norm(b, NORM_INF))
                << what << ": " << direction << ", " << cv::dynblur::kernels::kernelIsaName(isa);
        }
        cv::dynblur::kernels::forceKernelIsa(cv::dynblur::kernels::KERNELS_ISA_COUNT);
        return b;
    };
    const double lhs = compare([&](cv::dynblur::detail::BlurOperator& op, Mat& out) { op.forward(x, out); }, "forward")
                           .dot(y);
    const double rhs = x.dot(compare([&](cv::dynblur::detail::BlurOperator& op, Mat& out) { op.adjoint(y, out); },
                                     "adjoint"));
    EXPECT_LT(std::abs(lhs - rhs), adjointTolerance * std::abs(lhs)) << what << ": " << lhs << " vs " << rhs;
}

/* The 512-bit gathers do 128 columns per block and end a row with one masked block of 1 to 10
   vectors (a remainder of up to 32 columns joins the block before it): frame widths whose last
   block takes each of those, alone or after one or two blocks of 128; float against the general
   operator, packed against float and against the widened kernels of a CPU without AVX512-BF16. */
TEST(DeconvOperator, GathersAgreeForEveryWidthOfTheLastBlock)
{
    for (int width : {20, 100, 135, 150, 170, 185, 200, 215, 235, 250, 256, 280, 300})
    {
        SCOPED_TRACE(format("width %d", width));
        const PsfBank bank = withSlantedKernel(rowBank(Size(width, 41), 8, 20), 2, Point(-3, 2));
        cv::dynblur::detail::RowBankOperator rows(bank, true), packed(bank, true, true);
        expectSameAsGeneral(rows, bank, true);
        expectPackedAgrees(packed, rows, 1e-6, "packed rows");
    }
}

/* The tile adjoint reads the same whether the packed frame came as a plane (prepareAdjointPacked)
   or pair by pair (takePackedPair, as the RL loop hands its ratio over): after another frame's
   plane, and on a fresh operator (its copies' margins zero from the start); an odd height, both
   boundaries. */
TEST(DeconvOperator, TilePackedPairsGiveThePlanesAdjoint)
{
    const PsfBank bank = withSlantedKernel(unevenTaps(tileBank(Size(151, 111), 5, 4, 41), 6), 7, Point(-6, 3));
    for (bool pad : {true, false})
    {
        SCOPED_TRACE(pad ? "pad" : "zero");
        cv::dynblur::detail::TileBankOperator planeFed(bank, pad, true), pairFed(bank, pad, true);
        ASSERT_TRUE(pairFed.takesPackedPairs());
        Mat y(planeFed.frameSize(), CV_32F), packed, other;
        RNG(11).fill(y, RNG::UNIFORM, 0.1, 1);
        cv::dynblur::detail::packPlane(y, packed);
        cv::dynblur::detail::packPlane(Mat(y.size(), CV_32F, Scalar(0.5)), other);
        const Range rows(0, planeFed.latentSize().height);
        Mat expected(planeFed.latentSize(), CV_32F), fromPairs(planeFed.latentSize(), CV_32F);
        planeFed.prepareAdjointPacked(packed);
        planeFed.adjointPackedBlock(packed, rows, expected.ptr<float>(), expected.step1());
        EXPECT_GT(norm(expected, NORM_L1), 0.0);
        planeFed.prepareAdjointPacked(other);
        for (cv::dynblur::detail::TileBankOperator* op : {&planeFed, &pairFed})
        {
            for (int k = 0; k < packed.rows; k++)
                op->takePackedPair(k, packed.ptr<uint32_t>(k));
            fromPairs.setTo(-1);
            op->adjointPackedBlock(Mat(), rows, fromPairs.ptr<float>(), fromPairs.step1());
            EXPECT_EQ(norm(expected, fromPairs, NORM_INF), 0.0)
                << (op == &pairFed ? "fresh operator" : "after a plane");
        }
    }
}

// Odd heights (a last row without a partner), slanted kernels and large shifts, both boundaries.
TEST(DeconvOperator, PackedBfloat16GathersAgreeWithFloat)
{
    const PsfBank rows = withSlantedKernel(rowBank(Size(150, 161), 8, 120), 3, Point(-4, 3));
    const PsfBank tiles = unevenTaps(tileBank(Size(151, 111), 5, 4, 41), 6);
    for (bool pad : {true, false})
    {
        const std::string suffix = pad ? ", pad" : ", zero";
        cv::dynblur::detail::RowBankOperator rowPacked(rows, pad, true), rowExact(rows, pad);
        expectPackedAgrees(rowPacked, rowExact, 1e-6, "rows" + suffix);
        cv::dynblur::detail::TileBankOperator tilePacked(tiles, pad, true), tileExact(tiles, pad);
        expectPackedAgrees(tilePacked, tileExact, 1e-4, "tiles" + suffix);
    }
}

// ---------------------------------------------------------------------------------------------
// (3) The forward model is filter2D with the flipped kernel, moved by the shift.

TEST(DeconvApplyPsfBank, OneNodeEqualsFilter2D)
{
    Mat latent(80, 100, CV_32FC3);
    RNG(9).fill(latent, RNG::UNIFORM, 0, 1);
    Mat kernel(9, 5, CV_32F);
    RNG(10).fill(kernel, RNG::UNIFORM, 0, 1);
    kernel /= sum(kernel)[0];
    const Point shift(3, -7);
    Mat blurred, filtered, flipped;
    applyPsfBank(latent, oneNodeBank(latent.size(), kernel, shift), blurred);
    flip(kernel, flipped, -1);
    filter2D(latent, filtered, CV_32F, flipped, Point(-1, -1), 0, BORDER_CONSTANT);
    // B(p) = filtered(p − shift); compare where neither reaches past the frame.
    const int margin = 5;
    const Rect out(margin + shift.x, margin - shift.y + 4, 100 - 2 * margin - 2 * std::abs(shift.x),
                   80 - 2 * margin - 2 * std::abs(shift.y) - 4);
    const Rect in = out - shift;
    ASSERT_EQ(in & Rect(0, 0, 100, 80), in);
    EXPECT_LT(norm(blurred(out), filtered(in), NORM_INF), 1e-5);
}

/* Between two node columns the blend moves from one kernel to the other over the middle half of
   their interval, linearly, and keeps the nearer one elsewhere: with one-tap kernels shifted by 0
   and 10 px on a ramp L(x) = x, B(x) = x − 10 w₁(x) reads the second node's weight out. Node rows
   blend by the tent: the same along y. */
TEST(DeconvApplyPsfBank, NodeColumnsBlendOverTheMiddleHalfOfTheirIntervalNodeRowsByTheTent)
{
    const Mat delta(1, 1, CV_32F, Scalar(1));
    for (bool alongRows : {false, true})
    {
        SCOPED_TRACE(alongRows ? "node rows" : "node columns");
        PsfBank bank;
        bank.model = PSF_TILES;
        bank.imageSize = alongRows ? Size(20, 200) : Size(200, 20);
        bank.nodeRows = alongRows ? std::vector<double>{50, 150} : std::vector<double>{9.5};
        bank.nodeCols = alongRows ? std::vector<double>{9.5} : std::vector<double>{50, 150};
        bank.kernels = {delta, delta};
        bank.shifts = {Point(), alongRows ? Point(0, 10) : Point(10, 0)};
        Mat ramp(bank.imageSize, CV_32F), blurred;
        for (int y = 0; y < ramp.rows; y++)
            for (int x = 0; x < ramp.cols; x++)
                ramp.at<float>(y, x) = float(alongRows ? y : x);
        applyPsfBank(ramp, bank, blurred);
        for (int t = 20; t < 190; t++)
        {
            const double tent = std::min(std::max((t - 50) / 100.0, 0.0), 1.0);
            const double second = alongRows ? tent : std::min(std::max((tent - 0.5) / 0.5 + 0.5, 0.0), 1.0);
            const float b = alongRows ? blurred.at<float>(t, 10) : blurred.at<float>(10, t);
            EXPECT_NEAR(b, t - 10 * second, 1e-4) << "at " << t;
        }
    }
}

// ---------------------------------------------------------------------------------------------
// (4) Row-variant RL with large displacements: restores, and leaves no seams.

// (largest displacement, band rows): bands thin enough that neighbouring nodes' displacements
// differ by ≤ 2.5 px, as a generator would choose them.
class DeconvVariantShift : public ::testing::TestWithParam<std::pair<int, int>>
{
};

TEST_P(DeconvVariantShift, RowBankImprovesPsnrWithoutSeams)
{
    DYNBLUR_REQUIRE_DATA(path, "fruits.jpg");
    const int maxShift = GetParam().first, band = GetParam().second;
    const Size frame(240, 200);
    const Point offset(40, 140);
    const Mat canvas = loadImage(path, Size(320, 400), true);
    const PsfBank bank = rowBank(frame, band, maxShift);
    Mat blurredCanvas;
    applyPsfBank(canvas, onCanvas(bank, canvas.size(), offset), blurredCanvas);
    const Rect frameRect(offset, frame);
    const Mat truth = canvas(frameRect).clone();
    const Mat blurred = addGaussianNoise(blurredCanvas(frameRect), 0.005, 1);

    // Baseline: the same blur without its displacement, the best a shift-only correction could give.
    PsfBank still = bank;
    for (Point& s : still.shifts)
        s = Point();
    Mat stillCanvas;
    applyPsfBank(canvas, onCanvas(still, canvas.size(), offset), stillCanvas);
    const Mat baseline = addGaussianNoise(stillCanvas(frameRect), 0.005, 1);

    Mat restored, valid;
    richardsonLucyVariant(blurred, bank, restored, RLParams(), valid);
    ASSERT_EQ(restored.type(), CV_32FC3);
    ASSERT_EQ(valid.type(), CV_8UC1);
    // The top rows show content from up to 120 rows above them: all of it is on the canvas, so
    // with PAD nearly the whole frame counts as observed.
    EXPECT_GT(countNonZero(valid), int(0.95 * frame.area()));
    const double gain = psnr(restored, truth, valid) - psnr(baseline, truth, valid);
    std::printf("[ row bank, shifts 0..%d px, bands of %d rows ] baseline %.2f dB, restored %.2f dB (gain %.2f dB)\n",
                maxShift, band,
                psnr(baseline, truth, valid), psnr(restored, truth, valid), gain);
    EXPECT_GT(gain, 1.5);

    // Seams would show as rows with a larger error at node rows or halfway between nodes.
    const std::vector<double> e = rowErrors(restored, truth, valid);
    double atNodes = 0, between = 0, all = 0;
    int nNodes = 0, nBetween = 0, nAll = 0;
    for (int y = 10; y < frame.height - 10; y++)
    {
        if (e[size_t(y)] < 0)
            continue;
        all += e[size_t(y)];
        nAll++;
        if (2 * y % (2 * band) == band)
            atNodes += e[size_t(y)], nNodes++;
        if (y % band == 0)
            between += e[size_t(y)], nBetween++;
    }
    ASSERT_GT(nNodes, 5);
    EXPECT_LT(atNodes / nNodes, 1.15 * all / nAll);
    EXPECT_LT(between / nBetween, 1.15 * all / nAll);
}

INSTANTIATE_TEST_SUITE_P(Shifts, DeconvVariantShift, ::testing::Values(std::make_pair(0, 8), std::make_pair(40, 8),
                                                                       std::make_pair(120, 4)));

// ---------------------------------------------------------------------------------------------
// (5) Tile bank: no seam along the lines between nodes.

TEST(DeconvVariant, TileBankRestoresWithoutSeams)
{
    DYNBLUR_REQUIRE_DATA(path, "building.jpg");
    const Size frame(240, 180);
    const Point offset(40, 40);
    const Mat canvas = loadImage(path, Size(320, 260), false);
    const PsfBank bank = tileBank(frame, 4, 3, 12);
    Mat blurredCanvas;
    applyPsfBank(canvas, onCanvas(bank, canvas.size(), offset), blurredCanvas);
    const Rect frameRect(offset, frame);
    const Mat truth = canvas(frameRect).clone();
    const Mat blurred = addGaussianNoise(blurredCanvas(frameRect), 0.003, 2);

    Mat restored, valid;
    richardsonLucyVariant(blurred, bank, restored, RLParams(), valid);
    const double before = psnr(blurred, truth, valid), after = psnr(restored, truth, valid);
    std::printf("[ tile bank 4x3 ] blurred %.2f dB, restored %.2f dB\n", before, after);
    EXPECT_GT(after, before + 2.0);

    // Error in 3-px strips on the lines halfway between node columns / rows vs everywhere.
    Mat err;
    absdiff(restored, truth, err);
    const double overall = mean(err, valid)[0];
    for (int i = 1; i < 4; i++)
    {
        const int x = i * frame.width / 4;
        const Rect strip(x - 1, 10, 3, frame.height - 20);
        EXPECT_LT(mean(err(strip), valid(strip))[0], 1.3 * overall) << "column seam at x=" << x;
    }
    for (int j = 1; j < 3; j++)
    {
        const int y = j * frame.height / 3;
        const Rect strip(10, y - 1, frame.width - 20, 3);
        EXPECT_LT(mean(err(strip), valid(strip))[0], 1.3 * overall) << "row seam at y=" << y;
    }
}

// ---------------------------------------------------------------------------------------------
// (6) PAD boundary: no ringing at the frame's edges.

double borderToInterior(const Mat& restored, const Mat& truth, int border)
{
    Mat err;
    absdiff(restored, truth, err);
    Mat borderMask(err.size(), CV_8U, Scalar(255));
    borderMask(Rect(border, border, err.cols - 2 * border, err.rows - 2 * border)).setTo(0);
    return mean(err, borderMask)[0] / mean(err, ~borderMask)[0];
}

// bfloat16 blurs restore as float ones do, with and without extrapolation, in color and through
// the luminance phase, row-wise and tile-wise (odd heights: a last row without a partner).
TEST(DeconvVariant, Bfloat16BlursRestoreAsFloatDoes)
{
    /* docs/quality.md: |bfloat16 − float| measured ≤ 0.053 dB over the eight settings, float's gain
       over the blurred frame 4.96–7.54 dB; each bound a tenth from the worst case. */
    const double kBfloat16Tolerance = 0.058, kFloatGainFloor = 4.5;
    DYNBLUR_REQUIRE_DATA(path, "fruits.jpg");
    const Size frame(240, 181);
    const Point offset(40, 40);
    const Mat canvas = loadImage(path, Size(320, 261), true);
    for (const PsfBank& bank : {rowBank(frame, 8, 12), tileBank(frame, 4, 3, 12)})
    {
        Mat blurredCanvas;
        applyPsfBank(canvas, onCanvas(bank, canvas.size(), offset), blurredCanvas);
        const Rect frameRect(offset, frame);
        const Mat truth = canvas(frameRect).clone();
        const Mat blurred = addGaussianNoise(blurredCanvas(frameRect), 0.003, 2);
        for (bool accelerate : {true, false})
            for (int colorIterations : {-1, 2})
            {
                RLParams params;
                params.iterations = 10;
                params.accelerate = accelerate;
                params.colorIterations = colorIterations;
                Mat exact, fast, valid;
                richardsonLucyVariant(blurred, bank, exact, params, valid);
                params.blurPrecision = RL_BLUR_BFLOAT16;
                richardsonLucyVariant(blurred, bank, fast, params);
                const double before = psnr(blurred, truth, valid), floatPsnr = psnr(exact, truth, valid),
                             bfloat16Psnr = psnr(fast, truth, valid);
                const std::string what = format("%s, accelerate %d, colorIterations %d",
                                                bank.model == PSF_ROWS ? "rows" : "tiles", accelerate, colorIterations);
                std::printf("[ measured ] %s: blurred %.2f dB, float %.2f dB, bfloat16 %.2f dB (%+.3f dB, allowed "
                            "+-%.3f); float gains %.2f dB, floor %.2f dB\n",
                            what.c_str(), before, floatPsnr, bfloat16Psnr, bfloat16Psnr - floatPsnr, kBfloat16Tolerance,
                            floatPsnr - before, kFloatGainFloor);
                EXPECT_GT(floatPsnr, before + kFloatGainFloor) << what;
                EXPECT_NEAR(bfloat16Psnr, floatPsnr, kBfloat16Tolerance) << what;
            }
    }
}

TEST(DeconvVariant, UnobservedPixelsTakeTheNearestObservedOne)
{
    /* Every pixel holds its own index, so a filled pixel names the pixel it copied. Masks: a
       restoration's (a band of rows and slivers down both sides, tall enough for several strips of
       the fill), a band over a long run, blobs, bars and lines, a band with holes under it, and a
       single valid pixel; and whole rows, as a row-wise bank leaves them (bands at both edges, and
       one between valid rows as far above as below, whose row in the middle has two nearest rows).
       The source must be valid and as near as the exact Euclidean distance allows the 5×5 mask
       (0.95 px worse at most in these cases; exactly as near for whole rows, which are copied from
       the nearest valid row); every valid pixel keeps its value. */
    std::vector<cv::Mat> masks;
    cv::Mat edges(600, 320, CV_8U, cv::Scalar(255));
    edges.rowRange(0, 70).setTo(0);
    for (int y = 70; y < 520; y++)
    {
        edges.row(y).colRange(0, 1 + (520 - y) / 45).setTo(0);
        edges.row(y).colRange(320 - 1 - (520 - y) / 50, 320).setTo(0);
    }
    masks.push_back(edges);
    // A band of 128 rows over a row mostly unobserved: the band's bottom row is nearest the row below that.
    cv::Mat overhang(300, 200, CV_8U, cv::Scalar(255));
    overhang.rowRange(0, 128).setTo(0);
    overhang.row(128).colRange(0, 100).setTo(0);
    masks.push_back(overhang);
    cv::RNG rng(5);
    for (int t = 0; t < 6; t++)
    {
        cv::Mat m(300 + 40 * t, 400 - 30 * t, CV_8U, cv::Scalar(255));
        for (int k = 0; k < 3 + t; k++)
        {
            // One draw per declarator: the order of a call's arguments is the compiler's (GCC went right
            // to left, clang goes left to right). This is GCC's, the masks the tolerances were set on.
            const int cy = rng.uniform(0, m.rows);
            const cv::Point c(rng.uniform(0, m.cols), cy);
            if (k % 3 == 0)
                cv::circle(m, c, rng.uniform(2, 60), cv::Scalar(0), -1);
            else if (k % 3 == 1)
            {
                const int h = rng.uniform(1, 40);
                cv::rectangle(m, cv::Rect(c, cv::Size(rng.uniform(1, 200), h)), cv::Scalar(0), -1);
            }
            else
            {
                const int thickness = rng.uniform(1, 9), y = rng.uniform(0, m.rows);
                cv::line(m, c, cv::Point(rng.uniform(0, m.cols), y), cv::Scalar(0), thickness);
            }
        }
        if (t == 5)
            m.rowRange(0, 150).setTo(0);
        masks.push_back(m);
    }
    cv::Mat single(50, 60, CV_8U, cv::Scalar(0));
    single.at<uchar>(49, 0) = 255;
    masks.push_back(single);
    const size_t firstWholeRows = masks.size();
    cv::Mat bands(300, 90, CV_8U, cv::Scalar(255));
    bands.rowRange(0, 71).setTo(0);
    bands.rowRange(260, 300).setTo(0);
    masks.push_back(bands);
    cv::Mat middle(100, 70, CV_8U, cv::Scalar(255));
    middle.rowRange(40, 61).setTo(0);  // row 50 lies 10 rows from both
    masks.push_back(middle);

    for (size_t i = 0; i < masks.size(); i++)
    {
        SCOPED_TRACE(i);
        const cv::Mat& valid = masks[i];
        cv::Mat index(valid.size(), CV_32FC2);
        for (int y = 0; y < index.rows; y++)
            for (int x = 0; x < index.cols; x++)
                index.at<cv::Vec2f>(y, x) = cv::Vec2f(float(x), float(y));
        cv::Mat filled = index.clone();
        cv::dynblur::detail::fillFromNearest(filled, valid);
        cv::Mat exact;
        cv::distanceTransform(valid == 0, exact, cv::DIST_L2, cv::DIST_MASK_PRECISE);
        double worst = 0;
        int wrong = 0;
        for (int y = 0; y < valid.rows; y++)
            for (int x = 0; x < valid.cols; x++)
            {
                const cv::Vec2f source = filled.at<cv::Vec2f>(y, x);
                const cv::Point from{int(source[0]), int(source[1])};
                if (valid.at<uchar>(y, x))
                {
                    wrong += from != cv::Point(x, y);
                    continue;
                }
                if (!valid.at<uchar>(from))
                {
                    wrong++;
                    continue;
                }
                worst = std::max(worst, cv::norm(from - cv::Point(x, y)) - exact.at<float>(y, x));
            }
        EXPECT_EQ(wrong, 0);
        EXPECT_LE(worst, i >= firstWholeRows ? 0.0 : 0.95);
    }
    // No valid pixel: nothing to copy from, nothing changes.
    cv::Mat image(20, 30, CV_32FC3, cv::Scalar(0.25, 0.5, 0.75)), before = image.clone();
    cv::dynblur::detail::fillFromNearest(image, cv::Mat::zeros(image.size(), CV_8U));
    EXPECT_EQ(cv::norm(image, before, cv::NORM_INF), 0.0);
}

TEST(DeconvBoundary, PadDoesNotRingAtEdges)
{
    DYNBLUR_REQUIRE_DATA(path, "baboon.jpg");
    const Mat canvas = loadImage(path, Size(300, 260), false);
    const Rect frameRect(30, 30, 240, 200);
    const Mat kernel = pathKernel(Point2d(7, 2), 7, 17);
    Mat blurredCanvas, flipped;
    flip(kernel, flipped, -1);
    filter2D(canvas, blurredCanvas, CV_32F, flipped, Point(-1, -1), 0, BORDER_CONSTANT);
    const Mat truth = canvas(frameRect).clone();
    const Mat blurred = addGaussianNoise(blurredCanvas(frameRect), 0.002, 3);

    RLParams pad;
    Mat withPad, withZero, variantPad;
    richardsonLucy(blurred, kernel, withPad, pad);
    RLParams zero = pad;
    zero.boundary = RL_BOUNDARY_ZERO;
    richardsonLucy(blurred, kernel, withZero, zero);
    richardsonLucyVariant(blurred, oneNodeBank(blurred.size(), kernel, Point()), variantPad, pad);

    const double padRatio = borderToInterior(withPad, truth, 10);
    const double zeroRatio = borderToInterior(withZero, truth, 10);
    const double variantRatio = borderToInterior(variantPad, truth, 10);
    std::printf("[ edges ] border/interior error: PAD %.2f, ZERO %.2f, variant PAD %.2f\n", padRatio, zeroRatio,
                variantRatio);
    EXPECT_LT(padRatio, 1.5);
    EXPECT_LT(variantRatio, 1.5);
    EXPECT_GT(zeroRatio, 3 * padRatio);  // the comparison can fail: ZERO does ring
    EXPECT_GT(psnr(withPad, truth), psnr(blurred, truth) + 2.0);
    // One node without shift: the variant and the FFT path solve the same problem.
    EXPECT_GT(psnr(withPad, variantPad), 40.0);
}

// ---------------------------------------------------------------------------------------------
// (7) Wiener: a pure shift comes back exactly placed; blur is reduced.

TEST(DeconvWiener, PureShiftComesBackExactlyPlaced)
{
    Mat truth(90, 120, CV_32FC2);
    RNG(4).fill(truth, RNG::UNIFORM, 0, 1);
    const Point shift(13, -21);
    const PsfBank bank = oneNodeBank(truth.size(), Mat(1, 1, CV_32F, Scalar(1)), shift);
    Mat blurred, restored;
    applyPsfBank(truth, bank, blurred);
    const double nsr = 1e-2;
    wienerDeconvolve(blurred, bank, restored, nsr);
    // Latent q is seen at q + shift: compare where that lies in the frame. A flat spectrum is
    // scaled by 1 / (1 + nsr), exactly.
    const Rect seen = Rect(0, 0, 120, 90) & (Rect(0, 0, 120, 90) - shift);
    EXPECT_LT(norm(restored(seen) * (1 + nsr), truth(seen), NORM_INF), 1e-4);
}

TEST(DeconvWiener, ImprovesPsnrForUniformAndRowBanks)
{
    DYNBLUR_REQUIRE_DATA(path, "fruits.jpg");
    const Mat canvas = loadImage(path, Size(300, 260), false);
    const Rect frameRect(30, 30, 240, 200);
    const Mat truth = canvas(frameRect).clone();

    const Mat kernel = pathKernel(Point2d(6, 1), 5, 15);
    const PsfBank uniform = oneNodeBank(frameRect.size(), kernel, Point(0, 4));
    Mat blurredCanvas, restored;
    applyPsfBank(canvas, onCanvas(uniform, canvas.size(), frameRect.tl()), blurredCanvas);
    Mat blurred = addGaussianNoise(blurredCanvas(frameRect), 0.002, 5);
    wienerDeconvolve(blurred, uniform, restored, 2e-3);
    // Compare with the blurred frame moved back by the shift, so only sharpening counts.
    Mat unshifted;
    const Mat moveUp = (Mat_<double>(2, 3) << 1, 0, 0, 0, 1, -4);
    warpAffine(blurred, unshifted, moveUp, blurred.size(), INTER_NEAREST,
               BORDER_REPLICATE);
    const Rect inner(12, 12, 216, 176);
    std::printf("[ Wiener 1 node ] blurred %.2f dB, restored %.2f dB\n", psnr(unshifted(inner), truth(inner)),
                psnr(restored(inner), truth(inner)));
    EXPECT_GT(psnr(restored(inner), truth(inner)), psnr(unshifted(inner), truth(inner)) + 2.0);

    const PsfBank rows = rowBank(frameRect.size(), 16, 0);
    applyPsfBank(canvas, onCanvas(rows, canvas.size(), frameRect.tl()), blurredCanvas);
    blurred = addGaussianNoise(blurredCanvas(frameRect), 0.002, 6);
    wienerDeconvolve(blurred, rows, restored, 2e-3);
    std::printf("[ Wiener row bank ] blurred %.2f dB, restored %.2f dB\n", psnr(blurred(inner), truth(inner)),
                psnr(restored(inner), truth(inner)));
    EXPECT_GT(psnr(restored(inner), truth(inner)), psnr(blurred(inner), truth(inner)) + 2.0);
}

// ---------------------------------------------------------------------------------------------
// (8) Damping and TV hold back noise amplification; the defaults help on webcam-like noise.

TEST(DeconvRegularisation, DampingAndTvReduceNoiseAmplification)
{
    DYNBLUR_REQUIRE_DATA(path, "fruits.jpg");
    const Mat canvas = loadImage(path, Size(300, 260), false);
    const Rect frameRect(30, 30, 240, 200);
    const Mat truth = canvas(frameRect).clone();
    const Mat kernel = pathKernel(Point2d(5, 3), 9, 13);
    Mat blurredCanvas, flipped;
    flip(kernel, flipped, -1);
    filter2D(canvas, blurredCanvas, CV_32F, flipped, Point(-1, -1), 0, BORDER_CONSTANT);
    const Mat blurred = addGaussianNoise(blurredCanvas(frameRect), 0.02, 8);

    RLParams plain;
    plain.iterations = 40;
    plain.tvWeight = 0;
    plain.damping = 0;
    RLParams damped = plain, tv = plain;
    damped.damping = 3 * 0.02;
    tv.tvWeight = 0.01;
    Mat a, b, c;
    richardsonLucy(blurred, kernel, a, plain);
    richardsonLucy(blurred, kernel, b, damped);
    richardsonLucy(blurred, kernel, c, tv);
    const double plainPsnr = psnr(a, truth), dampedPsnr = psnr(b, truth), tvPsnr = psnr(c, truth),
                 blurredPsnr = psnr(blurred, truth);
    std::printf("[ noise sigma 0.02, 40 it ] plain %.2f dB, damping %.2f dB, TV %.2f dB (blurred %.2f dB)\n", plainPsnr,
                dampedPsnr, tvPsnr, blurredPsnr);
    /* docs/quality.md: over plain RL damping gains 11.07 dB and TV 13.07 dB; over the blurred frame
       TV gains 1.87 dB, while damping alone ends 0.13 dB below it (at this noise, 40 iterations of
       damped RL still fit some of it). Floors at 0.92 of each gain; the damped result may not fall
       further below the blurred frame than 0.2 dB. */
    struct Figure
    {
        const char* what;
        double gain, floor;
    };
    for (const Figure& f : {Figure{"damping - plain", dampedPsnr - plainPsnr, 10.18},
                            Figure{"TV - plain", tvPsnr - plainPsnr, 12.02},
                            Figure{"TV - blurred", tvPsnr - blurredPsnr, 1.72},
                            Figure{"damping - blurred", dampedPsnr - blurredPsnr, -0.2}})
    {
        std::printf("[ measured ] noise sigma 0.02, 40 iterations, %s: %+.3f dB, floor %+.2f dB\n", f.what, f.gain,
                    f.floor);
        EXPECT_GE(f.gain, f.floor) << f.what;
    }
}

TEST(DeconvRegularisation, DefaultsImproveWebcamNoisyFrame)
{
    DYNBLUR_REQUIRE_DATA(path, "fruits.jpg");
    const Size frame(320, 240);
    const Point offset(0, 100);
    const Mat canvas = loadImage(path, Size(320, 340), true);
    const PsfBank bank = rowBank(frame, 8, 60);
    Mat blurredCanvas;
    applyPsfBank(canvas, onCanvas(bank, canvas.size(), offset), blurredCanvas);
    const Rect frameRect(offset, frame);
    const Mat truth = canvas(frameRect).clone();
    const Mat blurred = addSensorNoise(blurredCanvas(frameRect), 4000, 8, 12);
    PsfBank still = bank;
    for (Point& s : still.shifts)
        s = Point();
    Mat stillCanvas;
    applyPsfBank(canvas, onCanvas(still, canvas.size(), offset), stillCanvas);
    const Mat baseline = addSensorNoise(stillCanvas(frameRect), 4000, 8, 12);

    Mat restored, valid;
    richardsonLucyVariant(blurred, bank, restored, RLParams(), valid);
    RLParams plain;
    plain.tvWeight = 0;
    plain.accelerate = false;
    Mat plainRestored;
    richardsonLucyVariant(blurred, bank, plainRestored, plain);
    std::printf("[ webcam noise 4000 e-, 8 e- read ] blurred (no shift) %.2f dB, defaults %.2f dB, "
                "plain RL 20 it %.2f dB\n",
                psnr(baseline, truth, valid), psnr(restored, truth, valid), psnr(plainRestored, truth, valid));
    EXPECT_GT(psnr(restored, truth, valid), psnr(baseline, truth, valid) + 1.5);
}

// ---------------------------------------------------------------------------------------------
// (9) Bad input is refused at the boundary, naming the argument.

std::string errorOf(const std::function<void()>& call)
{
    try
    {
        call();
    }
    catch (const cv::Exception& e)
    {
        return e.what();
    }
    return "";
}

/* A NaN or an infinity anywhere in a row is refused, wherever it falls in the check's 16-value
   blocks (the first value, which seeds the running range, a block, the tail after the last
   block), in one channel and in three; the smallest value is still found. */
TEST(DeconvArguments, NonFiniteValueAnywhereInARowIsRefused)
{
    const Mat kernel(3, 5, CV_32F, Scalar(1.0 / 15));
    for (int channels : {1, 3})
    {
        Mat image(4, 13, CV_32FC(channels), Scalar::all(0.5));  // 13 or 39 values a row
        const int n = image.cols * channels;
        for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity()})
            for (int x = 0; x < n; x++)
            {
                Mat corrupt = image.clone();
                corrupt.ptr<float>(2)[x] = bad;
                Mat out;
                EXPECT_NE(errorOf([&] { richardsonLucy(corrupt, kernel, out); }).find("NaN or Inf"), std::string::npos)
                    << channels << " channels, value " << bad << " at " << x;
            }
        image.ptr<float>(3)[n - 1] = -0.25f;  // the last value, after the last block
        Mat out;
        EXPECT_NE(errorOf([&] { richardsonLucy(image, kernel, out); }).find("-0.25"), std::string::npos) << channels;
    }
}

TEST(DeconvArguments, BadInputThrows)
{
    const Mat image(20, 30, CV_32F, Scalar(0.5));
    const Mat kernel(3, 5, CV_32F, Scalar(1.0 / 15));
    const PsfBank bank = oneNodeBank(image.size(), Mat(3, 3, CV_32F, Scalar(1.0 / 9)), Point());
    Mat out;
    RLParams p;

    EXPECT_THROW(richardsonLucy(Mat(), kernel, out), cv::Exception);
    EXPECT_THROW(richardsonLucy(Mat(20, 30, CV_8U, Scalar(1)), kernel, out), cv::Exception);
    EXPECT_THROW(richardsonLucy(Mat(20, 30, CV_64F, Scalar(1)), kernel, out), cv::Exception);
    // zeros, not Mat(rows, cols, type, Scalar): OpenCV 4.6 leaks that Mat when the 5-value Scalar throws.
    EXPECT_THROW(richardsonLucy(Mat::zeros(20, 30, CV_32FC(5)), kernel, out), cv::Exception);
    Mat nan = image.clone();
    nan.at<float>(3, 4) = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(richardsonLucy(nan, kernel, out), cv::Exception);
    Mat inf = image.clone();
    inf.at<float>(5, 5) = std::numeric_limits<float>::infinity();
    EXPECT_THROW(richardsonLucyVariant(inf, bank, out), cv::Exception);
    EXPECT_THROW(richardsonLucy(image, Mat(4, 3, CV_32F, Scalar(1)), out), cv::Exception);
    Mat negative = kernel.clone();
    negative.at<float>(0, 0) = -0.1f;
    EXPECT_THROW(richardsonLucy(image, negative, out), cv::Exception);
    EXPECT_THROW(richardsonLucy(image, Mat::zeros(3, 3, CV_32F), out), cv::Exception);
    EXPECT_THROW(richardsonLucy(image, Mat(), out), cv::Exception);
    EXPECT_THROW(richardsonLucy(image, kernel, out, p, Mat(10, 10, CV_32F, Scalar(1))), cv::Exception);

    RLParams bad = p;
    bad.iterations = 0;
    EXPECT_THROW(richardsonLucy(image, kernel, out, bad), cv::Exception);
    bad = p;
    bad.damping = -1;
    EXPECT_THROW(richardsonLucyVariant(image, bank, out, bad), cv::Exception);
    bad = p;
    bad.tvWeight = -0.1;
    EXPECT_THROW(richardsonLucy(image, kernel, out, bad), cv::Exception);
    bad = p;
    bad.tolerance = -1e-3;
    EXPECT_THROW(richardsonLucy(image, kernel, out, bad), cv::Exception);
    bad = p;
    bad.boundary = 7;
    EXPECT_THROW(richardsonLucy(image, kernel, out, bad), cv::Exception);

    PsfBank wrongSize = bank;
    wrongSize.imageSize = Size(31, 20);
    EXPECT_THROW(richardsonLucyVariant(image, wrongSize, out), cv::Exception);
    EXPECT_THROW(applyPsfBank(image, wrongSize, out), cv::Exception);
    EXPECT_THROW(wienerDeconvolve(image, wrongSize, out), cv::Exception);
    PsfBank missingKernel = bank;
    missingKernel.kernels.clear();
    EXPECT_THROW(richardsonLucyVariant(image, missingKernel, out), cv::Exception);
    PsfBank evenKernel = bank;
    evenKernel.kernels[0] = Mat(2, 3, CV_32F, Scalar(1.0 / 6));
    EXPECT_THROW(applyPsfBank(image, evenKernel, out), cv::Exception);
    EXPECT_THROW(wienerDeconvolve(image, bank, out, 0.0), cv::Exception);
    EXPECT_THROW(wienerDeconvolve(image, bank, out, -1.0), cv::Exception);
    EXPECT_THROW(applyPsfBank(Mat(20, 30, CV_8UC3), bank, out), cv::Exception);

    // The messages say which argument and what is allowed.
    EXPECT_NE(errorOf([&] { richardsonLucy(Mat(20, 30, CV_64F, Scalar(1)), kernel, out); }).find("CV_32F"),
              std::string::npos);
    bad = p;
    bad.iterations = 0;
    EXPECT_NE(errorOf([&] { richardsonLucy(image, kernel, out, bad); }).find("params.iterations"), std::string::npos);
    EXPECT_NE(errorOf([&] { richardsonLucy(nan, kernel, out); }).find("'blurred'"), std::string::npos);
    EXPECT_NE(errorOf([&] { richardsonLucy(image, Mat(4, 3, CV_32F, Scalar(1)), out); }).find("odd"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { wienerDeconvolve(image, bank, out, 0.0); }).find("noiseToSignal"), std::string::npos);
    EXPECT_NE(errorOf([&] { richardsonLucyVariant(image, wrongSize, out); }).find("'bank'"), std::string::npos);
    bad = p;
    bad.colorIterations = -2;
    EXPECT_NE(errorOf([&] { richardsonLucyVariant(image, bank, out, bad); }).find("params.colorIterations"),
              std::string::npos);
    bad = p;
    bad.blurPrecision = 2;
    EXPECT_NE(errorOf([&] { richardsonLucyVariant(image, bank, out, bad); }).find("params.blurPrecision"),
              std::string::npos);
}

// The single-kernel path takes the luminance phase's change as it writes its output, after which
// it undoes the frame's power-of-two scaling (a frame near 1e-3 is run near 1); its default start
// is the frame itself, which an explicit initial estimate equal to the frame must reproduce.
TEST(DeconvColorIterations, UniformPathTakesTheLuminanceChangeAndItsStart)
{
    Mat grey(64, 80, CV_32F), blurredGrey;
    RNG(23).fill(grey, RNG::UNIFORM, 0.1, 0.9);
    GaussianBlur(grey, grey, Size(0, 0), 1.0);
    const Mat kernel = Mat::ones(9, 1, CV_32F) / 9.0f;
    filter2D(grey, blurredGrey, -1, kernel, Point(-1, -1), 0, BORDER_REPLICATE);
    Mat equalPlanes;
    merge(std::vector<Mat>{blurredGrey, blurredGrey, blurredGrey}, equalPlanes);
    equalPlanes *= 1e-3;
    RLParams params;
    params.iterations = 8;
    params.accelerate = false;  // restarts with the luminance phase
    Mat full, reduced, started;
    richardsonLucy(equalPlanes, kernel, full, params);
    params.colorIterations = 3;
    richardsonLucy(equalPlanes, kernel, reduced, params);
    EXPECT_LT(norm(full, reduced, NORM_INF), 1e-4 * 1e-3);
    EXPECT_GT(norm(reduced, equalPlanes, NORM_INF), 1e-2 * 1e-3);  // it did restore
    richardsonLucy(equalPlanes, kernel, started, params, equalPlanes);
    EXPECT_EQ(norm(started, reduced, NORM_INF), 0.0);
}

// Luminance iterations: exact where they must be, and close to full color on a colorful frame.
TEST(DeconvColorIterations, LuminancePhaseAgreesWithFullColor)
{
    const PsfBank bank = rowBank(Size(120, 90), 6, 20);
    Mat grey(90, 120, CV_32F), blurredGrey;
    RNG(21).fill(grey, RNG::UNIFORM, 0.1, 0.9);
    GaussianBlur(grey, grey, Size(0, 0), 1.0);
    applyPsfBank(grey, bank, blurredGrey);
    RLParams params;
    params.iterations = 8;
    Mat full, reduced, above;

    /* Equal planes: their mean is each plane, so the luminance phase is color RL exactly (without
       acceleration, which restarts with the luminance phase). */
    params.accelerate = false;
    Mat equalPlanes;
    merge(std::vector<Mat>{blurredGrey, blurredGrey, blurredGrey}, equalPlanes);
    richardsonLucyVariant(equalPlanes, bank, full, params);
    params.colorIterations = 3;
    richardsonLucyVariant(equalPlanes, bank, reduced, params);
    EXPECT_LT(norm(full, reduced, NORM_INF), 1e-4);

    // colorIterations ≥ iterations is every iteration in color.
    params.colorIterations = 8;
    richardsonLucyVariant(equalPlanes, bank, above, params);
    EXPECT_EQ(norm(full, above, NORM_INF), 0.0);

    // A colorful frame: the luminance phase stays close to full color RL.
    params.accelerate = true;
    Mat color(90, 120, CV_32FC3), blurred;
    RNG(22).fill(color, RNG::UNIFORM, 0.05, 0.95);
    GaussianBlur(color, color, Size(0, 0), 1.5);
    applyPsfBank(color, bank, blurred);
    params.colorIterations = -1;
    richardsonLucyVariant(blurred, bank, full, params);
    params.colorIterations = 3;
    richardsonLucyVariant(blurred, bank, reduced, params);
    const Rect inner(10, 10, 100, 70);
    const double fullPsnr = psnr(full(inner), color(inner)), reducedPsnr = psnr(reduced(inner), color(inner));
    std::printf("[ measured ] colorful 120x90, 8 iterations: full color %.2f dB, 3 color + 5 luminance %.2f dB\n",
                fullPsnr, reducedPsnr);
    EXPECT_GT(reducedPsnr, fullPsnr - 1.0);
}

}  // namespace

TEST(DeconvRegularisation, AutomaticDampingFollowsTheFramesNoise)
{
    // A flat frame with known Gaussian noise: automatic damping (NaN) must hold the noise down
    // where undamped RL amplifies it, and be accepted where negative damping is refused.
    cv::Mat flat(200, 200, CV_32F, cv::Scalar(0.4)), noise(flat.size(), CV_32F), noisy;
    cv::RNG rng(3);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 0.01);
    noisy = flat + noise;
    cv::Mat kernel = cv::Mat::ones(9, 1, CV_32F) / 9.0f;
    cv::dynblur::RLParams plain, automatic;
    automatic.damping = std::numeric_limits<double>::quiet_NaN();
    cv::Mat restoredPlain, restoredAuto;
    cv::dynblur::richardsonLucy(noisy, kernel, restoredPlain, plain);
    cv::dynblur::richardsonLucy(noisy, kernel, restoredAuto, automatic);
    cv::Scalar meanPlain, stdPlain, meanAuto, stdAuto;
    const cv::Rect interior(20, 20, 160, 160);
    cv::meanStdDev(restoredPlain(interior), meanPlain, stdPlain);
    cv::meanStdDev(restoredAuto(interior), meanAuto, stdAuto);
    std::printf("[ measured ] flat frame, noise 0.01: output noise plain %.4f, automatic damping %.4f\n", stdPlain[0],
                stdAuto[0]);
    EXPECT_LT(stdAuto[0], 0.6 * stdPlain[0]);
    EXPECT_NEAR(meanAuto[0], 0.4, 0.01);
}

// The restoration splits a color frame and takes its means, level and noise in one pass
// (detail::observeFrame): each must equal what OpenCV computes separately, Immerkær's estimate must
// find the noise added to a smooth frame, and a one-channel frame is used in place.
TEST(DeconvRegularisation, ObservedFrameSplitsAndMeasuresInOnePass)
{
    for (int channels : {1, 3, 4})
    {
        SCOPED_TRACE(channels);
        // Smooth content (a ramp per channel) plus Gaussian noise of 0.02: the mask cancels the ramp.
        cv::Mat frame(131, 97, CV_32FC(channels)), noise(frame.size(), frame.type());
        for (int y = 0; y < frame.rows; y++)
            for (int x = 0; x < frame.cols; x++)
                for (int c = 0; c < channels; c++)
                    frame.ptr<float>(y)[x * channels + c] = 0.3f + 0.002f * float(x + 2 * y) + 0.05f * float(c);
        cv::RNG(11).fill(noise, cv::RNG::NORMAL, 0.0, 0.02);
        frame += noise;
        frame.at<float>(60, 40 * channels) = 1.75f;  // the peak, in the first channel

        std::vector<cv::Mat> pool, expected;
        const cv::dynblur::detail::ObservedFrame observed = cv::dynblur::detail::observeFrame(frame, pool, true);
        cv::split(frame, expected);
        ASSERT_EQ(observed.planes.size(), size_t(channels));
        const cv::Scalar means = cv::mean(frame);
        double overall = 0;
        for (int c = 0; c < channels; c++)
        {
            EXPECT_EQ(cv::norm(observed.planes[size_t(c)], expected[size_t(c)], cv::NORM_INF), 0.0);
            EXPECT_NEAR(observed.channelMean[c], means[c], 1e-6 * means[c]);
            overall += means[c] / channels;
        }
        if (channels == 1)
        {
            EXPECT_EQ(observed.planes[0].data, frame.data);  // no copy
        }
        EXPECT_NEAR(observed.level.mean, overall, 1e-6 * overall);
        EXPECT_EQ(observed.level.peak, 1.75);
        std::printf("[ measured ] %d channel(s), noise 0.02: Immerkaer estimate %.5f\n", channels, observed.noiseSigma);
        EXPECT_NEAR(observed.noiseSigma, 0.02, 0.02 * 0.05);
        EXPECT_EQ(cv::dynblur::detail::observeFrame(frame, pool, false).noiseSigma, 0.0);
    }
}

/* The damped ratio's deviance, log-free: against b ln(b / ab) − b + ab in double, it is never above
   it, within e²/18 + |e|³/15 relative where the damping acts (|e| ≤ 0.5 for the relative residual
   e), 3 % up to e = 1, 25 % down to b = 0; 0 where b = ab, including two zeros. */
TEST(DeconvRegularisation, DevianceFormAgreesWithThePoissonDeviance)
{
    using cv::dynblur::detail::halfPoissonDeviance;
    for (const double ab : {1e-6, 0.03, 1.0, 40.0})
        for (double e = -1.0; e <= 4.0; e += 1.0 / 64)
        {
            const double b = ab * (1 + e);
            const double exact = b > 0 ? b * std::log(b / ab) - b + ab : ab;
            const double form = halfPoissonDeviance(float(b), float(ab));
            SCOPED_TRACE(cv::format("ab = %g, e = %g", ab, e));
            EXPECT_LE(form, exact * (1 + 1e-5) + 1e-12 * ab);
            if (std::abs(e) <= 0.5)
            {
                EXPECT_GE(form, exact * (1 - (e * e / 18 + std::abs(e * e * e) / 15) * 1.1) - 1e-6 * exact -
                                    1e-12 * ab);
            }
            else if (e < 0)
            {
                EXPECT_GE(form, exact * 0.75 * (1 - 1e-6));
            }
            else if (e <= 1)
            {
                EXPECT_GE(form, exact * (1 - 0.03));
            }
            if (e == -1)
            {
                EXPECT_NEAR(form, 0.75 * ab, 1e-6 * ab);
            }
        }
    EXPECT_EQ(halfPoissonDeviance(0.f, 0.f), 0.f);
    EXPECT_EQ(halfPoissonDeviance(0.25f, 0.25f), 0.f);
}

// −0 is a valid black pixel (≥ 0 holds): the damped ratio must take it as 0 does, in the uniform
// and the row-variant restoration alike.
TEST(DeconvRegularisation, NegativeZeroPixelsRestoreAsZero)
{
    cv::Mat frame(64, 48, CV_32FC3);
    cv::RNG(5).fill(frame, cv::RNG::UNIFORM, 0.2, 0.8);
    frame(cv::Rect(10, 20, 12, 9)).setTo(0.f);
    cv::Mat negative = frame.clone();
    negative(cv::Rect(10, 20, 12, 9)).setTo(-0.f);
    ASSERT_TRUE(std::signbit(negative.at<cv::Vec3f>(20, 10)[0]));
    cv::dynblur::RLParams params;
    params.damping = std::numeric_limits<double>::quiet_NaN();
    params.iterations = 6;
    const cv::Mat kernel = cv::Mat::ones(7, 1, CV_32F) / 7.0f;
    cv::Mat expected, restored;
    cv::dynblur::richardsonLucy(frame, kernel, expected, params);
    cv::dynblur::richardsonLucy(negative, kernel, restored, params);
    EXPECT_TRUE(cv::checkRange(restored));
    EXPECT_EQ(cv::norm(restored, expected, cv::NORM_INF), 0.0);
    const PsfBank bank = rowBank(frame.size(), 8, 6);
    cv::dynblur::richardsonLucyVariant(frame, bank, expected, params);
    cv::dynblur::richardsonLucyVariant(negative, bank, restored, params);
    EXPECT_TRUE(cv::checkRange(restored));
    EXPECT_EQ(cv::norm(restored, expected, cv::NORM_INF), 0.0);
}

namespace {

// ---------------------------------------------------------------------------------------------
// (8) Memory: the frame-rate restoration's working set.

/* Counts the bytes of every Mat allocated while it is the default allocator (OpenCV's own
   allocator does the work), and the peak. */
class CountingAllocator CV_FINAL : public MatAllocator
{
public:
    UMatData* allocate(int dims, const int* sizes, int type, void* data, size_t* step, AccessFlag flags,
                       UMatUsageFlags usage) const CV_OVERRIDE
    {
        UMatData* u = std_->allocate(dims, sizes, type, data, step, flags, usage);
        if (u && !data)
        {
            u->currAllocator = this;
            const size_t now = current_ += u->size;
            size_t peak = peak_.load();
            while (now > peak && !peak_.compare_exchange_weak(peak, now))
            {
            }
        }
        return u;
    }
    bool allocate(UMatData* u, AccessFlag flags, UMatUsageFlags usage) const CV_OVERRIDE
    {
        return std_->allocate(u, flags, usage);
    }
    void deallocate(UMatData* u) const CV_OVERRIDE
    {
        if (u && !(u->flags & UMatData::USER_ALLOCATED))
            current_ -= u->size;
        std_->deallocate(u);
    }
    size_t peak() const { return peak_; }
    void resetPeak() { peak_ = current_.load(); }
    size_t current() const { return current_; }

private:
    MatAllocator* std_ = Mat::getStdAllocator();
    mutable std::atomic<size_t> current_{0}, peak_{0};
};

//! Bytes the heap holds right now (glibc; 0 where mallinfo2 is not what the allocator reports).
double heapInUse()
{
    const struct mallinfo2 m = mallinfo2();
    return double(m.uordblks + m.hblkhd);
}

/* Peak extra memory of richardsonLucyVariant on `frame` with `bank`, in frame planes per channel:
   its Mats, counted at their peak (the output excluded), plus the blur operator's tap lists, which
   live through the whole restoration. `operatorPlanes` receives the second part. */
double extraPlanesPerChannel(const Mat& frame, const PsfBank& bank, const RLParams& params, double& operatorPlanes)
{
    const double plane = double(frame.total()) * sizeof(float) * frame.channels();
    const double before = heapInUse();
    {
        const auto op = cv::dynblur::detail::createBankOperator(bank, true, params.blurPrecision == RL_BLUR_BFLOAT16);
        operatorPlanes = (heapInUse() - before) / plane;
    }
    Mat latent;
    CountingAllocator counter;
    MatAllocator* previous = Mat::getDefaultAllocator();
    Mat::setDefaultAllocator(&counter);
    richardsonLucyVariant(frame, bank, latent, params);
    Mat::setDefaultAllocator(previous);
    const double mats = (double(counter.peak()) - double(latent.total() * latent.elemSize())) / plane;
    latent.release();  // freed through the counter, which must outlive it
    return mats + operatorPlanes;
}

// The row-wise restoration of a 1280×960 RGB window III frame (the speed benchmark's) holds at
// most 4 frame-sized float planes per channel besides its input and output (the memory target of
// docs/performance.md). The tile-wise one is measured beside it and held to what it needs: its tap
// lists alone take ~3.9.
TEST(DeconvMemory, RowWiseRestorationStaysWithinFourFramePlanesPerChannel)
{
    Ptr<Plant> plant = Plant::create(14.4, 0.12, CV_PI / 180);
    Ptr<CameraModel> camera = CameraModel::create(1230, 1230, 639.5, 479.5, 1280, 960);
    const SwitchSchedule schedule = SwitchPlanner::create(plant, 16, PLAN_ROBUST)->plan(0.0, 10 * CV_PI / 180, 0.0);
    const RollingShutter shutter{0.012, 0.008, 1.0 / 30 / 960, 960};
    Ptr<PsfGenerator> generator = PsfGenerator::create(plant, camera);
    Mat frame(960, 1280, CV_32FC3);
    randu(frame, 0.05f, 0.95f);
    RLParams params = DynamicDeblurrer::create(plant, camera)->getRLParams();
    params.iterations = 10;
    for (int model : {PSF_ROWS, PSF_TILES})
    {
        const PsfBank bank = generator->generate(model, schedule, shutter);
        // Full color, then the frame-rate setting in float and in bfloat16.
        for (const std::pair<int, int>& setting :
             {std::make_pair(-1, int(RL_BLUR_FLOAT32)), std::make_pair(3, int(RL_BLUR_FLOAT32)),
              std::make_pair(3, int(RL_BLUR_BFLOAT16))})
        {
            params.colorIterations = setting.first;
            params.blurPrecision = setting.second;
            double taps = 0;
            const double extra = extraPlanesPerChannel(frame, bank, params, taps);
            std::cout << "[ measured ] " << (model == PSF_ROWS ? "row" : "tile")
                      << "-wise RL, 1280x960 RGB, 10 iterations, colorIterations " << setting.first
                      << (setting.second == RL_BLUR_BFLOAT16 ? ", bfloat16" : ", float32") << ": peak extra memory "
                      << extra << " frame planes per channel (Mats " << extra - taps << ", operator's taps " << taps
                      << ")" << std::endl;
            // the figures each setting measures are in docs/performance.md
            EXPECT_LE(extra, model == PSF_ROWS ? 4.0 : 8.0);
        }
    }

    /* The frame-rate setting as DynamicDeblurrer runs it, the color at half resolution: every Mat
       it keeps for the next frame (both workspaces, the half-size color, the luminance)
       and its temporaries, at their peak, plus the full-size operator's taps (the half-size one's
       are gone before it is built). Its figure is in docs/performance.md. */
    const double plane = double(frame.total()) * sizeof(float) * frame.channels();
    double taps = 0;
    {
        const double before = heapInUse();
        const auto op = cv::dynblur::detail::createBankOperator(generator->generate(PSF_ROWS, schedule, shutter), true,
                                                                true);
        taps = (heapInUse() - before) / plane;
    }
    CountingAllocator counter;
    MatAllocator* previous = Mat::getDefaultAllocator();
    Mat::setDefaultAllocator(&counter);
    Mat restored;
    {
        Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(plant, camera);
        deblurrer->setPsfModel(PSF_ROWS);
        params.colorIterations = 3;
        params.blurPrecision = RL_BLUR_BFLOAT16;
        deblurrer->setRLParams(params);
        deblurrer->setColorResolution(DEBLUR_COLOR_HALF_RESOLUTION);
        deblurrer->deblur(frame, schedule, shutter, restored);
    }
    Mat::setDefaultAllocator(previous);
    const double mats = (double(counter.peak()) - double(restored.total() * restored.elemSize())) / plane;
    restored.release();
    std::cout << "[ measured ] DynamicDeblurrer, row-wise, 1280x960 RGB, 10 iterations, 3 in color at half "
                 "resolution, bfloat16: peak extra memory "
              << mats + taps << " frame planes per channel (Mats " << mats << ", operator's taps " << taps << ")"
              << std::endl;
    EXPECT_LE(mats + taps, 4.0);
}

/* The default (tiles, 20 iterations, full color) on the same camera and shutter, its frame blurred by
   3-axis shakes of up to 30, 60 and 90 deg/s over a 20 ms exposure (blur paths up to ~40 px), holds at
   most twice the one-axis default's peak extra memory (the saccade frame above). */
TEST(DeconvMemory, ThreeAxisDefaultWithinTwiceTheOneAxis)
{
    Ptr<Plant> plant = Plant::create(14.4, 0.12, CV_PI / 180);
    Ptr<CameraModel> camera = CameraModel::create(1230, 1230, 639.5, 479.5, 1280, 960);
    const SwitchSchedule schedule = SwitchPlanner::create(plant, 16, PLAN_ROBUST)->plan(0.0, 10 * CV_PI / 180, 0.0);
    Mat frame(960, 1280, CV_32FC3);
    randu(frame, 0.05f, 0.95f);
    const RLParams params = DynamicDeblurrer::create(plant, camera)->getRLParams();
    double taps = 0;
    const double oneAxis = extraPlanesPerChannel(
        frame, PsfGenerator::create(plant, camera)->generate(PSF_TILES, schedule, RollingShutter(0.012, 0.008, 1.0 / 30 / 960, 960)),
        params, taps);
    std::cout << "[ measured ] one-axis default (tiles), 1280x960 RGB, window III: peak extra memory " << oneAxis
              << " frame planes per channel" << std::endl;
    for (double peakRate : {30.0, 60.0, 90.0})
    {
        const PsfBank bank = PsfGenerator::create(camera)->generate(PSF_TILES, dynblur_test::handShake(peakRate),
                                                                    RollingShutter(0.1, 0.020, 1.0 / 30 / 960, 960));
        const double threeAxis = extraPlanesPerChannel(frame, bank, params, taps);
        std::cout << "[ measured ] 3-axis shake " << peakRate << " deg/s, default (tiles), longest kernel "
                  << std::max(bank.maxKernelSize().width, bank.maxKernelSize().height) << " px: peak extra memory "
                  << threeAxis << " frame planes per channel (operator's taps " << taps << "), "
                  << threeAxis / oneAxis << "x the one-axis default's" << std::endl;
        EXPECT_LE(threeAxis, 2 * oneAxis) << peakRate << " deg/s";
    }
}

}  // namespace
