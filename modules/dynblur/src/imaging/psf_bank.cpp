// SPDX-License-Identifier: Apache-2.0
// PsfBank: the kernels of one frame, their nodes and displacements, and their checks.
#include "precomp.hpp"

namespace cv {
namespace dynblur {

PsfBank::PsfBank() : model(PSF_UNIFORM), imageSize(0, 0) {}

void PsfBank::validate() const
{
    if (model != PSF_UNIFORM && model != PSF_ROWS && model != PSF_TILES)
        CV_Error_(Error::StsBadArg, ("PsfBank: model=%d must be PSF_UNIFORM, PSF_ROWS or PSF_TILES", model));
    if (imageSize.width <= 0 || imageSize.height <= 0)
        CV_Error_(Error::StsBadArg, ("PsfBank: imageSize %dx%d must be positive", imageSize.width, imageSize.height));
    if (nodeRows.empty() || nodeCols.empty())
        CV_Error(Error::StsBadArg, "PsfBank: nodeRows and nodeCols must not be empty");
    for (size_t i = 0; i < nodeRows.size(); i++)
        if (!std::isfinite(nodeRows[i]) || (i > 0 && !(nodeRows[i] > nodeRows[i - 1])))
            CV_Error(Error::StsBadArg, "PsfBank: nodeRows must be finite and strictly increasing (pixels)");
    for (size_t i = 0; i < nodeCols.size(); i++)
        if (!std::isfinite(nodeCols[i]) || (i > 0 && !(nodeCols[i] > nodeCols[i - 1])))
            CV_Error(Error::StsBadArg, "PsfBank: nodeCols must be finite and strictly increasing (pixels)");
    const size_t n = nodeRows.size() * nodeCols.size();
    if (kernels.size() != n)
        CV_Error_(Error::StsBadArg, ("PsfBank: kernels has %d entries, nodeRows.size()*nodeCols.size() = %d",
                                     (int)kernels.size(), (int)n));
    if (shifts.size() != n)
        CV_Error_(Error::StsBadArg,
                  ("PsfBank: shifts has %d entries, expected %d (one per kernel)", (int)shifts.size(), (int)n));
    // A displacement many frames long is no blur any frame records, and its latent domain would not fit in memory.
    const int64 maxShift = 16 * int64(std::max(std::max(imageSize.width, imageSize.height), 64));
    for (size_t i = 0; i < n; i++)
        if (std::abs(int64(shifts[i].x)) > maxShift || std::abs(int64(shifts[i].y)) > maxShift)
            CV_Error_(Error::StsOutOfRange,
                      ("PsfBank: shifts[%d] = (%d, %d) px must be within ±%lld px (16 times the image's larger "
                       "side, at least 64)",
                       (int)i, shifts[i].x, shifts[i].y, (long long)maxShift));
    for (size_t i = 0; i < n; i++)
    {
        const Mat& k = kernels[i];
        if (k.empty() || k.type() != CV_32FC1)
            CV_Error_(Error::StsBadArg, ("PsfBank: kernel %d must be a non-empty CV_32FC1 matrix", (int)i));
        if (k.rows % 2 == 0 || k.cols % 2 == 0)
            CV_Error_(Error::StsBadArg, ("PsfBank: kernel %d is %dx%d; its sides must be odd", (int)i, k.cols, k.rows));
        double sum = 0, minv = 0;
        for (int y = 0; y < k.rows; y++)
            for (int x = 0; x < k.cols; x++)
            {
                const float v = k.at<float>(y, x);
                if (!std::isfinite(v))
                    CV_Error_(Error::StsBadArg, ("PsfBank: kernel %d has a non-finite element", (int)i));
                sum += v;
                minv = std::min(minv, (double)v);
            }
        if (minv < 0)
            CV_Error_(Error::StsBadArg, ("PsfBank: kernel %d has a negative element (%g)", (int)i, minv));
        if (std::abs(sum - 1.0) > 1e-3)
            CV_Error_(Error::StsBadArg, ("PsfBank: kernel %d sums to %g, must sum to 1 (±1e-3)", (int)i, sum));
    }
}

Size PsfBank::maxKernelSize() const
{
    Size s(0, 0);
    for (const Mat& k : kernels)
    {
        s.width = std::max(s.width, k.cols);
        s.height = std::max(s.height, k.rows);
    }
    return s;
}

bool PsfBank::isIdentity() const
{
    for (size_t i = 0; i < kernels.size(); i++)
    {
        if (kernels[i].total() != 1)
            return false;
        if (i < shifts.size() && shifts[i] != Point(0, 0))
            return false;
    }
    return true;
}

}  // namespace dynblur
}  // namespace cv
