// SPDX-License-Identifier: Apache-2.0
// Restoration bounds (docs/reliability.md): richardsonLucy, richardsonLucyVariant, wienerDeconvolve and
// DynamicDeblurrer::deblur on adversarial but valid inputs (zeros, constant, a single bright pixel,
// saturated, checkerboards, noise, values ~1e-30 and ~1e30, 1-row / 1-column / 1x1 images; delta,
// long, 2-D and two-tap kernels, kernels longer than the image, tile banks with shifts as large as
// the frame) never return NaN/Inf and stay within the input's range up to a stated margin.
//
// The margins, with M = max(input) (inputs are non-negative, as light is):
//   Richardson–Lucy (uniform and variant):
//       0 ≤ out ≤ M · G · (1 + 1e-2)
//     The update is multiplicative, so nothing goes negative. G is the bank's spot gain: a point of
//     brightness v blurs to a peak of v·max(k), and restoring it gives v back, so a restoration may
//     legitimately exceed the blurred maximum by G = 1 / max(k) (the largest over the kernels); a bank
//     whose nodes displace by different shifts may show a point as one ghost per node, so there
//     G = N_nodes / min max(k). For plain RL with the zero boundary the bound is a theorem:
//     x_j ← x_j Σ_u k(u) b_{j+u} / (k⊛x)_{j+u} ≤ Σ_{k(u)>0} b_{j+u} since (k⊛x)_{j+u} ≥ k(u) x_j.
//     plain RL (no acceleration, no damping);  0 ≤ out ≤ 2 · M · G  accelerated or damped (an
//     unprojected extrapolation may overshoot; the projected RL keeps the estimate within G · M).
//   Wiener: min(input) − m·M ≤ out ≤ max(input) + m·M with m = 1.5 / (2 sqrt(noiseToSignal)): 1.5
//     times the filter's largest gain max |K| / (|K|² + nsr) (a linear filter rings on both sides of
//     an edge; its gain on a pixel can exceed its largest frequency gain: measured worst 1.1 times).
//   DynamicDeblurrer: it clamps its result to [0, 1] (CV_32F) or encodes 8 bits, so saturation holds
//     by construction; checked: finite, within [0, 1], same type, on every window and PSF model.
// The [ measured ] lines give the worst case of each against its bound.
// Scale: restoring c·b should give c·restore(b) (RL and Wiener are homogeneous), c = 1e-30, 1e30.
#include "test_common.hpp"

#include "frame_timing.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

using namespace cv;
using namespace cv::dynblur;

