#include "restore/deconv_rl.hpp"
#include "restore/simd_clones.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace cv {
namespace dynblur {
namespace detail {

namespace {

// scikit-image adds this to the reblurred image before dividing; kept so ZERO-boundary results match.
constexpr float kRatioEpsilon = 1e-12f;

//! Rows blurred at a time by a row-gathering operator, then consumed row by row while in L2 (even: see bandRange).
constexpr int kBlockRows = 8;

/* ratio = b / (A x) over one row, damped as MATLAB's deconvlucy does (White 1994): where the
   Poisson deviance between b and A x is within the damping threshold, the ratio is pulled to 1
   (no update). The deviance is halfPoissonDeviance's log-free form: the exact one's log made this
   loop 58 instructions per 16 pixels, and the frame-rate frame took 0.90–0.93 of the time without
   it (DeblurQuality's figures moved by at most 0.01 dB). Intensities are taken times `scale`
   (1 / the image's level), so the epsilon and the deviance mean the same at any exposure and
   nothing under- or overflows. `invThreshold` is 2 / (damping² · scale). Branch-free, so it
   vectorises. */
DYNBLUR_SIMD_CLONES
void ratioRow(const float* __restrict b, const float* __restrict ab, float* __restrict r, int n, float scale,
              float invThreshold)
{
    if (invThreshold == 0.f)
    {
        for (int x = 0; x < n; x++)
            r[x] = ab[x] > 0.f ? b[x] * scale / (ab[x] * scale + kRatioEpsilon) : 0.f;
        return;
    }
    for (int x = 0; x < n; x++)
    {
        /* Every value is computed and then selected: a conditional division keeps the loop
           scalar. A x ≥ 0, so the quotient and the deviance are finite. */
        const float bs = b[x] * scale, abs = ab[x] * scale;
        const float quotient = bs / (abs + kRatioEpsilon);
        const bool both = (b[x] > 0.f) & (ab[x] > 0.f);
        float g = halfPoissonDeviance(bs, abs) * invThreshold;
        g = std::min(std::max(g, 0.f), 1.f);
        const float g2 = g * g, g4 = g2 * g2, g8 = g4 * g4;
        const float G = g8 * g * (10.f - 9.f * g);  // g^9 (10 − 9 g): 0 within the noise, 1 beyond
        r[x] = both ? 1.f + G * (quotient - 1.f) : ab[x] > 0.f ? quotient : 0.f;
    }
}

//! Sums an update accumulates over a band of rows, added up afterwards in band order.
struct UpdateSums
{
    double stepDot = 0, stepBeforeSq = 0, changeSq = 0, sizeSq = 0;
};

/* TV's terms for the update of one row of y. The curvature div(∇y/|∇y|) is nx[x] − nx[x−1] +
   ny[x] − nyAbove[x], with the unit gradient n = ∇y/|∇y| by forward differences (zero across the
   last column and below the last row) and the divergence by backward ones (the pair that makes
   −div the adjoint of ∇; nx[−1] and the first row's nyAbove are 0: zero flux across the edges).
   |∇y| is taken on y · scale, so the squares neither under- nor overflow, and regularised by eps2. */
struct RowTv
{
    const float* below;    //!< the next row of y; null on the last row
    const float* nyAbove;  //!< the row above's ny; null when only ny is computed (see updateRow)
    float* ny;             //!< where the row's own ny goes, for the row below
    float scale, eps2;
};

/* x_{k+1} = y ⊙ correction / (norm − λ curvature) over one row, kept within [0, upper]; with
   `correctionExcess`, `correction` holds correction − norm. With `norm` null the normaliser is
   `rowNorm` all along the row (kRowNorm): a row-wise bank's Aᵀ1 usually is, and not streaming it
   leaves the update's loads in the caches (3 % of a frame). Pixels whose normaliser is
   ≤ kUnobserved keep y. `tv` may be null (no curvature). `out` may be `y` (each element is read
   before it is written); with `out` null, only tv->ny is computed (the row just above a band).
   With `step`, the data term's step g = y ⊙ (correction / norm − 1) meets the last one, stored
   there as bfloat16 (a float's upper half, truncated: it only feeds the extrapolation's two dot
   products, whose ratio a 2^-8 relative error per element hardly moves, and half the bytes is half
   that plane's traffic): Σ g·g_old and Σ g_old² (times scale², which keeps the products from
   under- or overflowing) go to `sums`, and g replaces g_old. The extrapolation follows the data
   term's step only: TV's curvature term flips sign from one iteration to the next on noise, which
   would make successive steps look uncorrelated and switch acceleration off.
   One pass with every term in registers, sixteen lanes in vector types (GCC would vectorise
   neither the float sums nor the bfloat16 conversions well; nx[x − 1] is the lanes' nx shifted by
   one), the last columns through padded copies. kWhole: `tv`, `out` and `step` are all given (the
   accelerated, regularised case), which lets the loop drop its tests of null rows: GCC leaves them
   in, one per block, and they cost 2–3 % of a frame. */
template <bool kWhole, bool kRowNorm>
__attribute__((always_inline)) inline void updateRowTerms(const float* y, const float* __restrict correction,
                                                          bool correctionExcess, const float* __restrict norm,
                                                          float rowNorm, const RowTv* tv, float tvWeight, float upper,
                                                          int n, float* out, uint16_t* __restrict step, float scale,
                                                          UpdateSums& sums)
{
    constexpr int kLanes = 16;
    const bool hasTv = kWhole || tv;
    typedef float v16 __attribute__((vector_size(64), aligned(4)));  // aligned(4): unaligned loads allowed
    typedef int32_t v16i __attribute__((vector_size(64)));
    typedef uint32_t v16u __attribute__((vector_size(64), aligned(4)));
    typedef uint16_t v16h __attribute__((vector_size(32), aligned(2)));
    const v16 zero = {}, ceiling = zero + upper, constantNorm = zero + rowNorm;
    v16 stepDot = {}, stepBeforeSq = {}, nxLeft = {};
    /* Lanes x … x + 15 of every row, from the row or (the last ones) from padded copies; yRight is
       y one column on. Ifs, not ?: between vectors on a scalar condition, which GCC takes lane by
       lane (it made the update twice as slow). */
    const auto lanes = [&](const float* yAt, const float* yRightAt, const float* belowAt, const float* nyAboveAt,
                           float* nyAt, const float* correctionAt, const float* normAt, float* outAt,
                           uint16_t* stepAt) {
        const v16 yv = *(const v16*)yAt;
        v16 curvature = zero;
        if (hasTv)
        {
            // Null yRightAt: the row's last sixteen columns, the last one with no gradient across the edge.
            const v16 yRight = yRightAt ? *(const v16*)yRightAt
                                        : __builtin_shufflevector(yv, yv, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13,
                                                                  14, 15, 15);
            const v16 gx = (yRight - yv) * tv->scale;
            v16 gy = zero;
            if (belowAt)
                gy = (*(const v16*)belowAt - yv) * tv->scale;
            /* 1 / |∇y| to 5e-6 relative (TV needs no more): the exponent-halving first guess and
               two Newton steps, a few multiplies where a square root and a division each take
               longer than the whole. */
            const v16 q = gx * gx + gy * gy + tv->eps2, half = 0.5f * q;
            v16 inv = (v16)(0x5f375a86 - ((v16i)q >> 1));
            inv *= 1.5f - half * inv * inv;
            inv *= 1.5f - half * inv * inv;
            const v16 nx = gx * inv, ny = gy * inv;
            *(v16*)nyAt = ny;
            if (!kWhole && !outAt)
                return;  // the row above a band: its ny is all the walk needs
            curvature = nx - __builtin_shufflevector(nxLeft, nx, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27,
                                                     28, 29, 30) +
                        ny - *(const v16*)nyAboveAt;
            nxLeft = nx;
        }
        const v16 nv = kRowNorm ? constantNorm : *(const v16*)normAt;
        v16 cv = *(const v16*)correctionAt;
        if (correctionExcess)
            cv += nv;
        v16 den = nv;
        if (hasTv)
            den -= tvWeight * curvature;
        const v16 floor = 0.1f * nv;  // keeps a large λ from flipping the sign
        den = den > floor ? den : floor;
        const v16i seen = nv > kUnobserved;
        v16 x = yv * cv / den;
        x = x > zero ? x : zero;
        x = x < ceiling ? x : ceiling;
        *(v16*)outAt = seen ? x : yv;
        if (kWhole || stepAt)
        {
            const v16 g = seen ? yv * (cv / nv - 1.f) : zero;
            const v16 before = (v16)(__builtin_convertvector(*(const v16h*)stepAt, v16u) << 16) * scale;
            const v16 now = g * scale;
            stepDot += now * before;
            stepBeforeSq += before * before;
            *(v16h*)stepAt = __builtin_convertvector((v16u)g >> 16, v16h);
        }
    };
    const auto at = [](auto* row, int x) { return row ? row + x : nullptr; };
    const auto given = [&](auto* row, int x) { return kWhole ? row + x : at(row, x); };  // non-null when kWhole
    int x = 0;
    for (; x + kLanes <= n; x += kLanes)
        lanes(y + x, x + kLanes < n ? y + x + 1 : nullptr, hasTv ? at(tv->below, x) : nullptr,
              hasTv ? given(tv->nyAbove, x) : nullptr, hasTv ? tv->ny + x : nullptr, at(correction, x), at(norm, x),
              given(out, x), given(step, x));

    if (x < n)
    {
        /* The last 1 to 15 columns. Padding: y = 0 and a last step of 0 leave the sums alone, a
           normaliser of 1 the division finite; the last column's yRight is its y (no gradient
           across the edge). */
        const int rest = n - x;
        enum { Y, YRight, Below, NyAbove, Ny, Correction, Norm, Out, Rows };
        float padded[Rows][kLanes] = {};
        uint16_t stepTail[kLanes] = {};
        const auto copy = [&](const float* from, int row) {
            if (from)
                std::copy(from + x, from + n, padded[row]);
        };
        std::fill(padded[Norm], padded[Norm] + kLanes, 1.f);
        copy(y, Y);
        std::copy(y + x + 1, y + n, padded[YRight]);
        padded[YRight][rest - 1] = y[n - 1];
        copy(correction, Correction);
        copy(norm, Norm);
        if (tv)
        {
            copy(tv->below, Below);
            copy(tv->nyAbove, NyAbove);
        }
        if (step)
            std::copy(step + x, step + n, stepTail);
        lanes(padded[Y], padded[YRight], tv && tv->below ? padded[Below] : nullptr, padded[NyAbove], padded[Ny],
              padded[Correction], padded[Norm], out ? padded[Out] : nullptr, step ? stepTail : nullptr);
        if (tv)
            std::copy(padded[Ny], padded[Ny] + rest, tv->ny + x);
        if (out)
            std::copy(padded[Out], padded[Out] + rest, out + x);
        if (step)
            std::copy(stepTail, stepTail + rest, step + x);
    }
    for (int k = 0; k < kLanes; k++)
    {
        sums.stepDot += stepDot[k];
        sums.stepBeforeSq += stepBeforeSq[k];
    }
}

//! updateRowTerms, its loop built for the whole case when every term is given, and for each kind of normaliser.
DYNBLUR_SIMD_CLONES
void updateRow(const float* y, const float* __restrict correction, bool correctionExcess, const float* __restrict norm,
               float rowNorm, const RowTv* tv, float tvWeight, float upper, int n, float* out,
               uint16_t* __restrict step, float scale, UpdateSums& sums)
{
    const bool whole = tv && out && step;
    if (whole && !norm)
        updateRowTerms<true, true>(y, correction, correctionExcess, norm, rowNorm, tv, tvWeight, upper, n, out, step,
                                   scale, sums);
    else if (whole)
        updateRowTerms<true, false>(y, correction, correctionExcess, norm, rowNorm, tv, tvWeight, upper, n, out, step,
                                    scale, sums);
    else if (!norm)
        updateRowTerms<false, true>(y, correction, correctionExcess, norm, rowNorm, tv, tvWeight, upper, n, out, step,
                                    scale, sums);
    else
        updateRowTerms<false, false>(y, correction, correctionExcess, norm, rowNorm, tv, tvWeight, upper, n, out, step,
                                     scale, sums);
}

/* The value of a row whose elements are all equal, NaN otherwise. Blocks of 64 columns compared
   whole (that loop vectorises), so a row that varies early is left early. */
DYNBLUR_SIMD_CLONES
float constantValue(const float* p, int n)
{
    constexpr int kBlock = 64;
    const float first = p[0];
    for (int x0 = 0; x0 < n; x0 += kBlock)
    {
        int differs = 0;
        for (int x = x0; x < std::min(x0 + kBlock, n); x++)
            differs |= p[x] != first;
        if (differs)
            return std::numeric_limits<float>::quiet_NaN();
    }
    return first;
}

/* TV's terms row by row down a band. Each row's ny is computed by its own update and carried to
   the row below, so a row of y is not read after its update: y may be updated in place. The rows
   just outside the band come from copies taken before any band was updated; the row above's ny is
   computed up front. */
class TvWalk
{
public:
    TvWalk(const Mat& y, const Range& rows, float scale, float epsilon, const float* rowAbove, const float* rowBelow)
        : y_(y), end_(rows.end), rowBelow_(rowBelow), buffer_(size_t(y.cols) * 2, 0.f)
    {
        ny_ = buffer_.data();
        nyAbove_ = ny_ + y.cols;
        tv_.scale = scale;
        tv_.eps2 = epsilon * epsilon;
        if (rows.start > 0 && rowAbove)
        {
            RowTv above = tv_;
            above.below = y.ptr<float>(rows.start);
            above.nyAbove = nullptr;  // only ny is computed
            above.ny = nyAbove_;
            UpdateSums unused;
            updateRow(rowAbove, nullptr, false, nullptr, 0.f, &above, 0.f, 0.f, y.cols, nullptr, nullptr, 1.f, unused);
        }
    }

