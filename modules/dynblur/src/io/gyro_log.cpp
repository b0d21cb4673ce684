// SPDX-License-Identifier: Apache-2.0
// GyroLog: gyro logs (gcsv, CSV, phone apps' CSV) read into camera axes on a clock that keeps the
// file's precision, and the bias from still intervals. The layouts are in gyro_log_layout.cpp.
#include "precomp.hpp"

#include "io/gyro_log_layout.hpp"
#include "io/gyro_log_text.hpp"
#include "motion/sampled_motion.hpp"
#include "motion/so3.hpp"

#include <algorithm>
#include <cctype>
#include <limits>

namespace cv {
namespace dynblur {

using namespace gyro_log;

namespace {

//! A clock reading this many seconds or more is counted from a whole second near its first sample.
const double kOriginFromSeconds = 1e6;

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
    double unused;
    if (!o.timeUnit.empty() && !secondsPerTimeUnit(o.timeUnit, unused))
        CV_Error_(Error::StsBadArg, ("%s: options.timeUnit = '%s' is not one of %s", kLoad,
                                     o.timeUnit.substr(0, 40).c_str(), kTimeUnits));
    if (!o.rateUnit.empty() && !radPerRateUnit(o.rateUnit, unused))
        CV_Error_(Error::StsBadArg, ("%s: options.rateUnit = '%s' is not one of %s", kLoad,
                                     o.rateUnit.substr(0, 40).c_str(), kRateUnits));
    if (!o.timeUnit.empty() && o.timeScale != 1.0)
        CV_Error_(Error::StsBadArg, ("%s: options.timeUnit = '%s' and options.timeScale = %g both give the time's "
                                     "unit; give one (timeScale 1)",
                                     kLoad, o.timeUnit.c_str(), o.timeScale));
    if (!o.rateUnit.empty() && o.rateScale != 1.0)
        CV_Error_(Error::StsBadArg, ("%s: options.rateUnit = '%s' and options.rateScale = %g both give the rates' "
                                     "unit; give one (rateScale 1)",
                                     kLoad, o.rateUnit.c_str(), o.rateScale));
    if (std::isinf(o.timeOrigin))
        CV_Error_(Error::StsBadArg, ("%s: options.timeOrigin = %g must be finite seconds, or NaN to choose it from "
                                     "the first sample", kLoad, o.timeOrigin));
    if (o.gcsvAxes != "camera" && o.gcsvAxes != "gyroflow")
        CV_Error_(Error::StsBadArg, ("%s: options.gcsvAxes = '%s' is not 'camera' (this module's camera axes) or "
                                     "'gyroflow' (Gyroflow's frame)",
                                     kLoad, o.gcsvAxes.substr(0, 40).c_str()));
    if (!o.columns.empty())
    {
        const std::vector<std::string> specs = splitCommas(o.columns);
        const bool blank = std::any_of(specs.begin(), specs.end(), [](const std::string& c) { return c.empty(); });
        if (specs.size() != 4 || blank)
            CV_Error_(Error::StsBadArg, ("%s: options.columns = '%s' must name four columns, comma-separated: the "
                                         "time, then the rates about the gyro's x, y and z (names from the header "
                                         "row or 1-based positions, e.g. 'time,x,y,z' or '4,1,2,3')",
                                         kLoad, o.columns.substr(0, 80).c_str()));
    }
}

//! Seconds on the log's clock from timestamps in the file's units, counted from an origin once the
//! first sample has set it.
class LogClock
{
public:
    //! `origin`: seconds to subtract, NaN to choose from the first sample.
    LogClock(double secondsPerUnit, double origin) : secondsPerUnit_(secondsPerUnit), given_(origin)
    {
        const double unitsPerSecond = 1.0 / secondsPerUnit;
        const double whole = std::round(unitsPerSecond);
        if (whole >= 1 && whole < 9e18 && std::abs(unitsPerSecond - whole) <= 1e-9 * whole)
            unitsPerSecond_ = std::int64_t(whole);
    }

