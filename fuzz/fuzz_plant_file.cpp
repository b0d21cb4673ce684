// SPDX-License-Identifier: Apache-2.0
// Fuzzes loadPlantFile (samples/support/plant_file.cpp), the reader of the plant YAML the
// calibration tool writes and the demo, the simulator and the servoing sample read (--plant): OpenCV's
// FileStorage parser, then the field checks and Plant::create. A plant that loads must simulate.
#include "fuzz_common.hpp"
#include "plant_file.hpp"

#include <opencv2/dynblur.hpp>

using namespace cv::dynblur;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string& path = dynblur_fuzz::writeScratchFile(data, size, "_plant.yml");
    try
    {
        const dynblur_samples::PlantFile file = dynblur_samples::loadPlantFile(path);
        if (!file.plant || file.maxLevel < 1)
            std::abort();
        // What the programs do next: plan a move and predict it.
        const SwitchSchedule step({0.0}, {1}, 0);
        cv::Mat theta;
        file.plant->response(step, std::vector<double>{0.0, 0.01, 0.1}, theta);
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
    }
    return 0;
}
