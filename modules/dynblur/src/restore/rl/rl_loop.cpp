// SPDX-License-Identifier: Apache-2.0
#include "restore/deconv_rl.hpp"

#include "restore/rl/rl_rows.hpp"
#include "restore/operators/packed_gather.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>

namespace cv {
namespace dynblur {
namespace detail {

namespace {

//! Rows blurred at a time by a row-gathering operator, then consumed row by row while in L2 (even: see bandRange).
constexpr int kBlockRows = 8;

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

/* One plane's RL iterations, each a handful of named passes over bands of rows in parallel:
   extrapolate (Biggs–Andrews), ratio (b / A y, damped, each block of rows straight from its blur
   while in cache), keepHalo (the rows TV reads across band edges), prepareAdjoint, update (x_{k+1}
   from the adjoint's rows, TV, the step's sums). The planes are independent problems and run one
   after another, each through all its iterations with its own extrapolation and stopping test: one
   plane's working set fits in the last-level cache where all three did not.

   RL is scale-equivariant, and so is this loop: its element-wise work sees intensities divided by
   the image's level (the ratio's epsilon, the deviance, TV's |∇u| and the step products would
   otherwise under- or overflow far from [0, 1]). TV's |∇u| is regularised at 1e-3 of the level.

   Per plane: the estimate x_k; `next` (x_{k−1}, overwritten by the extrapolated y_k and then by
   x_{k+1} in place) and, when accelerating, `step`, the last step g_{k−1} (overwritten by g_k while
   its dot product with g_k is taken). Shared: the ratio and, for operators that cannot gather rows,
   whole reblurred and correction planes. A packed operator reads the ratio as ratio − 1 (its
   deviation from 1 is what a bfloat16 keeps to 2^-9 relative), so its adjoint gives Aᵀratio − Aᵀ1
   and the update adds Aᵀ1 back; it takes the packed ratio pair by pair where it can
   (takesPackedPairs), else as ws.packedRatio. */
class PlaneIterations
{
public:
    PlaneIterations(BlurOperator& op, const ImageLevel& level, const RowNormalizer& rowNormalizer,
                    const RLParams& params, RLWorkspace& ws)
        : op_(op), rows_(rowNormalizer), params_(params), ws_(ws), latent_(op.latentSize()), frame_(op.frameSize()),
          fused_(op.gathersRows()), packed_(op.gathersPackedRows()), takesPairs_(packed_ && op.takesPackedPairs()),
          bands_(std::max(1, std::min(latent_.height, 8 * getNumThreads()))), tvWeight_(float(params.tvWeight)),
          upper_(projectionBound(op, level))
    {
        CV_Assert(!packed_ || !rows_.plane.empty());
        const double mean = level.mean;
        scale_ = mean > 0 && std::isfinite(1.0 / mean) ? float(std::min(1.0 / mean, 1e37)) : 1.f;
        // The deviance is taken on scaled intensities, so its threshold 2 / damping² is divided by the scale.
        invThreshold_ =
            params.damping > 0 ? float(std::min(2.0 / (params.damping * params.damping * scale_), 1e37)) : 0.f;
        ws_.other.resize(std::max<size_t>(ws_.other.size(), 1));  // never shrunk: kept for the next frame
        if (!packed_)
            ws_.ratio.create(frame_, CV_32FC1);
        halo_.resize(size_t(2 * bands_) * size_t(latent_.width));
    }

