// SPDX-License-Identifier: Apache-2.0
#include "restore/operators/tile_bank_operator.hpp"

#include "restore/operators/bank_geometry.hpp"
#include "restore/operators/gather.hpp"
#include "restore/operators/packed_gather.hpp"
#include "restore/row_arithmetic.hpp"
#include "restore/kernels/gather_taps.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <climits>

namespace cv {
namespace dynblur {
namespace detail {

using kernels::roundToBfloat16;

namespace {

//! Rows a tile gather takes per node column before the next node column: a block's source stays in L1/L2.
constexpr int kTileBlockRows = 8;

/* One node column's kernels, read from the node table where they lie: each node row's taps in
   (dy, dx) order and where each of its dy's taps start. A frame row's kernel blends two node rows'
   (nodeRowWeights), and the walk reads both: merging them into union kernels first would cost as
   much as the walk itself, and write and read back a union table of megabytes per node column. */
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
                                  const std::vector<AxisWeight>& rowWeights, int rows)
{
    std::vector<RowKernel> kernels(static_cast<size_t>(rows));
    for (int row = 0; row < rows; row++)
    {
        const AxisWeight& rw = rowWeights[size_t(row)];
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
   first and merging them would be most of a tile-wise frame's set-up). Output rows come in pairs
   (2k, 2k + 1; the last alone when outRows is odd), source rows in groups of `group` (1, or 2 for
   packed pairs). For each pair k, each source group g in order and each column in order,
   term(k, g, col, weight) gets weight[o][h], the weight of source row group·g + h in output row
   2k + o (0 where none; term is called only where one of them is not), then pairEnd(k). The
   kernel and its blend are the frame row's: the output row's in the forward direction (source
   row = r + dy + originY, column colBase + dx), the source row's in the adjoint (source row =
   r − originY − dy, column colBase − dx, read from the weighted copy). Output rows where `skip` is
   not 0 get no terms (rows the operator gathers otherwise). */
template <typename Term, typename PairEnd>
void walkColumn(const ColumnKernels& column, const std::vector<RowKernel>& rowKernels, const std::vector<uchar>& skip,
                bool adjoint, int outRows, int sourceRows, int originY, int colBase, int group, const Term& term,
                const PairEnd& pairEnd)
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
    for (int r = 0; r < outRows; r++)
        if (skip[size_t(r)])
        {
            sourceFrom[size_t(r)] = INT_MAX;
            sourceTo[size_t(r)] = INT_MIN;
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
                    if (r >= outRows || source >= sourceRows || skip[size_t(r)])
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
void buildPackedColumn(const ColumnKernels& column, const std::vector<RowKernel>& kernels,
                       const std::vector<uchar>& skip, int outRows, int sourceRows, int originY, int colBase,
                       int outWidth, int sourceWidth, PackedGather& packed)
{
    packed.pairs.assign(size_t((outRows + 1) / 2), GatherRow());
    packed.taps.clear();
    packed.taps.reserve(totalTaps(kernels));  // room once, instead of growing
    int begin = 0, safeBegin = 0, safeEnd = outWidth;
    walkColumn(
        column, kernels, skip, false, outRows, sourceRows, originY, colBase, 2,
        [&](int, int pair, int col, const float(&weight)[2][2]) {
            packed.taps.push_back({pair, col, {0u, 0u}});
            for (int o = 0; o < 2; o++)
                packed.taps.back().weight[o] = roundToBfloat16(weight[o][0]) | (roundToBfloat16(weight[o][1]) << 16);
            safeBegin = std::max(safeBegin, -col);
            safeEnd = std::min(safeEnd, sourceWidth - col);
        },
        [&](int k) {
            GatherRow& g = packed.pairs[size_t(k)];
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
void buildFloatColumn(const ColumnKernels& column, const std::vector<RowKernel>& kernels,
                      const std::vector<uchar>& skip, bool adjoint, int outRows, int sourceRows, int originY,
                      int colBase, Gather& gather)
{
    /* No list grows past the frame rows' node kernels, so they are sized once and written in place
       (growing them by push_back copied and faulted in each several times). */
    const size_t most = totalTaps(kernels);
    gather.rows.assign(size_t(outRows), GatherRow());
    gather.pairs.assign(size_t(outRows / 2), GatherRow());
    gather.taps.resize(most);
    gather.pairTaps.resize(most);
    std::vector<Tap> second;  // the pair's second row, appended after the first's
    int taps = 0, pairTaps = 0;
    walkColumn(
        column, kernels, skip, adjoint, outRows, sourceRows, originY, colBase, 1,
        [&](int k, int row, int col, const float(&weight)[2][2]) {
            if (weight[0][0] != 0.f)
                gather.taps[size_t(taps++)] = {row, col, weight[0][0]};
            if (weight[1][0] != 0.f)
                second.push_back({row, col, weight[1][0]});
            if (2 * k + 1 < outRows)
                gather.pairTaps[size_t(pairTaps++)] = {row, col, {weight[0][0], weight[1][0]}};
        },
        [&](int k) {
            GatherRow& first = gather.rows[size_t(2 * k)];
            first.begin = k > 0 ? gather.rows[size_t(2 * k - 1)].end : 0;
            first.end = taps;
            if (2 * k + 1 >= outRows)
                return;
            GatherRow& next = gather.rows[size_t(2 * k + 1)];
            std::copy(second.begin(), second.end(), gather.taps.begin() + taps);
            next.begin = taps;
            next.end = taps += int(second.size());
            second.clear();
            GatherRow& pair = gather.pairs[size_t(k)];
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
   supportWidth) of its copy: a block of rows gathers only the columns its own rows write, fewer
   than the column's reach over every row. */
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

/* Flags of `count` rows taken by pairs, as the packed gathers take them: a pair's where `holds` holds
   for both its rows (for the last row alone when `count` is odd). */
template <typename Holds>
std::vector<uchar> byPairs(int count, const Holds& holds)
{
    std::vector<uchar> flags(static_cast<size_t>(count));
    for (int r = 0; r < count; r += 2)
        flags[size_t(r)] = flags[size_t(std::min(r + 1, count - 1))] = holds(r) && (r + 1 == count || holds(r + 1));
    return flags;
}

//! Whether two kernels' taps (shift included) are the same.
bool sameTaps(const KernelTap* a, size_t countA, const KernelTap* b, size_t countB)
{
    return countA == countB && std::equal(a, a + countA, b, [](const KernelTap& p, const KernelTap& q) {
               return p.dy == q.dy && p.dx == q.dx && p.weight == q.weight;
           });
}

}  // namespace

void TileBankOperator::gatherSameRowsOnce(const NodeTaps& nodes, int nodeRows,
                                          const std::vector<AxisWeight>& rowWeights)
{
    // Node rows whose kernel is the same in every node column, and each node row's dy over its columns.
    std::vector<uchar> same(size_t(nodeRows), 1);
    std::vector<int> dyLow(size_t(nodeRows), INT_MAX), dyHigh(size_t(nodeRows), INT_MIN);
    for (int j = 0; j < nodeRows; j++)
    {
        const int first = j * nodeCols_;
        for (int i = 0; i < nodeCols_; i++)
        {
            const KernelTap* taps = nodes.taps(first + i);
            const size_t count = nodes.count(first + i);
            if (count > 0)
            {
                dyLow[size_t(j)] = std::min(dyLow[size_t(j)], taps[0].dy);
                dyHigh[size_t(j)] = std::max(dyHigh[size_t(j)], taps[count - 1].dy);
            }
            if (!sameTaps(taps, count, nodes.taps(first), nodes.count(first)))
                same[size_t(j)] = 0;
        }
    }
    /* A frame row has one kernel where the node rows it blends have; a latent row is gathered once
       where only such frame rows read it (over every node column's taps). */
    const int height = frame_.height, latentHeight = latent_.height;
    std::vector<uchar> oneKernel(static_cast<size_t>(height));
    std::vector<Range> reads(static_cast<size_t>(height), Range(0, 0));  // the latent rows each frame row reads
    std::vector<int> tileReads(size_t(latentHeight) + 1, 0);  // per latent row, frame rows of tiles reading it
    for (int y = 0; y < height; y++)
    {
        const AxisWeight& w = rowWeights[size_t(y)];
        const bool second = w.node[1] != w.node[0] && w.weight[1] != 0.f;
        const int n0 = w.node[0], n1 = second ? w.node[1] : n0;
        oneKernel[size_t(y)] = same[size_t(n0)] && same[size_t(n1)];
        const int low = std::min(dyLow[size_t(n0)], dyLow[size_t(n1)]);
        const int high = std::max(dyHigh[size_t(n0)], dyHigh[size_t(n1)]);
        const int from = std::max(0, y + origin_.y + low), to = std::min(latentHeight, y + origin_.y + high + 1);
        if (from >= to)
            continue;  // an empty kernel, or one reading only outside an unpadded domain
        reads[size_t(y)] = Range(from, to);
        if (!oneKernel[size_t(y)])
        {
            tileReads[size_t(from)]++;
            tileReads[size_t(to)]--;
        }
    }
    for (int l = 1; l <= latentHeight; l++)
        tileReads[size_t(l)] += tileReads[size_t(l - 1)];
    forwardAsRows_ = byPairs(height, [&](int y) { return oneKernel[size_t(y)] != 0; });
    adjointAsRows_ = byPairs(latentHeight, [&](int l) { return tileReads[size_t(l)] == 0; });
    // The frame rows the adjoint's tile rows read: those keep their weighted copies.
    std::vector<int> tileRowsBefore(size_t(latentHeight) + 1, 0);
    for (int l = 0; l < latentHeight; l++)
        tileRowsBefore[size_t(l) + 1] = tileRowsBefore[size_t(l)] + !adjointAsRows_[size_t(l)];
    feedsTiles_.resize(size_t(height));
    for (int y = 0; y < height; y++)
    {
        const Range r = reads[size_t(y)];
        feedsTiles_[size_t(y)] = tileRowsBefore[size_t(r.end)] > tileRowsBefore[size_t(r.start)];
    }
    if (rowShare(false) == 0 && rowShare(true) == 0)
        return;
    rows_ = buildRowGathers(nodes, nodeCols_, 0, rowWeights, frame_, latent_, origin_, packed_, oneKernel);
    if (packed_)
        plainPacked_ = Mat::zeros((height + 1) / 2, frame_.width, CV_32SC1);
}

double TileBankOperator::rowShare(bool adjoint) const
{
    const std::vector<uchar>& asRows = adjoint ? adjointAsRows_ : forwardAsRows_;
    return double(std::count(asRows.begin(), asRows.end(), 1)) / double(std::max<size_t>(1, asRows.size()));
}

TileBankOperator::TileBankOperator(const PsfBank& bank, bool pad, bool packed)
    : BlurOperator(bank.imageSize, packed)
{
    nodeCols_ = int(bank.nodeCols.size());
    const int nodeRows = int(bank.nodeRows.size());
    int dxMin, dxMax, dyMin, dyMax;
    const NodeTaps nodes(bank, dxMin, dxMax, dyMin, dyMax);
    spotGain_ = spotGainOf(bank, nodes.smallestPeak());
    domain(frame_, pad, dxMin, dxMax, dyMin, dyMax, latent_, origin_);
    const std::vector<AxisWeight> rowWeights = nodeRowWeights(bank, frame_.height);
    const std::vector<AxisWeight> colWeights = nodeColumnWeights(bank, frame_.width);
    colSupport_ = supports(colWeights, nodeCols_);
    colWeight_ = supportWeights(colWeights, colSupport_);
    reach_.resize(size_t(nodeCols_));
    adjointWritten_.resize(size_t(nodeCols_));
    gatherSameRowsOnce(nodes, nodeRows, rowWeights);
    /* The tile gathers skip the rows gathered once: in the forward, a frame row unless a tile row
       of the adjoint reads it (the packed adjoint is the forward's transpose). */
    std::vector<uchar> skipForward(size_t(frame_.height));
    for (int y = 0; y < frame_.height; y++)
        skipForward[size_t(y)] = forwardAsRows_[size_t(y)] && !(packed_ && feedsTiles_[size_t(y)]);
    const std::vector<uchar>& skipAdjoint = adjointAsRows_;

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
                buildPackedColumn(column, kernels, skipForward, frame_.height, latent_.height, origin_.y, origin_.x,
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
            buildFloatColumn(column, kernels, skipForward, false, frame_.height, latent_.height, origin_.y, origin_.x,
                             fw);
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
            buildFloatColumn(column, kernels, skipAdjoint, true, latent_.height, frame_.height, origin_.y,
                             adjointColBase, aw);
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

template <typename GatherColumn, typename GatherRows>
void TileBankOperator::blocks(bool adjoint, const Range& outRows, float* out, size_t outStep,
                              const GatherColumn& gather, const GatherRows& gatherRows) const
{
    const std::vector<uchar>& asRows = adjoint ? adjointAsRows_ : forwardAsRows_;
    for (int start = outRows.start, end; start < outRows.end; start = end)
    {
        for (end = start + 1; end < outRows.end && asRows[size_t(end)] == asRows[size_t(start)];)
            end++;
        float* dst = out + size_t(start - outRows.start) * outStep;
        if (asRows[size_t(start)])
            gatherRows(Range(start, end), dst);
        else
            tileBlocks(adjoint, Range(start, end), dst, outStep, gather);
    }
}

template <typename GatherColumn>
void TileBankOperator::tileBlocks(bool adjoint, const Range& outRows, float* out, size_t outStep,
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
    }, [&](const Range& rows, float* dst) {
        gatherBlock(latent, rows_.forward, rows, Range(0, frame_.width), dst, outStep);
    });
}

void TileBankOperator::forwardPackedBlock(const Mat& packedLatent, const Range& frameRows, float* out,
                                          size_t outStep) const
{
    blocks(false, frameRows, out, outStep, [&](int i, const Range& rows, const Range& cols, float* dst,
                                               const GatherFold& fold) {
        gatherPackedBlock(packedLatent, packedForwardColumns_[size_t(i)], rows, cols, dst, outStep, fold);
    }, [&](const Range& rows, float* dst) {
        gatherPackedBlock(packedLatent, rows_.packedForward, rows, Range(0, frame_.width), dst, outStep);
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
            if (!feedsTiles_[size_t(r)])
                continue;
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
    if (!plainPacked_.empty())
        std::copy(packedRow, packedRow + frame_.width, plainPacked_.ptr<uint32_t>(pair));
    const size_t first = size_t(2 * pair), second = std::min(first + 1, feedsTiles_.size() - 1);
    if (!feedsTiles_[first] && !feedsTiles_[second])
        return;
    for (int i = 0; i < nodeCols_; i++)
    {
        const Range cols = colSupport_[size_t(i)];
        scalePackedRow(packedRow + cols.start, colWeight_[size_t(i)].data(), cols.size(),
                       weighted_[size_t(i)].ptr<uint32_t>(pair) + reach_[size_t(i)].margin());
    }
}

void TileBankOperator::adjointBlock(const Mat& frame, const Range& latentRows, float* out, size_t outStep) const
{
    // The tile rows read prepareAdjoint's weighted copies, the rows gathered once the frame.
    blocks(true, latentRows, out, outStep, [&](int i, const Range& rows, const Range& cols, float* dst,
                                               const GatherFold& fold) {
        gatherBlock(weighted_[size_t(i)], adjointColumns_[size_t(i)], rows, cols, dst, outStep, fold);
    }, [&](const Range& rows, float* dst) {
        gatherBlock(frame, rows_.adjoint, rows, Range(0, latent_.width), dst, outStep);
    });
}

void TileBankOperator::adjointPackedBlock(const Mat& /*packedFrame: read through the copies takePackedPair made*/,
                                          const Range& latentRows, float* out, size_t outStep) const
{
    blocks(true, latentRows, out, outStep, [&](int i, const Range& rows, const Range& cols, float* dst,
                                              const GatherFold& fold) {
        gatherPackedBlock(weighted_[size_t(i)], packedAdjointColumns_[size_t(i)], rows, cols, dst, outStep, fold);
    }, [&](const Range& rows, float* dst) {
        gatherPackedBlock(plainPacked_, rows_.packedAdjoint, rows, Range(0, latent_.width), dst, outStep);
    });
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
