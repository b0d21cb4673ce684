// SPDX-License-Identifier: Apache-2.0
// --model and --preset, declared and read the same way by every program that restores frames.
#ifndef DYNBLUR_SAMPLES_RESTORATION_OPTIONS_HPP
#define DYNBLUR_SAMPLES_RESTORATION_OPTIONS_HPP

#include "cli_args.hpp"

#include <string>

namespace dynblur_samples {

/** @brief --model NAME, defaulting to `defaultName` (a servo cycle restores with rows, a recording with
auto). */
CliOption modelOption(const std::string& defaultName = "auto");

//! --preset and --model (default auto), as a program that restores a recording declares them.
CliOptionGroup restorationOptions();

/** @brief --model's names: auto (PSF_AUTO: per band of rows the cheapest operator within 0.5 px of
the exact displacement), rows, tiles, uniform. Throws std::runtime_error naming --model and the
allowed names otherwise. */
int psfModelFromName(const std::string& name);

/** @brief --preset's names: frame-rate (DEBLUR_PRESET_FRAME_RATE) or default (DEBLUR_PRESET_DEFAULT).
Throws std::runtime_error naming --preset and the allowed names otherwise. */
int deblurPresetFromName(const std::string& name);

}  // namespace dynblur_samples

#endif
