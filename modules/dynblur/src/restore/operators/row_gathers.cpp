// SPDX-License-Identifier: Apache-2.0
#include "restore/operators/row_gathers.hpp"

#include "restore/operators/packed_gather.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>

namespace cv {
namespace dynblur {
namespace detail {

namespace {

//! Output columns [begin, end) of a row of `width` where every tap reads inside [0, sourceWidth).
void safeColumns(const Tap* taps, int count, int width, int sourceWidth, int& begin, int& end)
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
void buildPairs(Gather& gather)
{
    const int pairCount = int(gather.rows.size()) / 2;
    gather.pairs.assign(size_t(pairCount), GatherRow());
    gather.pairTaps.clear();
    // A pair's union holds at most both rows' taps; the list is trimmed to what it holds after.
    gather.pairTaps.reserve(gather.taps.size());
    for (int k = 0; k < pairCount; k++)
    {
        const GatherRow &first = gather.rows[size_t(2 * k)], &second = gather.rows[size_t(2 * k + 1)];
        GatherRow& g = gather.pairs[size_t(k)];
        g.begin = int(gather.pairTaps.size());
        forUnion(gather.taps.data() + first.begin, size_t(first.end - first.begin), gather.taps.data() + second.begin,
                 size_t(second.end - second.begin),
                 [](const Tap& t) { return std::make_pair(t.row, t.col); },
                 [&](const Tap& t, float w0, float w1) {
                     gather.pairTaps.push_back({t.row, t.col, {w0, w1}});
                 });
        g.end = int(gather.pairTaps.size());
    }
    gather.pairTaps.shrink_to_fit();
}

/* The transpose of a float forward gather: frame pixel (x, y) reads latent (x + col, row) with
   weight w, so latent row `row` gathers frame row y at column x − col with the same weight. */
void transposeGather(const Gather& forward, int latentRows, int latentWidth, int frameWidth, Gather& adjoint)
{
    std::vector<int> count(size_t(latentRows) + 1, 0);
    for (const Tap& t : forward.taps)
        count[size_t(t.row) + 1]++;
    for (size_t l = 1; l < count.size(); l++)
        count[l] += count[l - 1];
    adjoint.taps.resize(forward.taps.size());
    adjoint.rows.resize(size_t(latentRows));
    std::vector<int> fill(count.begin(), count.end() - 1);
    for (int y = 0; y < int(forward.rows.size()); y++)
    {
        const GatherRow& g = forward.rows[size_t(y)];
        for (int i = g.begin; i < g.end; i++)
        {
            const Tap& t = forward.taps[size_t(i)];
            adjoint.taps[size_t(fill[size_t(t.row)]++)] = {y, -t.col, t.weight};
        }
    }
    parallel_for_(Range(0, latentRows), [&](const Range& rows) {
        for (int l = rows.start; l < rows.end; l++)
        {
            GatherRow& g = adjoint.rows[size_t(l)];
            g.begin = count[size_t(l)];
            g.end = count[size_t(l) + 1];
            std::sort(adjoint.taps.begin() + g.begin, adjoint.taps.begin() + g.end,
                      [](const Tap& a, const Tap& b) { return a.row != b.row ? a.row < b.row : a.col < b.col; });
            safeColumns(adjoint.taps.data() + g.begin, g.end - g.begin, latentWidth, frameWidth, g.safeBegin,
                        g.safeEnd);
        }
    });
}

}  // namespace

RowGathers buildRowGathers(const NodeTaps& nodes, int nodeCols, int column, const std::vector<AxisWeight>& rowWeights,
                           Size frame, Size latent, Point origin, bool packed, const std::vector<uchar>& frameRows)
{
    RowGathers g;
    Gather& forward = g.forward;
    buildGatherRows(frame.height, forward.taps, forward.rows, [&](int y, std::vector<Tap>& taps) {
        GatherRow row;
        row.begin = int(taps.size());
        if (frameRows.empty() || frameRows[size_t(y)])
        {
            const AxisWeight& w = rowWeights[size_t(y)];
            const int n0 = w.node[0] * nodeCols + column, n1 = w.node[1] * nodeCols + column;
            // Both node kernels are in (dy, dx) order, so their union is a merge, not a sort.
            forUnion(nodes.taps(n0), w.weight[0] > 0.f ? nodes.count(n0) : 0, nodes.taps(n1),
                     w.weight[1] > 0.f ? nodes.count(n1) : 0,
                     [](const KernelTap& t) { return std::make_pair(t.dy, t.dx); },
                     [&](const KernelTap& t, float wa, float wb) {
                         const int ly = y + t.dy + origin.y;
                         if (ly >= 0 && ly < latent.height)
                             taps.push_back({ly, t.dx + origin.x, w.weight[0] * wa + w.weight[1] * wb});
                     });
        }
        row.end = int(taps.size());
        safeColumns(taps.data() + row.begin, row.end - row.begin, frame.width, latent.width, row.safeBegin,
                    row.safeEnd);
        return row;
    });

    if (packed)
    {
        buildPacked(forward, frame.width, latent.width, g.packedForward);
        transposePackedGather(g.packedForward, 0, latent.height, 0, latent.width, frame.width, g.packedAdjoint);
        forward = Gather();
        return g;
    }
    transposeGather(forward, latent.height, latent.width, frame.width, g.adjoint);
    // The two directions' pairs are built side by side.
    parallel_for_(Range(0, 2), [&](const Range& directions) {
        for (int d = directions.start; d < directions.end; d++)
            buildPairs(d == 0 ? g.forward : g.adjoint);
    });
    return g;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
