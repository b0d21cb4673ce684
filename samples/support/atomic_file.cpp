// SPDX-License-Identifier: Apache-2.0
#include "atomic_file.hpp"

#include <opencv2/core.hpp>

#include <cstdio>
#include <fstream>

namespace dynblur_samples {

std::string pathStem(const std::string& path)
{
    const size_t dot = path.find_last_of('.');
    const size_t slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
        return path;
    return path.substr(0, dot);
}

std::string temporaryPathFor(const std::string& path)
{
    const std::string stem = pathStem(path);
    return stem + ".tmp" + path.substr(stem.size());
}

void renameIntoPlace(const std::string& temporary, const std::string& path)
{
    if (std::rename(temporary.c_str(), path.c_str()) != 0)
    {
        std::remove(temporary.c_str());
        CV_Error(cv::Error::StsError, "cannot move '" + temporary + "' to '" + path + "'");
    }
}

void writeTextFile(const std::string& path, const std::string& text)
{
    const std::string temporary = temporaryPathFor(path);
    {
        std::ofstream out(temporary, std::ios::binary);
        out << text;
        if (!out)
        {
            std::remove(temporary.c_str());
            CV_Error(cv::Error::StsError, "cannot write '" + path + "'");
        }
    }
    renameIntoPlace(temporary, path);
}

}  // namespace dynblur_samples