namespace {

struct Case
{
    std::string name;
    Mat image;  // CV_32FC1
};

Mat checkerboard(Size size, int cell)
{
    Mat m(size, CV_32F);
    for (int y = 0; y < size.height; ++y)
        for (int x = 0; x < size.width; ++x)
            m.at<float>(y, x) = ((x / cell + y / cell) % 2) ? 1.f : 0.f;
    return m;
}

// Adversarial but valid images (finite, non-negative, linear intensity) of one size.
std::vector<Case> images(Size size, bool withExtremeScales)
{
    std::vector<Case> out;
    RNG rng(0x9u + (uint64)size.area());
    Mat noise(size, CV_32F);
    rng.fill(noise, RNG::UNIFORM, 0.0, 1.0);
    Mat spot = Mat::zeros(size, CV_32F);
    spot.at<float>(size.height / 2, size.width / 2) = 1.f;
    out.push_back({"zeros", Mat::zeros(size, CV_32F)});
    out.push_back({"constant 0.5", Mat(size, CV_32F, Scalar(0.5))});
    out.push_back({"single bright pixel", spot});
    out.push_back({"saturated (all 1)", Mat(size, CV_32F, Scalar(1.0))});
    Mat clipped = noise * 2.0;
    cv::min(clipped, 1.0, clipped);
    out.push_back({"half saturated noise", clipped});
    out.push_back({"checkerboard 1 px", checkerboard(size, 1)});
    out.push_back({"checkerboard 4 px", checkerboard(size, 4)});
    out.push_back({"uniform noise", noise});
    if (withExtremeScales)
    {
        out.push_back({"tiny noise ~1e-30", noise * 1e-30});
        out.push_back({"tiny spot 1e-30", spot * 1e-30});
        out.push_back({"huge noise ~1e30", noise * 1e30});
        out.push_back({"huge spot 1e30", spot * 1e30});
        out.push_back({"denormal 1e-40", Mat(size, CV_32F, Scalar(1e-40))});
    }
    return out;
}

struct Kernel
{
    std::string name;
    Mat k;
};

std::vector<Kernel> kernels()
{
    std::vector<Kernel> out;
    out.push_back({"delta", Mat::ones(1, 1, CV_32F)});
    out.push_back({"box 1x31", Mat::ones(1, 31, CV_32F) / 31.0});
    out.push_back({"box 31x1", Mat::ones(31, 1, CV_32F) / 31.0});
    Mat g = getGaussianKernel(9, 2.0, CV_32F);
    out.push_back({"gaussian 9x9", g * g.t()});
    Mat line = Mat::zeros(15, 15, CV_32F);
    for (int i = 0; i < 15; ++i)
        line.at<float>(i, i) = 1.f / 15;
    out.push_back({"diagonal 15x15", line});
    out.push_back({"box 1x201 (longer than the image)", Mat::ones(1, 201, CV_32F) / 201.0});
    Mat ends = Mat::zeros(1, 61, CV_32F);  // two taps far apart: a ghost, the hardest to invert
    ends.at<float>(0, 0) = 0.5f;
    ends.at<float>(0, 60) = 0.5f;
    out.push_back({"two taps 60 px apart", ends});
    return out;
}

PsfBank uniformBank(Size size, const Mat& k, Point shift = Point())
{
    PsfBank b;
    b.model = PSF_UNIFORM;
    b.imageSize = size;
    b.nodeRows = {(size.height - 1) / 2.0};
    b.nodeCols = {(size.width - 1) / 2.0};
    b.kernels = {k.clone()};
    b.shifts = {shift};
    return b;
}

// A 2x2 tile bank mixing the kernels, with shifts up to `reach` pixels (content moved by as much as
// the frame is wide: "shifts at the limit").
PsfBank tileBank(Size size, const std::vector<Kernel>& ks, int reach)
{
    PsfBank b;
    b.model = PSF_TILES;
    b.imageSize = size;
    b.nodeRows = {0.0, std::max(1.0, size.height - 1.0)};
    b.nodeCols = {0.0, std::max(1.0, size.width - 1.0)};
    for (int n = 0; n < 4; ++n)
    {
        b.kernels.push_back(ks[(size_t)(n + 1) % ks.size()].k.clone());
        b.shifts.push_back(Point(n % 2 ? reach : -reach / 2, n / 2 ? reach / 3 : 0));
    }
    return b;
}

// Every kernel as a one-node bank, a delta displaced by the frame width, and 2x2 tile banks with
// shifts up to the frame width and to three times it.
std::vector<std::pair<std::string, PsfBank>> banks(Size size)
{
    const std::vector<Kernel> ks = kernels();
    std::vector<std::pair<std::string, PsfBank>> out;
    for (const Kernel& k : ks)
        out.push_back({k.name, uniformBank(size, k.k)});
    out.push_back({"delta shifted by the frame width", uniformBank(size, ks[0].k, Point(size.width, 0))});
    out.push_back({"2x2 tiles, shifts to the frame width", tileBank(size, ks, size.width)});
    out.push_back({"2x2 tiles, shifts to 3x the frame width", tileBank(size, ks, 3 * size.width + 2)});
    return out;
}

// Spot gain of a bank: a point of brightness v blurs to a peak of at least v·max(k) through one
// kernel; through a bank whose nodes displace by different shifts it may be seen as one ghost per
// node, each with a share of its light, so up to N·max over the kernels of 1 / max(k).
double spotGain(const PsfBank& bank)
{
    double g = 1;
    for (const Mat& k : bank.kernels)
    {
        double mx = 0;
        minMaxLoc(k, nullptr, &mx);
        g = std::max(g, 1.0 / mx);
    }
    for (const Point& s : bank.shifts)
        if (s != bank.shifts[0])
            return g * (double)bank.kernels.size();
    return g;
}

double maxOf(const Mat& m)
{
    double mx = 0;
    minMaxLoc(m.reshape(1), nullptr, &mx);
    return mx;
}

double minOf(const Mat& m)
{
    double mn = 0;
    minMaxLoc(m.reshape(1), &mn);
    return mn;
}

// Cases run, how much of each bound the worst case used, and the cases out of bounds.
struct Tally
{
    Tally(const char* m, const char* reference) : method(m), referenceName(reference) {}
    const char* method;
    const char* referenceName;
    double worstRatio = 0;  // max(out) / reference (the bound is reference · factor)
    double worstAbove = 0;  // (max(out) − max(in)) / (hi − max(in)): share of the upper margin used
    double worstBelow = 0;  // (min(in) − min(out)) / (min(in) − lo): share of the lower margin used
    std::string worstRatioCase, worstAboveCase, worstBelowCase;
    int cases = 0, nonFinite = 0, outOfBounds = 0, threw = 0, lightLost = 0;
    std::vector<std::string> failures, lightLostExamples;

