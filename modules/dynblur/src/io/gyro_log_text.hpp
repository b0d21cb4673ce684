// SPDX-License-Identifier: Apache-2.0
// The text of a gyro log: its lines, its comma-separated fields, numbers and timestamps read at the
// file's precision, unit names, and errors that name the file and the line.
#ifndef DYNBLUR_SRC_IO_GYRO_LOG_TEXT_HPP
#define DYNBLUR_SRC_IO_GYRO_LOG_TEXT_HPP

#include <opencv2/core.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace cv {
namespace dynblur {
namespace gyro_log {

extern const char* const kLoad;  //!< "GyroLog::load", the prefix of every message

std::string trimmed(const std::string& s);
std::string lowered(std::string s);
std::vector<std::string> splitCommas(const std::string& line);

//! The whole field as one finite number.
bool parseNumber(const std::string& field, double& value);

/** A timestamp in the file's units, split into a whole part and a fraction: an epoch in nanoseconds
    (19 digits) is beyond a double's 53 bits, so the whole part is kept as an integer. */
struct Timestamp
{
    double value = 0;        //!< the field as a double (rounded for long integers)
    std::int64_t whole = 0;  //!< whole units (exact for plain decimal fields up to 19 digits)
    double fraction = 0;     //!< value − whole, in units, |fraction| < 1
};

//! The field as a finite timestamp.
bool parseTimestamp(const std::string& field, Timestamp& t);

/** Seconds per unit of a time unit name ("s", "ms", "us", "µs", "ns"); false for another name. */
bool secondsPerTimeUnit(const std::string& unit, double& seconds);
/** rad/s per unit of a rate unit name ("rad/s", "deg/s"); false for another name. */
bool radPerRateUnit(const std::string& unit, double& radPerSecond);
extern const char* const kTimeUnits;  //!< the names secondsPerTimeUnit takes, for messages
extern const char* const kRateUnits;  //!< the names radPerRateUnit takes, for messages

//! The file's lines, numbered from 1, and errors that name the file and the line.
class LogText
{
public:
    explicit LogText(const String& filename);
    size_t size() const { return lines_.size(); }
    const std::string& operator[](size_t i) const { return lines_[i]; }
    const String& name() const { return name_; }

    [[noreturn]] void fail(size_t i, const std::string& what) const;
    [[noreturn]] void failFile(const std::string& what) const;

private:
    String name_;
    std::vector<std::string> lines_;
};

}  // namespace gyro_log
}  // namespace dynblur
}  // namespace cv

#endif
