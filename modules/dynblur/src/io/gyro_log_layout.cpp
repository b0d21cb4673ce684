// SPDX-License-Identifier: Apache-2.0
// The layouts GyroLog::load reads, told apart by the first line and the header row. Written from
// public descriptions only: Gyroflow's "GCSV format" page (docs.gyroflow.xyz), Sensor Logger's
// UNITS.md, COORDINATES.md and README (github.com/tszheichoi/awesome-sensor-logger), OpenCamera
// Sensors' README (github.com/MobileRoboticsSkoltech/OpenCamera-Sensors).
#include "precomp.hpp"

#include "io/gyro_log_layout.hpp"

#include <algorithm>
#include <cctype>

namespace cv {
namespace dynblur {
namespace gyro_log {

namespace {

const char* const kGcsvColumns = "'t,gx,gy,gz' (optionally followed by ',ax,ay,az' and ',mx,my,mz')";

//! What the message of an unrecognised log says it reads, and how to describe another CSV.
const char* const kKnownLayouts =
    "the reader knows gcsv (first line 'GYROFLOW IMU LOG' or 'CAMERA IMU LOG'), CSV with the header row "
    "'t,gx,gy,gz' (s, rad/s), Sensor Logger's Gyroscope.csv (header row 'time,seconds_elapsed,z,y,x') and "
    "OpenCamera Sensors' <video>_gyro.csv (rows 'x,y,z,timestamp_ns', no header row); describe another CSV with "
    "options.columns (its time, x, y and z rate columns, by name or 1-based position), options.timeUnit and "
    "options.rateUnit (--gyro-columns, --gyro-time-unit, --gyro-rate-unit)";

//! The axis string of a phone app's rates (Android's sensor frame) for the back camera, phone upright.
const char* const kPhoneToCamera = "Xyz";

bool columnsAre(const std::vector<std::string>& fields, std::initializer_list<const char*> names, size_t at)
{
    size_t j = at;
    for (const char* name : names)
        if (j >= fields.size() || lowered(fields[j++]) != name)
            return false;
    return true;
}

int columnNamed(const std::vector<std::string>& fields, const std::string& name)
{
    for (size_t j = 0; j < fields.size(); ++j)
        if (lowered(fields[j]) == lowered(trimmed(name)))
            return int(j);
    return -1;
}

bool allNumbers(const std::vector<std::string>& fields)
{
    double value;
    return std::all_of(fields.begin(), fields.end(), [&](const std::string& f) { return parseNumber(f, value); });
}

bool endsWith(const std::string& s, const std::string& tail)
{
    return s.size() >= tail.size() && lowered(s.substr(s.size() - tail.size())) == tail;
}

LogLayout readGcsv(const LogText& text, const GyroLogOptions& options)
{
    std::string given;  // the CSV options that were set, each named
    if (options.timeScale != 1.0)
        given += format(" options.timeScale = %g", options.timeScale);
    if (options.rateScale != 1.0)
        given += format(" options.rateScale = %g", options.rateScale);
    for (const auto& option : {std::make_pair("columns", &options.columns), std::make_pair("timeUnit", &options.timeUnit),
                               std::make_pair("rateUnit", &options.rateUnit)})
        if (!option.second->empty())
            given += format(" options.%s = '%s'", option.first, option.second->substr(0, 40).c_str());
    if (!given.empty())
        CV_Error_(Error::StsBadArg, ("%s: '%s' is a gcsv file, which states its own columns, tscale and gscale, but"
                                     "%s; options.columns, timeUnit, rateUnit, timeScale and rateScale apply to CSV "
                                     "logs (leave them empty, the scales 1)",
                                     kLoad, text.name().c_str(), given.c_str()));
    LogLayout layout;
    layout.name = "gcsv";
    layout.everyFieldNumeric = true;
    layout.gyroflowAxes = options.gcsvAxes == "gyroflow";
    layout.orientation.clear();
    double tscale = NAN, gscale = NAN;
    size_t columnRow = 1;
    for (; columnRow < text.size(); ++columnRow)
    {
        const std::string& line = text[columnRow];
        if (line.empty())
            continue;
        const size_t comma = line.find(',');
        const std::string key = lowered(trimmed(line.substr(0, comma)));
        const std::string value = comma == std::string::npos ? std::string() : trimmed(line.substr(comma + 1));
        if (key == "t")
            break;
        double number;
        if (parseNumber(key, number))
            text.fail(columnRow, format("a data row before the column row %s", kGcsvColumns));
        if (key == "version" && value.substr(0, 2) != "1." && value != "1")
            text.fail(columnRow, format("gcsv version '%s' is not supported; version 1.x (up to 1.3) is",
                                        value.substr(0, 40).c_str()));
        if (key == "id")
            layout.id = value;
        if (key == "orientation")
        {
            layout.orientation = value;
            try
            {
                (void)GyroLog::orientationMatrix(value);
            }
            catch (const cv::Exception& e)
            {
                if (options.orientation.empty())
                    text.fail(columnRow, "field 'orientation': " + e.err);
            }
        }
        if (key == "tscale" || key == "gscale")
        {
            if (!parseNumber(value, number) || !(number > 0))
                text.fail(columnRow, format("field '%s' = '%s' must be a finite number > 0 (%s)", key.c_str(),
                                            value.substr(0, 40).c_str(),
                                            key == "tscale" ? "seconds per time unit" : "rad/s per gyro unit"));
            (key == "tscale" ? tscale : gscale) = number;
        }
        if (key == "frame_readout_time")
        {
            if (!parseNumber(value, number) || !(number >= 0))
                text.fail(columnRow, format("field 'frame_readout_time' = '%s' must be a finite number >= 0 "
                                            "(milliseconds to read a whole frame)",
                                            value.substr(0, 40).c_str()));
            layout.frameReadoutTime = number * 1e-3;
        }
        if (key == "frame_readout_direction")
        {
            if (value.size() != 1 || value[0] < '0' || value[0] > '3')
                text.fail(columnRow, format("field 'frame_readout_direction' = '%s' must be 0 (top to bottom), 1 "
                                            "(bottom to top), 2 (left to right) or 3 (right to left)",
                                            value.substr(0, 40).c_str()));
            layout.frameReadoutDirection = value[0] - '0';
        }
    }
    if (columnRow == text.size())
        text.failFile(format("no column row %s after the gcsv header", kGcsvColumns));
    if (std::isnan(tscale) || std::isnan(gscale))
        text.failFile(format("the gcsv header lacks '%s' (before line %zu); it must state tscale (seconds per "
                             "time unit) and gscale (rad/s per gyro unit)",
                             std::isnan(tscale) ? "tscale" : "gscale", columnRow + 1));
    if (layout.orientation.empty() && options.orientation.empty())
        text.failFile("the gcsv header lacks 'orientation' (the gyro's axis string, e.g. 'XYZ'); add it or give "
                      "options.orientation");
    layout.secondsPerUnit = tscale;
    layout.radPerUnit = gscale;
    layout.columns = splitCommas(text[columnRow]);
    const std::vector<std::string>& columns = layout.columns;
    const bool accel = columns.size() >= 7 && columnsAre(columns, {"ax", "ay", "az"}, 4);
    const bool magnet = accel && columns.size() == 10 && columnsAre(columns, {"mx", "my", "mz"}, 7);
    if (!columnsAre(columns, {"t", "gx", "gy", "gz"}, 0) ||
        !(columns.size() == 4 || (accel && columns.size() == 7) || magnet))
        text.fail(columnRow, format("the column row must be %s", kGcsvColumns));
    layout.firstRow = columnRow + 1;
    return layout;
}

//! The columns GyroLogOptions::columns gives, found in the header row (or by position).
void useGivenColumns(const LogText& text, size_t row, bool rowIsData, const std::string& given, LogLayout& layout)
{
    const std::vector<std::string> header = splitCommas(text[row]);
    const std::vector<std::string> specs = splitCommas(given);
    layout.name = "columns";
    bool byPosition = true;
    for (const std::string& spec : specs)
        byPosition = byPosition && std::all_of(spec.begin(), spec.end(), [](char c) {
                         return std::isdigit(static_cast<unsigned char>(c)) != 0;
                     });
    if (rowIsData && !byPosition)
        text.fail(row, format("options.columns = '%s' names columns, but the first row is data (no header row); "
                              "give 1-based positions (e.g. '4,1,2,3')",
                              given.c_str()));
    layout.headerRow = !rowIsData;
    if (rowIsData)
        for (size_t j = 0; j < header.size(); ++j)
            layout.columns.push_back(format("column %zu", j + 1));
    else
        layout.columns = header;
    layout.firstRow = rowIsData ? row : row + 1;
    int index[4];
    for (int i = 0; i < 4; ++i)
    {
        index[i] = byPosition ? std::atoi(specs[i].c_str()) - 1 : columnNamed(header, specs[i]);
        if (index[i] < 0 || index[i] >= int(header.size()))
            text.fail(row, byPosition ? format("options.columns: position %s is not one of the row's %zu columns",
                                               specs[i].c_str(), header.size())
                                      : format("options.columns: no column '%s' in the header row '%s'",
                                               specs[i].c_str(), text[row].substr(0, 120).c_str()));
        for (int k = 0; k < i; ++k)
            if (index[k] == index[i])
                text.fail(row, format("options.columns = '%s' names column '%s' twice; the time and the three "
                                      "rates are four different columns",
                                      given.c_str(), layout.columns[index[i]].c_str()));
    }
    layout.time = index[0];
    for (int i = 0; i < 3; ++i)
        layout.rate[i] = index[i + 1];
}

LogLayout readCsv(const LogText& text, const GyroLogOptions& options)
{
    size_t row = 0;
    while (row < text.size() && (text[row].empty() || text[row][0] == '#'))
        ++row;
    if (row == text.size())
        text.failFile("only comment lines; " + std::string(kKnownLayouts));
    const std::vector<std::string> first = splitCommas(text[row]);
    const bool rowIsData = allNumbers(first);
    LogLayout layout;
    if (!options.columns.empty())
        useGivenColumns(text, row, rowIsData, options.columns, layout);
    else if (rowIsData && first.size() == 4 && endsWith(text.name(), "_gyro.csv"))
    {
        layout.name = "opencamera-sensors";  // x, y, z (rad/s), timestamp (ns); no header row
        layout.headerRow = false;
        layout.firstRow = row;
        layout.columns = {"x", "y", "z", "timestamp"};
        layout.time = 3;
        for (int i = 0; i < 3; ++i)
            layout.rate[i] = i;
        layout.secondsPerUnit = 1e-9;
        layout.orientation = kPhoneToCamera;
    }
    else if (!rowIsData && columnsAre(first, {"t", "gx", "gy", "gz"}, 0))
    {
        layout.name = "csv";
        layout.firstRow = row + 1;
        layout.columns = first;
    }
    else if (!rowIsData && columnNamed(first, "time") >= 0 && columnNamed(first, "seconds_elapsed") >= 0 &&
             columnNamed(first, "x") >= 0 && columnNamed(first, "y") >= 0 && columnNamed(first, "z") >= 0)
    {
        layout.name = "sensor-logger";  // time (ns of the Unix epoch), seconds_elapsed, z, y, x (rad/s)
        layout.firstRow = row + 1;
        layout.columns = first;
        layout.time = columnNamed(first, "time");
        for (int i = 0; i < 3; ++i)
            layout.rate[i] = columnNamed(first, std::string(1, char('x' + i)));
        layout.secondsPerUnit = 1e-9;
        layout.orientation = kPhoneToCamera;
    }
    else
        text.fail(row, format("missing header: %s '%s' is of no known layout; %s",
                              rowIsData ? "the first row is data," : "the header row", text[row].substr(0, 80).c_str(),
                              kKnownLayouts));
    if (!options.timeUnit.empty())
        secondsPerTimeUnit(options.timeUnit, layout.secondsPerUnit);
    else if (options.timeScale != 1.0)
        layout.secondsPerUnit = options.timeScale;
    if (!options.rateUnit.empty())
        radPerRateUnit(options.rateUnit, layout.radPerUnit);
    else if (options.rateScale != 1.0)
        layout.radPerUnit = options.rateScale;
    return layout;
}

}  // namespace

LogLayout readLayout(const LogText& text, const GyroLogOptions& options)
{
    if (text[0] == "GYROFLOW IMU LOG" || text[0] == "CAMERA IMU LOG")
        return readGcsv(text, options);
    return readCsv(text, options);
}

}  // namespace gyro_log
}  // namespace dynblur
}  // namespace cv
