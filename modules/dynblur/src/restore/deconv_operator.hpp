// Private: the linear blur operators that Richardson–Lucy inverts, and their exact adjoints.
// tests/test_deconv.cpp includes this header to check <A x, y> == <x, Aᵀ y>.
#ifndef OPENCV_DYNBLUR_DECONV_OPERATOR_HPP
#define OPENCV_DYNBLUR_DECONV_OPERATOR_HPP

#include "opencv2/dynblur/deconv.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
/* The hot loops are compiled three times and the CPU picks at load time: one build runs on any
   x86-64 and still uses AVX-512, or AVX2 with FMA, where the CPU has them. */
#define DYNBLUR_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define DYNBLUR_SIMD_CLONES
#endif

namespace cv {
namespace dynblur {
namespace detail {

class FftKernel;

/** @brief A linear blur A from a latent domain (the frame, possibly extended by margins) to the
frame. Latent pixel (x, y) of the array is frame coordinate (x − origin.x, y − origin.y).
Planes are CV_32FC1. */
class CV_EXPORTS BlurOperator
{
public:
    virtual ~BlurOperator() {}
    Size frameSize() const { return frame_; }
    Size latentSize() const { return latent_; }
    Point origin() const { return origin_; }
    //! frame = A · latent
    virtual void forward(const Mat& latent, Mat& frame) = 0;
    //! latent = Aᵀ · frame
    virtual void adjoint(const Mat& frame, Mat& latent) = 0;
    /** The most a latent pixel can hold per unit of the brightest frame pixel: 1 / (the smallest
    weight with which it reaches its most-weighted frame pixel), bounded from the kernels' peaks
    and the number of kernels blended at a pixel. For data A x, x ≤ spotGain · max(A x). */
    double spotGain() const { return spotGain_; }

    /** True when a few rows of A·x (or of Aᵀ·y) can be computed on their own: the RL loop then
    fuses each block of blurred rows with the element-wise work that follows it while the block is
    still in cache. */
    virtual bool gathersRows() const { return false; }
    //! Rows `frameRows` of A · latent, row r at out + (r − frameRows.start)·outStep. Only when gathersRows().
    virtual void forwardBlock(const Mat& /*latent*/, const Range& /*frameRows*/, float* /*out*/, size_t /*outStep*/) const {}
    /** Rows `latentRows` of Aᵀ · frame, laid out likewise. Only when gathersRows(), and after
    prepareAdjoint(frame) for this `frame`. */
    virtual void adjointBlock(const Mat& /*frame*/, const Range& /*latentRows*/, float* /*out*/, size_t /*outStep*/) const {}
    //! Whatever adjointBlock needs of the whole `frame` first (before any block runs).
    virtual void prepareAdjoint(const Mat& /*frame*/) {}

    /** True when the operator works on packed planes (packRowPair: rows 2k and 2k + 1 as the
    bfloat16 halves of one CV_32SC1 row) with bfloat16 weights, summing in float: with AVX512-BF16
    one instruction takes two multiply-adds per lane, twice a float FMA, from half the bytes.
    forward() and adjoint() then pack their input first; gathersRows() is false, and the RL loop
    uses the packed blocks below. */
    bool gathersPackedRows() const { return packed_; }
    /** Rows `frameRows` (starting on an even row) of A · latent, from `packedLatent`, laid out as
    forwardBlock's. Only when gathersPackedRows(). */
    virtual void forwardPackedBlock(const Mat& /*packedLatent*/, const Range& /*frameRows*/, float* /*out*/,
                                    size_t /*outStep*/) const {}
    /** Rows `latentRows` (starting on an even row) of Aᵀ · frame, from the packed frame, after
    prepareAdjointPacked(packedFrame). Only when gathersPackedRows(). */
    virtual void adjointPackedBlock(const Mat& /*packedFrame*/, const Range& /*latentRows*/, float* /*out*/,
                                    size_t /*outStep*/) const {}
    //! Whatever adjointPackedBlock needs of the whole packed frame first.
    virtual void prepareAdjointPacked(const Mat& /*packedFrame*/) {}
    /** True when the RL loop may hand the packed frame over one row pair at a time as it computes
    it (takePackedPair, every pair before the next adjointPackedBlock) instead of as a plane
    through prepareAdjointPacked: the tile operator weights each pair into its node columns'
    copies while the pair is in cache, and no packed plane is written and read back. */
    virtual bool takesPackedPairs() const { return false; }
    /** Row pair `pair` (frame rows 2·pair and 2·pair + 1, packRowPair's layout, frame width) of the
    packed frame the next adjointPackedBlock calls read. Calls for different pairs may run at once.
    Only when takesPackedPairs(). */
    virtual void takePackedPair(int /*pair*/, const uint32_t* /*packedRow*/) {}

