#include "plant_file.hpp"

#include "atomic_file.hpp"

#include <cstdio>

namespace dynblur_samples {

PlantFile loadPlantFile(const std::string& path)
{
    cv::FileStorage fs;
    try
    {
        fs.open(path, cv::FileStorage::READ);
    }
    catch (const cv::Exception& e)
    {
        CV_Error(cv::Error::StsParseError, "plant file '" + path + "' cannot be parsed: " + e.msg);
    }
    if (!fs.isOpened())
        CV_Error(cv::Error::StsError, "cannot open plant file '" + path + "'");
    auto number = [&](const char* key) {
        const cv::FileNode node = fs[key];
        if (node.empty() || !(node.isReal() || node.isInt()))
            CV_Error(cv::Error::StsParseError, std::string("plant file '") + path + "' needs a number '" + key + "'");
        return node.real();
    };
    PlantFile file;
    file.plant = cv::dynblur::Plant::create(number("naturalFreqHz"), number("dampingRatio"), number("gain"));
    const cv::FileNode maxLevel = fs["maxLevel"];
    if (!maxLevel.empty())
    {
        if (!maxLevel.isInt() || static_cast<int>(maxLevel) < 1)
            CV_Error(cv::Error::StsParseError, "plant file '" + path + "': maxLevel must be an integer >= 1");
        file.maxLevel = static_cast<int>(maxLevel);
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
