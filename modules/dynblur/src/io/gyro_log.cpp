// SPDX-License-Identifier: Apache-2.0
// GyroLog: Gyroflow's gcsv and plain CSV gyro logs read into camera axes, and the bias from still
// intervals. Written from the gcsv format's public description (docs.gyroflow.xyz, "GCSV format").
#include "precomp.hpp"

#include "motion/sampled_motion.hpp"
#include "motion/so3.hpp"

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <fstream>

namespace cv {
namespace dynblur {

namespace {

const char* const kLoad = "GyroLog::load";

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

//! The whole field as one finite number.
bool parseNumber(const std::string& field, double& value)
{
    if (field.empty() || field.find('\0') != std::string::npos)
        return false;
    errno = 0;
    char* end = nullptr;
    value = std::strtod(field.c_str(), &end);
    return end == field.c_str() + field.size() && errno != ERANGE && std::isfinite(value);
}

//! The file's lines, numbered from 1, and errors that name the file and the line.
class LogText
{
public:
    explicit LogText(const String& filename) : name_(filename)
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
            CV_Error_(Error::StsParseError, ("%s: '%s' is empty; a gyro log (gcsv or CSV 't,gx,gy,gz') was expected",
                                             kLoad, filename.c_str()));
    }
    size_t size() const { return lines_.size(); }
    const std::string& operator[](size_t i) const { return lines_[i]; }