    /** latent = Aᵀ1, the adjoint of a frame of ones (RL's normaliser). A packed operator reads the
    ones packed as packPlane would pack them, written straight into `ones` without a float frame.
    @param ones scratch: the frame of ones (packed when gathersPackedRows()), reused when it fits. */
    virtual void adjointOfOnes(Mat& latent, Mat& ones);

protected:
    //! The latent domain starts as the frame; operators with padding grow it.
    explicit BlurOperator(Size frameSize, bool packed = false)
        : frame_(frameSize), latent_(frameSize), packed_(packed)
    {
    }
    /** forward() of an operator that gathers rows: its blocks, in parallel over the frame (packed:
    the latent packed first, then the packed blocks over row pairs). */
    void forwardByBlocks(const Mat& latent, Mat& frame) const;
    //! adjoint() of an operator that gathers rows: prepareAdjoint, then its blocks in parallel (packed: likewise).
    void adjointByBlocks(const Mat& frame, Mat& latent);
    //! adjointByBlocks from the packed frame (gathersPackedRows()).
    void adjointOfPacked(const Mat& packedFrame, Mat& latent);
    //! `ones` = a frame of ones, packed as packPlane packs it when gathersPackedRows().
    void onesFrame(Mat& ones) const;
    Size frame_, latent_;
    bool packed_;
    Point origin_;
    double spotGain_ = 1;
};

/** @brief One kernel everywhere (convolution form), through FFTW. With `pad` the latent domain is
the frame grown by the kernel's half-size on each side; otherwise it is the frame, zero outside. */
class CV_EXPORTS UniformBlurOperator CV_FINAL : public BlurOperator
{
public:
    UniformBlurOperator(Size frameSize, const Mat& kernel32f, bool pad);
    ~UniformBlurOperator();
    void forward(const Mat& latent, Mat& frame) CV_OVERRIDE;
    void adjoint(const Mat& frame, Mat& latent) CV_OVERRIDE;

private:
    std::unique_ptr<FftKernel> fft_;
    Mat scratch_;
};

/** @brief The PsfBank's blended blur B(p) = Σ_n w_n(p) Σ_u k_n(u) L(p − s_n − (u − c)), applied
in the spatial domain as sparse taps (zero taps skipped, shifts are index offsets), rows in
parallel. With `pad` the latent domain is the bounding box of every pixel any tap reads (the
kernels' reach, shifts included); otherwise it is the frame and reads outside it are zero.
The bank is trusted (validated by the caller). This is the operator in its plainest form (each
node's taps scattered); createBankOperator picks the gathering ones below, and the tests hold them
to it. */
class CV_EXPORTS BankBlurOperator CV_FINAL : public BlurOperator
{
public:
    BankBlurOperator(const PsfBank& bank, bool pad);
    void forward(const Mat& latent, Mat& frame) CV_OVERRIDE;
    void adjoint(const Mat& frame, Mat& latent) CV_OVERRIDE;

    struct TapRow
    {
        int dy = 0;               // latent row read = frame row + dy
        std::vector<int> dx;      // latent col read = frame col + dx
        std::vector<float> weight;
    };
    struct Node
    {
        std::vector<TapRow> rows;
        int dyMin = 0, dyMax = 0;
        std::vector<int> rowOfDy;  // index into rows of each dy in [dyMin, dyMax], -1 where none
    };
    //! Blending weight along one axis: up to two (node index, weight) pairs per coordinate.
    struct AxisWeight
    {
        int node[2] = {0, 0};
        float weight[2] = {0.f, 0.f};
    };

private:
    void forwardRows(const Mat& latent, Mat& frame, const Range& rows) const;
    void adjointRows(const Mat& frame, Mat& latent, const Range& rows) const;
    float rowWeight(int nodeRow, int frameRow) const;

