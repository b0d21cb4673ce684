// SPDX-License-Identifier: Apache-2.0
#include "precomp.hpp"

#include "io/whole_file.hpp"

#include <cstdio>

namespace cv {
namespace dynblur {
namespace detail {

void saveWhole(const String& filename, const String& who, const std::function<void(FileStorage&)>& write)
{
    const size_t dot = filename.find_last_of('.');
    const String temporary = filename + ".partial" + (dot == String::npos ? String(".yml") : filename.substr(dot));
    try
    {
        FileStorage fs(temporary, FileStorage::WRITE);
        if (!fs.isOpened())
            CV_Error(Error::StsError, who + ": cannot open '" + temporary + "' for writing");
        write(fs);
    }
    catch (...)
    {
        std::remove(temporary.c_str());
        throw;
    }
    if (std::rename(temporary.c_str(), filename.c_str()) != 0)
    {
        std::remove(temporary.c_str());
        CV_Error(Error::StsError, who + ": cannot write '" + filename + "'");
    }
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