    //! Row r's terms, valid until the next call; call for each row of the band in order.
    const RowTv* next(int r)
    {
        tv_.below = r + 1 >= y_.rows ? nullptr : r + 1 == end_ ? rowBelow_ : y_.ptr<float>(r + 1);
        tv_.nyAbove = nyAbove_;
        tv_.ny = ny_;
        std::swap(ny_, nyAbove_);
        return &tv_;
    }

private:
    const Mat& y_;
    int end_;
    const float* rowBelow_;
    std::vector<float> buffer_;
    float *ny_, *nyAbove_;
    RowTv tv_{};
};

//! y = max(x + a (x − y), 0) over one row: x_{k−1} in, the extrapolated y_k out (RL needs y ≥ 0).
DYNBLUR_SIMD_CLONES
void extrapolateRow(const float* __restrict x, float a, int n, float* __restrict y)
{
    for (int i = 0; i < n; i++)
        y[i] = std::max(x[i] + a * (x[i] - y[i]), 0.f);
}

/* Band b of `bands` fixed bands of [0, rows). Inner bands start on even rows, as blocks of
   kBlockRows then do: a row-gathering operator computes rows 2k and 2k + 1 together. */
Range bandRange(int rows, int bands, int b)
{
    const auto start = [&](int k) { return k >= bands ? rows : int(int64_t(rows) * k / bands) & ~1; };
    return Range(start(b), start(b + 1));
}

//! Runs body(band, rows) over the bands in parallel: partial sums come out the same on every run.
template <typename Body>
void forBands(int rows, int bands, const Body& body)
{
    parallel_for_(Range(0, bands), [&](const Range& r) {
        for (int b = r.start; b < r.end; b++)
            body(b, bandRange(rows, bands, b));
    });
}

//! Σ p[x] (in eight-lane float sums) and max p[x] over a row.
DYNBLUR_SIMD_CLONES
double rowSumAndPeak(const float* p, int n, double& peak)
{
    typedef float v8 __attribute__((vector_size(32), aligned(4)));
    v8 s = {}, m = v8{} - FLT_MAX;
    int x = 0;
    for (; x + 8 <= n; x += 8)
    {
        const v8 v = *(const v8*)(p + x);
        s += v;
        m = v > m ? v : m;
    }
    double total = 0;
    float largest = -FLT_MAX;
    for (int k = 0; k < 8; k++)
    {
        total += s[k];
        largest = std::max(largest, m[k]);
    }
    for (; x < n; x++)
    {
        total += p[x];
        largest = std::max(largest, p[x]);
    }
    peak = largest;
    return total;
}

/* Σ |mask * image| over one row of Immerkær's 3×3 mask, `channels` interleaved: eight float
   lanes, in the form GCC vectorises (a single float sum is a reduction it must keep in order). */
DYNBLUR_SIMD_CLONES
float noiseMaskSumRow(const float* __restrict a, const float* __restrict m, const float* __restrict b, int width,
                      int channels)
{
    const int c = channels, r = 2 * channels;  // centre and right of a pixel, from its left
    auto term = [&](int i) {
        return std::abs(a[i] - 2 * a[i + c] + a[i + r] - 2 * (m[i] - 2 * m[i + c] + m[i + r]) + b[i] - 2 * b[i + c] +
                        b[i + r]);
    };
    float lanes[8] = {};
    int i = 0;
    for (; i + 8 <= width; i += 8)
        for (int k = 0; k < 8; k++)
            lanes[k] += term(i + k);
    for (; i < width; i++)
        lanes[0] += term(i);
    float sum = 0.f;
    for (int k = 0; k < 8; k++)
        sum += lanes[k];
    return sum;
}

//! The level of an image from per-row (or per-row-and-channel) sums and peaks, added in order over `count` values.
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

/* Projected RL: no latent pixel can hold more than spotGain × the brightest frame pixel, and the
   estimate is kept there. On consistent data the bound never binds; on data no blur of a
   non-negative image explains, extrapolation could otherwise pile the light into spikes (10³ × the
   data on a 1-px checkerboard under a 31-px box). */
float projectionBound(const BlurOperator& op, const ImageLevel& level)
{
    return float(std::min(op.spotGain() * std::max(level.peak, 0.0), double(FLT_MAX)));
}

/* Aᵀ1 as the update reads it: its plane (empty: 1 everywhere) and, for each latent row that holds
   one value, that value (NaN where the row varies), found once for both phases of a restoration;
   and the rows no frame pixel sees (every normaliser ≤ kUnobserved). A padded domain's first and
   last rows often are (the bounding box of every kernel's reach, where the kernels near the
   frame's top and bottom reach less): 185 of the frame-rate frame's 1077 latent rows. */
struct RowNormalizer
{
    RowNormalizer(const Mat& normalizer, int rows)
        : plane(normalizer), constant(size_t(rows), 1.f), unseen(size_t(rows), 0)
    {
        if (!plane.empty())
            parallel_for_(Range(0, rows), [&](const Range& range) {
                for (int r = range.start; r < range.end; r++)
                {
                    const float* p = plane.ptr<float>(r);
                    constant[size_t(r)] = constantValue(p, plane.cols);
                    // A seen row is left at its first seen pixel.
                    unseen[size_t(r)] = std::none_of(p, p + plane.cols, [](float v) { return v > kUnobserved; });
                }
            });
    }
    const Mat& plane;
    std::vector<float> constant;
    std::vector<uchar> unseen;
};

/* RL over every plane for params.iterations (colorIterations ignored): `observed` holds the frame's
   planes, `level` is the frame's (ObservedFrame::level). Returns the most iterations a plane ran. */
int iteratePlanes(BlurOperator& op, const std::vector<Mat>& observed, const ImageLevel& level,
                  const RowNormalizer& rowNormalizer, const RLParams& params, std::vector<Mat>& estimate,
                  RLWorkspace& ws)
{
    const Mat& normalizer = rowNormalizer.plane;
    const size_t channels = observed.size();
    CV_Assert(estimate.size() == channels);
    const Size latentSize = op.latentSize(), frameSize = op.frameSize();
    const float tvWeight = float(params.tvWeight);
    const bool fused = op.gathersRows();
    /* A packed operator reads the ratio as ratio − 1 (its deviation from 1 is what a bfloat16 keeps
       to 2^-9 relative), so its adjoint gives Aᵀratio − Aᵀ1, and the update adds Aᵀ1 back. */
    const bool packed = op.gathersPackedRows();
    CV_Assert(!packed || !normalizer.empty());
    // The packed ratio goes to the operator pair by pair, or as ws.packedRatio.
    const bool takesPairs = packed && op.takesPackedPairs();

    const int bands = std::max(1, std::min(latentSize.height, 8 * getNumThreads()));

    /* RL is scale-equivariant, and so is this loop: its element-wise work sees intensities divided
       by the image's level (the ratio's epsilon, the deviance, TV's |∇u| and the step products
       would otherwise under- or overflow far from [0, 1]). TV's |∇u| is regularised at 1e-3 of
       the level. */
    const double mean = level.mean;
    const float scale = mean > 0 && std::isfinite(1.0 / mean) ? float(std::min(1.0 / mean, 1e37)) : 1.f;
    // The deviance is taken on scaled intensities, so its threshold 2 / damping² is divided by the scale.
    const float invThreshold =
        params.damping > 0 ? float(std::min(2.0 / (params.damping * params.damping * scale), 1e37)) : 0.f;
    const float tvEpsilon = 1e-3f;
    const float upper = projectionBound(op, level);

    /* The planes are independent problems and run one after another, each through all its
       iterations with its own extrapolation and stopping test: one plane's working set fits in the
       last-level cache where all three did not. Per plane: the estimate x_k. For the plane running:
       `other[0]` (x_{k−1}, overwritten by the extrapolated y_k and then by x_{k+1} in place) and,
       when accelerating, `step`, the last step g_{k−1} (overwritten by g_k while its dot product
       with g_k is taken). Shared: the ratio and, for operators that cannot gather rows, whole
       reblurred and correction planes. */
    // Never shrunk: a workspace keeps its planes for the next frame.
    ws.other.resize(std::max<size_t>(ws.other.size(), 1));
    Mat& step = ws.step;
    Mat& ratio = ws.ratio;
    Mat& reblurred = ws.reblurred;
    Mat& correction = ws.correction;
    if (!packed)
        ratio.create(frameSize, CV_32FC1);
    std::vector<float> halo(size_t(2 * bands) * size_t(latentSize.width));
    int most = 0;
    for (size_t c = 0; c < channels; c++)
    {
        if (params.accelerate)
        {
            step.create(latentSize, CV_16UC1);  // bfloat16
            step.setTo(0);
        }
        double alpha = 0;
        bool packedReady = false;  // ws.packedEstimate holds the next iteration's y
        UpdateSums previousSums;
        int iteration = 0;
        for (; iteration < params.iterations; iteration++)
        {
            // Biggs–Andrews: extrapolate along the last step, by how well the last two steps agree.
            if (params.accelerate && iteration >= 2)
                alpha = previousSums.stepBeforeSq > 0
                            ? std::min(std::max(previousSums.stepDot / previousSums.stepBeforeSq, 0.0), 1.0)
                            : 0.0;
            std::vector<UpdateSums> sums(static_cast<size_t>(bands));
            const Mat& x = estimate[c];
            Mat& next = ws.other[0];
            next.create(latentSize, CV_32FC1);
            const Mat* predicted = &x;
            Mat& packedY = ws.packedEstimate;
            if (packed)
                packedY.create((latentSize.height + 1) / 2, latentSize.width, CV_32SC1);
            // Packs rows r and r + 1 of `plane` (r even) once both hold their final values.
            const auto packPair = [&](const Mat& plane, int r) {
                packRowPair(plane.ptr<float>(r), r + 1 < latentSize.height ? plane.ptr<float>(r + 1) : nullptr, 0.f,
                            latentSize.width, packedY.ptr<uint32_t>(r / 2));
            };
            /* Rows that no frame pixel sees keep their start: from the second iteration on, both
               planes hold it, and their extrapolation, packing (packedY holds them from the first
               two iterations), adjoint and update are skipped. */
            const auto unseen = [&](const Range& rows) {
                return iteration > 0 && std::all_of(rowNormalizer.unseen.begin() + rows.start,
                                                    rowNormalizer.unseen.begin() + rows.end,
                                                    [](uchar u) { return u != 0; });
            };
            // Rows r and r + 1 (r even, the second only where the plane has it).
            const auto pairOf = [&](int r) { return Range(r, std::min(r + 2, latentSize.height)); };
            if (alpha > 0)
            {
                const float a = float(alpha);
                forBands(latentSize.height, bands, [&](int, const Range& rows) {
                    for (int r = rows.start; r < rows.end; r++)
                    {
                        if (!unseen(Range(r, r + 1)))
                            extrapolateRow(x.ptr<float>(r), a, latentSize.width, next.ptr<float>(r));
                        if (packed && (r % 2 == 1 || r + 1 == rows.end) && !unseen(pairOf(r & ~1)))
                            packPair(next, r & ~1);
                    }
                });
                predicted = &next;
                packedReady = true;
            }
            const Mat& y = *predicted;

            // ratio = damped(b / A y), each row straight from its blur while it is in cache.
            if (!fused && !packed)
                op.forward(y, reblurred);
            if (packed)
            {
                if (!packedReady)
                    packPlane(y, packedY);
                Mat& packedRatio = ws.packedRatio;
                if (!takesPairs)
                    packedRatio.create((frameSize.height + 1) / 2, frameSize.width, CV_32SC1);
                forBands(frameSize.height, bands, [&](int, const Range& rows) {
                    const int width = frameSize.width;
                    std::vector<float> buffer(size_t(width) * 2 * kBlockRows);
                    float *reblurredBlock = buffer.data(), *ratioBlock = reblurredBlock + size_t(width) * kBlockRows;
                    std::vector<uint32_t> pairBuffer(takesPairs ? size_t(width) : 0);
                    for (int r = rows.start; r < rows.end; r += kBlockRows)
                    {
                        const Range block(r, std::min(r + kBlockRows, rows.end));
                        op.forwardPackedBlock(packedY, block, reblurredBlock, size_t(width));
                        for (int i = 0; i < block.size(); i++)
                            ratioRow(observed[c].ptr<float>(r + i), reblurredBlock + size_t(i) * size_t(width),
                                     ratioBlock + size_t(i) * size_t(width), width, scale, invThreshold);
                        for (int i = 0; i < block.size(); i += 2)
                        {
                            uint32_t* pair = takesPairs ? pairBuffer.data() : packedRatio.ptr<uint32_t>((r + i) / 2);
                            packRowPair(ratioBlock + size_t(i) * size_t(width),
                                        i + 1 < block.size() ? ratioBlock + size_t(i + 1) * size_t(width) : nullptr,
                                        -1.f, width, pair);
                            if (takesPairs)
                                op.takePackedPair((r + i) / 2, pair);
                        }
                    }
                });
            }
            else
            {
                forBands(frameSize.height, bands, [&](int, const Range& rows) {
                    const int width = frameSize.width;
                    std::vector<float> reblurredBlock(size_t(width) * kBlockRows);
                    for (int r = rows.start; r < rows.end; r++)
                    {
                        const int inBlock = (r - rows.start) % kBlockRows;
                        if (fused && inBlock == 0)
                            op.forwardBlock(y, Range(r, std::min(r + kBlockRows, rows.end)), reblurredBlock.data(),
                                            size_t(width));
                        const float* ab =
                            fused ? reblurredBlock.data() + size_t(inBlock) * size_t(width) : reblurred.ptr<float>(r);
                        ratioRow(observed[c].ptr<float>(r), ab, ratio.ptr<float>(r), width, scale, invThreshold);
                    }
                });
            }
            // The rows around each band, as they are before any band updates y in place.
            const int width = latentSize.width;
            if (tvWeight > 0)
                for (int b = 0; b < bands; b++)
                {
                    const Range rows = bandRange(latentSize.height, bands, b);
                    float* above = halo.data() + size_t(2 * b) * size_t(width);
                    if (rows.start > 0)
                        std::memcpy(above, y.ptr<float>(rows.start - 1), sizeof(float) * size_t(width));
                    if (rows.end < latentSize.height)
                        std::memcpy(above + width, y.ptr<float>(rows.end), sizeof(float) * size_t(width));
                }
            if (packed)
            {
                if (!takesPairs)
                    op.prepareAdjointPacked(ws.packedRatio);
            }
            else if (fused)
                op.prepareAdjoint(ratio);
            else
                op.adjoint(ratio, correction);

            // x_{k+1} = y ⊙ Aᵀratio / (Aᵀ1 − λ div(∇y/|∇y|)), row by row from the adjoint's row.
            const bool accelerate = params.accelerate, measure = params.tolerance > 0;
            // The next iteration's y is this one's output where it will not extrapolate.
            packedReady = packed && iteration + 1 < params.iterations && (!params.accelerate || iteration + 1 < 2);
            forBands(latentSize.height, bands, [&](int band, const Range& rows) {
                UpdateSums& s = sums[size_t(band)];
                std::vector<float> correctionBlock(size_t(width) * kBlockRows);
                const bool tv = tvWeight > 0;
                const float* above = halo.data() + size_t(2 * band) * size_t(width);
                TvWalk tvWalk(y, rows, scale, tvEpsilon, tv ? above : nullptr, above + width);
                for (int r = rows.start; r < rows.end; r++)
                {
                    const RowTv* rowTv = tv ? tvWalk.next(r) : nullptr;
                    const int inBlock = (r - rows.start) % kBlockRows;
                    const Range block(r, std::min(r + kBlockRows, rows.end));
                    if (inBlock == 0 && !unseen(block))
                    {
                        if (packed)
                            op.adjointPackedBlock(ws.packedRatio, block, correctionBlock.data(), size_t(width));
                        else if (fused)
                            op.adjointBlock(ratio, block, correctionBlock.data(), size_t(width));
                    }
                    const float* cp = fused || packed ? correctionBlock.data() + size_t(inBlock) * size_t(width)
                                            : correction.ptr<float>(r);
                    // `next` may be y itself: no later row reads row r of y (its ny is carried).
                    float* out = next.ptr<float>(r);
                    const float constant = rowNormalizer.constant[size_t(r)];
                    // An unseen row's step stays 0; TV's row below, where it is seen, still takes its ny.
                    if (unseen(Range(r, r + 1)))
                    {
                        if (rowTv && r + 1 < rows.end && !rowNormalizer.unseen[size_t(r + 1)])
                        {
                            UpdateSums unused;
                            updateRow(y.ptr<float>(r), nullptr, false, nullptr, 0.f, rowTv, 0.f, 0.f, width, nullptr,
                                      nullptr, 1.f, unused);
                        }
                    }
                    else
                        updateRow(y.ptr<float>(r), cp, packed,
                                  std::isnan(constant) ? normalizer.ptr<float>(r) : nullptr, constant, rowTv, tvWeight,
                                  upper, width, out, accelerate ? step.ptr<uint16_t>(r) : nullptr, scale, s);
                    if (packedReady && (r % 2 == 1 || r + 1 == rows.end))
                        packPair(next, r & ~1);
                    if (measure)
                    {
                        const float* xp = x.ptr<float>(r);
                        for (int col = 0; col < width; col++)
                        {
                            const double change = double(out[col]) - xp[col];
                            s.changeSq += change * change;
                            s.sizeSq += double(xp[col]) * xp[col];
                        }
                    }
                }
            });
            std::swap(estimate[c], next);  // next now holds x_k, the next extrapolation's x_{k−1}
            UpdateSums total;
            for (const UpdateSums& s : sums)
            {
                total.stepDot += s.stepDot;
                total.stepBeforeSq += s.stepBeforeSq;
                total.changeSq += s.changeSq;
                total.sizeSq += s.sizeSq;
            }
            previousSums = total;
            if (params.tolerance > 0 && total.sizeSq > 0 && std::sqrt(total.changeSq / total.sizeSq) < params.tolerance)
            {
                iteration++;
                break;
            }
        }
        most = std::max(most, iteration);
    }
    return most;
}

//! p[x] = p[x] · factor.
DYNBLUR_SIMD_CLONES
void scaleRow(float* __restrict p, float factor, int n)
{
    for (int x = 0; x < n; x++)
        p[x] *= factor;
}

//! One plane's row takes the luminance's change from `before` to `restored` (luminanceChanged).
DYNBLUR_SIMD_CLONES
void applyLuminanceRow(const float* __restrict restored, const float* __restrict before, float black, float upper,
                       int n, const float* __restrict plane, float* __restrict out)
{
    for (int x = 0; x < n; x++)
    {
        const bool lit = before[x] > black;
        const float gain = restored[x] / (lit ? before[x] : 1.f);  // the divisor made safe
        out[x] = luminanceChanged(plane[x], lit, gain, restored[x], before[x], upper);
    }
}

/* out[x] = the mean of the planes' rows (the sum in plane order, then times 1 / planes): the
   luminance phase's start, and the same value again when the planes take its change. */
void meanRow(const std::vector<Mat>& planes, int y, int x0, int n, float* out)
{
    std::fill(out, out + n, 0.f);
    for (const Mat& p : planes)
        addRow(p.ptr<float>(y) + x0, n, out);
    scaleRow(out, 1.f / float(planes.size()), n);
}

}  // namespace

DYNBLUR_SIMD_CLONES
void channelMeanRow(const float* __restrict interleaved, int channels, int n, float* __restrict out)
{
    switch (channels)
    {
    case 3:
        for (int x = 0; x < n; x++)
            out[x] = (interleaved[3 * x] + interleaved[3 * x + 1] + interleaved[3 * x + 2]) * (1.f / 3.f);
        return;
    case 4:
        for (int x = 0; x < n; x++)
            out[x] = (interleaved[4 * x] + interleaved[4 * x + 1] + interleaved[4 * x + 2] + interleaved[4 * x + 3]) *
                     0.25f;
        return;
    default:
        for (int x = 0; x < n; x++)
        {
            float s = 0.f;
            for (int c = 0; c < channels; c++)
                s += interleaved[x * channels + c];
            out[x] = s / float(channels);
        }
    }
}

/* The strides a frame has are spelled out: with a constant stride the compiler loads whole vectors
   and shuffles, where a variable one reads float by float. */
DYNBLUR_SIMD_CLONES
void channelRow(const float* interleaved, int channels, int channel, int n, float* __restrict out)
{
    const float* p = interleaved + channel;
    switch (channels)
    {
    case 1:
        std::memcpy(out, p, sizeof(float) * size_t(n));
        return;
    case 3:
        for (int x = 0; x < n; x++)
            out[x] = p[3 * x];
        return;
    case 4:
        for (int x = 0; x < n; x++)
            out[x] = p[4 * x];
        return;
    default:
        for (int x = 0; x < n; x++)
            out[x] = p[x * channels];
    }
}

DYNBLUR_SIMD_CLONES
void interleaveRow(const float* const* planes, int channels, int n, float* __restrict out)
{
    switch (channels)
    {
    case 1:
        std::memcpy(out, planes[0], sizeof(float) * size_t(n));
        return;
    case 3:
        for (int x = 0; x < n; x++)
        {
            out[3 * x] = planes[0][x];
            out[3 * x + 1] = planes[1][x];
            out[3 * x + 2] = planes[2][x];
        }
        return;
    default:
        for (int x = 0; x < n; x++)
            for (int c = 0; c < channels; c++)
                out[x * channels + c] = planes[c][x];
    }
}

DYNBLUR_SIMD_CLONES
void clampRowToUnit(float* __restrict p, int n)
{
    for (int x = 0; x < n; x++)
        p[x] = std::min(std::max(p[x], 0.f), 1.f);
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

namespace {

/* Whether a row holds only finite values, and its least and largest: a NaN fails every
   comparison, so v == v catches it, and ±Inf shows in the range. Sixteen lanes of running minima,
   maxima and flags, in vector types (written per lane, GCC left this loop scalar). */
DYNBLUR_SIMD_CLONES
bool finiteRow(const float* p, int n, float& low, float& high)
{
    typedef float v16 __attribute__((vector_size(64), aligned(4)));  // aligned(4): unaligned loads allowed
    typedef int32_t v16i __attribute__((vector_size(64)));
    v16 lo = v16{} + p[0], hi = lo;
    v16i number = v16i{} - 1;  // all ones while every value seen in the lane is a number
    int x = 0;
    for (; x + 16 <= n; x += 16)
    {
        const v16 v = *(const v16*)(p + x);
        number &= v == v;
        lo = v < lo ? v : lo;
        hi = v > hi ? v : hi;
    }
    bool numbers = true;
    low = lo[0];
    high = hi[0];
    for (int k = 0; k < 16; k++)
    {
        numbers &= number[k] != 0;
        low = std::min(low, lo[k]);
        high = std::max(high, hi[k]);
    }
    for (; x < n; x++)
    {
        numbers &= p[x] == p[x];
        low = std::min(low, p[x]);
        high = std::max(high, p[x]);
    }
    return numbers && std::isfinite(low) && std::isfinite(high);
}

}  // namespace

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

int iterateRichardsonLucy(BlurOperator& op, const Mat& blurred, const ObservedFrame& observed, const Mat& normalizer,
                          const RLParams& params, std::vector<Mat>& estimate, RLWorkspace& ws, LuminanceChange& change)
{
    change = LuminanceChange();
    const RowNormalizer rowNormalizer(normalizer, op.latentSize().height);
    const int colour = params.colorIterations;
    const ImageLevel& colourLevel = observed.level;
    if (blurred.channels() < 3 || colour < 0 || colour >= params.iterations)
        return iteratePlanes(op, observed.planes, colourLevel, rowNormalizer, params, estimate, ws);

    int done = 0;
    if (colour > 0)
    {
        RLParams first = params;
        first.iterations = colour;
        done = iteratePlanes(op, observed.planes, colourLevel, rowNormalizer, first, estimate, ws);
        if (params.tolerance > 0 && done < colour)
            return done;  // converged in colour already
    }
    /* The luminance phase works in the colour phase's buffers (`observed`, whose planes that phase
       no longer reads, `other` and `step`), `other` grown to two latent planes: the running
       plane's and the luminance estimate. */
    const Size latentSize = op.latentSize();
    ws.other.resize(std::max<size_t>(ws.other.size(), 2));
    for (Mat& m : ws.other)
        m.create(latentSize, CV_32FC1);
    ws.observed.resize(std::max<size_t>(ws.observed.size(), 1));
    ws.observed[0].create(op.frameSize(), CV_32FC1);
    Mat luminance = ws.observed[0];
    std::vector<Mat> latent{ws.other[1]};
    // Blur is linear and the same for every plane, so the planes' mean is blurred by it too.
    const int channels = blurred.channels();
    std::vector<double> rowSum(size_t(luminance.rows)), rowPeak(size_t(luminance.rows));
    parallel_for_(Range(0, std::max(latentSize.height, luminance.rows)), [&](const Range& rows) {
        for (int y = rows.start; y < rows.end; y++)
        {
            if (y < luminance.rows)
            {
                channelMeanRow(blurred.ptr<float>(y), channels, luminance.cols, luminance.ptr<float>(y));
                rowSum[size_t(y)] = rowSumAndPeak(luminance.ptr<float>(y), luminance.cols, rowPeak[size_t(y)]);
            }
            if (y < latentSize.height)
                meanRow(estimate, y, 0, latentSize.width, latent[0].ptr<float>(y));
        }
    });
    RLParams rest = params;
    rest.iterations = params.iterations - colour;
    done += iteratePlanes(op, {luminance}, foldLevel(rowSum, rowPeak, double(luminance.total())), rowNormalizer,
                          rest, latent, ws);
    ws.other[1] = latent[0];  // the two buffers may have swapped: keep the pool's set intact
    /* The luminance's change goes to every plane as a ratio, which keeps each pixel's chromaticity
       (an added difference shifts dark and saturated colours: in DeblurQuality's fruits it cost
       3.5 dB with no colour iteration, 0.5 dB with one). Where the start is (nearly) black the difference is added instead.
       The planes stay within the bound the colour phase kept them in (see iteratePlanes). */
    change.restored = latent[0];
    change.black = float(1e-6 * std::max(colourLevel.mean, 0.0));
    change.upper = projectionBound(op, colourLevel);
    return done;
}

void LuminanceChange::applyRow(const std::vector<Mat>& planes, int y, int x0, int n, float* before,
                               float* const* out) const
{
    meanRow(planes, y, x0, n, before);
    for (size_t c = 0; c < planes.size(); c++)
        applyLuminanceRow(restored.ptr<float>(y) + x0, before, black, upper, n, planes[c].ptr<float>(y) + x0, out[c]);
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