    int nodeCols_ = 1, nodeRows_ = 1;
    int dyMin_ = 0, dyMax_ = 0;  // the bank's range of row offsets (latent row − frame row)
    std::vector<Node> nodes_;                 // row-major, nodeRows_ × nodeCols_
    std::vector<AxisWeight> rowWeights_;      // per frame row
    std::vector<Range> nodeRowSupport_;       // frame rows where each node row's weight > 0
    std::vector<Range> nodeColSupport_;       // frame cols where each node col's weight > 0
    std::vector<std::vector<float>> colWeight_;  // per node col, weights over its support
    Mat weighted_[2];  // adjoint's input times the even / odd node columns' weights
};

/** @brief A bank with one node column (PSF_ROWS, or one kernel): every pixel of a frame row shares
one kernel, the tent blend of its two row nodes' kernels, so a row of A·x is a weighted sum of
shifted latent rows and a row of Aᵀ·y a weighted sum of shifted frame rows. Both directions are
gathers over tap lists merged once per row (the adjoint's are the forward's, transposed), summed
in registers over 64 columns at a time, a few rows at a time in column chunks that keep their
source rows in L1, so each output row is written once and a delta kernel costs one pass. Domains
and padding as BankBlurOperator. The bank is trusted (validated by the caller). */
class CV_EXPORTS RowBankOperator CV_FINAL : public BlurOperator
{
public:
    //! `packed`: bfloat16 packed planes and weights (gathersPackedRows), float otherwise.
    RowBankOperator(const PsfBank& bank, bool pad, bool packed = false);
    void forward(const Mat& latent, Mat& frame) CV_OVERRIDE { forwardByBlocks(latent, frame); }
    void adjoint(const Mat& frame, Mat& latent) CV_OVERRIDE { adjointByBlocks(frame, latent); }
    bool gathersRows() const CV_OVERRIDE { return !packed_; }
    void forwardBlock(const Mat& latent, const Range& frameRows, float* out, size_t outStep) const CV_OVERRIDE;
    void adjointBlock(const Mat& frame, const Range& latentRows, float* out, size_t outStep) const CV_OVERRIDE;
    void forwardPackedBlock(const Mat& packedLatent, const Range& frameRows, float* out,
                            size_t outStep) const CV_OVERRIDE;
    void adjointPackedBlock(const Mat& packedFrame, const Range& latentRows, float* out,
                            size_t outStep) const CV_OVERRIDE;
    /** Every row of a row bank's Aᵀ1 holds one value between the columns where all its taps read
    inside the frame: those are filled with it, and only the columns near the edges are gathered.
    The result is the full gather's to the bit (a tap's weight times one is exact, so every such
    column sums the same values in the same order). */
    void adjointOfOnes(Mat& latent, Mat& ones) CV_OVERRIDE;