    //! params.iterations on one plane (fewer when it converges); returns how many ran.
    int run(const Mat& observed, Mat& estimate)
    {
        if (params_.accelerate)
        {
            ws_.step.create(latent_, CV_16UC1);  // bfloat16
            ws_.step.setTo(0);
        }
        packedReady_ = false;
        UpdateSums previous;
        int iteration = 0;
        while (iteration < params_.iterations)
        {
            iteration_ = iteration;
            Mat& next = ws_.other[0];
            next.create(latent_, CV_32FC1);
            if (packed_)
                ws_.packedEstimate.create((latent_.height + 1) / 2, latent_.width, CV_32SC1);
            const Mat& y = extrapolate(estimate, next, alpha(previous, iteration));
            ratio(observed, y);
            if (tvWeight_ > 0)
                keepHalo(y);
            prepareAdjoint();
            // The next iteration's y is this one's output where it will not extrapolate.
            packedReady_ =
                packed_ && iteration + 1 < params_.iterations && (!params_.accelerate || iteration + 1 < 2);
            previous = update(y, estimate, next);
            std::swap(estimate, next);  // next now holds x_k, the next extrapolation's x_{k−1}
            iteration++;
            if (params_.tolerance > 0 && previous.sizeSq > 0 &&
                std::sqrt(previous.changeSq / previous.sizeSq) < params_.tolerance)
                break;
        }
        return iteration;
    }

private:
    //! Biggs–Andrews: extrapolate along the last step, by how well the last two steps agree.
    double alpha(const UpdateSums& previous, int iteration) const
    {
        if (!params_.accelerate || iteration < 2)
            return 0;
        return previous.stepBeforeSq > 0 ? std::min(std::max(previous.stepDot / previous.stepBeforeSq, 0.0), 1.0)
                                         : 0.0;
    }

    /* Rows that no frame pixel sees keep their start: from the second iteration on, both planes
       hold it, and their extrapolation, packing (the packed estimate holds them from the first two
       iterations), adjoint and update are skipped. */
    bool unseen(const Range& rows) const
    {
        return iteration_ > 0 && std::all_of(rows_.unseen.begin() + rows.start, rows_.unseen.begin() + rows.end,
                                             [](uchar u) { return u != 0; });
    }

    //! Rows r and r + 1 (r even, the second only where the plane has it).
    Range pairOf(int r) const { return Range(r, std::min(r + 2, latent_.height)); }

    //! Packs rows r and r + 1 of `plane` (r even) into the packed estimate once both hold their final values.
    void packPair(const Mat& plane, int r)
    {
        packRowPair(plane.ptr<float>(r), r + 1 < latent_.height ? plane.ptr<float>(r + 1) : nullptr, 0.f,
                    latent_.width, ws_.packedEstimate.ptr<uint32_t>(r / 2));
    }

    //! y = max(x + a (x − next), 0) into `next` (holding x_{k−1}) when a > 0; x itself otherwise.
    const Mat& extrapolate(const Mat& x, Mat& next, double a)
    {
        if (a <= 0)
            return x;
        forBands(latent_.height, bands_, [&](int, const Range& rows) {
            for (int r = rows.start; r < rows.end; r++)
            {
                if (!unseen(Range(r, r + 1)))
                    extrapolateRow(x.ptr<float>(r), float(a), latent_.width, next.ptr<float>(r));
                if (packed_ && (r % 2 == 1 || r + 1 == rows.end) && !unseen(pairOf(r & ~1)))
                    packPair(next, r & ~1);
            }
        });
        packedReady_ = true;
        return next;
    }

    //! ratio = damped(b / A y): packed (as ratio − 1), or float.
    void ratio(const Mat& observed, const Mat& y)
    {
        if (packed_)
            packedRatio(observed, y);
        else
            floatRatio(observed, y);
    }

    void packedRatio(const Mat& observed, const Mat& y)
    {
        if (!packedReady_)
            packPlane(y, ws_.packedEstimate);
        if (!takesPairs_)
            ws_.packedRatio.create((frame_.height + 1) / 2, frame_.width, CV_32SC1);
        forBands(frame_.height, bands_, [&](int, const Range& rows) {
            const int width = frame_.width;
            std::vector<float> buffer(size_t(width) * 2 * kBlockRows);
            float *reblurredBlock = buffer.data(), *ratioBlock = reblurredBlock + size_t(width) * kBlockRows;
            std::vector<uint32_t> pairBuffer(takesPairs_ ? size_t(width) : 0);
            for (int r = rows.start; r < rows.end; r += kBlockRows)
            {
                const Range block(r, std::min(r + kBlockRows, rows.end));
                op_.forwardPackedBlock(ws_.packedEstimate, block, reblurredBlock, size_t(width));
                for (int i = 0; i < block.size(); i++)
                    ratioRow(observed.ptr<float>(r + i), reblurredBlock + size_t(i) * size_t(width),
                             ratioBlock + size_t(i) * size_t(width), width, scale_, invThreshold_);
                for (int i = 0; i < block.size(); i += 2)
                {
                    uint32_t* pair = takesPairs_ ? pairBuffer.data() : ws_.packedRatio.ptr<uint32_t>((r + i) / 2);
                    packRowPair(ratioBlock + size_t(i) * size_t(width),
                                i + 1 < block.size() ? ratioBlock + size_t(i + 1) * size_t(width) : nullptr, -1.f,
                                width, pair);
                    if (takesPairs_)
                        op_.takePackedPair((r + i) / 2, pair);
                }
            }
        });
    }

