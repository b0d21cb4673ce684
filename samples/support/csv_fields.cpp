// SPDX-License-Identifier: Apache-2.0
#include "csv_fields.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace dynblur_samples {
namespace csv {

namespace {

//! Every character std::isspace and operator>> treat as blank (the "C" locale): a line that is blank
//! here is skipped, so a field split by spaces always finds at least one field.
const char* const kBlank = " \t\r\n\v\f";

}  // namespace

std::string trim(const std::string& s)
{
    const size_t a = s.find_first_not_of(kBlank);
    if (a == std::string::npos)
        return std::string();
    const size_t b = s.find_last_not_of(kBlank);
    return s.substr(a, b - a + 1);
}

std::vector<std::string> splitFields(const std::string& line)
{
    std::vector<std::string> fields;
    const bool hasDelimiter = line.find_first_of(",;\t") != std::string::npos;
    if (hasDelimiter)
    {
        std::string field;
        for (char c : line)
        {
            if (c == ',' || c == ';' || c == '\t')
            {
                fields.push_back(trim(field));
                field.clear();
            }
            else
                field += c;
        }
        fields.push_back(trim(field));
    }
    else
    {
        std::istringstream in(line);
        std::string field;
        while (in >> field)
            fields.push_back(field);
    }
    return fields;
}

std::string lower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

[[noreturn]] void parseError(const std::string& source, size_t line, const std::string& what)
{
    CV_Error(cv::Error::StsParseError, source + ":" + std::to_string(line) + ": " + what);
}

bool toDouble(const std::string& field, double& value)
{
    if (field.empty())
        return false;
    errno = 0;
    char* end = nullptr;
    value = std::strtod(field.c_str(), &end);
    return end == field.c_str() + field.size() && errno == 0 && std::isfinite(value);
}

std::string readTextFile(const std::string& path, const std::string& what)
{
    std::ifstream in(path, std::ios::binary);
    if (!in)
        CV_Error(cv::Error::StsError, "cannot open the " + what + " '" + path + "'");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad())
        CV_Error(cv::Error::StsError, "cannot read " + what + " '" + path + "'");
    return text.str();
}

}  // namespace csv
}  // namespace dynblur_samples