    //! One term of a gathered row: out[x] += weight · source(row, x + col).
    struct Tap
    {
        int row;
        int col;
        float weight;
    };
    //! One term of two gathered rows at once: out_k[x] += weight[k] · source(row, x + col).
    struct PairTap
    {
        int row;
        int col;
        float weight[2];
    };
    //! Taps of one output row (or row pair), and the output columns where every tap reads inside its source.
    struct GatherRow
    {
        int begin = 0, end = 0;  // into the tap array
        int safeBegin = 0, safeEnd = 0;
    };
    /** One direction's gather: each output row's taps and, for each pair of output rows (2k, 2k+1),
    the union of their taps with a weight for each, so a source vector loaded once feeds both rows. */
    struct Gather
    {
        std::vector<Tap> taps;
        std::vector<GatherRow> rows;
        std::vector<PairTap> pairTaps;
        std::vector<GatherRow> pairs;
    };
    /** One term of output rows 2k and 2k + 1 from a packed source: out_k[x] += the dot product of
    the two bfloat16 halves of weight[k] (rows 2·pair and 2·pair + 1) with those of packed(pair, x + col). */
    struct PackedTap
    {
        int pair;
        int col;
        uint32_t weight[2];
    };
    //! A gather over packed sources: the taps of each output row pair (the last one single when the rows are odd).
    struct PackedGather
    {
        std::vector<PackedTap> taps;
        std::vector<GatherRow> pairs;
    };

private:
    Gather forward_, adjoint_;                      // float mode
    PackedGather packedForward_, packedAdjoint_;    // packed mode
};

/** @brief A bank with several node columns (PSF_TILES): a frame pixel blends the kernels of its
two node rows and of one or two node columns (nodeColumnWeights). Along a frame row the node-row
blend is fixed, so for each node column the row's kernel is one tap list (the union of the two node
rows' taps, mixed by the row's weights), gathered like RowBankOperator's over the columns that node
column covers and added with the column's weight. The adjoint gathers too, from the frame weighted
by each node column's weight, kept per node column with zero margins as wide as that column's own
kernels reach, so every tap reads inside and no read strays into a neighbour column's share; a
block of latent rows gathers only as far as its own rows' taps reach (a keystone's kernels slant
more toward the frame's sides, and their shifts move along the column). In the packed RL loop the
copies are written from each ratio row pair as it is computed (takesPackedPairs): the frame-rate
tile-wise frame took 0.979–0.987 of the time against weighting a packed ratio plane afterwards.
Each node column's gathered rows are folded into the output by the gathers themselves
(GatherFold). Both directions' tap lists are built once per bank.
Domains and padding as BankBlurOperator. The bank is trusted (validated by the caller). */
class CV_EXPORTS TileBankOperator CV_FINAL : public BlurOperator
{
public:
    //! `packed`: as RowBankOperator's.
    TileBankOperator(const PsfBank& bank, bool pad, bool packed = false);
    void forward(const Mat& latent, Mat& frame) CV_OVERRIDE { forwardByBlocks(latent, frame); }
    void adjoint(const Mat& frame, Mat& latent) CV_OVERRIDE { adjointByBlocks(frame, latent); }
    bool gathersRows() const CV_OVERRIDE { return !packed_; }
    void forwardBlock(const Mat& latent, const Range& frameRows, float* out, size_t outStep) const CV_OVERRIDE;
    void adjointBlock(const Mat& frame, const Range& latentRows, float* out, size_t outStep) const CV_OVERRIDE;
    void prepareAdjoint(const Mat& frame) CV_OVERRIDE;
    void forwardPackedBlock(const Mat& packedLatent, const Range& frameRows, float* out,
                            size_t outStep) const CV_OVERRIDE;
    void adjointPackedBlock(const Mat& packedFrame, const Range& latentRows, float* out,
                            size_t outStep) const CV_OVERRIDE;
    void prepareAdjointPacked(const Mat& packedFrame) CV_OVERRIDE;
    bool takesPackedPairs() const CV_OVERRIDE { return packed_; }
    void takePackedPair(int pair, const uint32_t* packedRow) CV_OVERRIDE;

private:
    typedef RowBankOperator::Tap Tap;
    typedef RowBankOperator::GatherRow GatherRow;
    typedef RowBankOperator::Gather Gather;
    typedef RowBankOperator::PackedGather PackedGather;

    /* Rows `outRows` of A · latent (or of Aᵀ · frame with `adjoint`), where gather(i, rows, cols,
       dst, fold) gathers node column i's rows, float or packed, into the output block at dst (step
       outStep) as `fold` says. */
    template <typename GatherColumn>
    void blocks(bool adjoint, const Range& outRows, float* out, size_t outStep, const GatherColumn& gather) const;

    //! A node column's column offsets (latent − frame), 0 included.
    struct Reach
    {
        int dxMin = 0, dxMax = 0;
        //! The zero columns each side of its weighted copy, so that every read of its adjoint lands inside.
        int margin() const { return dxMax - dxMin; }
    };