    // Judges one output against [lo, hi]; `ratio` = max(out) / reference, reported.
    void judge(const std::string& what, const Mat& in, const Mat& out, double lo, double hi, double reference)
    {
        ++cases;
        if (out.empty() || out.size() != in.size() || out.type() != in.type())
        {
            ++outOfBounds;
            failures.push_back(what + ": output of the wrong size or type");
            return;
        }
        if (!checkRange(out, true))
        {
            ++nonFinite;
            failures.push_back(what + ": NaN or Inf in the output");
            return;
        }
        const double outMax = maxOf(out), outMin = minOf(out);
        if (maxOf(in) >= 1e-20 && outMax <= 0)
        {
            // Within the bounds, but black: the light of a non-zero frame is gone. Reported, not a
            // bound (multiplicative RL started from the frame keeps the frame's support: a lone bright
            // pixel whose kernel has no centre tap has nothing to grow from). Tinier frames: see
            // ScaleEquivariance.
            if (lightLostExamples.size() < 6)
                lightLostExamples.push_back(what);
            ++lightLost;
        }
        const double ratio = reference > 0 ? outMax / reference : 0;
        if (ratio > worstRatio)
        {
            worstRatio = ratio;
            worstRatioCase = what;
        }
        const double inMax = maxOf(in), inMin = minOf(in);
        const double above = hi > inMax ? (outMax - inMax) / (hi - inMax) : 0;
        const double below = inMin > lo ? (inMin - outMin) / (inMin - lo) : 0;
        if (above > worstAbove)
        {
            worstAbove = above;
            worstAboveCase = what;
        }
        if (below > worstBelow)
        {
            worstBelow = below;
            worstBelowCase = what;
        }
        if (outMax > hi || outMin < lo)
        {
            ++outOfBounds;
            failures.push_back(cv::format("%s: input [%g, %g], output [%g, %g], allowed [%g, %g]", what.c_str(),
                                          minOf(in), maxOf(in), outMin, outMax, lo, hi));
        }
    }

    void threwOn(const std::string& what, const cv::Exception& e)
    {
        ++cases;
        ++threw;
        failures.push_back(what + ": threw " + e.err);
    }

    void print(const char* boundText) const
    {
        std::printf("[ measured ] %s: %d cases, bound %s; worst max(out) = %.4g x %s (%s); share of the upper margin "
                    "used %.3g (%s), of the lower %.3g (%s); non-finite %d, out of bounds %d, threw %d\n",
                    method, cases, boundText, worstRatio, referenceName, worstRatioCase.c_str(), worstAbove,
                    worstAboveCase.c_str(), worstBelow, worstBelowCase.c_str(), nonFinite, outOfBounds, threw);
        for (size_t i = 0; i < failures.size() && i < 12; ++i)
            std::printf("    %s\n", failures[i].c_str());
        if (lightLost > 0)
        {
            std::printf("[ measured ] %s: %d cases come back all zero from a non-zero input, e.g.\n", method, lightLost);
            for (const std::string& w : lightLostExamples)
                std::printf("    %s\n", w.c_str());
        }
    }