    //! Seconds of `t`, relative to the origin given or chosen by the first call (0 below kOriginFromSeconds).
    double seconds(const Timestamp& t)
    {
        if (!started_)
        {
            started_ = true;
            const double first = t.value * secondsPerUnit_;
            if (!std::isnan(given_))
                startAt(given_);
            else if (!(std::abs(first) >= kOriginFromSeconds))
                return first;
            else if (unitsPerSecond_ > 0)  // floor((whole + fraction) / unitsPerSecond), in integers
            {
                std::int64_t q = t.whole / unitsPerSecond_, r = t.whole % unitsPerSecond_;
                if (r < 0)
                {
                    q -= 1;
                    r += unitsPerSecond_;
                }
                if (double(r) + t.fraction < 0)
                    q -= 1;
                originUnits_ = q * unitsPerSecond_;
                origin_ = double(q);
            }
            else
                origin_ = std::floor(first);
        }
        if (origin_ == 0)
            return t.value * secondsPerUnit_;
        if (unitsPerSecond_ > 0)  // exact in integer units: s, ms, us, ns and decimal tscales
            return (double(t.whole - originUnits_) + t.fraction) / double(unitsPerSecond_);
        return (double(t.whole) * secondsPerUnit_ - origin_) + t.fraction * secondsPerUnit_;
    }
    double origin() const { return origin_; }

private:
    //! The given origin in the file's units: exact for whole seconds, to the nearest unit otherwise.
    void startAt(double origin)
    {
        origin_ = origin;
        const double whole = std::floor(origin);
        if (unitsPerSecond_ > 0 && std::abs(whole) * double(unitsPerSecond_) < 9e18)
            originUnits_ = std::int64_t(whole) * unitsPerSecond_ +
                           std::int64_t(std::llround((origin - whole) * double(unitsPerSecond_)));
        else
            unitsPerSecond_ = 0;  // seconds in doubles
    }

