// SPDX-License-Identifier: Apache-2.0
// Private: the blur of a bank with several node columns, as row gathers per node column.
#ifndef OPENCV_DYNBLUR_RESTORE_TILE_BANK_OPERATOR_HPP
#define OPENCV_DYNBLUR_RESTORE_TILE_BANK_OPERATOR_HPP

#include "restore/operators/blur_operator.hpp"
#include "restore/operators/bank_geometry.hpp"
#include "restore/operators/gather.hpp"
#include "restore/operators/row_gathers.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief A bank with several node columns (PSF_TILES): a frame pixel blends the kernels of its
two node rows and of one or two node columns (nodeColumnWeights). Along a frame row the node-row
blend is fixed, so for each node column the row's kernel is one tap list (the union of the two node
rows' taps, mixed by the row's weights), gathered like RowBankOperator's over the columns that node
column covers and added with the column's weight. The adjoint gathers too, from the frame weighted
by each node column's weight, kept per node column with zero margins as wide as that column's own
kernels reach, so every tap reads inside and no read strays into a neighbour column's share; a
block of latent rows gathers only as far as its own rows' taps reach (a keystone's kernels slant
more toward the frame's sides, and their shifts move along the column). In the packed RL loop the
copies are written from each ratio row pair as it is computed (takesPackedPairs), while it is in
cache, instead of from a packed ratio plane written and read back.
Each node column's gathered rows are folded into the output by the gathers themselves
(GatherFold). Both directions' tap lists are built once per bank.
Rows whose kernel is the same in every node column (PSF_AUTO's row bands) are gathered once across
the frame, as RowBankOperator gathers them, instead of once per node column and weighted: a frame
whose motion needs tiles in a few bands no longer costs what tiles everywhere cost
(docs/performance.md, BM_AutoPaired frames 3 and 4).
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

    /** The share of frame rows (`adjoint`: latent rows) gathered once across the frame, as a row bank's
    are, instead of once per node column: the rows whose kernel is the same in every node column. */
    double rowShare(bool adjoint) const;

private:
    /* Rows `outRows` of A · latent (or of Aᵀ · frame with `adjoint`): runs of rows gathered once
       by gatherRows(rows, dst), the others by tileBlocks. */
    template <typename GatherColumn, typename GatherRows>
    void blocks(bool adjoint, const Range& outRows, float* out, size_t outStep, const GatherColumn& gather,
                const GatherRows& gatherRows) const;
    /* Rows `outRows` gathered per node column: gather(i, rows, cols, dst, fold) gathers node column
       i's rows, float or packed, into the output block at dst (step outStep) as `fold` says. */
    template <typename GatherColumn>
    void tileBlocks(bool adjoint, const Range& outRows, float* out, size_t outStep, const GatherColumn& gather) const;
    /* Finds the rows whose kernel is the same in every node column (PSF_AUTO's row bands) and
       builds their row gathers: forwardAsRows_, adjointAsRows_, feedsTiles_, rows_. */
    void gatherSameRowsOnce(const NodeTaps& nodes, int nodeRows, const std::vector<AxisWeight>& rowWeights);

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
    /* Rows gathered once across the frame, as RowBankOperator gathers them, instead of once per
       node column: frame rows whose kernel is the same in every node column (forwardAsRows_),
       latent rows only such frame rows read (adjointAsRows_); both by row pairs. */
    std::vector<uchar> forwardAsRows_, adjointAsRows_;
    std::vector<uchar> feedsTiles_;  // per frame row: a tile row of the adjoint reads it (its weighted copies are made)
    RowGathers rows_;
    Mat plainPacked_;  // packed: the frame's pairs as takePackedPair took them, which rows_'s adjoint reads
};

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
