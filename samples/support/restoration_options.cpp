// SPDX-License-Identifier: Apache-2.0
#include "restoration_options.hpp"

#include <opencv2/dynblur.hpp>

#include <stdexcept>

namespace dynblur_samples {

const char* const kModelOptionHelp =
    "  --model NAME         PSF model: auto (default: per band of rows, the cheapest of uniform, rows and\n"
    "                       tiles within 0.5 px of the exact motion), rows, tiles or uniform\n";

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