    void expectClean() const
    {
        EXPECT_EQ(nonFinite, 0) << method;
        EXPECT_EQ(outOfBounds, 0) << method;
        EXPECT_EQ(threw, 0) << method;
    }
};

const double kRlSlack = 1e-2;        // plain RL: relative, on M·G (float rounding)
const double kRlAcceleratedFactor = 2;  // accelerated or damped RL: the extrapolation may overshoot
const double kDirectTolerance = 1e-3;   // plain RL vs the direct loop, relative to M·G (float against double)
double wienerMargin(double nsr) { return 1.5 / (2.0 * std::sqrt(nsr)); }

// RL's bound for one case: [0, M·G·(1 + slack)] for plain RL, [0, 2·M·G] when accelerated or
// damped (plus float rounding of a zero image).
void judgeRl(Tally& t, const std::string& what, const Mat& in, const Mat& out, double gain, const RLParams& p)
{
    const double M = maxOf(in);
    const bool plain = !p.accelerate && p.damping == 0;
    t.judge(what, in, out, -1e-6 * M, M * gain * (plain ? 1 + kRlSlack : kRlAcceleratedFactor) + 1e-37, M * gain);
}

const std::vector<Size> kSizes = {Size(64, 48), Size(64, 1), Size(1, 48), Size(1, 1), Size(3, 2)};

std::vector<std::pair<std::string, RLParams>> rlVariants()
{
    std::vector<std::pair<std::string, RLParams>> out;
    out.push_back({"default", RLParams()});
    RLParams z;
    z.boundary = RL_BOUNDARY_ZERO;
    z.accelerate = false;
    z.tvWeight = 0;
    z.iterations = 30;
    out.push_back({"zero boundary, plain", z});
    RLParams a;
    a.damping = std::numeric_limits<double>::quiet_NaN();
    out.push_back({"auto damping", a});
    return out;
}

std::string caseName(const Case& c, const Size& size, const std::string& kernel, const std::string& params)
{
    return c.name + cv::format(" %dx%d, ", size.width, size.height) + kernel + ", " + params;
}

/* Textbook Richardson–Lucy with the zero boundary, in double precision, as a plain loop:
   x ← x ⊙ Kᵀ(b / Kx), K the "same" convolution with zero outside the image, from x = b. Where
   (Kx)_i = 0 the ratio is taken as 0: every latent pixel that reaches frame pixel i is then 0, and
   Kᵀ carries the ratio to those pixels only, so any value gives the same x. */
Mat directRichardsonLucy(const Mat& blurred, const Mat& kernel, int iterations)
{
    struct Tap
    {
        int dy, dx;
        double w;
    };
    const double total = sum(kernel)[0];
    const int cy = (kernel.rows - 1) / 2, cx = (kernel.cols - 1) / 2;
    std::vector<Tap> taps;
    for (int v = 0; v < kernel.rows; ++v)
        for (int u = 0; u < kernel.cols; ++u)
            if (kernel.at<float>(v, u) != 0.f)
                taps.push_back({v - cy, u - cx, kernel.at<float>(v, u) / total});
    Mat b, x, kx(blurred.size(), CV_64F), ratio(blurred.size(), CV_64F);
    blurred.convertTo(b, CV_64F);
    x = b.clone();
    const int h = b.rows, w = b.cols;
    for (int it = 0; it < iterations; ++it)
    {
        for (int y = 0; y < h; ++y)
            for (int c = 0; c < w; ++c)
            {
                double acc = 0;  // (Kx)(y, c) = Σ k(v, u) x(y − v, c − u)
                for (const Tap& t : taps)
                {
                    const int sy = y - t.dy, sx = c - t.dx;
                    if (sy >= 0 && sy < h && sx >= 0 && sx < w)
                        acc += t.w * x.at<double>(sy, sx);
                }
                kx.at<double>(y, c) = acc;
                ratio.at<double>(y, c) = acc > 0 ? b.at<double>(y, c) / acc : 0.0;
            }
        for (int y = 0; y < h; ++y)
            for (int c = 0; c < w; ++c)
            {
                double acc = 0;  // (Kᵀr)(y, c) = Σ k(v, u) r(y + v, c + u)
                for (const Tap& t : taps)
                {
                    const int sy = y + t.dy, sx = c + t.dx;
                    if (sy >= 0 && sy < h && sx >= 0 && sx < w)
                        acc += t.w * ratio.at<double>(sy, sx);
                }
                x.at<double>(y, c) *= acc;
            }
    }
    Mat out;
    x.convertTo(out, CV_32F);
    return out;
}

}  // namespace

