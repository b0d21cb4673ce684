#include "restore/deconv_operator.hpp"

#include "restore/fft_kernel.hpp"

#include <opencv2/core/utility.hpp>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstring>
#include <mutex>
#include <utility>

namespace cv {
namespace dynblur {
namespace detail {

// ---------------------------------------------------------------------------------------------
// One kernel, FFT.

UniformBlurOperator::UniformBlurOperator(Size frameSize, const Mat& kernel32f, bool pad) : BlurOperator(frameSize)
{
    CV_Assert(kernel32f.type() == CV_32FC1);
    double peak = 0;
    minMaxLoc(kernel32f, nullptr, &peak);
    spotGain_ = peak > 0 ? 1.0 / peak : 1.0;
    if (pad)
    {
        origin_ = Point((kernel32f.cols - 1) / 2, (kernel32f.rows - 1) / 2);
        latent_ = Size(frame_.width + kernel32f.cols - 1, frame_.height + kernel32f.rows - 1);
    }
    fft_.reset(new FftKernel(FftKernel::linearSize(latent_, kernel32f.size()), kernel32f));
}

UniformBlurOperator::~UniformBlurOperator() {}

/* A float FFT's product is exact only to its rounding: where A x is zero (every latent pixel that
   reaches the frame pixel is zero, as RL's multiplicative update keeps the start's zeros) it returns
   ±1e-8 instead, b / (A x) turns that into a ratio of 1e8 on a lit pixel, and the adjoint's rounding
   spreads it over the whole row (a 64-pixel checkerboard under two taps came back black). Values
   within the rounding are taken as zero, so the ratio there is 0 as for an exact zero; the adjoint
   then carries it only to latent pixels that are zero already, as in exact arithmetic. The rounding
   measured up to 7.4 ε·rms(x) on frames up to 1280×960 (random, half zeros); the floor is
   2·log2(grid elements)·ε·rms(x), 40 ε·rms(x) on such a grid. */
void UniformBlurOperator::forward(const Mat& latent, Mat& frame)
{
    const double rms = norm(latent, NORM_L2) / std::sqrt(double(latent.total()));
    const Size grid = fft_->transformSize();
    const double floor = 2.0 * std::log2(std::max(2.0, double(grid.area()))) * FLT_EPSILON * rms;
    if (latent_ == frame_)
        fft_->convolve(latent, frame);
    else
    {
        fft_->convolve(latent, scratch_);
        scratch_(Rect(origin_, frame_)).copyTo(frame);
    }
    const float f = float(floor);
    for (int y = 0; y < frame.rows; y++)
    {
        float* row = frame.ptr<float>(y);
        for (int x = 0; x < frame.cols; x++)
            row[x] = row[x] > f ? row[x] : 0.f;
    }
}

void UniformBlurOperator::adjoint(const Mat& frame, Mat& latent)
{
    if (latent_ == frame_)
    {
        fft_->convolve(frame, latent, true);
        return;
    }
    scratch_.create(latent_, CV_32FC1);
    scratch_.setTo(0);
    frame.copyTo(scratch_(Rect(origin_, frame_)));
    fft_->convolve(scratch_, latent, true);
}

// ---------------------------------------------------------------------------------------------
// Bank of kernels, spatial domain.

namespace {

/* Blending weights of every integer coordinate in [0, length) between nodes `z` (increasing):
   between two nodes, linear over the middle `transition` of the interval and constant (the nearer
   node) outside it, so transition 1 is the bilinear tent; constant beyond the outermost nodes.
   They sum to 1 everywhere. */
std::vector<BankBlurOperator::AxisWeight> axisWeights(const std::vector<double>& z, int length, double transition)
{
    std::vector<BankBlurOperator::AxisWeight> weights(size_t(std::max(length, 0)));
    const int last = int(z.size()) - 1;
    int k = 0;
    for (int t = 0; t < length; t++)
    {
        BankBlurOperator::AxisWeight& w = weights[size_t(t)];
        if (last <= 0 || t <= z[0])
        {
            w.weight[0] = 1.f;
            continue;
        }
        if (t >= z[size_t(last)])
        {
            w.node[0] = w.node[1] = last;
            w.weight[0] = 1.f;
            continue;
        }
        while (k + 1 < last && t >= z[size_t(k + 1)])
            k++;
        double a = (z[size_t(k + 1)] - t) / (z[size_t(k + 1)] - z[size_t(k)]);
        if (transition < 1)
            a = std::min(std::max((a - 0.5) / transition + 0.5, 0.0), 1.0);
        w.node[0] = k;
        w.node[1] = k + 1;
        w.weight[0] = float(a);
        w.weight[1] = float(1.0 - a);
    }
    return weights;
}

}  // namespace

std::vector<BankBlurOperator::AxisWeight> nodeRowWeights(const PsfBank& bank, int height)
{
    return axisWeights(bank.nodeRows, height, 1.0);
}

std::vector<BankBlurOperator::AxisWeight> nodeColumnWeights(const PsfBank& bank, int width)
{
    return axisWeights(bank.nodeCols, width, kColumnBlendTransition);
}

namespace {

//! For each node, the range of coordinates where its weight is positive.
std::vector<Range> supports(const std::vector<BankBlurOperator::AxisWeight>& weights, int nodes)
{
    std::vector<Range> result(size_t(nodes), Range(0, 0));
    std::vector<bool> seen(size_t(nodes), false);
    for (int t = 0; t < int(weights.size()); t++)
        for (int k = 0; k < 2; k++)
        {
            if (weights[size_t(t)].weight[k] <= 0.f)
                continue;
            const size_t n = size_t(weights[size_t(t)].node[k]);
            if (!seen[n])
                result[n] = Range(t, t + 1);
            result[n].end = t + 1;
            seen[n] = true;
        }
    return result;
}

//! Each node's weights over its support (`support` from supports()).
std::vector<std::vector<float>> supportWeights(const std::vector<BankBlurOperator::AxisWeight>& weights,
                                               const std::vector<Range>& support)
{
    std::vector<std::vector<float>> result(support.size());
    for (size_t i = 0; i < support.size(); i++)
    {
        const Range r = support[i];
        result[i].assign(size_t(r.size()), 0.f);
        for (int t = r.start; t < r.end; t++)
            for (int k = 0; k < 2; k++)
                if (weights[size_t(t)].node[k] == int(i))
                    result[i][size_t(t - r.start)] += weights[size_t(t)].weight[k];
    }
    return result;
}

/* Walks two tap lists sorted by `key` (a pair of ints, compared lexicographically) side by side and
   calls emit(tap, weight in a, weight in b) once per key either holds, with 0 where a list lacks it. */
template <typename TapT, typename Key, typename Emit>
void forUnion(const TapT* a, size_t countA, const TapT* b, size_t countB, Key key, Emit emit)
{
    size_t p = 0, q = 0;
    while (p < countA || q < countB)
    {
        const bool takeA = p < countA && (q == countB || key(a[p]) <= key(b[q]));
        const bool takeB = q < countB && (p == countA || key(b[q]) <= key(a[p]));
        emit(takeA ? a[p] : b[q], takeA ? a[p].weight : 0.f, takeB ? b[q].weight : 0.f);
        p += takeA;
        q += takeB;
    }
}

/* A gather's tap array and its rows (or row pairs) [0, count), built in parallel: build(i, taps)
   appends row i's taps to `taps` and returns its GatherRow with begin and end indexing `taps`.
   Each part of the rows fills an array of its own, joined in row order afterwards, so the result
   is the serial build's. A frame-rate row bank's forward list took 1.1 ms on one core. */
template <typename T, typename Build>
void buildGatherRows(int count, std::vector<T>& taps, std::vector<RowBankOperator::GatherRow>& rows,
                     const Build& build)
{
    rows.resize(size_t(count));
    const int parts = std::max(1, std::min(count, 4 * getNumThreads()));
    std::vector<std::vector<T>> partTaps(static_cast<size_t>(parts));
    const auto partRows = [&](int part) {
        return Range(int(int64_t(count) * part / parts), int(int64_t(count) * (part + 1) / parts));
    };
    parallel_for_(Range(0, parts), [&](const Range& range) {
        for (int part = range.start; part < range.end; part++)
        {
            const Range r = partRows(part);
            for (int i = r.start; i < r.end; i++)
                rows[size_t(i)] = build(i, partTaps[size_t(part)]);
        }
    });
    std::vector<size_t> offset(size_t(parts) + 1, 0);
    for (int part = 0; part < parts; part++)
        offset[size_t(part) + 1] = offset[size_t(part)] + partTaps[size_t(part)].size();
    taps.resize(offset.back());
    parallel_for_(Range(0, parts), [&](const Range& range) {
        for (int part = range.start; part < range.end; part++)
        {
            const std::vector<T>& own = partTaps[size_t(part)];
            std::copy(own.begin(), own.end(), taps.begin() + ptrdiff_t(offset[size_t(part)]));
            const Range r = partRows(part);
            for (int i = r.start; i < r.end; i++)
            {
                rows[size_t(i)].begin += int(offset[size_t(part)]);
                rows[size_t(i)].end += int(offset[size_t(part)]);
            }
        }
    });
}

//! One non-zero kernel element as a read offset: frame pixel p reads latent p + (dx, dy).
struct KernelTap
{
    int dy, dx;
    float weight;
};

/* The non-zero taps of a kernel with its shift, in (dy, dx) order, written from `out` on: the
   kernel walked backwards, since a read offset is the negated kernel position. Returns the end. */
KernelTap* writeKernelTaps(const Mat& kernel32f, Point shift, KernelTap* out)
{
    const int cx = (kernel32f.cols - 1) / 2, cy = (kernel32f.rows - 1) / 2;
    for (int v = kernel32f.rows - 1; v >= 0; v--)
    {
        const float* row = kernel32f.ptr<float>(v);
        for (int u = kernel32f.cols - 1; u >= 0; u--)
            if (row[u] != 0.f)  // skip, do not multiply by zero
                *out++ = {-(shift.y + v - cy), -(shift.x + u - cx), row[u]};
    }
    return out;
}

std::vector<KernelTap> kernelTaps(const Mat& kernel32f, Point shift)
{
    std::vector<KernelTap> taps(size_t(countNonZero(kernel32f)));  // motion kernels are mostly empty
    writeKernelTaps(kernel32f, shift, taps.data());
    return taps;
}

/* Every node's kernel as taps (writeKernelTaps) in one table, node columns one after the other (a
   tile operator walks down one node column at a time), nodes in parallel; the offsets' reach
   (each range includes 0) and the kernels' smallest peak (bankSpotGain's, without a pass of its
   own). One table instead of a list per node: a tile bank's ~10⁴ lists were as many allocations,
   and the walk down a column read them from all over the heap. */
class NodeTaps
{
public:
    NodeTaps(const PsfBank& bank, int& dxMin, int& dxMax, int& dyMin, int& dyMax)
        : nodeCols_(int(bank.nodeCols.size())), nodeRows_(int(bank.nodeRows.size())),
          start_(bank.kernels.size() + 1, 0)
    {
        const int nodes = int(bank.kernels.size());
        parallel_for_(Range(0, nodes), [&](const Range& r) {
            for (int n = r.start; n < r.end; n++)
                start_[slot(n) + 1] = countNonZero(bank.kernels[size_t(n)]);
        });
        for (size_t i = 1; i < start_.size(); i++)
            start_[i] += start_[i - 1];
        // Left uninitialised (every tap is written below): zeroing a tile bank's 12 MB first took 0.5 ms on one core.
        taps_.reset(new KernelTap[size_t(start_.back())]);
        std::mutex mutex;
        dxMin = dxMax = dyMin = dyMax = 0;
        parallel_for_(Range(0, nodes), [&](const Range& r) {
            int reach[4] = {0, 0, 0, 0};  // dxMin, dxMax, dyMin, dyMax of these nodes
            float smallest = 1;
            for (int n = r.start; n < r.end; n++)
            {
                KernelTap* const first = taps_.get() + start_[slot(n)];
                KernelTap* const last = writeKernelTaps(bank.kernels[size_t(n)], bank.shifts[size_t(n)], first);
                float peak = 0;  // the kernel's largest element, zeros included
                for (const KernelTap* t = first; t < last; t++)
                {
                    reach[0] = std::min(reach[0], t->dx);
                    reach[1] = std::max(reach[1], t->dx);
                    reach[2] = std::min(reach[2], t->dy);
                    reach[3] = std::max(reach[3], t->dy);
                    peak = std::max(peak, t->weight);
                }
                smallest = std::min(smallest, peak);
            }
            std::lock_guard<std::mutex> lock(mutex);
            dxMin = std::min(dxMin, reach[0]);
            dxMax = std::max(dxMax, reach[1]);
            dyMin = std::min(dyMin, reach[2]);
            dyMax = std::max(dyMax, reach[3]);
            smallestPeak_ = std::min(smallestPeak_, double(smallest));
        });
    }
    //! The smallest of the kernels' peaks (their largest elements), at most 1.
    double smallestPeak() const { return smallestPeak_; }
    //! Node n's taps (n = node row · node columns + node column, as in the bank).
    const KernelTap* taps(int n) const { return taps_.get() + start_[slot(n)]; }
    size_t count(int n) const { return size_t(start_[slot(n) + 1] - start_[slot(n)]); }

private:
    size_t slot(int n) const { return size_t(n % nodeCols_) * size_t(nodeRows_) + size_t(n / nodeCols_); }
    int nodeCols_, nodeRows_;
    double smallestPeak_ = 1;
    std::vector<int> start_;  // by slot
    std::unique_ptr<KernelTap[]> taps_;
};

/* The latent domain: with padding, the bounding box of every pixel a tap reads (offsets in
   [dxMin, dxMax] × [dyMin, dyMax], which include 0); otherwise the frame. */
void domain(Size frame, bool pad, int dxMin, int dxMax, int dyMin, int dyMax, Size& latent, Point& origin)
{
    latent = frame;
    origin = Point();
    if (pad)
    {
        origin = Point(-dxMin, -dyMin);
        latent = Size(frame.width + dxMax - dxMin, frame.height + dyMax - dyMin);
    }
}

/* The columns a gather takes at a time, across all rows of a block before the next chunk: a
   chunk's ~60 source rows (~30 packed pairs) fit a 32 KiB L1, and the 512-bit kernels do it in one
   block of sixteen sums (against 64 columns, tile-wise frames took 5–7 % less: half the calls,
   twice the sums to hide the latency). A remainder of up to kGatherChunkSlack columns joins the
   chunk before it, in blocks of up to 10 vectors: alone, its single vector per row waited on each
   tap's multiply-add latency, and the adjoint of a tile bank's node columns, 123–143 columns wide
   on the benchmark frame, took 1.10× as long. */
constexpr int kGatherChunk = 128, kGatherChunkSlack = 32;

//! Where the chunk of [x, end) that starts at x ends.
inline int chunkEnd(int x, int end)
{
    const int next = std::min(x + kGatherChunk, end);
    return end - next <= kGatherChunkSlack ? end : next;
}

/* How a gather's sums go into its output rows: added to what the columns below `split` hold,
   written from it on, each first times weight[x] (by output column) where `weight` is given. A tile
   operator adds its node columns up this way (TileBankOperator::blocks); the default writes. */
struct GatherFold
{
    const float* weight = nullptr;
    int split = INT_MIN;
    bool writes() const { return weight == nullptr && split == INT_MIN; }
};

/* out[x] for x in [begin, end) from sums[x], as `fold` says (the 512-bit gathers do it in
   registers, alike). Cloned for the CPU's widest vectors: this file's own loops are built for the
   baseline's SSE, and a node column's rows added up by them took the tile-wise frame 1.3–1.5 % longer. */
DYNBLUR_SIMD_CLONES
void foldRow(const float* __restrict sums, const GatherFold& fold, int begin, int end, float* __restrict out)
{
    const int split = std::min(std::max(fold.split, begin), end);
    const float* __restrict weight = fold.weight;
    if (weight)
    {
        for (int x = begin; x < split; x++)
            out[x] += weight[x] * sums[x];
        for (int x = split; x < end; x++)
            out[x] = weight[x] * sums[x];
        return;
    }
    for (int x = begin; x < split; x++)
        out[x] += sums[x];
    for (int x = split; x < end; x++)
        out[x] = sums[x];
}

/* For the gathers that cannot fold their sums in themselves: gather(sums0, sums1) writes columns
   [begin, end) of two rows (the second may be unused) into a per-thread buffer, then both are
   folded into out0 and out1 (out1 may be null). */
template <typename Gather>
void gatherThenFold(const GatherFold& fold, int begin, int end, float* out0, float* out1, const Gather& gather)
{
    thread_local std::vector<float> sums;
    sums.resize(std::max(sums.size(), 2 * size_t(end)));
    gather(sums.data(), sums.data() + end);
    foldRow(sums.data(), fold, begin, end, out0);
    if (out1)
        foldRow(sums.data() + end, fold, begin, end, out1);
}

/* Blocks of `Vectors` × 8 columns of one gathered row from x while they fit before `end`, one FMA
   chain per vector; returns where it stopped. Inlined into each ISA clone of its caller, and fully
   unrolled there, so the sums stay in registers. */
template <int Vectors>
__attribute__((always_inline)) inline int gatherColumns(float* __restrict out, const float* source, size_t sourceStep,
                         const RowBankOperator::Tap* taps, int tapCount, int x, int end)
{
    typedef float v8 __attribute__((vector_size(32), aligned(4)));  // aligned(4): unaligned loads allowed
    for (; x + 8 * Vectors <= end; x += 8 * Vectors)
    {
        v8 s[Vectors] = {};
        for (int t = 0; t < tapCount; t++)
        {
            const float* p = source + size_t(taps[t].row) * sourceStep + (taps[t].col + x);
            const v8 w = v8{} + taps[t].weight;
#pragma GCC unroll 8
            for (int k = 0; k < Vectors; k++)
                s[k] += w * *(const v8*)(p + 8 * k);
        }
#pragma GCC unroll 8
        for (int k = 0; k < Vectors; k++)
            *(v8*)(out + x + 8 * k) = s[k];
    }
    return x;
}

/* out[x] = Σ_t w_t · source(row_t, x + col_t) for x in [begin, end), every read inside `source`.
   Eight 8-float sums stay in registers while all taps stream past (one load and one FMA per tap
   and vector, one store per output vector): with the tap loop outermost each tap would instead
   load, add and store the whole output row again. */
DYNBLUR_SIMD_CLONES
void gatherInterior(float* __restrict out, const float* source, size_t sourceStep,
                    const RowBankOperator::Tap* taps, int tapCount, int begin, int end)
{
    typedef float v8 __attribute__((vector_size(32), aligned(4)));  // aligned(4): unaligned loads allowed
    int x = begin;
    x = gatherColumns<8>(out, source, sourceStep, taps, tapCount, x, end);
    // Narrower tails still keep four chains: one 8-float sum would wait on each FMA's latency.
    x = gatherColumns<4>(out, source, sourceStep, taps, tapCount, x, end);
    for (; x + 8 <= end; x += 8)
    {
        v8 s = {};
        for (int t = 0; t < tapCount; t++)
            s += (v8{} + taps[t].weight) *
                 *(const v8*)(source + size_t(taps[t].row) * sourceStep + (taps[t].col + x));
        *(v8*)(out + x) = s;
    }
    for (; x < end; x++)
    {
        float s = 0.f;
        for (int t = 0; t < tapCount; t++)
            s += taps[t].weight * source[size_t(taps[t].row) * sourceStep + size_t(taps[t].col + x)];
        out[x] = s;
    }
}

/* Two output rows at once, out0[x] = Σ_t w_t[0] · source(row_t, x + col_t) and out1 likewise, for
   x in [begin, end), every read inside `source`. Neighbouring rows read nearly the same source rows,
   so each vector loaded feeds two FMA chains: loads, not FMAs, bound the one-row gather. Four
   vectors per row keep 8 sums, 4 loads and 2 weights within AVX2's 16 registers. */
DYNBLUR_SIMD_CLONES
void gatherPairInterior(float* __restrict out0, float* __restrict out1, const float* source, size_t sourceStep,
                        const RowBankOperator::PairTap* taps, int tapCount, int begin, int end, const GatherFold& fold)
{
    if (!fold.writes())
        return gatherThenFold(fold, begin, end, out0, out1, [&](float* sums0, float* sums1) {
            gatherPairInterior(sums0, sums1, source, sourceStep, taps, tapCount, begin, end, GatherFold());
        });
    typedef float v8 __attribute__((vector_size(32), aligned(4)));
    int x = begin;
    for (; x + 32 <= end; x += 32)
    {
        v8 a0 = {}, a1 = {}, a2 = {}, a3 = {}, b0 = {}, b1 = {}, b2 = {}, b3 = {};
        for (int t = 0; t < tapCount; t++)
        {
            const float* p = source + size_t(taps[t].row) * sourceStep + (taps[t].col + x);
            const v8 w = v8{} + taps[t].weight[0], u = v8{} + taps[t].weight[1];
            const v8 l0 = *(const v8*)(p), l1 = *(const v8*)(p + 8), l2 = *(const v8*)(p + 16),
                     l3 = *(const v8*)(p + 24);
            a0 += w * l0;
            a1 += w * l1;
            a2 += w * l2;
            a3 += w * l3;
            b0 += u * l0;
            b1 += u * l1;
            b2 += u * l2;
            b3 += u * l3;
        }
        *(v8*)(out0 + x) = a0;
        *(v8*)(out0 + x + 8) = a1;
        *(v8*)(out0 + x + 16) = a2;
        *(v8*)(out0 + x + 24) = a3;
        *(v8*)(out1 + x) = b0;
        *(v8*)(out1 + x + 8) = b1;
        *(v8*)(out1 + x + 16) = b2;
        *(v8*)(out1 + x + 24) = b3;
    }
    for (; x + 8 <= end; x += 8)
    {
        v8 a = {}, b = {};
        for (int t = 0; t < tapCount; t++)
        {
            const v8 l = *(const v8*)(source + size_t(taps[t].row) * sourceStep + (taps[t].col + x));
            a += (v8{} + taps[t].weight[0]) * l;
            b += (v8{} + taps[t].weight[1]) * l;
        }
        *(v8*)(out0 + x) = a;
        *(v8*)(out1 + x) = b;
    }
    for (; x < end; x++)
    {
        float a = 0.f, b = 0.f;
        for (int t = 0; t < tapCount; t++)
        {
            const float l = source[size_t(taps[t].row) * sourceStep + size_t(taps[t].col + x)];
            a += taps[t].weight[0] * l;
            b += taps[t].weight[1] * l;
        }
        out0[x] = a;
        out1[x] = b;
    }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define DYNBLUR_AVX512_TARGET __attribute__((target("avx512f,avx2,fma")))

//! The lanes of the last of `Vectors` 16-column vectors from x before `end` (end − x > 16 · (Vectors − 1)).
template <int Vectors>
inline __mmask16 lastVectorMask(int x, int end)
{
    return __mmask16(0xffffu >> (16 - (end - x - 16 * (Vectors - 1))));
}

//! The sums of a block of both output rows: full vectors, then the last one masked.
template <int Vectors>
DYNBLUR_AVX512_TARGET __attribute__((always_inline)) inline void
storeBlock(float* __restrict out0, float* __restrict out1, int x, __mmask16 last, const __m512 (&a)[Vectors],
           const __m512 (&b)[Vectors])
{
#pragma GCC unroll 16
    for (int k = 0; k + 1 < Vectors; k++)
    {
        _mm512_storeu_ps(out0 + x + 16 * k, a[k]);
        _mm512_storeu_ps(out1 + x + 16 * k, b[k]);
    }
    _mm512_mask_storeu_ps(out0 + x + 16 * (Vectors - 1), last, a[Vectors - 1]);
    _mm512_mask_storeu_ps(out1 + x + 16 * (Vectors - 1), last, b[Vectors - 1]);
}

/* storeBlock as `fold` says: the added lanes as weight · sum + out in one rounding (foldRow's
   loop, contracted to an FMA, gives the same), the written ones as weight · sum. */
template <int Vectors>
DYNBLUR_AVX512_TARGET __attribute__((always_inline)) inline void
foldBlock(float* __restrict out0, float* __restrict out1, int x, __mmask16 last, const __m512 (&a)[Vectors],
          const __m512 (&b)[Vectors], const GatherFold& fold)
{
    if (fold.writes())
    {
        storeBlock<Vectors>(out0, out1, x, last, a, b);
        return;
    }
#pragma GCC unroll 16
    for (int k = 0; k < Vectors; k++)
    {
        const int col = x + 16 * k;
        const __mmask16 lanes = k + 1 < Vectors ? __mmask16(0xffffu) : last;
        const int added = std::min(16, std::max(0, fold.split - col));
        const __mmask16 add = lanes & __mmask16(added >= 16 ? 0xffffu : (1u << added) - 1u);
        __m512 sa = a[k], sb = b[k];
        if (fold.weight)
        {
            const __m512 w = _mm512_maskz_loadu_ps(lanes, fold.weight + col);
            const __m512 wa = _mm512_mul_ps(w, sa), wb = _mm512_mul_ps(w, sb);
            if (add)
            {
                sa = _mm512_mask_fmadd_ps(sa, add, w, _mm512_maskz_loadu_ps(add, out0 + col));
                sb = _mm512_mask_fmadd_ps(sb, add, w, _mm512_maskz_loadu_ps(add, out1 + col));
            }
            sa = _mm512_mask_mov_ps(wa, add, sa);
            sb = _mm512_mask_mov_ps(wb, add, sb);
        }
        else if (add)
        {
            sa = _mm512_mask_add_ps(sa, add, sa, _mm512_maskz_loadu_ps(add, out0 + col));
            sb = _mm512_mask_add_ps(sb, add, sb, _mm512_maskz_loadu_ps(add, out1 + col));
        }
        _mm512_mask_storeu_ps(out0 + col, lanes, sa);
        _mm512_mask_storeu_ps(out1 + col, lanes, sb);
    }
}

/* Up to Vectors × 16 columns of both output rows from x (the last vector cut by `end`), as
   gatherPackedBlockBf16 does it for packed sources. */
template <int Vectors>
DYNBLUR_AVX512_TARGET __attribute__((always_inline)) inline void
gatherPairBlockAvx512(float* __restrict out0, float* __restrict out1, const float* source, size_t sourceStep,
                      const RowBankOperator::PairTap* taps, int tapCount, int x, int end, const GatherFold& fold)
{
    const __mmask16 last = lastVectorMask<Vectors>(x, end);
    __m512 a[Vectors], b[Vectors];
#pragma GCC unroll 16
    for (int k = 0; k < Vectors; k++)
        a[k] = b[k] = _mm512_setzero_ps();
    for (int t = 0; t < tapCount; t++)
    {
        const float* p = source + size_t(taps[t].row) * sourceStep + (taps[t].col + x);
        const __m512 w = _mm512_set1_ps(taps[t].weight[0]), u = _mm512_set1_ps(taps[t].weight[1]);
#pragma GCC unroll 16
        for (int k = 0; k < Vectors; k++)
        {
            const __m512 l = k + 1 < Vectors ? _mm512_loadu_ps(p + 16 * k) : _mm512_maskz_loadu_ps(last, p + 16 * k);
            a[k] = _mm512_fmadd_ps(w, l, a[k]);
            b[k] = _mm512_fmadd_ps(u, l, b[k]);
        }
    }
    foldBlock<Vectors>(out0, out1, x, last, a, b, fold);
}

/* gatherPairInterior in 512-bit vectors: on an Intel Xeon a zmm FMA does 1.46× the multiply-adds
   of a ymm one per cycle, and masked loads leave no scalar tail; on an AMD Zen 4, where 512-bit
   work is double-pumped, the 256-bit kernel still took 13–15 % longer (frame-rate frames, float
   blurs). */
DYNBLUR_AVX512_TARGET void gatherPairInteriorAvx512(float* __restrict out0, float* __restrict out1, const float* source,
                                                    size_t sourceStep, const RowBankOperator::PairTap* taps,
                                                    int tapCount, int begin, int end, const GatherFold& fold)
{
    int x = begin;
    for (int stop; (stop = chunkEnd(x, end)) < end; x = stop)
        gatherPairBlockAvx512<8>(out0, out1, source, sourceStep, taps, tapCount, x, stop, fold);
    switch ((end - x + 15) / 16)
    {
    case 10: gatherPairBlockAvx512<10>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 9: gatherPairBlockAvx512<9>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 8: gatherPairBlockAvx512<8>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 7: gatherPairBlockAvx512<7>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 6: gatherPairBlockAvx512<6>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 5: gatherPairBlockAvx512<5>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 4: gatherPairBlockAvx512<4>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 3: gatherPairBlockAvx512<3>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 2: gatherPairBlockAvx512<2>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 1: gatherPairBlockAvx512<1>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    default: break;
    }
}
#endif

typedef void (*PairKernel)(float* __restrict, float* __restrict, const float*, size_t, const RowBankOperator::PairTap*,
                           int, int, int, const GatherFold&);

//! Gathers use the kernels of a CPU without AVX-512 (setPortableGathers).
std::atomic<bool> portableGathers{false};

//! The pair gather for this CPU, chosen once.
PairKernel pairKernel()
{
    static const PairKernel best = [] {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
        if (__builtin_cpu_supports("avx512f"))
            return PairKernel(gatherPairInteriorAvx512);
#endif
        return PairKernel(gatherPairInterior);
    }();
    return portableGathers.load(std::memory_order_relaxed) ? PairKernel(gatherPairInterior) : best;
}

//! Columns [begin, end) of one gathered row: where every tap reads inside, fast; elsewhere checked.
void gatherRowRange(const Mat& source, const RowBankOperator::Tap* t, int count, const RowBankOperator::GatherRow& row,
                    int begin, int end, float* out, const GatherFold& fold = GatherFold())
{
    if (begin >= end)
        return;
    if (!fold.writes())
        return gatherThenFold(fold, begin, end, out, nullptr, [&](float* sums, float*) {
            gatherRowRange(source, t, count, row, begin, end, sums);
        });
    const float* base = source.ptr<float>();
    const size_t step = source.step1();
    const int safeBegin = std::max(begin, row.safeBegin), safeEnd = std::min(end, row.safeEnd);
    if (safeBegin < safeEnd)
        gatherInterior(out, base, step, t, count, safeBegin, safeEnd);
    for (int x = begin; x < end; x++)
    {
        if (x == safeBegin && safeBegin < safeEnd)
            x = safeEnd;
        if (x >= end)
            break;
        float s = 0.f;
        for (int k = 0; k < count; k++)
        {
            const int c = x + t[k].col;
            if (c >= 0 && c < source.cols)
                s += t[k].weight * base[size_t(t[k].row) * step + size_t(c)];
        }
        out[x] = s;
    }
}

/* Rows [rows.start, rows.end) and columns `cols` of a gather, row r at out + (r − rows.start)·outStep,
   two rows at a time where a pair (2k, 2k+1) lies inside. Columns run in chunks across all the rows before the
   next chunk: neighbouring rows read nearly the same source rows, so a chunk's source stays in L1
   for the whole block instead of every row pulling its ~kernel-height source rows from L2 again. */
void gatherBlock(const Mat& source, const RowBankOperator::Gather& gather, const Range& rows, const Range& cols,
                 float* out, size_t outStep, const GatherFold& fold = GatherFold())
{
    int commonBegin = cols.start, commonEnd = cols.end;
    for (int r = rows.start; r < rows.end; r++)
    {
        commonBegin = std::max(commonBegin, gather.rows[size_t(r)].safeBegin);
        commonEnd = std::min(commonEnd, gather.rows[size_t(r)].safeEnd);
    }
    commonEnd = std::max(commonEnd, commonBegin);
    const PairKernel kernel = pairKernel();
    const float* base = source.ptr<float>();
    const size_t step = source.step1();
    auto single = [&](int r, int begin, int end) {
        const RowBankOperator::GatherRow& g = gather.rows[size_t(r)];
        float* o = out + size_t(r - rows.start) * outStep;
        const auto row = [&](float* sums, float*) {
            gatherInterior(sums, base, step, gather.taps.data() + g.begin, g.end - g.begin, begin, end);
        };
        if (fold.writes())
            row(o, nullptr);
        else
            gatherThenFold(fold, begin, end, o, nullptr, row);
    };
    for (int x = commonBegin, end; x < commonEnd; x = end)
    {
        end = chunkEnd(x, commonEnd);
        int r = rows.start;
        if (r % 2 != 0)
            single(r++, x, end);
        for (; r + 1 < rows.end; r += 2)
        {
            const RowBankOperator::GatherRow& g = gather.pairs[size_t(r / 2)];
            float* o = out + size_t(r - rows.start) * outStep;
            kernel(o, o + outStep, base, step, gather.pairTaps.data() + g.begin, g.end - g.begin, x, end, fold);
        }
        if (r < rows.end)
            single(r, x, end);
    }
    for (int r = rows.start; r < rows.end; r++)
    {
        const RowBankOperator::GatherRow& g = gather.rows[size_t(r)];
        float* o = out + size_t(r - rows.start) * outStep;
        gatherRowRange(source, gather.taps.data() + g.begin, g.end - g.begin, g, cols.start, commonBegin, o, fold);
        gatherRowRange(source, gather.taps.data() + g.begin, g.end - g.begin, g, commonEnd, cols.end, o, fold);
    }
}

/* Packed bfloat16 row pairs. A row kernel of a tilting camera runs down a column, so consecutive
   source rows meet the same column offset: AVX512-BF16's dot product of two bfloat16 pairs takes
   both in one instruction, twice the multiply-adds of a float FMA, and the packed plane is half
   the bytes. */

inline uint32_t roundToBfloat16(float v)
{
    const uint32_t bits = __builtin_bit_cast(uint32_t, v);
    return (bits + 0x7fffu + ((bits >> 16) & 1u)) >> 16;  // to nearest, ties to even
}

inline float lowBfloat16(uint32_t packed)
{
    return __builtin_bit_cast(float, packed << 16);
}

inline float highBfloat16(uint32_t packed)
{
    return __builtin_bit_cast(float, packed & 0xffff0000u);
}

//! The dot product of two bfloat16 pairs (each in one 32-bit word), in float.
inline float packedDot(uint32_t a, uint32_t b)
{
    return lowBfloat16(a) * lowBfloat16(b) + highBfloat16(a) * highBfloat16(b);
}

//! The packed pair gathers' last columns [begin, end), one at a time.
void gatherPackedTail(float* __restrict out0, float* __restrict out1, const uint32_t* source, size_t sourceStep,
                      const RowBankOperator::PackedTap* taps, int tapCount, int begin, int end)
{
    for (int x = begin; x < end; x++)
    {
        float a = 0.f, b = 0.f;
        for (int t = 0; t < tapCount; t++)
        {
            const uint32_t l = source[size_t(taps[t].pair) * sourceStep + size_t(taps[t].col + x)];
            a += packedDot(taps[t].weight[0], l);
            b += packedDot(taps[t].weight[1], l);
        }
        out0[x] = a;
        out1[x] = b;
    }
}

typedef void (*PackedPairKernel)(float* __restrict, float* __restrict, const uint32_t*, size_t,
                                 const RowBankOperator::PackedTap*, int, int, int, const GatherFold&);

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define DYNBLUR_BF16_TARGET __attribute__((target("avx512bf16,avx512vl,avx512f,avx2,fma")))

/* Up to Vectors × 16 columns of both output rows from x (the last vector cut by `end`): one sum per
   vector and row in a zmm register while all taps stream past. The last vector's masked load reads
   nothing past `end`, so a support whose width is not a multiple of 16 needs no scalar tail; only
   it is masked (a mask per vector would need more than the seven mask registers at 9 and 10). The
   loops over the vectors are unrolled by pragma: GCC otherwise unrolled them after giving the sums
   a place on the stack, and a row's last, masked block stored every sum there at every tap (the
   tile-wise frame took 4–10 % longer, alternating frame by frame). */
template <int Vectors>
DYNBLUR_BF16_TARGET __attribute__((always_inline)) inline void
gatherPackedBlockBf16(float* __restrict out0, float* __restrict out1, const uint32_t* source, size_t sourceStep,
                      const RowBankOperator::PackedTap* taps, int tapCount, int x, int end, const GatherFold& fold)
{
    const __mmask16 last = lastVectorMask<Vectors>(x, end);
    __m512 a[Vectors], b[Vectors];
#pragma GCC unroll 16
    for (int k = 0; k < Vectors; k++)
        a[k] = b[k] = _mm512_setzero_ps();
    for (int t = 0; t < tapCount; t++)
    {
        const uint32_t* p = source + size_t(taps[t].pair) * sourceStep + (taps[t].col + x);
        const __m512bh w = (__m512bh)_mm512_set1_epi32(int(taps[t].weight[0]));
        const __m512bh u = (__m512bh)_mm512_set1_epi32(int(taps[t].weight[1]));
#pragma GCC unroll 16
        for (int k = 0; k < Vectors; k++)
        {
            const __m512bh l = (__m512bh)(k + 1 < Vectors ? _mm512_loadu_si512(p + 16 * k)
                                                          : _mm512_maskz_loadu_epi32(last, p + 16 * k));
            a[k] = _mm512_dpbf16_ps(a[k], l, w);
            b[k] = _mm512_dpbf16_ps(b[k], l, u);
        }
    }
    foldBlock<Vectors>(out0, out1, x, last, a, b, fold);
}

/* out0[x], out1[x] = Σ_t dot(weight_t[k], packed(pair_t, x + col_t)) for x in [begin, end), every
   read inside: 128 columns at a time in sixteen 16-float sums (zmm: on an Intel Xeon a 512-bit
   vdpbf16ps does 1.44× the multiply-adds of a 256-bit one per cycle; where 512-bit work is
   double-pumped, as on AMD Zen 4, as many), the last up to 160 in one block (kGatherChunkSlack). */
DYNBLUR_BF16_TARGET void gatherPackedPairBf16(float* __restrict out0, float* __restrict out1, const uint32_t* source,
                                              size_t sourceStep, const RowBankOperator::PackedTap* taps, int tapCount,
                                              int begin, int end, const GatherFold& fold)
{
    int x = begin;
    for (int stop; (stop = chunkEnd(x, end)) < end; x = stop)
        gatherPackedBlockBf16<8>(out0, out1, source, sourceStep, taps, tapCount, x, stop, fold);
    switch ((end - x + 15) / 16)
    {
    case 10: gatherPackedBlockBf16<10>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 9: gatherPackedBlockBf16<9>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 8: gatherPackedBlockBf16<8>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 7: gatherPackedBlockBf16<7>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 6: gatherPackedBlockBf16<6>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 5: gatherPackedBlockBf16<5>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 4: gatherPackedBlockBf16<4>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 3: gatherPackedBlockBf16<3>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 2: gatherPackedBlockBf16<2>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    case 1: gatherPackedBlockBf16<1>(out0, out1, source, sourceStep, taps, tapCount, x, end, fold); break;
    default: break;
    }
}

#endif

//! gatherPackedPairBf16 for CPUs without AVX512-BF16: the halves widened to floats, two FMAs each.
DYNBLUR_SIMD_CLONES
void gatherPackedPairWidened(float* __restrict out0, float* __restrict out1, const uint32_t* source,
                             size_t sourceStep, const RowBankOperator::PackedTap* taps, int tapCount, int begin,
                             int end, const GatherFold& fold)
{
    if (!fold.writes())
        return gatherThenFold(fold, begin, end, out0, out1, [&](float* sums0, float* sums1) {
            gatherPackedPairWidened(sums0, sums1, source, sourceStep, taps, tapCount, begin, end, GatherFold());
        });
    typedef float v8 __attribute__((vector_size(32), aligned(4)));
    typedef uint32_t v8u __attribute__((vector_size(32), aligned(4)));
    int x = begin;
    for (; x + 16 <= end; x += 16)
    {
        v8 a0 = {}, a1 = {}, b0 = {}, b1 = {};
        for (int t = 0; t < tapCount; t++)
        {
            const uint32_t* p = source + size_t(taps[t].pair) * sourceStep + (taps[t].col + x);
            const uint32_t w = taps[t].weight[0], u = taps[t].weight[1];
            const v8 wl = v8{} + lowBfloat16(w), wh = v8{} + highBfloat16(w);
            const v8 ul = v8{} + lowBfloat16(u), uh = v8{} + highBfloat16(u);
            const v8u p0 = *(const v8u*)p, p1 = *(const v8u*)(p + 8);
            const v8 l0 = (v8)(p0 << 16), h0 = (v8)(p0 & 0xffff0000u), l1 = (v8)(p1 << 16),
                     h1 = (v8)(p1 & 0xffff0000u);
            a0 += wl * l0 + wh * h0;
            a1 += wl * l1 + wh * h1;
            b0 += ul * l0 + uh * h0;
            b1 += ul * l1 + uh * h1;
        }
        *(v8*)(out0 + x) = a0;
        *(v8*)(out0 + x + 8) = a1;
        *(v8*)(out1 + x) = b0;
        *(v8*)(out1 + x + 8) = b1;
    }
    gatherPackedTail(out0, out1, source, sourceStep, taps, tapCount, x, end);
}

//! The packed pair gather for this CPU, chosen once, as pairKernel() chooses the float one.
PackedPairKernel packedPairKernel()
{
    static const PackedPairKernel best = [] {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
        if (__builtin_cpu_supports("avx512bf16"))
            return PackedPairKernel(gatherPackedPairBf16);
#endif
        return PackedPairKernel(gatherPackedPairWidened);
    }();
    return portableGathers.load(std::memory_order_relaxed) ? PackedPairKernel(gatherPackedPairWidened) : best;
}

/* Columns [begin, end) of output rows 2k, 2k + 1 of a packed gather, reads outside the source
   skipped (border columns). */
void gatherPackedRange(const Mat& packed, const RowBankOperator::PackedTap* taps, int count, int begin, int end,
                       float* out0, float* out1, const GatherFold& fold)
{
    if (begin >= end)
        return;
    if (!fold.writes())
        return gatherThenFold(fold, begin, end, out0, out1, [&](float* sums0, float* sums1) {
            gatherPackedRange(packed, taps, count, begin, end, sums0, sums1, GatherFold());
        });
    const uint32_t* base = packed.ptr<uint32_t>();
    const size_t step = packed.step1();
    for (int x = begin; x < end; x++)
    {
        float a = 0.f, b = 0.f;
        for (int t = 0; t < count; t++)
        {
            const int c = x + taps[t].col;
            if (c < 0 || c >= packed.cols)
                continue;
            const uint32_t l = base[size_t(taps[t].pair) * step + size_t(c)];
            a += packedDot(taps[t].weight[0], l);
            b += packedDot(taps[t].weight[1], l);
        }
        out0[x] = a;
        out1[x] = b;
    }
}

/* gatherBlock over a packed source: rows [rows.start, rows.end) (rows.start even) and columns
   `cols`, in the same column chunks; the second row of an odd last pair goes to a scratch row. */
void gatherPackedBlock(const Mat& packed, const RowBankOperator::PackedGather& gather, const Range& rows,
                       const Range& cols, float* out, size_t outStep, const GatherFold& fold = GatherFold())
{
    const PackedPairKernel kernel = packedPairKernel();
    CV_DbgAssert(rows.start % 2 == 0);
    const int pairBegin = rows.start / 2, pairEnd = (rows.end + 1) / 2;
    std::vector<float> scratch(rows.size() % 2 ? size_t(cols.end) : 0);
    const auto outputs = [&](int k, float*& o0, float*& o1) {
        o0 = out + size_t(2 * k - rows.start) * outStep;
        o1 = 2 * k + 1 < rows.end ? o0 + outStep : scratch.data();
    };
    int commonBegin = cols.start, commonEnd = cols.end;
    for (int k = pairBegin; k < pairEnd; k++)
    {
        commonBegin = std::max(commonBegin, gather.pairs[size_t(k)].safeBegin);
        commonEnd = std::min(commonEnd, gather.pairs[size_t(k)].safeEnd);
    }
    commonEnd = std::max(commonEnd, commonBegin);
    const uint32_t* base = packed.ptr<uint32_t>();
    const size_t step = packed.step1();
    float *o0, *o1;
    for (int x = commonBegin, end; x < commonEnd; x = end)
    {
        end = chunkEnd(x, commonEnd);
        for (int k = pairBegin; k < pairEnd; k++)
        {
            const RowBankOperator::GatherRow& g = gather.pairs[size_t(k)];
            outputs(k, o0, o1);
            kernel(o0, o1, base, step, gather.taps.data() + g.begin, g.end - g.begin, x, end, fold);
        }
    }
    for (int k = pairBegin; k < pairEnd; k++)
    {
        const RowBankOperator::GatherRow& g = gather.pairs[size_t(k)];
        outputs(k, o0, o1);
        gatherPackedRange(packed, gather.taps.data() + g.begin, g.end - g.begin, cols.start, commonBegin, o0, o1, fold);
        gatherPackedRange(packed, gather.taps.data() + g.begin, g.end - g.begin, commonEnd, cols.end, o0, o1, fold);
    }
}

/* The packed form of a gather whose rows are filled, each row's taps in (row, col) order
   (sourceWidth: the source's columns): output rows 2k and 2k + 1 together, each term taking source
   rows 2j and 2j + 1 at one column offset, weights rounded to bfloat16. Two linear merges per pair
   (a sort took a sixth of a tile-wise frame): the output rows' taps by (row, col), then each
   source row pair's two runs by column. */
void buildPacked(const RowBankOperator::Gather& gather, int outWidth, int sourceWidth,
                 RowBankOperator::PackedGather& packed)
{
    typedef RowBankOperator::Tap Tap;
    typedef RowBankOperator::PairTap PairTap;
    const int rows = int(gather.rows.size());
    typedef RowBankOperator::PackedTap PackedTap;
    buildGatherRows((rows + 1) / 2, packed.taps, packed.pairs, [&](int k, std::vector<PackedTap>& taps) {
        thread_local std::vector<PairTap> merged;
        const RowBankOperator::GatherRow& first = gather.rows[size_t(2 * k)];
        const RowBankOperator::GatherRow* second = 2 * k + 1 < rows ? &gather.rows[size_t(2 * k + 1)] : nullptr;
        merged.clear();
        forUnion(gather.taps.data() + first.begin, size_t(first.end - first.begin),
                 second ? gather.taps.data() + second->begin : nullptr, second ? size_t(second->end - second->begin) : 0,
                 [](const Tap& t) { return std::make_pair(t.row, t.col); },
                 [&](const Tap& t, float w0, float w1) { merged.push_back({t.row, t.col, {w0, w1}}); });
        RowBankOperator::GatherRow g;
        g.begin = int(taps.size());
        g.safeBegin = 0;
        g.safeEnd = outWidth;
        for (size_t i = 0; i < merged.size();)
        {
            // The run of source row 2j (empty when the pair starts at an odd row), then of 2j + 1.
            const int pair = merged[i].row / 2;
            size_t even = i;
            while (even < merged.size() && merged[even].row == 2 * pair)
                even++;
            size_t odd = even;
            while (odd < merged.size() && merged[odd].row == 2 * pair + 1)
                odd++;
            for (size_t p = i, q = even; p < even || q < odd;)
            {
                const bool takeEven = p < even && (q == odd || merged[p].col <= merged[q].col);
                const bool takeOdd = q < odd && (p == even || merged[q].col <= merged[p].col);
                const int col = takeEven ? merged[p].col : merged[q].col;
                PackedTap term{pair, col, {0u, 0u}};
                for (int o = 0; o < 2; o++)
                    term.weight[o] = (takeEven ? roundToBfloat16(merged[p].weight[o]) : 0u) |
                                     (takeOdd ? roundToBfloat16(merged[q].weight[o]) << 16 : 0u);
                taps.push_back(term);
                g.safeBegin = std::max(g.safeBegin, -col);
                g.safeEnd = std::min(g.safeEnd, sourceWidth - col);
                p += takeEven;
                q += takeOdd;
            }
            i = odd;
        }
        g.end = int(taps.size());
        g.safeBegin = std::min(g.safeBegin, outWidth);
        g.safeEnd = std::max(g.safeEnd, g.safeBegin);
        return g;
    });
}

/* The packed adjoint transposed from the packed forward gather: a forward tap (frame pair k, latent
   pair g, column colBase + dx) holds the 2×2 block of A between frame rows 2k + o and latent rows
   2g + h, so Aᵀ's block between latent pair g and frame pair k is the same four weights with o and
   h swapped, read at column adjointColBase − dx. Both gathers list a pair's taps by source pair,
   then by column ascending: a forward block's run (dx ascending) goes in reversed. The adjoint is
   then the packed forward's to the bit, in the time of a counting sort (transposing the float lists,
   sorting them and packing them again, or walking a tile column's kernels again, took longer). */
void transposePackedGather(const RowBankOperator::PackedGather& forward, int colBase, int outRows, int adjointColBase,
                           int outWidth, int sourceWidth, RowBankOperator::PackedGather& adjoint)
{
    const size_t pairs = size_t((outRows + 1) / 2);
    std::vector<int> start(pairs + 1, 0);  // each adjoint pair's first tap
    for (const RowBankOperator::PackedTap& t : forward.taps)
        start[size_t(t.pair) + 1]++;
    for (size_t g = 0; g < pairs; g++)
        start[g + 1] += start[g];
    adjoint.taps.resize(forward.taps.size());
    adjoint.pairs.assign(pairs, RowBankOperator::GatherRow());
    std::vector<int> next(start.begin(), start.end() - 1);
    std::vector<int> safeBegin(pairs, 0), safeEnd(pairs, outWidth);
    for (int k = 0; k < int(forward.pairs.size()); k++)
    {
        const RowBankOperator::GatherRow& row = forward.pairs[size_t(k)];
        for (int runEnd = row.begin; runEnd < row.end;)
        {
            const int runBegin = runEnd, g = forward.taps[size_t(runBegin)].pair;
            while (runEnd < row.end && forward.taps[size_t(runEnd)].pair == g)
                runEnd++;
            int& at = next[size_t(g)];
            for (int t = runEnd - 1; t >= runBegin; t--)
            {
                const RowBankOperator::PackedTap& f = forward.taps[size_t(t)];
                const int col = adjointColBase - (f.col - colBase);
                adjoint.taps[size_t(at++)] = {k, col,
                                              {(f.weight[0] & 0xFFFFu) | (f.weight[1] << 16),
                                               (f.weight[0] >> 16) | (f.weight[1] & 0xFFFF0000u)}};
                safeBegin[size_t(g)] = std::max(safeBegin[size_t(g)], -col);
                safeEnd[size_t(g)] = std::min(safeEnd[size_t(g)], sourceWidth - col);
            }
        }
    }
    for (size_t g = 0; g < pairs; g++)
    {
        RowBankOperator::GatherRow& row = adjoint.pairs[g];
        row.begin = start[g];
        row.end = start[g + 1];
        row.safeBegin = std::min(safeBegin[g], outWidth);
        row.safeEnd = std::max(safeEnd[g], row.safeBegin);
    }
}

//! dst = src ⊙ weight over n packed pairs (both halves of element x times weight[x]), re-rounded.
DYNBLUR_SIMD_CLONES
void scalePackedRow(const uint32_t* __restrict src, const float* __restrict weight, int n, uint32_t* __restrict dst)
{
    for (int x = 0; x < n; x++)
        dst[x] = roundToBfloat16(lowBfloat16(src[x]) * weight[x]) |
                 (roundToBfloat16(highBfloat16(src[x]) * weight[x]) << 16);
}

/* The inner loops: contiguous, restrict-qualified so the compiler vectorises them, and cloned for
   the CPU's widest vectors (this file is built for the baseline's SSE). */
DYNBLUR_SIMD_CLONES
void accumulateScaled(float* __restrict dst, const float* __restrict src, float w, int begin, int end)
{
    for (int x = begin; x < end; x++)
        dst[x] += w * src[x];
}

DYNBLUR_SIMD_CLONES
void multiplyInto(float* __restrict dst, const float* __restrict a, const float* __restrict b, int n)
{
    for (int x = 0; x < n; x++)
        dst[x] = a[x] * b[x];
}

//! bankSpotGain, given the smallest of the kernels' peaks.
double spotGainOf(const PsfBank& bank, double smallestPeak)
{
    const double blended = double(std::min<size_t>(bank.nodeRows.size(), 2) * std::min<size_t>(bank.nodeCols.size(), 2));
    return smallestPeak > 0 ? blended / smallestPeak : 1.0;
}

}  // namespace

double bankSpotGain(const PsfBank& bank)
{
    // A tile bank holds ~10⁴ kernels: their peaks in parallel (serially they took 3 ms).
    std::mutex mutex;
    double smallestPeak = 1;
    parallel_for_(Range(0, int(bank.kernels.size())), [&](const Range& range) {
        double smallest = 1;
        for (int n = range.start; n < range.end; n++)
        {
            double peak = 0;
            minMaxLoc(bank.kernels[size_t(n)], nullptr, &peak);
            smallest = std::min(smallest, peak);
        }
        std::lock_guard<std::mutex> lock(mutex);
        smallestPeak = std::min(smallestPeak, smallest);
    });
    return spotGainOf(bank, smallestPeak);
}

std::vector<Point> displacementShifts(const PsfBank& bank)
{
    std::vector<Point> shifts(bank.shifts.size());
    // A tile bank holds ~10⁴ kernels: plain sums in parallel, where cv::moments took 9 ms serially.
    parallel_for_(Range(0, int(bank.kernels.size())), [&](const Range& range) {
        Mat converted;
        std::vector<double> columnMass, columnMoment;  // of each kernel column: Σ k, Σ v·k
        for (int n = range.start; n < range.end; n++)
        {
            const Mat& kernel = bank.kernels[size_t(n)];
            if (kernel.type() != CV_32F)
                kernel.convertTo(converted, CV_32F);
            const Mat& k = kernel.type() == CV_32F ? kernel : converted;
            /* Column sums first: one chain of additions per column, side by side, where a sum along
               each row waits on its previous element (a tile kernel's rows are ~5 wide). */
            columnMass.assign(size_t(k.cols), 0.0);
            columnMoment.assign(size_t(k.cols), 0.0);
            for (int v = 0; v < k.rows; v++)
            {
                const float* row = k.ptr<float>(v);
                for (int u = 0; u < k.cols; u++)
                {
                    columnMass[size_t(u)] += row[u];
                    columnMoment[size_t(u)] += double(v) * row[u];
                }
            }
            double mass = 0, sumU = 0, sumV = 0;
            for (int u = 0; u < k.cols; u++)
            {
                mass += columnMass[size_t(u)];
                sumU += double(u) * columnMass[size_t(u)];
                sumV += columnMoment[size_t(u)];
            }
            const Point centre((k.cols - 1) / 2, (k.rows - 1) / 2);
            const Point centroid = mass > 0 ? Point(cvRound(sumU / mass), cvRound(sumV / mass)) : centre;
            shifts[size_t(n)] = bank.shifts[size_t(n)] + centroid - centre;
        }
    });
    return shifts;
}

namespace {

/* sum[x] += scale · columnWeight[x] · source[x]: a node column's share of one frame row, as
   displacementAdjoint adds it. */
DYNBLUR_SIMD_CLONES
void addColumnWeightedRow(const float* __restrict columnWeight, const float* __restrict source, float scale, int n,
                          float* __restrict sum)
{
    for (int x = 0; x < n; x++)
        sum[x] += scale * columnWeight[x] * source[x];
}

}  // namespace

void displacementAdjoint(const PsfBank& bank, const std::vector<Point>& shifts, Size latentSize, Point origin,
                         const std::vector<Mat>& frames,
                         const std::function<void(int, const float*, const float* const*)>& rowDone)
{
    const Size frame = bank.imageSize;
    const int nodeCols = int(bank.nodeCols.size());
    const std::vector<BankBlurOperator::AxisWeight> rowWeights = nodeRowWeights(bank, frame.height);
    const std::vector<BankBlurOperator::AxisWeight> colWeights = nodeColumnWeights(bank, frame.width);
    const std::vector<Range> colSupport = supports(colWeights, nodeCols);
    const std::vector<std::vector<float>> colWeight = supportWeights(colWeights, colSupport);

    /* One segment per frame row, node row blended into it and node column: the column's support in
       that row, moved by the node's shift into one latent row. Segments are filed by their latent
       row (a counting sort), so latent rows are summed in parallel, each in a fixed order, in a
       buffer that stays in cache until rowDone has used it. The general operators took 3 ms per
       plane (node-column copies and per-row tap lists), and summing into planes 2–3 ms for all. */
    struct Segment
    {
        int frameRow, node;
        float weight;  // the node row's blend weight
    };
    const auto forEachSegment = [&](const auto& emit) {
        for (int y = 0; y < frame.height; y++)
            for (int k = 0; k < 2; k++)
            {
                const BankBlurOperator::AxisWeight& rw = rowWeights[size_t(y)];
                if (!(rw.weight[k] > 0.f))  // also the second node at the outer rows, where both are one
                    continue;
                for (int c = 0; c < nodeCols; c++)
                {
                    const int node = rw.node[k] * nodeCols + c;
                    const int row = y - shifts[size_t(node)].y + origin.y;
                    if (row >= 0 && row < latentSize.height && !colSupport[size_t(c)].empty())
                        emit(row, Segment{y, node, rw.weight[k]});
                }
            }
    };
    std::vector<int> rowStart(size_t(latentSize.height) + 1, 0);
    forEachSegment([&](int row, const Segment&) { rowStart[size_t(row) + 1]++; });
    for (int row = 0; row < latentSize.height; row++)
        rowStart[size_t(row) + 1] += rowStart[size_t(row)];
    std::vector<Segment> segments(size_t(rowStart.back()));
    std::vector<int> filled(rowStart.begin(), rowStart.end() - 1);
    forEachSegment([&](int row, const Segment& s) { segments[size_t(filled[size_t(row)]++)] = s; });

    const int planes = int(frames.size()), width = latentSize.width;
    parallel_for_(Range(0, latentSize.height), [&](const Range& rows) {
        std::vector<float> sums(size_t(planes + 1) * size_t(width));  // the weight, then each plane's
        std::vector<float*> adjoints(static_cast<size_t>(planes));
        for (int p = 0; p < planes; p++)
            adjoints[size_t(p)] = &sums[size_t(p + 1) * size_t(width)];
        for (int row = rows.start; row < rows.end; row++)
        {
            std::fill(sums.begin(), sums.end(), 0.f);
            for (int i = rowStart[size_t(row)]; i < rowStart[size_t(row) + 1]; i++)
            {
                const Segment& s = segments[size_t(i)];
                const int c = s.node % nodeCols;
                const Range support = colSupport[size_t(c)];
                const int offset = origin.x - shifts[size_t(s.node)].x;  // latent column − frame column
                const int begin = std::max(support.start, -offset);
                const int end = std::min(support.end, width - offset);
                if (begin >= end)
                    continue;
                const float* columnWeight = colWeight[size_t(c)].data() + (begin - support.start);
                accumulateScaled(sums.data() + begin + offset, columnWeight, s.weight, 0, end - begin);
                for (int p = 0; p < planes; p++)
                    addColumnWeightedRow(columnWeight, frames[size_t(p)].ptr<float>(s.frameRow) + begin, s.weight,
                                         end - begin, adjoints[size_t(p)] + begin + offset);
            }
            rowDone(row, sums.data(), adjoints.data());
        }
    });
}

BankBlurOperator::BankBlurOperator(const PsfBank& bank, bool pad) : BlurOperator(bank.imageSize)
{
    spotGain_ = bankSpotGain(bank);
    nodeCols_ = int(bank.nodeCols.size());
    nodeRows_ = int(bank.nodeRows.size());
    nodes_.resize(bank.kernels.size());
    int dxMin = 0, dxMax = 0, dyMin = 0, dyMax = 0;
    for (size_t n = 0; n < bank.kernels.size(); n++)
    {
        Node& node = nodes_[n];
        for (const KernelTap& tap : kernelTaps(bank.kernels[n], bank.shifts[n]))
        {
            if (node.rows.empty() || node.rows.back().dy != tap.dy)
            {
                node.rows.emplace_back();
                node.rows.back().dy = tap.dy;
            }
            node.rows.back().dx.push_back(tap.dx);
            node.rows.back().weight.push_back(tap.weight);
            dxMin = std::min(dxMin, tap.dx);
            dxMax = std::max(dxMax, tap.dx);
            dyMin = std::min(dyMin, tap.dy);
            dyMax = std::max(dyMax, tap.dy);
        }
        if (!node.rows.empty())
        {
            node.dyMin = node.rows.front().dy;  // kernelTaps runs down the kernel: dy decreases
            node.dyMax = node.rows.back().dy;
            if (node.dyMin > node.dyMax)
                std::swap(node.dyMin, node.dyMax);
            node.rowOfDy.assign(size_t(node.dyMax - node.dyMin + 1), -1);
            for (size_t k = 0; k < node.rows.size(); k++)
                node.rowOfDy[size_t(node.rows[k].dy - node.dyMin)] = int(k);
        }
    }
    domain(frame_, pad, dxMin, dxMax, dyMin, dyMax, latent_, origin_);
    dyMin_ = dyMin;
    dyMax_ = dyMax;

    rowWeights_ = nodeRowWeights(bank, frame_.height);
    nodeRowSupport_ = supports(rowWeights_, nodeRows_);
    const std::vector<AxisWeight> colWeights = nodeColumnWeights(bank, frame_.width);
    nodeColSupport_ = supports(colWeights, nodeCols_);
    colWeight_ = supportWeights(colWeights, nodeColSupport_);
}

float BankBlurOperator::rowWeight(int nodeRow, int frameRow) const
{
    const AxisWeight& w = rowWeights_[size_t(frameRow)];
    return (w.node[0] == nodeRow ? w.weight[0] : 0.f) + (w.node[1] == nodeRow ? w.weight[1] : 0.f);
}

void BankBlurOperator::forward(const Mat& latent, Mat& frame)
{
    CV_DbgAssert(latent.type() == CV_32FC1 && latent.size() == latent_);
    frame.create(frame_, CV_32FC1);
    parallel_for_(Range(0, frame_.height), [&](const Range& rows) { forwardRows(latent, frame, rows); });
}

void BankBlurOperator::adjoint(const Mat& frame, Mat& latent)
{
    CV_DbgAssert(frame.type() == CV_32FC1 && frame.size() == frame_);
    latent.create(latent_, CV_32FC1);
    if (nodeCols_ > 1)
    {
        /* The frame weighted by each node column's weight, once per call rather than once per tap
           row: columns of one parity have disjoint supports, so two planes hold them all. */
        for (Mat& w : weighted_)
            w.create(frame_, CV_32FC1);
        parallel_for_(Range(0, frame_.height), [&](const Range& rows) {
            for (int r = rows.start; r < rows.end; r++)
            {
                const float* src = frame.ptr<float>(r);
                for (int i = 0; i < nodeCols_; i++)
                {
                    const Range cols = nodeColSupport_[size_t(i)];
                    multiplyInto(weighted_[i % 2].ptr<float>(r) + cols.start, colWeight_[size_t(i)].data(),
                                 src + cols.start, cols.size());
                }
            }
        });
    }
    parallel_for_(Range(0, latent_.height), [&](const Range& rows) { adjointRows(frame, latent, rows); });
}

void BankBlurOperator::forwardRows(const Mat& latent, Mat& frame, const Range& rows) const
{
    const int width = frame_.width;
    std::vector<float> tile(nodeCols_ > 1 ? size_t(width) : 0);
    for (int y = rows.start; y < rows.end; y++)
    {
        float* out = frame.ptr<float>(y);
        std::memset(out, 0, sizeof(float) * size_t(width));
        const AxisWeight& rw = rowWeights_[size_t(y)];
        for (int k = 0; k < 2; k++)
        {
            const float a = rw.weight[k];
            if (a <= 0.f)
                continue;
            const int j = rw.node[k];
            for (int i = 0; i < nodeCols_; i++)
            {
                const Node& node = nodes_[size_t(j * nodeCols_ + i)];
                const Range cols = nodeColSupport_[size_t(i)];
                // Row-variant banks (one node column) accumulate straight into the output.
                float* target = out;
                float scale = a;
                if (nodeCols_ > 1)
                {
                    target = tile.data();
                    scale = 1.f;
                    std::fill(tile.begin() + cols.start, tile.begin() + cols.end, 0.f);
                }
                for (const TapRow& tr : node.rows)
                {
                    const int ly = y + tr.dy + origin_.y;
                    if (ly < 0 || ly >= latent_.height)
                        continue;
                    const float* lrow = latent.ptr<float>(ly);
                    for (size_t t = 0; t < tr.dx.size(); t++)
                    {
                        const int off = tr.dx[t] + origin_.x;
                        const int begin = std::max(cols.start, -off);
                        const int end = std::min(cols.end, latent_.width - off);
                        if (begin < end)
                            accumulateScaled(target, lrow + off, scale * tr.weight[t], begin, end);
                    }
                }
                if (nodeCols_ > 1)
                {
                    const float* cw = colWeight_[size_t(i)].data() - cols.start;
                    for (int x = cols.start; x < cols.end; x++)
                        out[x] += a * cw[x] * tile[size_t(x)];
                }
            }
        }
    }
}

void BankBlurOperator::adjointRows(const Mat& frame, Mat& latent, const Range& rows) const
{
    for (int ly = rows.start; ly < rows.end; ly++)
    {
        float* out = latent.ptr<float>(ly);
        std::memset(out, 0, sizeof(float) * size_t(latent_.width));
        const int qy = ly - origin_.y;  // frame coordinate of this latent row
        /* Frame rows that read this latent row lie in [qy − dyMax_, qy − dyMin_]; node rows are in
           order, so only those whose support meets that range need a look. */
        const int rowLow = qy - dyMax_, rowHigh = qy - dyMin_;
        int j = int(std::lower_bound(nodeRowSupport_.begin(), nodeRowSupport_.end(), rowLow,
                                     [](const Range& r, int row) { return r.end <= row; }) -
                    nodeRowSupport_.begin());
        for (; j < nodeRows_ && nodeRowSupport_[size_t(j)].start <= rowHigh; j++)
        {
            const Range support = nodeRowSupport_[size_t(j)];
            for (int i = 0; i < nodeCols_; i++)
            {
                const Node& node = nodes_[size_t(j * nodeCols_ + i)];
                // Frame row r reads latent row r + dy: this node touches qy only if r = qy − dy
                // can fall inside its row support.
                if (node.rows.empty() || qy - node.dyMin < support.start || qy - node.dyMax >= support.end)
                    continue;
                const Range cols = nodeColSupport_[size_t(i)];
                // Only the tap rows whose frame row r = qy − dy lies in the support: look them up by dy.
                const int dyLow = std::max(node.dyMin, qy - support.end + 1);
                const int dyHigh = std::min(node.dyMax, qy - support.start);
                for (int dy = dyLow; dy <= dyHigh; dy++)
                {
                    const int k = node.rowOfDy[size_t(dy - node.dyMin)];
                    if (k < 0)
                        continue;
                    const TapRow& tr = node.rows[size_t(k)];
                    const int r = qy - tr.dy;
                    const float a = rowWeight(j, r);
                    if (a <= 0.f)
                        continue;
                    const float* src = nodeCols_ > 1 ? weighted_[i % 2].ptr<float>(r) : frame.ptr<float>(r);
                    for (size_t t = 0; t < tr.dx.size(); t++)
                    {
                        // Frame col x read latent col x + off: scatter back along the row.
                        const int off = tr.dx[t] + origin_.x;
                        const int begin = std::max(cols.start, -off);
                        const int end = std::min(cols.end, latent_.width - off);
                        if (begin < end)
                            accumulateScaled(out + off, src, a * tr.weight[t], begin, end);
                    }
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Bank with one node column: gathered rows.

namespace {

//! Output columns [begin, end) of a row of `width` where every tap reads inside [0, sourceWidth).
void safeColumns(const RowBankOperator::Tap* taps, int count, int width, int sourceWidth, int& begin, int& end)
{
    begin = 0;
    end = width;
    for (int k = 0; k < count; k++)
    {
        begin = std::max(begin, -taps[k].col);
        end = std::min(end, sourceWidth - taps[k].col);
    }
    begin = std::min(begin, width);
    end = std::max(end, begin);
}

/* The row pairs (2k, 2k+1) of a gather whose rows are filled, each row's taps in (row, col) order:
   each pair's taps are the union of its rows' taps, with both rows' weights (0 where a row has no
   such tap). */
void buildPairs(RowBankOperator::Gather& gather)
{
    const int pairCount = int(gather.rows.size()) / 2;
    gather.pairs.assign(size_t(pairCount), RowBankOperator::GatherRow());
    gather.pairTaps.clear();
    // A pair's union holds at most both rows' taps; the list is trimmed to what it holds after.
    gather.pairTaps.reserve(gather.taps.size());
    for (int k = 0; k < pairCount; k++)
    {
        const RowBankOperator::GatherRow &first = gather.rows[size_t(2 * k)], &second = gather.rows[size_t(2 * k + 1)];
        RowBankOperator::GatherRow& g = gather.pairs[size_t(k)];
        g.begin = int(gather.pairTaps.size());
        forUnion(gather.taps.data() + first.begin, size_t(first.end - first.begin), gather.taps.data() + second.begin,
                 size_t(second.end - second.begin),
                 [](const RowBankOperator::Tap& t) { return std::make_pair(t.row, t.col); },
                 [&](const RowBankOperator::Tap& t, float w0, float w1) {
                     gather.pairTaps.push_back({t.row, t.col, {w0, w1}});
                 });
        g.end = int(gather.pairTaps.size());
    }
    gather.pairTaps.shrink_to_fit();
}

}  // namespace

RowBankOperator::RowBankOperator(const PsfBank& bank, bool pad, bool packed)
    : BlurOperator(bank.imageSize, packed)
{
    CV_Assert(bank.nodeCols.size() == 1 && bank.kernels.size() == bank.nodeRows.size());
    int dxMin, dxMax, dyMin, dyMax;
    const NodeTaps nodes(bank, dxMin, dxMax, dyMin, dyMax);
    spotGain_ = spotGainOf(bank, nodes.smallestPeak());
    domain(frame_, pad, dxMin, dxMax, dyMin, dyMax, latent_, origin_);

    // Each frame row's kernel: its row nodes' taps, weighted and merged; reads of latent rows
    // outside the domain (possible without padding) read zero and are dropped.
    const std::vector<BankBlurOperator::AxisWeight> rowWeights = nodeRowWeights(bank, frame_.height);
    buildGatherRows(frame_.height, forward_.taps, forward_.rows, [&](int y, std::vector<Tap>& taps) {
        GatherRow g;
        g.begin = int(taps.size());
        const BankBlurOperator::AxisWeight& w = rowWeights[size_t(y)];
        // Both node kernels are in (dy, dx) order, so their union is a merge, not a sort.
        forUnion(nodes.taps(w.node[0]), w.weight[0] > 0.f ? nodes.count(w.node[0]) : 0, nodes.taps(w.node[1]),
                 w.weight[1] > 0.f ? nodes.count(w.node[1]) : 0,
                 [](const KernelTap& t) { return std::make_pair(t.dy, t.dx); },
                 [&](const KernelTap& t, float wa, float wb) {
                     const int ly = y + t.dy + origin_.y;
                     if (ly >= 0 && ly < latent_.height)
                         taps.push_back({ly, t.dx + origin_.x, w.weight[0] * wa + w.weight[1] * wb});
                 });
        g.end = int(taps.size());
        safeColumns(taps.data() + g.begin, g.end - g.begin, frame_.width, latent_.width, g.safeBegin, g.safeEnd);
        return g;
    });

    if (packed_)
    {
        buildPacked(forward_, frame_.width, latent_.width, packedForward_);
        transposePackedGather(packedForward_, 0, latent_.height, 0, latent_.width, frame_.width, packedAdjoint_);
        forward_ = Gather();
        return;
    }
    // Transpose: frame pixel (x, y) reads latent (x + col, row) with weight w, so latent row `row`
    // gathers frame row y at column x − col with the same weight.
    std::vector<int> count(size_t(latent_.height) + 1, 0);
    for (const Tap& t : forward_.taps)
        count[size_t(t.row) + 1]++;
    for (size_t l = 1; l < count.size(); l++)
        count[l] += count[l - 1];
    adjoint_.taps.resize(forward_.taps.size());
    adjoint_.rows.resize(size_t(latent_.height));
    std::vector<int> fill(count.begin(), count.end() - 1);
    for (int y = 0; y < frame_.height; y++)
    {
        const GatherRow& g = forward_.rows[size_t(y)];
        for (int i = g.begin; i < g.end; i++)
        {
            const Tap& t = forward_.taps[size_t(i)];
            adjoint_.taps[size_t(fill[size_t(t.row)]++)] = {y, -t.col, t.weight};
        }
    }
    parallel_for_(Range(0, latent_.height), [&](const Range& rows) {
        for (int l = rows.start; l < rows.end; l++)
        {
            GatherRow& g = adjoint_.rows[size_t(l)];
            g.begin = count[size_t(l)];
            g.end = count[size_t(l) + 1];
            std::sort(adjoint_.taps.begin() + g.begin, adjoint_.taps.begin() + g.end,
                      [](const Tap& a, const Tap& b) { return a.row != b.row ? a.row < b.row : a.col < b.col; });
            safeColumns(adjoint_.taps.data() + g.begin, g.end - g.begin, latent_.width, frame_.width, g.safeBegin,
                        g.safeEnd);
        }
    });
    // The two directions' pairs are built side by side.
    parallel_for_(Range(0, 2), [&](const Range& directions) {
        for (int d = directions.start; d < directions.end; d++)
            buildPairs(d == 0 ? forward_ : adjoint_);
    });
}

void RowBankOperator::forwardBlock(const Mat& latent, const Range& frameRows, float* out, size_t outStep) const
{
    gatherBlock(latent, forward_, frameRows, Range(0, frame_.width), out, outStep);
}

void RowBankOperator::adjointBlock(const Mat& frame, const Range& latentRows, float* out, size_t outStep) const
{
    gatherBlock(frame, adjoint_, latentRows, Range(0, latent_.width), out, outStep);
}

void RowBankOperator::forwardPackedBlock(const Mat& packedLatent, const Range& frameRows, float* out,
                                         size_t outStep) const
{
    CV_DbgAssert(packedLatent.type() == CV_32SC1 && packedLatent.rows == (latent_.height + 1) / 2);
    gatherPackedBlock(packedLatent, packedForward_, frameRows, Range(0, frame_.width), out, outStep);
}

void RowBankOperator::adjointPackedBlock(const Mat& packedFrame, const Range& latentRows, float* out,
                                         size_t outStep) const
{
    CV_DbgAssert(packedFrame.type() == CV_32SC1 && packedFrame.rows == (frame_.height + 1) / 2);
    gatherPackedBlock(packedFrame, packedAdjoint_, latentRows, Range(0, latent_.width), out, outStep);
}

void setPortableGathers(bool portable)
{
    portableGathers = portable;
}

DYNBLUR_SIMD_CLONES
void addRow(const float* __restrict p, int n, float* __restrict sum)
{
    for (int x = 0; x < n; x++)
        sum[x] += p[x];
}

DYNBLUR_SIMD_CLONES
void packRowPair(const float* __restrict first, const float* __restrict second, float offset, int n,
                 uint32_t* __restrict out)
{
    if (second)
        for (int x = 0; x < n; x++)
            out[x] = roundToBfloat16(first[x] + offset) | (roundToBfloat16(second[x] + offset) << 16);
    else
        for (int x = 0; x < n; x++)
            out[x] = roundToBfloat16(first[x] + offset);
}

void packPlane(const Mat& plane, Mat& packed)
{
    packed.create((plane.rows + 1) / 2, plane.cols, CV_32SC1);
    parallel_for_(Range(0, packed.rows), [&](const Range& pairs) {
        for (int k = pairs.start; k < pairs.end; k++)
            packRowPair(plane.ptr<float>(2 * k), 2 * k + 1 < plane.rows ? plane.ptr<float>(2 * k + 1) : nullptr, 0.f,
                        plane.cols, packed.ptr<uint32_t>(k));
    });
}

namespace {

//! Row pairs of `rows` in parallel, each part's rows starting on an even row.
template <typename Body>
void forRowPairs(int rows, const Body& body)
{
    parallel_for_(Range(0, (rows + 1) / 2),
                  [&](const Range& pairs) { body(Range(2 * pairs.start, std::min(2 * pairs.end, rows))); });
}

}  // namespace

void BlurOperator::forwardByBlocks(const Mat& latent, Mat& frame) const
{
    CV_DbgAssert(latent.type() == CV_32FC1 && latent.size() == latent_);
    frame.create(frame_, CV_32FC1);
    if (packed_)
    {
        Mat packed;
        packPlane(latent, packed);
        forRowPairs(frame_.height, [&](const Range& rows) {
            forwardPackedBlock(packed, rows, frame.ptr<float>(rows.start), frame.step1());
        });
        return;
    }
    parallel_for_(Range(0, frame_.height),
                  [&](const Range& rows) { forwardBlock(latent, rows, frame.ptr<float>(rows.start), frame.step1()); });
}

void BlurOperator::adjointByBlocks(const Mat& frame, Mat& latent)
{
    CV_DbgAssert(frame.type() == CV_32FC1 && frame.size() == frame_);
    latent.create(latent_, CV_32FC1);
    if (packed_)
    {
        Mat packed;
        packPlane(frame, packed);
        adjointOfPacked(packed, latent);
        return;
    }
    prepareAdjoint(frame);
    parallel_for_(Range(0, latent_.height),
                  [&](const Range& rows) { adjointBlock(frame, rows, latent.ptr<float>(rows.start), latent.step1()); });
}

void BlurOperator::adjointOfPacked(const Mat& packedFrame, Mat& latent)
{
    latent.create(latent_, CV_32FC1);
    prepareAdjointPacked(packedFrame);
    forRowPairs(latent_.height, [&](const Range& rows) {
        adjointPackedBlock(packedFrame, rows, latent.ptr<float>(rows.start), latent.step1());
    });
}

void BlurOperator::onesFrame(Mat& ones) const
{
    if (!packed_)
    {
        ones.create(frame_, CV_32FC1);
        ones.setTo(1);
        return;
    }
    const float one = 1.f;
    uint32_t pair = 0, single = 0;  // a pair of rows of ones; an odd last row alone
    packRowPair(&one, &one, 0.f, 1, &pair);
    packRowPair(&one, nullptr, 0.f, 1, &single);
    ones.create((frame_.height + 1) / 2, frame_.width, CV_32SC1);
    ones.setTo(Scalar::all(int(pair)));
    if (frame_.height % 2 == 1)
        ones.row(ones.rows - 1).setTo(Scalar::all(int(single)));
}

void BlurOperator::adjointOfOnes(Mat& latent, Mat& ones)
{
    onesFrame(ones);
    if (packed_)
        adjointOfPacked(ones, latent);
    else
        adjoint(ones, latent);
}

void RowBankOperator::adjointOfOnes(Mat& latent, Mat& ones)
{
    onesFrame(ones);
    latent.create(latent_, CV_32FC1);
    const int width = latent_.width;
    /* Columns gathered inside the safe span at each end: enough for a vector of the gather, so the
       value copied across comes from the same kernel as the full gather's. For a 1280×960 row bank
       the whole gather took 0.36–0.48 ms (bfloat16) and 0.95–0.99 ms (float), this 0.13–0.19 and
       0.27 ms. */
    constexpr int kEdge = 16;
    forRowPairs(latent_.height, [&](const Range& rows) {
        const auto gather = [&](const Range& cols) {
            if (packed_)
                gatherPackedBlock(ones, packedAdjoint_, rows, cols, latent.ptr<float>(rows.start), latent.step1());
            else
                gatherBlock(ones, adjoint_, rows, cols, latent.ptr<float>(rows.start), latent.step1());
        };
        int begin = 0, end = width;  // where every row's taps read inside, in this block
        for (int r = rows.start; r < rows.end; r++)
        {
            const GatherRow& g = packed_ ? packedAdjoint_.pairs[size_t(r / 2)] : adjoint_.rows[size_t(r)];
            begin = std::max(begin, g.safeBegin);
            end = std::min(end, g.safeEnd);
        }
        if (end - begin <= 2 * kEdge)
        {
            gather(Range(0, width));
            return;
        }
        gather(Range(0, begin + kEdge));
        gather(Range(end - kEdge, width));
        for (int r = rows.start; r < rows.end; r++)
        {
            float* row = latent.ptr<float>(r);
            std::fill(row + begin + kEdge, row + end - kEdge, row[begin]);
        }
    });
}

// ---------------------------------------------------------------------------------------------
// Bank with several node columns: gathered rows per node column.

namespace {

//! Rows a tile gather takes per node column before the next node column: a block's source stays in L1/L2.
constexpr int kTileBlockRows = 8;

/* One node column's kernels, read from the node table where they lie: each node row's taps in
   (dy, dx) order and where each of its dy's taps start. A frame row's kernel blends two node rows'
   (nodeRowWeights), and the walk reads both: merging them into union kernels first took as long
   as the walk itself, and wrote and read back a union table of ~1.4 MB per node column. */
class ColumnKernels
{
public:
    struct Kernel
    {
        const KernelTap* taps = nullptr;
        const int* runStart = nullptr;  // runStart[dy − dyMin] … runStart[dy − dyMin + 1]: the taps of dy
        int dyMin = 0, dyMax = -1;      // empty: dyMin > dyMax
    };

    ColumnKernels(const NodeTaps& nodes, int nodeRows, int nodeCols, int column) : kernels_(size_t(nodeRows))
    {
        size_t runs = 0;
        for (int j = 0; j < nodeRows; j++)
        {
            const int n = j * nodeCols + column;
            if (nodes.count(n) > 0)
                runs += size_t(nodes.taps(n)[nodes.count(n) - 1].dy - nodes.taps(n)[0].dy + 2);
        }
        runStart_.resize(runs);
        int* run = runStart_.data();
        for (int j = 0; j < nodeRows; j++)
        {
            const int n = j * nodeCols + column;
            const KernelTap* taps = nodes.taps(n);
            const int count = int(nodes.count(n));
            Kernel& k = kernels_[size_t(j)];
            k.taps = taps;
            if (count == 0)
                continue;
            k.dyMin = taps[0].dy;
            k.dyMax = taps[count - 1].dy;
            k.runStart = run;
            for (int t = 0, dy = k.dyMin; dy <= k.dyMax + 1; dy++)
            {
                while (t < count && taps[t].dy < dy)
                    t++;
                *run++ = t;
            }
            for (int t = 0; t < count; t++)
            {
                dxMin = std::min(dxMin, taps[t].dx);
                dxMax = std::max(dxMax, taps[t].dx);
            }
        }
    }
    const Kernel& operator[](int nodeRow) const { return kernels_[size_t(nodeRow)]; }
    bool empty() const { return dxMin > dxMax; }

    int dxMin = INT_MAX, dxMax = INT_MIN;  // over every tap of the column

private:
    std::vector<Kernel> kernels_;
    std::vector<int> runStart_;
};

/* The node kernels a frame row blends in one node column (the second only where its weight is not
   0), their weights and the rows they span together. */
struct RowKernel
{
    const ColumnKernels::Kernel* node[2];
    float weight[2];
    int count, dyMin, dyMax;  // empty: dyMin > dyMax

    //! How many taps the row's node kernels hold together (at least as many as it reads).
    size_t taps() const
    {
        size_t n = 0;
        for (int i = 0; i < count; i++)
            if (node[i]->dyMin <= node[i]->dyMax)
                n += size_t(node[i]->runStart[node[i]->dyMax - node[i]->dyMin + 1]);
        return n;
    }
};

//! RowKernel of each of the first `rows` frame rows in `column`.
std::vector<RowKernel> rowKernels(const ColumnKernels& column,
                                  const std::vector<BankBlurOperator::AxisWeight>& rowWeights, int rows)
{
    std::vector<RowKernel> kernels(static_cast<size_t>(rows));
    for (int row = 0; row < rows; row++)
    {
        const BankBlurOperator::AxisWeight& rw = rowWeights[size_t(row)];
        RowKernel& k = kernels[size_t(row)];
        k = RowKernel{{&column[rw.node[0]], &column[rw.node[1]]}, {rw.weight[0], rw.weight[1]}, 1, INT_MAX, INT_MIN};
        if (rw.node[1] != rw.node[0] && rw.weight[1] != 0.f)
            k.count = 2;
        for (int i = 0; i < k.count; i++)
            if (k.node[i]->dyMin <= k.node[i]->dyMax)
            {
                k.dyMin = std::min(k.dyMin, k.node[i]->dyMin);
                k.dyMax = std::max(k.dyMax, k.node[i]->dyMax);
            }
    }
    return kernels;
}

//! How many taps the rows' node kernels hold together: no list built from them grows past it.
size_t totalTaps(const std::vector<RowKernel>& kernels)
{
    size_t most = 0;
    for (const RowKernel& kernel : kernels)
        most += kernel.taps();
    return most;
}

/* One node column's gather, walked straight from its node kernels (building per-row float lists
   first and merging them took most of a tile-wise frame's set-up). Output rows come in pairs
   (2k, 2k + 1; the last alone when outRows is odd), source rows in groups of `group` (1, or 2 for
   packed pairs). For each pair k, each source group g in order and each column in order,
   term(k, g, col, weight) gets weight[o][h], the weight of source row group·g + h in output row
   2k + o (0 where none; term is called only where one of them is not), then pairEnd(k). The
   kernel and its blend are the frame row's: the output row's in the forward direction (source
   row = r + dy + originY, column colBase + dx), the source row's in the adjoint (source row =
   r − originY − dy, column colBase − dx, read from the weighted copy). */
template <typename Term, typename PairEnd>
void walkColumn(const ColumnKernels& column, const std::vector<RowKernel>& rowKernels, bool adjoint, int outRows,
                int sourceRows, int originY, int colBase, int group, const Term& term, const PairEnd& pairEnd)
{
    /* The source rows each output row reads: its kernel's rows, which the shifts move along the
       frame, so the whole column's span would visit mostly empty groups. */
    std::vector<int> sourceFrom(size_t(outRows), INT_MAX), sourceTo(size_t(outRows), INT_MIN);
    for (int row = 0; row < (adjoint ? sourceRows : outRows); row++)
    {
        const RowKernel& kernel = rowKernels[size_t(row)];
        if (kernel.dyMin > kernel.dyMax)
            continue;
        if (!adjoint)
        {
            sourceFrom[size_t(row)] = row + originY + kernel.dyMin;
            sourceTo[size_t(row)] = row + originY + kernel.dyMax;
            continue;
        }
        for (int r = std::max(0, row + originY + kernel.dyMin); r <= std::min(outRows - 1, row + originY + kernel.dyMax);
             r++)
        {
            sourceFrom[size_t(r)] = std::min(sourceFrom[size_t(r)], row);
            sourceTo[size_t(r)] = std::max(sourceTo[size_t(r)], row);
        }
    }
    struct Slot
    {
        float weight[2][2];
        /* Whether a term holds a weight, taken when the slot is emitted: a flag set at every tap
           (w != 0) cost a compare and a spilled flag per tap, a tenth of the tile operator's
           build. A bank's weights are ≥ 0, so the sum is 0 only where every term was; where a
           user's negative weights cancel, the tap left out weighed nothing. */
        bool used() const
        {
            return weight[0][0] != 0.f || weight[0][1] != 0.f || weight[1][0] != 0.f || weight[1][1] != 0.f;
        }
    };
    const Slot empty{{{0.f, 0.f}, {0.f, 0.f}}};
    std::vector<Slot> slots(column.empty() ? 0 : size_t(column.dxMax - column.dxMin + 1), empty);  // one per dx
    const int groups = (sourceRows + group - 1) / group;
    for (int k = 0; k < (outRows + 1) / 2; k++)
    {
        const size_t high = size_t(std::min(2 * k + 1, outRows - 1));
        const int from = std::min(sourceFrom[size_t(2 * k)], sourceFrom[high]);
        const int to = std::max(sourceTo[size_t(2 * k)], sourceTo[high]);
        for (int g = std::max(0, from / group); g <= std::min(groups - 1, to / group); g++)  // none if no reads
        {
            int lowest = INT_MAX, highest = INT_MIN;  // the slots filled
            for (int output = 0; output < 2; output++)
                for (int half = 0; half < group; half++)
                {
                    const int r = 2 * k + output, source = group * g + half;
                    if (r >= outRows || source >= sourceRows)
                        continue;
                    const RowKernel& kernel = rowKernels[size_t(adjoint ? source : r)];
                    const int dy = adjoint ? r - originY - source : source - r - originY;
                    if (dy < kernel.dyMin || dy > kernel.dyMax)  // also when the kernel is empty
                        continue;
                    /* Each node kernel's taps of this dy, added with its blend weight: a tap both
                       hold gets a0·w0 + a1·w1, as a merged kernel would give it. */
                    for (int i = 0; i < kernel.count; i++)
                    {
                        const ColumnKernels::Kernel& node = *kernel.node[i];
                        if (dy < node.dyMin || dy > node.dyMax)
                            continue;
                        const float a = kernel.weight[i];
                        const int* run = node.runStart + (dy - node.dyMin);
                        for (int t = run[0]; t < run[1]; t++)
                        {
                            const KernelTap& u = node.taps[t];
                            const float w = a * u.weight;
                            const int index = u.dx - column.dxMin;
                            slots[size_t(index)].weight[output][half] += w;
                            lowest = std::min(lowest, index);
                            highest = std::max(highest, index);
                        }
                    }
                }
            // Columns ascending: dx ascending forward, descending in the adjoint.
            for (int i = 0; lowest <= highest && i <= highest - lowest; i++)
            {
                const int index = adjoint ? highest - i : lowest + i;
                Slot& slot = slots[size_t(index)];
                if (!slot.used())
                    continue;
                term(k, g, adjoint ? colBase - (column.dxMin + index) : colBase + column.dxMin + index, slot.weight);
                slot = empty;
            }
        }
        pairEnd(k);
    }
}

/* The packed forward gather of one node column (walkColumn's pairs of source rows, weights as
   bfloat16; the adjoint is its transpose, transposePackedGather). `kernels`: rowKernels of every
   frame row. */
void buildPackedColumn(const ColumnKernels& column, const std::vector<RowKernel>& kernels, int outRows,
                       int sourceRows, int originY, int colBase, int outWidth, int sourceWidth,
                       RowBankOperator::PackedGather& packed)
{
    packed.pairs.assign(size_t((outRows + 1) / 2), RowBankOperator::GatherRow());
    packed.taps.clear();
    packed.taps.reserve(totalTaps(kernels));  // room once, instead of growing
    int begin = 0, safeBegin = 0, safeEnd = outWidth;
    walkColumn(
        column, kernels, false, outRows, sourceRows, originY, colBase, 2,
        [&](int, int pair, int col, const float(&weight)[2][2]) {
            packed.taps.push_back({pair, col, {0u, 0u}});
            for (int o = 0; o < 2; o++)
                packed.taps.back().weight[o] = roundToBfloat16(weight[o][0]) | (roundToBfloat16(weight[o][1]) << 16);
            safeBegin = std::max(safeBegin, -col);
            safeEnd = std::min(safeEnd, sourceWidth - col);
        },
        [&](int k) {
            RowBankOperator::GatherRow& g = packed.pairs[size_t(k)];
            g.begin = begin;
            g.end = begin = int(packed.taps.size());
            g.safeBegin = std::min(safeBegin, outWidth);
            g.safeEnd = std::max(safeEnd, g.safeBegin);
            safeBegin = 0;
            safeEnd = outWidth;
        });
    packed.taps.shrink_to_fit();
}

/* The float gather of one node column: each output row's taps (walkColumn's single source rows,
   zero weights left out) and each full pair's union, as buildPairs makes it. Safe columns are the
   caller's. `kernels`: rowKernels of every frame row. */
void buildFloatColumn(const ColumnKernels& column, const std::vector<RowKernel>& kernels, bool adjoint, int outRows,
                      int sourceRows, int originY, int colBase, RowBankOperator::Gather& gather)
{
    /* No list grows past the frame rows' node kernels, so they are sized once and written in place
       (growing them by push_back copied and faulted in each several times). */
    const size_t most = totalTaps(kernels);
    gather.rows.assign(size_t(outRows), RowBankOperator::GatherRow());
    gather.pairs.assign(size_t(outRows / 2), RowBankOperator::GatherRow());
    gather.taps.resize(most);
    gather.pairTaps.resize(most);
    std::vector<RowBankOperator::Tap> second;  // the pair's second row, appended after the first's
    int taps = 0, pairTaps = 0;
    walkColumn(
        column, kernels, adjoint, outRows, sourceRows, originY, colBase, 1,
        [&](int k, int row, int col, const float(&weight)[2][2]) {
            if (weight[0][0] != 0.f)
                gather.taps[size_t(taps++)] = {row, col, weight[0][0]};
            if (weight[1][0] != 0.f)
                second.push_back({row, col, weight[1][0]});
            if (2 * k + 1 < outRows)
                gather.pairTaps[size_t(pairTaps++)] = {row, col, {weight[0][0], weight[1][0]}};
        },
        [&](int k) {
            RowBankOperator::GatherRow& first = gather.rows[size_t(2 * k)];
            first.begin = k > 0 ? gather.rows[size_t(2 * k - 1)].end : 0;
            first.end = taps;
            if (2 * k + 1 >= outRows)
                return;
            RowBankOperator::GatherRow& next = gather.rows[size_t(2 * k + 1)];
            std::copy(second.begin(), second.end(), gather.taps.begin() + taps);
            next.begin = taps;
            next.end = taps += int(second.size());
            second.clear();
            RowBankOperator::GatherRow& pair = gather.pairs[size_t(k)];
            pair.begin = k > 0 ? gather.pairs[size_t(k - 1)].end : 0;
            pair.end = pairTaps;
        });
    gather.taps.resize(size_t(taps));
    gather.taps.shrink_to_fit();
    gather.pairTaps.resize(size_t(pairTaps));
    gather.pairTaps.shrink_to_fit();
}

/* The latent columns (within [0, width)) an adjoint row of a node column gives anything to: those
   whose reads x + col meet the node column's weighted frame, columns [margin, margin +
   supportWidth) of its copy. The column's reach spans every row's: on the benchmark frame an
   8-row block's columns took 0.913 of the multiply-adds. */
template <typename TapT>
Range adjointWrites(const TapT* taps, int count, int margin, int supportWidth, int width)
{
    int colMin = INT_MAX, colMax = INT_MIN;
    for (int t = 0; t < count; t++)
    {
        colMin = std::min(colMin, taps[t].col);
        colMax = std::max(colMax, taps[t].col);
    }
    const int begin = count > 0 ? std::max(0, margin - colMax) : 0;
    const int end = count > 0 ? std::min(width, margin + supportWidth - colMin) : 0;
    return begin < end ? Range(begin, end) : Range(0, 0);
}

}  // namespace

TileBankOperator::TileBankOperator(const PsfBank& bank, bool pad, bool packed)
    : BlurOperator(bank.imageSize, packed)
{
    nodeCols_ = int(bank.nodeCols.size());
    const int nodeRows = int(bank.nodeRows.size());
    int dxMin, dxMax, dyMin, dyMax;
    const NodeTaps nodes(bank, dxMin, dxMax, dyMin, dyMax);
    spotGain_ = spotGainOf(bank, nodes.smallestPeak());
    domain(frame_, pad, dxMin, dxMax, dyMin, dyMax, latent_, origin_);
    const std::vector<BankBlurOperator::AxisWeight> rowWeights = nodeRowWeights(bank, frame_.height);
    const std::vector<BankBlurOperator::AxisWeight> colWeights = nodeColumnWeights(bank, frame_.width);
    colSupport_ = supports(colWeights, nodeCols_);
    colWeight_ = supportWeights(colWeights, colSupport_);
    reach_.resize(size_t(nodeCols_));
    adjointWritten_.resize(size_t(nodeCols_));

    /* Each node column's taps for every frame row (forward) and every latent row (adjoint), with
       the row blend's weights applied: built once per bank, node columns in parallel. */
    std::vector<Gather> forwardParts(static_cast<size_t>(nodeCols_)), adjointParts(static_cast<size_t>(nodeCols_));
    if (packed_)
    {
        packedForwardColumns_.resize(size_t(nodeCols_));
        packedAdjointColumns_.resize(size_t(nodeCols_));
    }
    parallel_for_(Range(0, nodeCols_), [&](const Range& range) {
        for (int i = range.start; i < range.end; i++)
        {
            const ColumnKernels column(nodes, nodeRows, nodeCols_, i);
            const std::vector<RowKernel> kernels = rowKernels(column, rowWeights, frame_.height);
            const Range cols = colSupport_[size_t(i)];
            Reach& reach = reach_[size_t(i)];
            if (!column.empty())
            {
                reach.dxMin = std::min(0, column.dxMin);
                reach.dxMax = std::max(0, column.dxMax);
            }
            const int margin = reach.margin();
            const int adjointColBase = margin - cols.start - origin_.x;  // frame column → weighted copy's
            if (packed_)
            {
                buildPackedColumn(column, kernels, frame_.height, latent_.height, origin_.y, origin_.x,
                                  frame_.width, latent_.width, packedForwardColumns_[size_t(i)]);
                transposePackedGather(packedForwardColumns_[size_t(i)], origin_.x, latent_.height, adjointColBase,
                                      latent_.width, cols.size() + 2 * margin, packedAdjointColumns_[size_t(i)]);
                const PackedGather& adjoint = packedAdjointColumns_[size_t(i)];
                std::vector<Range>& written = adjointWritten_[size_t(i)];
                written.resize(size_t(latent_.height));
                for (int l = 0; l < latent_.height; l += 2)  // both rows of a pair: its taps
                {
                    const GatherRow& g = adjoint.pairs[size_t(l / 2)];
                    written[size_t(l)] = adjointWrites(adjoint.taps.data() + g.begin, g.end - g.begin, margin,
                                                       cols.size(), latent_.width);
                    if (l + 1 < latent_.height)
                        written[size_t(l + 1)] = written[size_t(l)];
                }
                continue;
            }
            // Forward: frame row y reads latent row y + dy + origin.y at column x + dx + origin.x.
            Gather& fw = forwardParts[size_t(i)];
            buildFloatColumn(column, kernels, false, frame_.height, latent_.height, origin_.y, origin_.x, fw);
            for (GatherRow& g : fw.rows)
            {
                int colMin = INT_MAX, colMax = INT_MIN;
                for (int t = g.begin; t < g.end; t++)
                {
                    colMin = std::min(colMin, fw.taps[size_t(t)].col);
                    colMax = std::max(colMax, fw.taps[size_t(t)].col);
                }
                g.safeBegin = g.end > g.begin ? std::max(cols.start, -colMin) : cols.start;
                g.safeEnd = g.end > g.begin ? std::max(g.safeBegin, std::min(cols.end, latent_.width - colMax)) : cols.end;
            }
            /* Adjoint: latent row l gathers frame row y = l − origin.y − dy, column x − dx − origin.x,
               at its place in the node column's weighted copy, where every column it produces reads
               inside (zero margins). */
            Gather& aw = adjointParts[size_t(i)];
            buildFloatColumn(column, kernels, true, latent_.height, frame_.height, origin_.y, adjointColBase, aw);
            std::vector<Range>& written = adjointWritten_[size_t(i)];
            written.resize(size_t(latent_.height));
            for (int l = 0; l < latent_.height; l++)
            {
                GatherRow& g = aw.rows[size_t(l)];
                g.safeBegin = std::max(0, cols.start + reach.dxMin + origin_.x);
                g.safeEnd = std::min(latent_.width, cols.end + reach.dxMax + origin_.x);
                written[size_t(l)] =
                    adjointWrites(aw.taps.data() + g.begin, g.end - g.begin, margin, cols.size(), latent_.width);
            }
        }
    });
    forwardColumns_ = std::move(forwardParts);
    adjointColumns_ = std::move(adjointParts);
    if (packed_)
    {
        // takePackedPair writes only the supports: the margins stay as zeroed here.
        weighted_.resize(size_t(nodeCols_));
        for (int i = 0; i < nodeCols_; i++)
            weighted_[size_t(i)] = Mat::zeros((frame_.height + 1) / 2,
                                              colSupport_[size_t(i)].size() + 2 * reach_[size_t(i)].margin(), CV_32SC1);
    }
}

template <typename GatherColumn>
void TileBankOperator::blocks(bool adjoint, const Range& outRows, float* out, size_t outStep,
                              const GatherColumn& gather) const
{
    const int width = adjoint ? latent_.width : frame_.width;
    for (int start = outRows.start; start < outRows.end; start += kTileBlockRows)
    {
        const Range rows(start, std::min(start + kTileBlockRows, outRows.end));
        /* A column's first contribution is written, later ones added, so no pass zeroes the block
           first: [0, covered) holds a contribution. The non-empty supports of the node columns'
           weights, a partition of unity, tile the row in order; the adjoint's ranges widen them by
           each column's own reach, so one may start past `covered` (nothing reaches the columns
           between: they are zeroed) or end before it. */
        int covered = 0;
        const auto zero = [&](int from, int to) {
            for (int y = rows.start; y < rows.end; y++)
            {
                float* o = out + size_t(y - outRows.start) * outStep;
                std::fill(o + from, o + to, 0.f);
            }
        };
        for (int i = 0; i < nodeCols_; i++)
        {
            const Range support = colSupport_[size_t(i)];
            if (support.empty())
                continue;  // a node column beside the frame weights nothing
            /* The adjoint's weights are in the source (prepareAdjoint), and its rows reach past the
               support, each as far as its own taps: the block as far as its rows do. */
            Range cols = support;
            if (adjoint)
            {
                cols = Range(width, 0);
                for (int y = rows.start; y < rows.end; y++)
                {
                    const Range written = adjointWritten_[size_t(i)][size_t(y)];
                    if (!written.empty())
                        cols = Range(std::min(cols.start, written.start), std::max(cols.end, written.end));
                }
                if (cols.empty())
                    continue;
            }
            if (cols.start > covered)
                zero(covered, cols.start);
            covered = std::max(covered, cols.start);
            // Added below the split, written from it; the forward's times the column's weight.
            const GatherFold fold{adjoint ? nullptr : colWeight_[size_t(i)].data() - support.start,
                                  std::min(covered, cols.end)};
            gather(i, rows, cols, out + size_t(rows.start - outRows.start) * outStep, fold);
            covered = std::max(covered, cols.end);
        }
        if (covered < width)
            zero(covered, width);
    }
}

void TileBankOperator::forwardBlock(const Mat& latent, const Range& frameRows, float* out, size_t outStep) const
{
    blocks(false, frameRows, out, outStep, [&](int i, const Range& rows, const Range& cols, float* dst,
                                               const GatherFold& fold) {
        gatherBlock(latent, forwardColumns_[size_t(i)], rows, cols, dst, outStep, fold);
    });
}

void TileBankOperator::forwardPackedBlock(const Mat& packedLatent, const Range& frameRows, float* out,
                                          size_t outStep) const
{
    blocks(false, frameRows, out, outStep, [&](int i, const Range& rows, const Range& cols, float* dst,
                                               const GatherFold& fold) {
        gatherPackedBlock(packedLatent, packedForwardColumns_[size_t(i)], rows, cols, dst, outStep, fold);
    });
}

void TileBankOperator::prepareAdjoint(const Mat& frame)
{
    weighted_.resize(size_t(nodeCols_));
    for (int i = 0; i < nodeCols_; i++)
        weighted_[size_t(i)].create(frame.rows, colSupport_[size_t(i)].size() + 2 * reach_[size_t(i)].margin(),
                                    CV_32FC1);
    parallel_for_(Range(0, frame.rows), [&](const Range& rows) {
        for (int r = rows.start; r < rows.end; r++)
        {
            const float* src = frame.ptr<float>(r);
            for (int i = 0; i < nodeCols_; i++)
            {
                const Range cols = colSupport_[size_t(i)];
                const int margin = reach_[size_t(i)].margin();
                float* w = weighted_[size_t(i)].ptr<float>(r);
                std::fill(w, w + margin, 0.f);
                multiplyInto(w + margin, colWeight_[size_t(i)].data(), src + cols.start, cols.size());
                std::fill(w + margin + cols.size(), w + cols.size() + 2 * margin, 0.f);
            }
        }
    });
}

void TileBankOperator::prepareAdjointPacked(const Mat& packedFrame)
{
    // The packed copies and their zero margins are the constructor's: only the supports change.
    parallel_for_(Range(0, packedFrame.rows), [&](const Range& rows) {
        for (int pair = rows.start; pair < rows.end; pair++)
            takePackedPair(pair, packedFrame.ptr<uint32_t>(pair));
    });
}

void TileBankOperator::takePackedPair(int pair, const uint32_t* packedRow)
{
    for (int i = 0; i < nodeCols_; i++)
    {
        const Range cols = colSupport_[size_t(i)];
        scalePackedRow(packedRow + cols.start, colWeight_[size_t(i)].data(), cols.size(),
                       weighted_[size_t(i)].ptr<uint32_t>(pair) + reach_[size_t(i)].margin());
    }
}

void TileBankOperator::adjointBlock(const Mat& /*frame: read through prepareAdjoint's weighted copies*/,
                                    const Range& latentRows, float* out, size_t outStep) const
{
    blocks(true, latentRows, out, outStep, [&](int i, const Range& rows, const Range& cols, float* dst,
                                               const GatherFold& fold) {
        gatherBlock(weighted_[size_t(i)], adjointColumns_[size_t(i)], rows, cols, dst, outStep, fold);
    });
}

void TileBankOperator::adjointPackedBlock(const Mat& /*packedFrame: read through the weighted copies*/,
                                          const Range& latentRows, float* out, size_t outStep) const
{
    blocks(true, latentRows, out, outStep, [&](int i, const Range& rows, const Range& cols, float* dst,
                                              const GatherFold& fold) {
        gatherPackedBlock(weighted_[size_t(i)], packedAdjointColumns_[size_t(i)], rows, cols, dst, outStep, fold);
    });
}

std::unique_ptr<BlurOperator> createBankOperator(const PsfBank& bank, bool pad, bool packed)
{
    if (bank.nodeCols.size() == 1)
        return std::unique_ptr<BlurOperator>(new RowBankOperator(bank, pad, packed));
    return std::unique_ptr<BlurOperator>(new TileBankOperator(bank, pad, packed));
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
