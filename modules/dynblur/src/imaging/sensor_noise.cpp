// SPDX-License-Identifier: Apache-2.0
// A sensor's noise on a linear frame: photon shot noise, dark current and read noise in electrons.
#include "precomp.hpp"

#include <random>

namespace cv {
namespace dynblur {

void addSensorNoise(InputArray _linear, OutputArray _noisy, double fullWellElectrons, double readNoiseElectrons,
                    double darkElectrons, uint64 seed)
{
    Mat src = _linear.getMat();
    if (src.empty())
        CV_Error(Error::StsBadArg, "addSensorNoise: 'linear' is empty");
    CV_CheckType(src.type(), src.depth() == CV_32F, "addSensorNoise: linear must be CV_32F");
    if (!checkRange(src))
        CV_Error(Error::StsBadArg, "addSensorNoise: 'linear' holds NaN or Inf; it must be finite");
    if (!(std::isfinite(fullWellElectrons) && fullWellElectrons > 0))
        CV_Error_(Error::StsBadArg, ("addSensorNoise: fullWellElectrons=%g must be finite and > 0", fullWellElectrons));
    if (!(std::isfinite(readNoiseElectrons) && readNoiseElectrons >= 0))
        CV_Error_(Error::StsBadArg,
                  ("addSensorNoise: readNoiseElectrons=%g must be finite and >= 0", readNoiseElectrons));
    if (!(std::isfinite(darkElectrons) && darkElectrons >= 0))
        CV_Error_(Error::StsBadArg, ("addSensorNoise: darkElectrons=%g must be finite and >= 0", darkElectrons));
    Mat out = src.clone();
    std::mt19937_64 engine(seed);
    std::normal_distribution<double> read(0.0, 1.0);
    for (int y = 0; y < out.rows; y++)
    {
        float* d = out.ptr<float>(y);
        const int n = out.cols * out.channels();
        for (int x = 0; x < n; x++)
        {
            // Photo-electrons plus dark electrons are Poisson; the camera subtracts the mean dark
            // level (black clamp), so the result is unbiased before clipping.
            const double mean = std::max(0.0, (double)d[x]) * fullWellElectrons + darkElectrons;
            double e = 0.0;
            if (mean > 0)
            {
                std::poisson_distribution<long long> shot(mean);
                e = (double)shot(engine);
            }
            e += readNoiseElectrons * read(engine) - darkElectrons;
            d[x] = (float)std::min(1.0, std::max(0.0, e / fullWellElectrons));
        }
    }
    out.copyTo(_noisy);
}

}  // namespace dynblur
}  // namespace cv
