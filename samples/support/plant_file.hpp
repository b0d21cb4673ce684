// SPDX-License-Identifier: Apache-2.0
// The plant file the calibration tools write and the programs read (YAML or any cv::FileStorage
// format): naturalFreqHz, dampingRatio, gain (radians per level), maxLevel.
#ifndef DYNBLUR_SAMPLES_PLANT_FILE_HPP
#define DYNBLUR_SAMPLES_PLANT_FILE_HPP

#include <opencv2/dynblur.hpp>

#include <string>

namespace dynblur_samples {

struct PlantFile
{
    cv::Ptr<cv::dynblur::Plant> plant;
    int maxLevel = 16;
};

/** Reads a plant file; throws cv::Exception naming the missing or bad field. */
PlantFile loadPlantFile(const std::string& path);

/** Writes a plant file atomically (temporary file, then rename). */
void savePlantFile(const std::string& path, const cv::dynblur::Plant& plant, int maxLevel, const std::string& comment);

}  // namespace dynblur_samples

#endif