TEST(RestorationBounds, RichardsonLucyUniform)
{
    Tally t("richardsonLucy", "M*G");
    for (const Size& size : kSizes)
        for (const Case& c : images(size, true))
            for (const Kernel& k : kernels())
                for (const auto& p : rlVariants())
                {
                    if (p.first == "auto damping" && size.area() > 1 && size.area() < 64 * 48)
                        continue;  // damping on thin images: the 64x48 and 1x1 cases suffice
                    const std::string what = caseName(c, size, k.name, p.first);
                    Mat out;
                    try
                    {
                        richardsonLucy(c.image, k.k, out, p.second);
                    }
                    catch (const cv::Exception& e)
                    {
                        t.threwOn(what, e);
                        continue;
                    }
                    judgeRl(t, what, c.image, out, spotGain(uniformBank(size, k.k)), p.second);
                }
    t.print("[0, M*G*(1+1e-2)] plain, [0, 2*M*G] accelerated or damped");
    t.expectClean();
}

/* Plain RL (zero boundary, no acceleration, no TV) is bounded by Σ of the taps' data: for a two-tap
   kernel out ≤ 2·max(input). On a 64x1 checkerboard with 4 px cells and taps 60 px apart the data is
   no blur of any image (the two taps see cells of opposite phase), so RL keeps the cells that one tap
   explains and drops the others: textbook RL returns half the lit pixels at exactly 1. The FFT's
   rounding of A x where it is zero once made this 11.3·max(input), later all black; both are
   measured here against the direct loop. */
TEST(RestorationBounds, RichardsonLucyZeroBoundaryTwoTaps)
{
    const Kernel k = kernels()[6];
    ASSERT_EQ(k.name, "two taps 60 px apart");
    const Mat in = checkerboard(Size(64, 1), 4);
    RLParams p = rlVariants()[1].second;
    Mat out;
    richardsonLucy(in, k.k, out, p);
    ASSERT_TRUE(checkRange(out, true));
    const Mat direct = directRichardsonLucy(in, k.k, p.iterations);
    const double ratio = maxOf(out) / (maxOf(in) * spotGain(uniformBank(in.size(), k.k)));
    const double error = norm(out, direct, NORM_INF) / maxOf(in);
    std::printf("[ measured ] plain RL, zero boundary, two taps 60 px apart, 64x1 checkerboard (4 px): max(out) = "
                "%.3f x max(input) (direct RL %.3f), bound %.0f; max |out - direct| = %.2g x max(input) (allowed "
                "1e-4); lit pixels %d (direct %d)\n",
                maxOf(out) / maxOf(in), maxOf(direct) / maxOf(in), spotGain(uniformBank(in.size(), k.k)), error,
                countNonZero(out > 0.5f), countNonZero(direct > 0.5f));
    EXPECT_LE(ratio, 1 + kRlSlack);
    EXPECT_LE(error, 1e-4);
    EXPECT_GT(countNonZero(direct > 0.5f), 0) << "the reference itself comes back black: the case proves nothing";
    EXPECT_EQ(countNonZero(out > 0.5f), countNonZero(direct > 0.5f));
}

/* The library's plain zero-boundary RL against the direct loop on the adversarial images and every
   kernel: thin and tiny images in full, and on 64x48 the images whose support has holes (where the
   FFT's rounding of a zero A x mattered). The error is relative to M·G, RL's bound. */
TEST(RestorationBounds, RichardsonLucyZeroBoundaryMatchesDirectLoop)
{
    RLParams p = rlVariants()[1].second;
    p.iterations = 10;
    double worst = 0;
    std::string worstCase;
    int compared = 0;
    for (const Size& size : kSizes)
        for (const Case& c : images(size, false))
        {
            if (size == Size(64, 48) && c.name != "checkerboard 1 px" && c.name != "checkerboard 4 px" &&
                c.name != "single bright pixel" && c.name != "half saturated noise")
                continue;  // the direct loop is slow; these have the zeros that matter
            if (maxOf(c.image) <= 0)
                continue;
            for (const Kernel& k : kernels())
            {
                Mat out;
                richardsonLucy(c.image, k.k, out, p);
                const Mat direct = directRichardsonLucy(c.image, k.k, p.iterations);
                const double scale = maxOf(c.image) * spotGain(uniformBank(size, k.k));
                const double error = norm(out, direct, NORM_INF) / scale;
                ++compared;
                if (error > worst)
                {
                    worst = error;
                    worstCase = caseName(c, size, k.name, "zero boundary, plain, 10 iterations");
                }
                EXPECT_LE(error, kDirectTolerance) << caseName(c, size, k.name, "zero boundary, plain");
            }
        }
    std::printf("[ measured ] plain zero-boundary RL vs the direct loop: %d cases, worst |out - direct| = %.2g x M*G "
                "(%s), allowed %.0g\n",
                compared, worst, worstCase.c_str(), kDirectTolerance);
    EXPECT_GE(compared, 100);
}

