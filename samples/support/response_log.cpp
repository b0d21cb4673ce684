// SPDX-License-Identifier: Apache-2.0
#include "response_log.hpp"

#include "atomic_file.hpp"
#include "csv_fields.hpp"

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

using namespace csv;

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
    return parseResponseLog(readTextFile(path, "response log"), path);
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