    void floatRatio(const Mat& observed, const Mat& y)
    {
        if (!fused_)
            op_.forward(y, ws_.reblurred);
        forBands(frame_.height, bands_, [&](int, const Range& rows) {
            const int width = frame_.width;
            std::vector<float> reblurredBlock(size_t(width) * kBlockRows);
            for (int r = rows.start; r < rows.end; r++)
            {
                const int inBlock = (r - rows.start) % kBlockRows;
                if (fused_ && inBlock == 0)
                    op_.forwardBlock(y, Range(r, std::min(r + kBlockRows, rows.end)), reblurredBlock.data(),
                                     size_t(width));
                const float* ab =
                    fused_ ? reblurredBlock.data() + size_t(inBlock) * size_t(width) : ws_.reblurred.ptr<float>(r);
                ratioRow(observed.ptr<float>(r), ab, ws_.ratio.ptr<float>(r), width, scale_, invThreshold_);
            }
        });
    }

    //! The rows around each band, as they are before any band updates y in place.
    void keepHalo(const Mat& y)
    {
        const int width = latent_.width;
        for (int b = 0; b < bands_; b++)
        {
            const Range rows = bandRange(latent_.height, bands_, b);
            float* above = halo_.data() + size_t(2 * b) * size_t(width);
            if (rows.start > 0)
                std::memcpy(above, y.ptr<float>(rows.start - 1), sizeof(float) * size_t(width));
            if (rows.end < latent_.height)
                std::memcpy(above + width, y.ptr<float>(rows.end), sizeof(float) * size_t(width));
        }
    }

    //! Whatever the adjoint's blocks need of the whole ratio first; a whole adjoint plane where the operator has no blocks.
    void prepareAdjoint()
    {
        if (packed_)
        {
            if (!takesPairs_)
                op_.prepareAdjointPacked(ws_.packedRatio);
        }
        else if (fused_)
            op_.prepareAdjoint(ws_.ratio);
        else
            op_.adjoint(ws_.ratio, ws_.correction);
    }

