// SPDX-License-Identifier: Apache-2.0
#include "restore/arguments.hpp"

#include "restore/rl/frame_planes.hpp"

#include <cmath>

namespace cv {
namespace dynblur {

/* `nonNegative`: Richardson–Lucy's data are intensities; its multiplicative update divides by the
   blurred estimate and turns a negative pixel into a pull of either sign, so a dark frame with
   zero-mean noise comes back with spikes up to the projection bound. The linear operators take
   any finite values. */
void checkImage(InputArray image, const char* name, const char* function, bool nonNegative)
{
    if (image.empty())
        CV_Error(Error::StsBadArg, format("%s: '%s' is empty", function, name));
    if (image.depth() != CV_32F)
        CV_Error(Error::StsUnsupportedFormat,
                 format("%s: '%s' has depth %s; only CV_32F (linear intensity) is accepted", function, name,
                        depthToString(image.depth())));
    if (image.channels() < 1 || image.channels() > 4)
        CV_Error(Error::StsBadArg,
                 format("%s: '%s' has %d channels; 1 to 4 are accepted", function, name, image.channels()));
    if (image.dims() > 2)
        CV_Error(Error::StsBadArg, format("%s: '%s' must be a 2-D image", function, name));
    float low = 0, high = 0;
    if (!detail::finiteRange(image.getMat(), low, high))
        CV_Error(Error::StsBadArg, format("%s: '%s' contains NaN or Inf; it must be finite", function, name));
    if (nonNegative && low < 0)
        CV_Error(Error::StsOutOfRange,
                 format("%s: '%s' has a pixel of %g; intensities must be >= 0 (clip the data at 0 first, as a "
                        "sensor does)",
                        function, name, low));
}

void checkBank(const PsfBank& bank, Size imageSize, const char* function)
{
    const size_t nodes = bank.nodeRows.size() * bank.nodeCols.size();
    if (nodes == 0)
        CV_Error(Error::StsBadArg, format("%s: 'bank' has no nodes (nodeRows and nodeCols must be non-empty)",
                                          function));
    if (bank.kernels.size() != nodes || bank.shifts.size() != nodes)
        CV_Error(Error::StsBadArg,
                 format("%s: 'bank' has %zu kernels and %zu shifts for %zu nodes (nodeRows x nodeCols)", function,
                        bank.kernels.size(), bank.shifts.size(), nodes));
    if (bank.imageSize != imageSize)
        CV_Error(Error::StsBadSize,
                 format("%s: 'bank' is for %dx%d images but the image is %dx%d", function, bank.imageSize.width,
                        bank.imageSize.height, imageSize.width, imageSize.height));
    for (size_t n = 0; n < nodes; n++)
    {
        const Mat& k = bank.kernels[n];
        if (k.empty() || k.type() != CV_32FC1 || k.rows % 2 == 0 || k.cols % 2 == 0)
            CV_Error(Error::StsBadArg,
                     format("%s: 'bank.kernels[%zu]' must be a non-empty, odd-sized, one-channel CV_32F kernel",
                            function, n));
    }
    bank.validate();  // sums, signs, node order: the bank's own contract
}

void checkRLParams(const RLParams& params, const char* function)
{
    if (params.iterations < 1 || params.iterations > 100000)
        CV_Error(Error::StsOutOfRange,
                 format("%s: params.iterations = %d must be in [1, 100000]", function, params.iterations));
    if (!std::isnan(params.damping) && !(params.damping >= 0 && std::isfinite(params.damping)))
        CV_Error(Error::StsOutOfRange,
                 format("%s: params.damping = %g must be finite and >= 0 (0: off), or NaN (automatic)", function,
                        params.damping));
    if (!(params.tvWeight >= 0) || !std::isfinite(params.tvWeight))
        CV_Error(Error::StsOutOfRange,
                 format("%s: params.tvWeight = %g must be finite and >= 0 (0: off)", function, params.tvWeight));
    if (!(params.tolerance >= 0) || !std::isfinite(params.tolerance))
        CV_Error(Error::StsOutOfRange,
                 format("%s: params.tolerance = %g must be finite and >= 0 (0: never stop early)", function,
                        params.tolerance));
    if (params.colorIterations < -1)
        CV_Error(Error::StsOutOfRange,
                 format("%s: params.colorIterations = %d must be >= 0, or -1 (every iteration in color)", function,
                        params.colorIterations));
    if (params.boundary != RL_BOUNDARY_ZERO && params.boundary != RL_BOUNDARY_PAD)
        CV_Error(Error::StsOutOfRange,
                 format("%s: params.boundary = %d must be RL_BOUNDARY_ZERO (0) or RL_BOUNDARY_PAD (1)", function,
                        params.boundary));
    if (params.blurPrecision != RL_BLUR_FLOAT32 && params.blurPrecision != RL_BLUR_BFLOAT16)
        CV_Error(Error::StsOutOfRange,
                 format("%s: params.blurPrecision = %d must be RL_BLUR_FLOAT32 (0) or RL_BLUR_BFLOAT16 (1)", function,
                        params.blurPrecision));
}

}  // namespace dynblur
}  // namespace cv