    int nodeCols_ = 1;
    std::vector<Reach> reach_;  // per node column: its kernels' column offsets (its weighted copy's margins)
    std::vector<std::vector<Range>> adjointWritten_;  // per node column and latent row: the columns its adjoint writes
    /* Per node column i: rows[y] of forwardColumns_[i] is frame row y's gather (safe columns
       within the column's support); rows[l] of adjointColumns_[i] latent row l's, reading the
       weighted copy of node column i. */
    std::vector<Gather> forwardColumns_, adjointColumns_;                // float mode
    std::vector<PackedGather> packedForwardColumns_, packedAdjointColumns_;  // packed mode
    std::vector<Range> colSupport_;                // frame columns each node column covers
    std::vector<std::vector<float>> colWeight_;    // per node column, over its support
    std::vector<Mat> weighted_;  // per node column: frame × its weight, zero margins (packed: built with the operator)
};

/** @brief packRowPair over every row pair of `plane` (CV_32FC1) into `packed` (CV_32SC1,
⌈rows / 2⌉ × cols), pairs in parallel. */
CV_EXPORTS void packPlane(const Mat& plane, Mat& packed);

//! sum[x] += p[x] for x in [0, n), in the CPU's widest vectors.
void addRow(const float* p, int n, float* sum);

/** @brief Rows 2k and 2k + 1 of a plane, plus `offset`, as bfloat16 (rounded to nearest even) in
the low and high halves of out[x], x in [0, n): the packed sources of gathersPackedRows().
`second` null: the high halves are 0 (the last row of an odd height). */
CV_EXPORTS void packRowPair(const float* first, const float* second, float offset, int n, uint32_t* out);

/** @brief For tests: every gather uses the kernels of a CPU without AVX-512 (`portable` true):
packed ones widen the bfloat16 halves to floats, float ones use 256-bit or narrower vectors, even
where the CPU has AVX-512 and AVX512-BF16; false (the default): the CPU's best. */
CV_EXPORTS void setPortableGathers(bool portable);

/** @brief spotGain of a bank: blended kernels per pixel / the smallest kernel peak. */
double bankSpotGain(const PsfBank& bank);

/** @brief The operator that applies `bank` fastest: RowBankOperator when the bank has one node
column, TileBankOperator otherwise. */
std::unique_ptr<BlurOperator> createBankOperator(const PsfBank& bank, bool pad, bool packed = false);

/** @brief The bank's displacement alone, which the restoration's start undoes: each node's shift
moved to its kernel's centroid (rounded to a pixel), as if the kernel were one tap there. */
std::vector<Point> displacementShifts(const PsfBank& bank);

/** @brief Bᵀ applied at once to each plane of `frames` (the bank's frame size, CV_32F) and to a
plane of ones, row by row, where B is the blur of `bank` with every kernel one tap of 1 at its
node's `shifts` (displacementShifts()): frame pixel p reads latent pixel p − shift + `origin`,
blended across node rows and columns as every bank operator blends them. The latent domain is
`latentSize` with the frame at `origin` (another operator's, so the rows land in its domain); what
falls outside it is left out. Calls rowDone(row, weight, adjoints) once per latent row, rows in
parallel: `weight` is the row of Bᵀ1 and adjoints[p] that of Bᵀ frames[p], latentSize.width values
each, valid until rowDone returns. Equals the adjoint of createBankOperator on that one-tap bank up
to float rounding, for a fraction of its cost and without a plane of its own. */
void displacementAdjoint(const PsfBank& bank, const std::vector<Point>& shifts, Size latentSize, Point origin,
                         const std::vector<Mat>& frames,
                         const std::function<void(int, const float*, const float* const*)>& rowDone);

/** @brief The PsfBank blending weights along its node rows of every row in [0, height): the bilinear
tent between the two nodes around it, constant beyond the outermost nodes. Shared by the spatial
operators and the Wiener path, like nodeColumnWeights. */
std::vector<BankBlurOperator::AxisWeight> nodeRowWeights(const PsfBank& bank, int height);

/** @brief The PsfBank blending weights along its node columns of every column in [0, width): 1 for
the nearer node column except over the middle half of the interval between two, where they move
linearly from one to the other (kColumnBlendTransition); constant beyond the outermost nodes. */
std::vector<BankBlurOperator::AxisWeight> nodeColumnWeights(const PsfBank& bank, int width);

/** The fraction of each interval between node columns over which the blend moves from one node's
kernel to the next (1 would be the bilinear tent). A tile gather computes every pixel once per
node column whose weight there is positive: two node columns for every pixel with the tent, 1.5 on
average with a transition over half the interval, and the tile-wise frame-rate frame took 12 % less
time. PsfGenerator spaces an automatic bank's node columns for neighbouring paths to differ by
0.4 px (up to 16 columns); DeblurQuality's tile-wise figures moved by at most 0.07 dB against the
tent. Node rows (one to two pixels apart in an automatic bank) keep the tent. */
constexpr double kColumnBlendTransition = 0.5;

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
