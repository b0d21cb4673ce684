// SPDX-License-Identifier: Apache-2.0
#include "restore/operators/blur_operator.hpp"

#include "restore/operators/packed_gather.hpp"

#include <opencv2/core/utility.hpp>

namespace cv {
namespace dynblur {
namespace detail {

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

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
