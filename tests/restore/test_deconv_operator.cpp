// SPDX-License-Identifier: Apache-2.0
// The bank operators: exact adjoints (tiles, rows, displacement), the gathers against the general
// operator and each other, bfloat16 packing; the forward model against filter2D.
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

/* The bank with node rows `rows` one kernel wide, as PSF_AUTO's row bands are: node column 0's kernel
   and shift in every column. */
PsfBank withRowBands(PsfBank bank, const std::vector<int>& rows)
{
    const size_t nx = bank.nodeCols.size();
    for (int j : rows)
        for (size_t i = 1; i < nx; i++)
        {
            bank.kernels[size_t(j) * nx + i] = bank.kernels[size_t(j) * nx];
            bank.shifts[size_t(j) * nx + i] = bank.shifts[size_t(j) * nx];
        }
    return bank;
}

/* A bank with row bands among its tile rows: the rows one kernel wide are gathered once across the
   frame, the others per node column, and the result is the general operator's (both directions,
   every instruction set, both boundaries, an odd height), in bfloat16 the float one's, and fed by
   pairs the plane's. Shifts of 6 px leave latent rows that only row bands' frame rows read; of
   41 px, the tile rows' reach covers more of them; tile rows moved 45 px along the frame at its top
   and bottom read only outside it without padding. */
TEST(DeconvOperator, RowBandsOfATileBankAreGatheredOnce)
{
    PsfBank outside = withRowBands(unevenTaps(tileBank(Size(151, 111), 5, 6, 6), 6), {1, 2, 3});
    for (size_t i = 0; i < 5; i++)
        outside.shifts[i] = outside.shifts[25 + i] = Point(0, 45);
    const std::pair<const char*, PsfBank> banks[] = {
        {"shifts up to 6 px", withRowBands(unevenTaps(tileBank(Size(151, 111), 5, 6, 6), 6), {0, 1, 2, 5})},
        {"shifts up to 41 px", withRowBands(unevenTaps(tileBank(Size(151, 111), 5, 6, 41), 6), {0, 1, 2, 5})},
        {"tile rows reading outside", outside}};
    for (const auto& [name, bank] : banks)
    {
        for (bool pad : {true, false})
        {
            SCOPED_TRACE(cv::format("%s, %s", name, pad ? "pad" : "zero"));
            cv::dynblur::detail::TileBankOperator exact(bank, pad), packed(bank, pad, true), pairFed(bank, pad, true);
            for (const cv::dynblur::detail::TileBankOperator* op : {&exact, &packed})
            {
                EXPECT_GT(op->rowShare(false), 0.2);
                EXPECT_LT(op->rowShare(false), 0.8);
                EXPECT_GT(op->rowShare(true), 0.0);  // the tile rows' reach covers most latent rows in the third bank
                EXPECT_LT(op->rowShare(true), 0.8);
            }
            for (cv::dynblur::kernels::KernelIsa isa : cv::dynblur::kernels::availableKernelIsas())
            {
                SCOPED_TRACE(cv::dynblur::kernels::kernelIsaName(isa));
                cv::dynblur::kernels::forceKernelIsa(isa);
                expectAdjoint(exact, pad);
                expectSameAsGeneral(exact, bank, pad);
            }
            cv::dynblur::kernels::forceKernelIsa(cv::dynblur::kernels::KERNELS_ISA_COUNT);
            expectPackedAgrees(packed, exact, 1e-4, "row bands");

            Mat y(packed.frameSize(), CV_32F), packedFrame, viaPlane, viaPairs;
            RNG(12).fill(y, RNG::UNIFORM, 0.1, 1);
            cv::dynblur::detail::packPlane(y, packedFrame);
            const Range rows(0, packed.latentSize().height);
            viaPlane.create(packed.latentSize(), CV_32F);
            viaPairs.create(packed.latentSize(), CV_32F);
            packed.prepareAdjointPacked(packedFrame);
            packed.adjointPackedBlock(packedFrame, rows, viaPlane.ptr<float>(), viaPlane.step1());
            for (int k = 0; k < packedFrame.rows; k++)
                pairFed.takePackedPair(k, packedFrame.ptr<uint32_t>(k));
            pairFed.adjointPackedBlock(Mat(), rows, viaPairs.ptr<float>(), viaPairs.step1());
            EXPECT_EQ(norm(viaPlane, viaPairs, NORM_INF), 0.0);
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


}  // namespace
