// SPDX-License-Identifier: Apache-2.0
// Private: gathers, the tap lists of a bank operator's rows, and the blocks of rows they compute.
#ifndef OPENCV_DYNBLUR_RESTORE_GATHER_HPP
#define OPENCV_DYNBLUR_RESTORE_GATHER_HPP

#include "restore/kernels/gather_taps.hpp"

#include <opencv2/core.hpp>

#include <algorithm>
#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

using kernels::GatherFold;
using kernels::PackedTap;
using kernels::PairTap;
using kernels::Tap;

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

//! A gather over packed sources: the taps of each output row pair (the last one single when the rows are odd).
struct PackedGather
{
    std::vector<PackedTap> taps;
    std::vector<GatherRow> pairs;
};

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
   is the serial build's; a frame-rate row bank's lists are large enough for it to pay. */
template <typename T, typename Build>
void buildGatherRows(int count, std::vector<T>& taps, std::vector<GatherRow>& rows,
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


/* Rows [rows.start, rows.end) and columns `cols` of a gather, row r at out + (r − rows.start)·outStep,
   folded in as `fold` says. */
void gatherBlock(const Mat& source, const Gather& gather, const Range& rows, const Range& cols, float* out,
                 size_t outStep, const GatherFold& fold = GatherFold());

/* gatherBlock over a packed source: rows [rows.start, rows.end) (rows.start even) and columns `cols`. */
void gatherPackedBlock(const Mat& packed, const PackedGather& gather, const Range& rows, const Range& cols, float* out,
                       size_t outStep, const GatherFold& fold = GatherFold());

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
