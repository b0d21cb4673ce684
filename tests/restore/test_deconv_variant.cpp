// SPDX-License-Identifier: Apache-2.0
// Spatially variant RL (rows with large shifts, tiles) without seams, bfloat16 blurs, unobserved pixels,
// the PAD boundary, and Wiener.
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


}  // namespace