    /* x_{k+1} = y ⊙ Aᵀratio / (Aᵀ1 − λ div(∇y/|∇y|)) into `next`, row by row from the adjoint's
       row; returns the step's and the change's sums, added in band order. */
    UpdateSums update(const Mat& y, const Mat& x, Mat& next)
    {
        const int width = latent_.width;
        const bool tv = tvWeight_ > 0, measure = params_.tolerance > 0;
        std::vector<UpdateSums> sums(static_cast<size_t>(bands_));
        forBands(latent_.height, bands_, [&](int band, const Range& rows) {
            UpdateSums& s = sums[size_t(band)];
            std::vector<float> correctionBlock(size_t(width) * kBlockRows);
            const float* above = halo_.data() + size_t(2 * band) * size_t(width);
            TvWalk tvWalk(y, rows, scale_, kTvEpsilon, tv ? above : nullptr, above + width);
            for (int r = rows.start; r < rows.end; r++)
            {
                const RowTv* rowTv = tv ? tvWalk.next(r) : nullptr;
                const int inBlock = (r - rows.start) % kBlockRows;
                const Range block(r, std::min(r + kBlockRows, rows.end));
                if (inBlock == 0 && !unseen(block))
                {
                    if (packed_)
                        op_.adjointPackedBlock(ws_.packedRatio, block, correctionBlock.data(), size_t(width));
                    else if (fused_)
                        op_.adjointBlock(ws_.ratio, block, correctionBlock.data(), size_t(width));
                }
                const float* cp = fused_ || packed_ ? correctionBlock.data() + size_t(inBlock) * size_t(width)
                                                    : ws_.correction.ptr<float>(r);
                // `next` may be y itself: no later row reads row r of y (its ny is carried).
                float* out = next.ptr<float>(r);
                const float constant = rows_.constant[size_t(r)];
                // An unseen row's step stays 0; TV's row below, where it is seen, still takes its ny.
                if (unseen(Range(r, r + 1)))
                {
                    if (rowTv && r + 1 < rows.end && !rows_.unseen[size_t(r + 1)])
                    {
                        UpdateSums unused;
                        updateRow(y.ptr<float>(r), nullptr, false, nullptr, 0.f, rowTv, 0.f, 0.f, width, nullptr,
                                  nullptr, 1.f, unused);
                    }
                }
                else
                    updateRow(y.ptr<float>(r), cp, packed_, std::isnan(constant) ? rows_.plane.ptr<float>(r) : nullptr,
                              constant, rowTv, tvWeight_, upper_, width, out,
                              params_.accelerate ? ws_.step.ptr<uint16_t>(r) : nullptr, scale_, s);
                if (packedReady_ && (r % 2 == 1 || r + 1 == rows.end))
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
        UpdateSums total;
        for (const UpdateSums& s : sums)
        {
            total.stepDot += s.stepDot;
            total.stepBeforeSq += s.stepBeforeSq;
            total.changeSq += s.changeSq;
            total.sizeSq += s.sizeSq;
        }
        return total;
    }

    static constexpr float kTvEpsilon = 1e-3f;
    BlurOperator& op_;
    const RowNormalizer& rows_;
    const RLParams& params_;
    RLWorkspace& ws_;
    const Size latent_, frame_;
    const bool fused_, packed_, takesPairs_;
    const int bands_;
    const float tvWeight_, upper_;
    float scale_ = 1, invThreshold_ = 0;
    std::vector<float> halo_;  // per band: the row above it and the row below it
    int iteration_ = 0;
    bool packedReady_ = false;  // the packed estimate holds the next iteration's y
};

/* RL over every plane for params.iterations (colorIterations ignored): `observed` holds the frame's
   planes, `level` is the frame's (ObservedFrame::level). Returns the most iterations a plane ran. */
int iteratePlanes(BlurOperator& op, const std::vector<Mat>& observed, const ImageLevel& level,
                  const RowNormalizer& rowNormalizer, const RLParams& params, std::vector<Mat>& estimate,
                  RLWorkspace& ws)
{
    CV_Assert(estimate.size() == observed.size());
    PlaneIterations iterations(op, level, rowNormalizer, params, ws);
    int most = 0;
    for (size_t c = 0; c < observed.size(); c++)
        most = std::max(most, iterations.run(observed[c], estimate[c]));
    return most;
}

}  // namespace

int iterateRichardsonLucy(BlurOperator& op, const Mat& blurred, const ObservedFrame& observed, const Mat& normalizer,
                          const RLParams& params, std::vector<Mat>& estimate, RLWorkspace& ws, LuminanceChange& change)
{
    change = LuminanceChange();
    const RowNormalizer rowNormalizer(normalizer, op.latentSize().height);
    const int color = params.colorIterations;
    const ImageLevel& colorLevel = observed.level;
    if (blurred.channels() < 3 || color < 0 || color >= params.iterations)
        return iteratePlanes(op, observed.planes, colorLevel, rowNormalizer, params, estimate, ws);

    int done = 0;
    if (color > 0)
    {
        RLParams first = params;
        first.iterations = color;
        done = iteratePlanes(op, observed.planes, colorLevel, rowNormalizer, first, estimate, ws);
        if (params.tolerance > 0 && done < color)
            return done;  // converged in color already
    }
    /* The luminance phase works in the color phase's buffers (`observed`, whose planes that phase
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
    rest.iterations = params.iterations - color;
    done += iteratePlanes(op, {luminance}, foldLevel(rowSum, rowPeak, double(luminance.total())), rowNormalizer,
                          rest, latent, ws);
    ws.other[1] = latent[0];  // the two buffers may have swapped: keep the pool's set intact
    /* The luminance's change goes to every plane as a ratio, which keeps each pixel's chromaticity
       (an added difference shifts dark and saturated colors: in DeblurQuality's fruits it cost
       3.5 dB with no color iteration, 0.5 dB with one). Where the start is (nearly) black the difference is added instead.
       The planes stay within the bound the color phase kept them in (see iteratePlanes). */
    change.restored = latent[0];
    change.black = float(1e-6 * std::max(colorLevel.mean, 0.0));
    change.upper = projectionBound(op, colorLevel);
    return done;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
