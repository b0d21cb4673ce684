// SPDX-License-Identifier: Apache-2.0
// Accuracy of richardsonLucy and richardsonLucyVariant against direct references: the FFT path, total
// variation, the normalised update, unseen rows, the automatic stop.
#include "rotation_motion.hpp"
#include "test_common.hpp"
#include "deconv_fixtures.hpp"

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

using namespace deconv_test;

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


}  // namespace