    double secondsPerUnit_;
    double given_;
    std::int64_t unitsPerSecond_ = 0;  //!< 0: not a whole number of units per second
    bool started_ = false;
    double origin_ = 0;                //!< seconds (whole unless given otherwise)
    std::int64_t originUnits_ = 0;     //!< the origin in the file's units (when unitsPerSecond_ > 0)
};

/** The data rows of `layout`: each with one field per column, the time and the three rates finite
    numbers; the time in seconds (LogClock), the rates in rad/s mapped by `toCamera`. */
void readRows(const LogText& text, const LogLayout& layout, const Matx33d& toCamera, double origin, bool dropRepeats,
              GyroLog& log)
{
    std::vector<Vec3d> rates;
    std::vector<size_t> lineOf;
    LogClock clock(layout.secondsPerUnit, origin);
    const size_t fieldCount = layout.columns.size();
    Vec3d previous;
    for (size_t i = layout.firstRow; i < text.size(); ++i)
    {
        if (text[i].empty() || (layout.name != "gcsv" && text[i][0] == '#'))
            continue;
        const std::vector<std::string> fields = splitCommas(text[i]);
        if (fields.size() != fieldCount)
            text.fail(i, format("%zu fields, but the %s %zu; one value per column", fields.size(),
                                !layout.headerRow          ? "first row has"
                                : layout.name == "gcsv"    ? "column row names"
                                                           : "header row names",
                                fieldCount));
        const auto number = [&](int j) {
            double value;
            if (!parseNumber(fields[j], value))
                text.fail(i, format("field '%s' = '%s' is not a finite number", layout.columns[j].c_str(),
                                    fields[j].substr(0, 40).c_str()));
            return value;
        };
        if (layout.everyFieldNumeric)
            for (size_t j = 0; j < fields.size(); ++j)
                number(int(j));
        Timestamp stamp;
        if (!parseTimestamp(fields[layout.time], stamp))
        {
            number(layout.time);  // not a number: named as such
            text.fail(i, format("field '%s' = '%s' is beyond any clock (|t| >= 9e18 units)", layout.columns[layout.time].c_str(),
                                fields[layout.time].substr(0, 40).c_str()));
        }
        const Vec3d raw(number(layout.rate[0]), number(layout.rate[1]), number(layout.rate[2]));
        const double t = clock.seconds(stamp);
        const Vec3d w = toCamera * raw * layout.radPerUnit;
        if (!std::isfinite(t) || !std::isfinite(w[0]) || !std::isfinite(w[1]) || !std::isfinite(w[2]))
            text.fail(i, "the scaled time or rate overflows");
        if (!log.times.empty() && t == log.times.back() && raw == previous && dropRepeats)
        {
            log.droppedSamples++;
            continue;
        }
        if (!log.times.empty() && !(t > log.times.back()))
            text.fail(i, format("field '%s': %.9f s is not after the previous sample's %.9f s (line %zu); timestamps "
                                "must be strictly increasing, without repeats%s",
                                layout.columns[layout.time].c_str(), t + clock.origin(), log.times.back() + clock.origin(),
                                lineOf.back() + 1,
                                t == log.times.back() && raw == previous && !dropRepeats
                                    ? " (a sample repeated whole, as some loggers write, is dropped with "
                                      "options.dropRepeatedSamples or --gyro-drop-repeats)"
                                    : ""));
        log.times.push_back(t);
        rates.push_back(w);
        lineOf.push_back(i);
        previous = raw;
    }
    log.timeOrigin = clock.origin();
    if (log.times.size() < 2)
        text.failFile(format("%zu sample(s)%s; a gyro log needs at least 2", log.times.size(),
                             layout.headerRow ? " after the header" : ""));
    double median = 0;
    if (const size_t k = detail::findLongGap(log.times, median))
        text.fail(lineOf[k], format("a gap of %.6g s after the sample of line %zu, longer than %g median sample "
                                    "intervals (%.6g s): samples are missing",
                                    log.times[k] - log.times[k - 1], lineOf[k - 1] + 1,
                                    detail::kMaxGapInMedianIntervals, median));
    log.rates = Mat(int(rates.size()), 3, CV_64F, rates.data()).clone();
}

}  // namespace

GyroLogOptions::GyroLogOptions()
    : cameraFromGyro(Matx33d::eye()), timeScale(1.0), rateScale(1.0), gcsvAxes("camera"),
      timeOrigin(std::numeric_limits<double>::quiet_NaN()), dropRepeatedSamples(false), estimateBias(false),
      stillThreshold(0.05), stillMinDuration(0.5)
{
}

GyroLog::GyroLog()
    : bias(0, 0, 0), biasStillSeconds(0), cameraFromGyro(Matx33d::eye()), orientation("XYZ"), timeOrigin(0),
      frameReadoutTime(std::numeric_limits<double>::quiet_NaN()), frameReadoutDirection(READOUT_DIRECTION_UNKNOWN),
      droppedSamples(0)
{
}

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
    const LogLayout layout = readLayout(text, options);
    GyroLog log;
    log.layout = layout.name;
    log.id = layout.id;
    log.frameReadoutTime = layout.frameReadoutTime;
    log.frameReadoutDirection = layout.frameReadoutDirection;
    log.orientation = options.orientation.empty() ? layout.orientation : options.orientation;
    // Gyroflow's frame (x up, y left, z backward) to camera axes (x right, y down, z forward).
    const Matx33d fromGyroflow = layout.gyroflowAxes ? orientationMatrix("yxz") : Matx33d::eye();
    log.cameraFromGyro = options.cameraFromGyro * fromGyroflow * orientationMatrix(log.orientation);
    readRows(text, layout, log.cameraFromGyro, options.timeOrigin, options.dropRepeatedSamples, log);
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

GyroLog GyroLog::withAxisCorrection(const Matx33d& axisCorrection) const
{
    if (!(so3::rotationDefect(axisCorrection) <= 1e-6))
        CV_Error(Error::StsBadArg, "GyroLog::withAxisCorrection: 'axisCorrection' is not a rotation (orthonormal, "
                                   "determinant +1)");
    GyroLog corrected = *this;
    Mat rates64;
    rates.convertTo(rates64, CV_64F);
    // A new matrix: assigned as an expression, it would be written into the rates this log shares.
    const Mat mapped = rates64 * Mat(axisCorrection).t();
    corrected.rates = mapped;
    corrected.bias = axisCorrection * bias;
    corrected.cameraFromGyro = axisCorrection * cameraFromGyro;
    return corrected;
}

}  // namespace dynblur
}  // namespace cv
