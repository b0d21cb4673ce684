#include "response_log.hpp"

#include "atomic_file.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace dynblur_samples {

namespace {

//! Every character std::isspace and operator>> treat as blank (the "C" locale): a line that is blank
//! here is skipped, so a field split by spaces always finds at least one field.
const char* const kBlank = " \t\r\n\v\f";

std::string trim(const std::string& s)
{
    const size_t a = s.find_first_not_of(kBlank);
    if (a == std::string::npos)
        return std::string();
    const size_t b = s.find_last_not_of(kBlank);
    return s.substr(a, b - a + 1);
}

//! Fields separated by ',', ';', tab or runs of spaces.
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

double medianOf(std::vector<double> v)
{
    if (v.empty())
        return 0;
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

}  // namespace

ResponseLog parseResponseLog(const std::string& text, const std::string& source)
{
    std::istringstream in(text);
    std::string raw;
    size_t lineNo = 0;
    int tCol = -1, thetaCol = -1, levelCol = -1;
    size_t columns = 0;
    bool haveHeader = false;
    ResponseLog log;
    while (std::getline(in, raw))
    {
        ++lineNo;
        const std::string line = trim(raw);
        if (line.empty() || line[0] == '#')
            continue;
        const std::vector<std::string> fields = splitFields(line);
        if (!haveHeader)
        {
            double probe;
            if (toDouble(fields[0], probe))
                parseError(source, lineNo, "expected a header line naming the columns (e.g. 't,theta,level'), got "
                                           "numbers");
            for (size_t c = 0; c < fields.size(); ++c)
            {
                const std::string name = lower(fields[c]);
                if (name == "t" || name == "time" || name == "t_s" || name == "t[s]")
                    tCol = static_cast<int>(c);
                else if (name == "theta" || name == "theta_rad" || name == "theta[rad]")
                    thetaCol = static_cast<int>(c);
                else if (name == "level" || name == "u")
                    levelCol = static_cast<int>(c);
            }
            if (tCol < 0 || thetaCol < 0)
                parseError(source, lineNo, "the header '" + line + "' must name the columns 't' and 'theta' "
                                           "(and optionally 'level')");
            columns = fields.size();
            haveHeader = true;
            continue;
        }
        if (fields.size() != columns)
            parseError(source, lineNo, "expected " + std::to_string(columns) + " fields like the header, found " +
                                           std::to_string(fields.size()) + ": '" + line + "'");
        double t, theta;
        if (!toDouble(fields[static_cast<size_t>(tCol)], t))
            parseError(source, lineNo, "'" + fields[static_cast<size_t>(tCol)] + "' is not a finite number (t, seconds)");
        if (!toDouble(fields[static_cast<size_t>(thetaCol)], theta))
            parseError(source, lineNo,
                       "'" + fields[static_cast<size_t>(thetaCol)] + "' is not a finite number (theta, radians)");
        if (!log.t.empty() && !(t > log.t.back()))
            parseError(source, lineNo, cv::format("t=%.9g does not increase (previous sample t=%.9g)", t, log.t.back()));
        log.t.push_back(t);
        log.theta.push_back(theta);
        if (levelCol >= 0)
        {
            double level;
            const std::string& f = fields[static_cast<size_t>(levelCol)];
            if (!toDouble(f, level) || level != std::round(level) || std::abs(level) > 1e6)
                parseError(source, lineNo, "'" + f + "' is not an integer level (cells)");
            log.level.push_back(static_cast<int>(level));
        }
    }
    if (!haveHeader)
        CV_Error(cv::Error::StsParseError, source + ": no header line and no samples (an empty log)");
    return log;
}

ResponseLog readResponseLog(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in)
        CV_Error(cv::Error::StsError, "cannot open response log '" + path + "'");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad())
        CV_Error(cv::Error::StsError, "cannot read response log '" + path + "'");
    return parseResponseLog(text.str(), path);
}

void writeResponseLog(const std::string& path, const ResponseLog& log)
{
    if (log.theta.size() != log.t.size() || (log.hasLevel() && log.level.size() != log.t.size()))
        CV_Error(cv::Error::StsBadArg, "writeResponseLog: t, theta and level must have the same length");
    const std::string temporary = path + ".tmp";
    {
        std::ofstream out(temporary);
        if (!out)
            CV_Error(cv::Error::StsError, "cannot write '" + temporary + "'");
        out << (log.hasLevel() ? "t,theta,level\n" : "t,theta\n");
        char buffer[96];
        for (size_t i = 0; i < log.t.size(); ++i)
        {
            if (log.hasLevel())
                std::snprintf(buffer, sizeof(buffer), "%.9f,%.12g,%d\n", log.t[i], log.theta[i], log.level[i]);
            else
                std::snprintf(buffer, sizeof(buffer), "%.9f,%.12g\n", log.t[i], log.theta[i]);
            out << buffer;
        }
        out.flush();
        if (!out)
        {
            std::remove(temporary.c_str());
            CV_Error(cv::Error::StsError, "cannot write '" + temporary + "'");
        }
    }
    renameIntoPlace(temporary, path);
}

cv::dynblur::SwitchSchedule scheduleFromLevels(const ResponseLog& log)
{
    if (!log.hasLevel())
        CV_Error(cv::Error::StsBadArg, "the log has no 'level' column; give the command as a schedule file");
    cv::dynblur::SwitchSchedule schedule;
    schedule.initialLevel = log.level.front();
    for (size_t i = 1; i < log.level.size(); ++i)
        if (log.level[i] != log.level[i - 1])
        {
            schedule.times.push_back(0.5 * (log.t[i - 1] + log.t[i]));
            schedule.levels.push_back(log.level[i]);
        }
    if (schedule.times.empty())
        CV_Error(cv::Error::StsBadArg, cv::format("the commanded level never changes (%d throughout the log): "
                                                  "a step response is needed",
                                                  log.level.front()));
    return schedule;
}

void checkResponseLog(const ResponseLog& log, size_t minSamples)
{
    if (log.t.size() < minSamples)
        CV_Error(cv::Error::StsBadArg, cv::format("the log has %zu samples; at least %zu are needed to identify the "
                                                  "plant",
                                                  log.t.size(), minSamples));
    const auto range = std::minmax_element(log.theta.begin(), log.theta.end());
    const double peakToPeak = *range.second - *range.first;
    // Noise from second differences (a smooth response hardly contributes): for white noise of
    // standard deviation s, theta[i+1] - 2 theta[i] + theta[i-1] has standard deviation s*sqrt(6).
    std::vector<double> d2;
    for (size_t i = 1; i + 1 < log.theta.size(); ++i)
        d2.push_back(std::abs(log.theta[i + 1] - 2 * log.theta[i] + log.theta[i - 1]));
    const double noise = 1.4826 * medianOf(d2) / std::sqrt(6.0);
    if (!(peakToPeak > 0) || peakToPeak < 12 * noise)
        CV_Error(cv::Error::StsBadArg,
                 cv::format("no motion in the log: theta spans %.3g rad (%.3g deg) peak to peak, within its noise "
                            "(%.3g rad rms); was the actuator powered and the command applied?",
                            peakToPeak, peakToPeak * 180 / CV_PI, noise));
}

}  // namespace dynblur_samples
