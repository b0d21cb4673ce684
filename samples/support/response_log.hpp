// SPDX-License-Identifier: Apache-2.0
// The logged step-response format shared by the plant identification tool (calib/identify_plant.cpp)
// and the actuator-bus simulator: a CSV text file with a header line naming the columns, then one
// sample per line.
//
//     # optional comment lines start with '#'; blank lines are ignored
//     t,theta,level
//     0.000000,0.000000000,0
//     0.001000,0.000000000,4
//     ...
//
//   t      sample time, seconds, strictly increasing (any origin)
//   theta  measured angle, radians
//   level  commanded actuator level in force at t, integer cells (optional: without it the command
//          comes from a SwitchSchedule file instead)
//
// Columns are found by name (case-insensitive; "time" is accepted for t), in any order; extra
// columns are ignored. Separators: comma, semicolon, tab or spaces.
#ifndef DYNBLUR_SAMPLES_RESPONSE_LOG_HPP
#define DYNBLUR_SAMPLES_RESPONSE_LOG_HPP

#include <opencv2/dynblur.hpp>

#include <string>
#include <vector>

namespace dynblur_samples {

struct ResponseLog
{
    std::vector<double> t;      //!< seconds
    std::vector<double> theta;  //!< radians
    std::vector<int> level;     //!< cells; empty when the log has no level column
    bool hasLevel() const { return !level.empty(); }
};

/** Parses a response log from text; `source` names it in errors. Throws cv::Exception (StsParseError)
naming the line for a missing header or column, a wrong field count, a non-numeric field, a
non-integer level or a time that does not increase. */
ResponseLog parseResponseLog(const std::string& text, const std::string& source = "<text>");

/** Reads a response log file; throws cv::Exception when the file cannot be read or is malformed. */
ResponseLog readResponseLog(const std::string& path);

/** Writes a response log (header "t,theta,level", or "t,theta" when level is empty) atomically:
to a temporary file, then renamed. */
void writeResponseLog(const std::string& path, const ResponseLog& log);

/** The schedule a level column describes: initialLevel is the first sample's level; each change
between samples i-1 and i becomes a switch at the midpoint (t[i-1] + t[i]) / 2 (the true instant
lies somewhere between; the midpoint halves the worst-case error, and a fitted delay absorbs a
constant bias). Throws when the level never changes. */
cv::dynblur::SwitchSchedule scheduleFromLevels(const ResponseLog& log);

/** Checks that a log can identify a plant: at least `minSamples` samples and visible motion
(peak-to-peak θ above 10× the sample-to-sample noise, estimated from the median absolute
difference of successive samples). Throws cv::Exception with a sentence a user can act on. */
void checkResponseLog(const ResponseLog& log, size_t minSamples = 20);

}  // namespace dynblur_samples

#endif
