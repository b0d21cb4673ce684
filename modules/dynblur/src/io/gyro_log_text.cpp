// SPDX-License-Identifier: Apache-2.0
// The text of a gyro log: lines, fields, numbers, timestamps at the file's precision, unit names.
#include "precomp.hpp"

#include "io/gyro_log_text.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>

namespace cv {
namespace dynblur {
namespace gyro_log {

const char* const kLoad = "GyroLog::load";
const char* const kTimeUnits = "'s', 'ms', 'us' (or 'µs'), 'ns'";
const char* const kRateUnits = "'rad/s', 'deg/s'";

std::string trimmed(const std::string& s)
{
    const char* blank = " \t\r\n\v\f";
    const size_t first = s.find_first_not_of(blank);
    return first == std::string::npos ? std::string() : s.substr(first, s.find_last_not_of(blank) - first + 1);
}

std::string lowered(std::string s)
{
    for (char& c : s)
        c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::vector<std::string> splitCommas(const std::string& line)
{
    std::vector<std::string> fields;
    size_t start = 0;
    for (;;)
    {
        const size_t comma = line.find(',', start);
        fields.push_back(trimmed(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
        if (comma == std::string::npos)
            return fields;
        start = comma + 1;
    }
}

bool parseNumber(const std::string& field, double& value)
{
    if (field.empty() || field.find('\0') != std::string::npos)
        return false;
    errno = 0;
    char* end = nullptr;
    value = std::strtod(field.c_str(), &end);
    return end == field.c_str() + field.size() && errno != ERANGE && std::isfinite(value);
}

bool parseTimestamp(const std::string& field, Timestamp& t)
{
    if (!parseNumber(field, t.value))
        return false;
    // Plain decimal digits: the whole part read as an integer, the fraction apart.
    size_t i = field[0] == '-' || field[0] == '+' ? 1 : 0;
    const size_t digitsFrom = i;
    while (i < field.size() && std::isdigit(static_cast<unsigned char>(field[i])))
        ++i;
    const size_t wholeDigits = i - digitsFrom;
    bool plain = wholeDigits >= 1 && wholeDigits <= 19;  // int64 holds 19 digits up to 9223372036854775807
    if (plain && i < field.size())
    {
        plain = field[i] == '.';
        for (size_t j = i + 1; plain && j < field.size(); ++j)
            plain = std::isdigit(static_cast<unsigned char>(field[j])) != 0;
    }
    std::int64_t whole = 0;
    if (plain)
    {
        errno = 0;
        whole = std::strtoll(field.substr(digitsFrom, wholeDigits).c_str(), nullptr, 10);
        plain = errno != ERANGE;
    }
    if (plain)
    {
        const double sign = field[0] == '-' ? -1.0 : 1.0;
        t.whole = sign < 0 ? -whole : whole;
        t.fraction = i < field.size() && i + 1 < field.size() ? sign * std::strtod(("0" + field.substr(i)).c_str(), nullptr)
                                                               : 0.0;
        return true;
    }
    if (!(std::abs(t.value) < 9e18))
        return false;  // beyond any clock a log keeps
    t.whole = std::int64_t(std::floor(t.value));
    t.fraction = t.value - double(t.whole);
    return true;
}

namespace {

struct UnitName
{
    const char* name;  //!< lower case
    double factor;     //!< SI units (s, rad/s) per unit
};

template <size_t N>
bool lookUp(const UnitName (&table)[N], const std::string& unit, double& factor)
{
    const std::string u = lowered(trimmed(unit));
    for (const UnitName& entry : table)
        if (u == entry.name)
        {
            factor = entry.factor;
            return true;
        }
    return false;
}

const UnitName kTimeUnitTable[] = {{"s", 1.0},   {"ms", 1e-3}, {"us", 1e-6},
                                   {"\xC2\xB5s", 1e-6},  // micro sign
                                   {"\xCE\xBCs", 1e-6},  // Greek mu
                                   {"ns", 1e-9}};
const UnitName kRateUnitTable[] = {{"rad/s", 1.0}, {"deg/s", CV_PI / 180.0}};

}  // namespace

bool secondsPerTimeUnit(const std::string& unit, double& seconds)
{
    return lookUp(kTimeUnitTable, unit, seconds);
}

bool radPerRateUnit(const std::string& unit, double& radPerSecond)
{
    return lookUp(kRateUnitTable, unit, radPerSecond);
}

LogText::LogText(const String& filename) : name_(filename)
{
    std::ifstream in(filename, std::ios::binary);
    if (!in)
        CV_Error_(Error::StsError, ("%s: cannot open the gyro log '%s'", kLoad, filename.c_str()));
    std::string line;
    while (std::getline(in, line))
        lines_.push_back(trimmed(line));
    if (!lines_.empty() && lines_[0].compare(0, 3, "\xEF\xBB\xBF") == 0)
        lines_[0] = trimmed(lines_[0].substr(3));  // a UTF-8 byte order mark, as some editors write
    while (!lines_.empty() && lines_.back().empty())
        lines_.pop_back();
    if (lines_.empty())
        CV_Error_(Error::StsParseError, ("%s: '%s' is empty; a gyro log (gcsv or CSV) was expected", kLoad,
                                         filename.c_str()));
}

void LogText::fail(size_t i, const std::string& what) const
{
    CV_Error_(Error::StsParseError, ("%s: %s:%zu: %s", kLoad, name_.c_str(), i + 1, what.c_str()));
}

void LogText::failFile(const std::string& what) const
{
    CV_Error_(Error::StsParseError, ("%s: %s: %s", kLoad, name_.c_str(), what.c_str()));
}

}  // namespace gyro_log
}  // namespace dynblur
}  // namespace cv