    [[noreturn]] void fail(size_t i, const std::string& what) const
    {
        CV_Error_(Error::StsParseError, ("%s: %s:%zu: %s", kLoad, name_.c_str(), i + 1, what.c_str()));
    }
    [[noreturn]] void failFile(const std::string& what) const
    {
        CV_Error_(Error::StsParseError, ("%s: %s: %s", kLoad, name_.c_str(), what.c_str()));
    }

private:
    String name_;
    std::vector<std::string> lines_;
};

const char* const kColumnsWanted = "'t,gx,gy,gz' (gcsv: optionally followed by ',ax,ay,az' and ',mx,my,mz')";

/** The data rows from line `first` on: each with as many fields as `columns` names, every field a
    finite number; t scaled by timeScale, (gx, gy, gz) by rateScale and mapped by `toCamera`. */
void readRows(const LogText& text, size_t first, const std::vector<std::string>& columns, double timeScale,
              double rateScale, const Matx33d& toCamera, GyroLog& log)
{
    std::vector<Vec3d> rates;
    std::vector<size_t> lineOf;
    for (size_t i = first; i < text.size(); ++i)
    {
        if (text[i].empty())
            continue;
        const std::vector<std::string> fields = splitCommas(text[i]);
        if (fields.size() != columns.size())
            text.fail(i, format("%zu fields, but the column row names %zu; one value per column", fields.size(),
                                columns.size()));
        double v[4];
        for (size_t j = 0; j < fields.size(); ++j)
        {
            double value;
            if (!parseNumber(fields[j], value))
                text.fail(i, format("field '%s' = '%s' is not a finite number", columns[j].c_str(),
                                    fields[j].substr(0, 40).c_str()));
            if (j < 4)
                v[j] = value;
        }
        const double t = v[0] * timeScale;
        const Vec3d w = toCamera * Vec3d(v[1], v[2], v[3]) * rateScale;
        if (!std::isfinite(t) || !std::isfinite(w[0]) || !std::isfinite(w[1]) || !std::isfinite(w[2]))
            text.fail(i, "the scaled time or rate overflows");
        if (!log.times.empty() && !(t > log.times.back()))
            text.fail(i, format("field 't': %.9g s is not after the previous sample's %.9g s (line %zu); timestamps "
                                "must be strictly increasing, without repeats",
                                t, log.times.back(), lineOf.back() + 1));
        log.times.push_back(t);
        rates.push_back(w);
        lineOf.push_back(i);
    }
    if (log.times.size() < 2)
        text.failFile(format("%zu sample(s) after the column row; a gyro log needs at least 2", log.times.size()));
    double median = 0;
    if (const size_t k = detail::findLongGap(log.times, median))
        text.fail(lineOf[k], format("a gap of %.6g s after the sample of line %zu, longer than %g median sample "
                                    "intervals (%.6g s): samples are missing",
                                    log.times[k] - log.times[k - 1], lineOf[k - 1] + 1,
                                    detail::kMaxGapInMedianIntervals, median));
    log.rates = Mat(int(rates.size()), 3, CV_64F, rates.data()).clone();
}

bool columnsAre(const std::vector<std::string>& fields, std::initializer_list<const char*> names, size_t at)
{
    size_t j = at;
    for (const char* name : names)
        if (j >= fields.size() || lowered(fields[j++]) != name)
            return false;
    return true;
}

void checkOptions(const GyroLogOptions& o)
{
    if (!(o.timeScale > 0) || !std::isfinite(o.timeScale))
        CV_Error_(Error::StsOutOfRange, ("%s: options.timeScale = %g must be finite and > 0 (seconds per unit)",
                                         kLoad, o.timeScale));
    if (!(o.rateScale > 0) || !std::isfinite(o.rateScale))
        CV_Error_(Error::StsOutOfRange, ("%s: options.rateScale = %g must be finite and > 0 (rad/s per unit)",
                                         kLoad, o.rateScale));
    if (!(so3::rotationDefect(o.cameraFromGyro) <= 1e-3))
        CV_Error_(Error::StsBadArg, ("%s: options.cameraFromGyro is not a rotation (det = %.6g); a proper rotation "
                                     "(orthonormal, det = +1, within 1e-3) is required",
                                     kLoad, determinant(o.cameraFromGyro)));
}

}  // namespace

GyroLogOptions::GyroLogOptions()
    : cameraFromGyro(Matx33d::eye()), timeScale(1.0), rateScale(1.0), estimateBias(false), stillThreshold(0.05),
      stillMinDuration(0.5)
{
}

GyroLog::GyroLog() : bias(0, 0, 0), biasStillSeconds(0), cameraFromGyro(Matx33d::eye()), orientation("XYZ") {}

Matx33d GyroLog::orientationMatrix(const String& orientation)
{
    Matx33d S = Matx33d::zeros();
    bool used[3] = {false, false, false};
    bool valid = orientation.size() == 3;
    for (size_t i = 0; valid && i < 3; ++i)
    {
        const char c = orientation[i];
        const int axis = std::tolower(static_cast<unsigned char>(c)) - 'x';
        valid = axis >= 0 && axis < 3 && !used[axis];
        if (valid)
        {
            used[axis] = true;
            S(int(i), axis) = std::isupper(static_cast<unsigned char>(c)) ? 1.0 : -1.0;
        }
    }
    if (!valid)
        CV_Error_(Error::StsBadArg, ("GyroLog::orientationMatrix: unknown orientation string '%s'; three letters, one "
                                     "each of x, y and z in any order, uppercase for a gyro axis along the camera "
                                     "axis and lowercase for one against it (e.g. 'XYZ', 'YxZ')",
                                     orientation.substr(0, 40).c_str()));
    if (determinant(S) < 0)
        CV_Error_(Error::StsBadArg, ("GyroLog::orientationMatrix: orientation string '%s' describes a mirrored "
                                     "(left-handed) frame, det = -1; flip the case of one letter, or of all three",
                                     orientation.c_str()));
    return S;
}

GyroLog GyroLog::load(const String& filename, const GyroLogOptions& options)
{
    checkOptions(options);
    const LogText text(filename);
    GyroLog log;
    String axes = "XYZ";
    double timeScale = options.timeScale, rateScale = options.rateScale;
    size_t columnRow = 0;
    std::vector<std::string> columns;
    if (text[0] == "GYROFLOW IMU LOG" || text[0] == "CAMERA IMU LOG")
    {
        if (options.timeScale != 1.0 || options.rateScale != 1.0)
            CV_Error_(Error::StsBadArg, ("%s: '%s' is a gcsv file, which states its own tscale and gscale; "
                                         "options.timeScale and options.rateScale apply to plain CSV and must stay 1",
                                         kLoad, filename.c_str()));
        double tscale = NAN, gscale = NAN;
        bool hasOrientation = false;
        for (columnRow = 1; columnRow < text.size(); ++columnRow)
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
                text.fail(columnRow, format("a data row before the column row %s", kColumnsWanted));
            if (key == "version" && value.substr(0, 2) != "1." && value != "1")
                text.fail(columnRow, format("gcsv version '%s' is not supported; version 1.x (up to 1.3) is",
                                            value.substr(0, 40).c_str()));
            if (key == "id")
                log.id = value;
            if (key == "orientation")
            {
                axes = value;
                hasOrientation = true;
                try
                {
                    (void)orientationMatrix(value);
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
        }
        if (columnRow == text.size())
            text.failFile(format("no column row %s after the gcsv header", kColumnsWanted));
        if (std::isnan(tscale) || std::isnan(gscale))
            text.failFile(format("the gcsv header lacks '%s' (before line %zu); it must state tscale (seconds per "
                                 "time unit) and gscale (rad/s per gyro unit)",
                                 std::isnan(tscale) ? "tscale" : "gscale", columnRow + 1));
        if (!hasOrientation && options.orientation.empty())
            text.failFile("the gcsv header lacks 'orientation' (the gyro's axis string, e.g. 'XYZ'); add it or give "
                          "options.orientation");
        timeScale = tscale;
        rateScale = gscale;
        columns = splitCommas(text[columnRow]);
        const bool accel = columns.size() >= 7 && columnsAre(columns, {"ax", "ay", "az"}, 4);
        const bool magnet = accel && columns.size() == 10 && columnsAre(columns, {"mx", "my", "mz"}, 7);
        if (!columnsAre(columns, {"t", "gx", "gy", "gz"}, 0) ||
            !(columns.size() == 4 || (accel && columns.size() == 7) || magnet))
            text.fail(columnRow, format("the column row must be %s", kColumnsWanted));
    }
    else
    {
        while (columnRow < text.size() && (text[columnRow].empty() || text[columnRow][0] == '#'))
            ++columnRow;
        if (columnRow < text.size())
            columns = splitCommas(text[columnRow]);
        if (!columnsAre(columns, {"t", "gx", "gy", "gz"}, 0))
            text.fail(std::min(columnRow, text.size() - 1),
                      "missing header: a gcsv file starts with 'GYROFLOW IMU LOG' or 'CAMERA IMU LOG', a plain CSV "
                      "with the column row 't,gx,gy,gz' (extra columns after these are ignored)");
    }
    if (!options.orientation.empty())
        axes = options.orientation;
    log.orientation = axes;
    log.cameraFromGyro = options.cameraFromGyro * orientationMatrix(axes);
    readRows(text, columnRow + 1, columns, timeScale, rateScale, log.cameraFromGyro, log);
    if (options.estimateBias)
        log.estimateBias(options.stillThreshold, options.stillMinDuration);
    return log;
}

Vec3d GyroLog::estimateBias(double stillThreshold, double stillMinDuration)
{
    if (!(stillThreshold > 0) || !std::isfinite(stillThreshold))
        CV_Error_(Error::StsOutOfRange, ("GyroLog::estimateBias: stillThreshold = %g must be finite and > 0 (rad/s)",
                                         stillThreshold));
    if (!(stillMinDuration > 0) || !std::isfinite(stillMinDuration))
        CV_Error_(Error::StsOutOfRange, ("GyroLog::estimateBias: stillMinDuration = %g must be finite and > 0 "
                                         "(seconds)", stillMinDuration));
    if (rates.rows != int(times.size()) || rates.cols != 3 || rates.type() != CV_64F)
        CV_Error_(Error::StsBadArg, ("GyroLog::estimateBias: 'rates' must be N×3 CV_64F with one row per entry of "
                                     "'times' (%zu), got %d×%d of type %d",
                                     times.size(), rates.rows, rates.cols, rates.type()));
    Vec3d sum;
    double still = 0, longest = 0;
    size_t count = 0;
    for (size_t start = 0; start < times.size();)
    {
        size_t end = start;
        while (end < times.size() && norm(Vec3d(rates.ptr<double>(int(end)))) < stillThreshold)
            ++end;
        if (end > start)
        {
            const double duration = times[end - 1] - times[start];
            longest = std::max(longest, duration);
            if (duration >= stillMinDuration)
            {
                for (size_t k = start; k < end; ++k)
                    sum += Vec3d(rates.ptr<double>(int(k)));
                count += end - start;
                still += duration;
            }
        }
        start = end + 1;
    }
    if (count == 0)
        CV_Error_(Error::StsError, ("GyroLog::estimateBias: no still interval: |ω| < stillThreshold = %g rad/s lasts "
                                    "at most %.3g s, less than stillMinDuration = %g s; record the camera at rest, or "
                                    "raise stillThreshold above the bias and noise",
                                    stillThreshold, longest, stillMinDuration));
    bias = sum * (1.0 / double(count));
    biasStillSeconds = still;
    return bias;
}

Ptr<CameraMotion> GyroLog::toMotion(const Matx33d& initialOrientation) const
{
    if (bias == Vec3d() || rates.cols != 3 || rates.channels() != 1)
        return CameraMotion::fromAngularVelocity(times, rates, initialOrientation);  // it checks the shape
    Mat corrected;
    rates.convertTo(corrected, CV_64F);
    for (int k = 0; k < corrected.rows; ++k)
        for (int i = 0; i < 3; ++i)
            corrected.at<double>(k, i) -= bias[i];
    return CameraMotion::fromAngularVelocity(times, corrected, initialOrientation);
}

}  // namespace dynblur
}  // namespace cv