TEST(RestorationBounds, RichardsonLucyVariant)
{
    Tally t("richardsonLucyVariant", "M*G");
    for (const Size& size : kSizes)
        for (const Case& c : images(size, true))
        {
            for (const auto& b : banks(size))
                for (const auto& p : rlVariants())
                {
                    if (p.first == "zero boundary, plain" && b.first != "delta")
                        continue;  // the variant operator pads; one zero-boundary case is enough
                    const std::string what = caseName(c, size, b.first, p.first);
                    Mat out, mask;
                    try
                    {
                        richardsonLucyVariant(c.image, b.second, out, p.second, mask);
                    }
                    catch (const cv::Exception& e)
                    {
                        t.threwOn(what, e);
                        continue;
                    }
                    judgeRl(t, what, c.image, out, spotGain(b.second), p.second);
                }
        }
    t.print("[0, M*G*(1+1e-2)] plain, [0, 2*M*G] accelerated or damped");
    t.expectClean();
}

TEST(RestorationBounds, Wiener)
{
    Tally t("wienerDeconvolve", "M");
    for (const Size& size : kSizes)
        for (const Case& c : images(size, true))
        {
            for (const auto& b : banks(size))
                for (double nsr : {1e-2, 1e-4})
                {
                    const std::string what = caseName(c, size, b.first, cv::format("nsr %g", nsr));
                    Mat out;
                    try
                    {
                        wienerDeconvolve(c.image, b.second, out, nsr);
                    }
                    catch (const cv::Exception& e)
                    {
                        t.threwOn(what, e);
                        continue;
                    }
                    // The filter's largest gain, max |K| / (|K|² + nsr) ≤ 1 / (2·sqrt(nsr)), as the margin.
                    const double M = maxOf(c.image), margin = wienerMargin(nsr);
                    t.judge(what, c.image, out, minOf(c.image) - margin * M, M * (1 + margin) + 1e-37, M);
                }
        }
    t.print("[min - m*M, max + m*M], m = 1.5/(2 sqrt(nsr))");
    t.expectClean();
}

namespace {

// Whether restore(c·b) = c·restore(b) within 1e-3 of the output's scale.
template <class F>
void checkScale(Tally& t, const std::string& what, const Mat& in, double c, F restore)
{
    Mat ref, scaled;
    restore(in, ref);
    restore(in * c, scaled);
    ++t.cases;
    const double refMax = std::max(maxOf(ref), std::abs(minOf(ref)));
    if (!checkRange(scaled, true))
    {
        ++t.nonFinite;
        t.failures.push_back(what + cv::format(" x %g: NaN or Inf", c));
        return;
    }
    const double err = norm(scaled / c, ref, NORM_INF) / std::max(refMax, 1e-30);
    if (err > 1e-3)
    {
        ++t.outOfBounds;
        t.failures.push_back(cv::format("%s x %g: relative error %.3g (max |out/c| %g, expected %g)", what.c_str(), c,
                                        err, std::max(maxOf(scaled), std::abs(minOf(scaled))) / c, refMax));
    }
}

}  // namespace

