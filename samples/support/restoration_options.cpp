// SPDX-License-Identifier: Apache-2.0
#include "restoration_options.hpp"

#include <opencv2/dynblur.hpp>

#include <stdexcept>

namespace dynblur_samples {

CliOption modelOption(const std::string& defaultName)
{
    return {"model", "NAME", defaultName,
            "PSF model: auto (per band of rows, the cheapest of uniform, rows and tiles within 0.5 px of the exact "
            "motion), rows, tiles or uniform"};
}

CliOptionGroup restorationOptions()
{
    return {"", "",
            {{"preset", "NAME", "frame-rate",
              "frame-rate (iterations by the blur's length, color at half resolution) or default (20 iterations, "
              "full color); docs/quality.md gives both per window"},
             modelOption()}};
}

int psfModelFromName(const std::string& name)
{
    if (name == "auto")
        return cv::dynblur::PSF_AUTO;
    if (name == "rows")
        return cv::dynblur::PSF_ROWS;
    if (name == "tiles")
        return cv::dynblur::PSF_TILES;
    if (name == "uniform")
        return cv::dynblur::PSF_UNIFORM;
    throw std::runtime_error("--model must be auto, rows, tiles or uniform (got '" + name + "')");
}

int deblurPresetFromName(const std::string& name)
{
    if (name == "frame-rate")
        return cv::dynblur::DEBLUR_PRESET_FRAME_RATE;
    if (name == "default")
        return cv::dynblur::DEBLUR_PRESET_DEFAULT;
    throw std::runtime_error("--preset must be frame-rate or default (got '" + name + "')");
}

}  // namespace dynblur_samples
