// SPDX-License-Identifier: Apache-2.0
#include "plant_file.hpp"

#include "atomic_file.hpp"

#include <cstdio>

namespace dynblur_samples {

PlantFile loadPlantFile(const std::string& path)
{
    // Not cv::FileStorage: its readers trust their input (see cv::dynblur::ParameterFile).
    const cv::dynblur::ParameterFile in = cv::dynblur::ParameterFile::load(path, "plant file");
    for (const char* key : {"naturalFreqHz", "dampingRatio", "gain"})
        if (!in.has(key))
            CV_Error(cv::Error::StsParseError, "plant file '" + path + "' needs a number '" + key + "'");
    PlantFile file;
    try
    {
        file.plant = cv::dynblur::Plant::create(in.real("naturalFreqHz"), in.real("dampingRatio"), in.real("gain"));
    }
    catch (const cv::Exception& e)
    {
        CV_Error(e.code, "plant file '" + path + "': " + e.err);
    }
    if (in.has("maxLevel"))
    {
        file.maxLevel = in.integer("maxLevel");
        if (file.maxLevel < 1)
            CV_Error_(cv::Error::StsOutOfRange,
                      ("plant file '%s': maxLevel = %d must be an integer >= 1 (cells)", path.c_str(), file.maxLevel));
    }
    return file;
}

void savePlantFile(const std::string& path, const cv::dynblur::Plant& plant, int maxLevel, const std::string& comment)
{
    const std::string temporary = temporaryPathFor(path);
    {
        cv::FileStorage fs(temporary, cv::FileStorage::WRITE);
        if (!fs.isOpened())
            CV_Error(cv::Error::StsError, "cannot write '" + temporary + "'");
        if (!comment.empty())
            fs.writeComment(comment);
        fs << "naturalFreqHz" << plant.getNaturalFreqHz() << "dampingRatio" << plant.getDampingRatio()
           << "gain" << plant.getGain() << "maxLevel" << maxLevel;
    }
    renameIntoPlace(temporary, path);
}

}  // namespace dynblur_samples