// RL and Wiener are homogeneous: scaling the frame scales the result. Checked for c = 2^-100 and
// 2^100 (about 1e-30 and 1e30) on noise, a spot and a checkerboard, with the kernels above. Powers of
// two scale a float exactly: with 1e-30 the frame itself is rounded (relative 6e-8), and the
// accelerated RL of an ill-conditioned kernel (two taps 60 px apart) amplifies that to 0.1 after
// 20 iterations, which says nothing about the restoration's scaling.
TEST(RestorationBounds, ScaleEquivariance)
{
    Tally rl("richardsonLucy scale", "-"), variant("richardsonLucyVariant scale", "-"), wiener("wienerDeconvolve scale", "-");
    const Size size(64, 48);
    std::vector<Case> base;
    for (const Case& c : images(size, false))
        if (c.name == "uniform noise" || c.name == "single bright pixel" || c.name == "checkerboard 4 px")
            base.push_back(c);
    for (const Case& c : base)
        for (const Kernel& k : kernels())
            for (double scale : {std::ldexp(1.0, -100), std::ldexp(1.0, 100)})
            {
                const std::string what = c.name + ", " + k.name;
                checkScale(rl, what, c.image, scale, [&](const Mat& in, Mat& out) { richardsonLucy(in, k.k, out); });
                const PsfBank bank = uniformBank(size, k.k);
                checkScale(variant, what, c.image, scale,
                           [&](const Mat& in, Mat& out) { richardsonLucyVariant(in, bank, out); });
                checkScale(wiener, what, c.image, scale, [&](const Mat& in, Mat& out) { wienerDeconvolve(in, bank, out); });
            }
    rl.print("relative error <= 1e-3");
    variant.print("relative error <= 1e-3");
    wiener.print("relative error <= 1e-3");
    EXPECT_EQ(wiener.nonFinite + wiener.outOfBounds, 0);
    EXPECT_EQ(rl.nonFinite + rl.outOfBounds, 0);
    EXPECT_EQ(variant.nonFinite + variant.outOfBounds, 0);
}

// The whole pipeline on a small rolling-shutter camera, frames in every window, all PSF models and
// both methods, float (1 channel) and 8-bit (3 channels).
TEST(RestorationBounds, DynamicDeblurrer)
{
    const Size size(64, 48);
    Ptr<Plant> plant = Plant::create(14.4, 0.12, CV_PI / 180);
    Ptr<CameraModel> camera = CameraModel::create(120.0, 120.0, 31.5, 23.5, size.width, size.height);
    // The robust move settles in 45 ms: longer than a 20 ms readout, so window II exists.
    const SwitchSchedule move = SwitchPlanner::create(plant, 16, PLAN_ROBUST)->plan(0.0, 10 * CV_PI / 180, 0.0);
    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(plant, camera);
    Tally t("DynamicDeblurrer::deblur", "1");
    int windowsSeen[5] = {};
    for (int window = EXPOSURE_I; window <= EXPOSURE_IV; ++window)
    {
        RollingShutter shutter(0.0, 0.008, 0.020 / size.height, size.height);
        ASSERT_TRUE(dynblur_samples::frameStartInWindow(plant, move, shutter, window, shutter.frameStart)) << window;
        for (int model : {PSF_UNIFORM, PSF_ROWS, PSF_TILES})
            for (int method : {DEBLUR_RICHARDSON_LUCY, DEBLUR_WIENER})
            {
                deblurrer->setPsfModel(model);
                deblurrer->setMethod(method);
                for (const Case& c : images(size, false))
                    for (int variant = 0; variant < 2; ++variant)
                    {
                        if (c.name == "constant 0.5" || c.name == "checkerboard 4 px" || c.name == "half saturated noise")
                            continue;  // the uniform tests cover these; the pipeline is slower
                        Mat frame;
                        std::string what = c.name + cv::format(", window %d, model %d, method %d", window, model, method);
                        if (variant == 0)
                            frame = c.image;
                        else
                        {
                            Mat color;
                            merge(std::vector<Mat>{c.image, c.image * 0.5, c.image * 0.25}, color);
                            color.convertTo(frame, CV_8U, 255.0);
                            what += ", 8-bit, 3 channels";
                        }
                        Mat out, mask;
                        try
                        {
                            deblurrer->deblur(frame, move, shutter, out, std::numeric_limits<double>::quiet_NaN(), mask);
                        }
                        catch (const cv::Exception& e)
                        {
                            t.threwOn(what, e);
                            continue;
                        }
                        ++windowsSeen[deblurrer->getLastExposureWindow()];
                        if (frame.depth() == CV_8U)
                        {
                            t.judge(what, frame, out, 0, 255, 255);
                            continue;
                        }
                        t.judge(what, frame, out, 0.0, 1.0, 1.0);
                        if (window == EXPOSURE_IV)
                        {
                            EXPECT_EQ(norm(out, frame, NORM_INF), 0.0) << what;
                        }
                    }
            }
    }
    t.print("[0, 1] (8-bit: [0, 255])");
    t.expectClean();
    for (int w = EXPOSURE_I; w <= EXPOSURE_IV; ++w)
        EXPECT_GT(windowsSeen[w], 0) << "window " << w;
}
