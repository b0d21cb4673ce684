// SPDX-License-Identifier: Apache-2.0
#include "restore/operators/displacement.hpp"

#include "restore/operators/bank_geometry.hpp"
#include "restore/row_arithmetic.hpp"
#include "restore/simd_clones.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>

namespace cv {
namespace dynblur {
namespace detail {

std::vector<Point> displacementShifts(const PsfBank& bank)
{
    std::vector<Point> shifts(bank.shifts.size());
    // A tile bank holds ~10⁴ kernels: plain sums in parallel, not cv::moments one kernel after another.
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
    const std::vector<AxisWeight> rowWeights = nodeRowWeights(bank, frame.height);
    const std::vector<AxisWeight> colWeights = nodeColumnWeights(bank, frame.width);
    const std::vector<Range> colSupport = supports(colWeights, nodeCols);
    const std::vector<std::vector<float>> colWeight = supportWeights(colWeights, colSupport);

    /* One segment per frame row, node row blended into it and node column: the column's support in
       that row, moved by the node's shift into one latent row. Segments are filed by their latent
       row (a counting sort), so latent rows are summed in parallel, each in a fixed order, in a
       buffer that stays in cache until rowDone has used it: no node-column copies, no per-row tap
       lists and no planes of its own, as the general operators would need. */
    struct Segment
    {
        int frameRow, node;
        float weight;  // the node row's blend weight
    };
    const auto forEachSegment = [&](const auto& emit) {
        for (int y = 0; y < frame.height; y++)
            for (int k = 0; k < 2; k++)
            {
                const AxisWeight& rw = rowWeights[size_t(y)];
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

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
