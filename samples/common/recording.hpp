// A recording of the camera positioner at work, as the timing calibration (and a video restorer)
// reads it: the frames (a video or an image sequence, read with cv::VideoCapture), a frame log that
// says when each frame was exposed on the camera's clock, and a command log of the actuator's
// switches on its own clock. The formats are documented in docs/recording-format.md.
//
//     frames.csv                          commands.csv
//     frame,frame_start,exposure,line_delay   t,level
//     0,0.000000,0.008,6.94e-05           0.000,0
//     1,0.033333,0.008,6.94e-05           0.500,6
//     ...                                 ...
#ifndef DYNBLUR_SAMPLES_RECORDING_HPP
#define DYNBLUR_SAMPLES_RECORDING_HPP

#include <opencv2/dynblur.hpp>

#include <string>
#include <vector>

namespace dynblur_samples {

//! One line of a frame log.
struct FrameRecord
{
    int frame = 0;          //!< index of the frame in the video (0 = the first), increasing
    double frameStart = 0;  //!< start of row 0's exposure, seconds, camera clock, increasing
    double exposure = 0;    //!< exposure of one row, seconds
    double lineDelay = 0;   //!< row-to-row readout delay, seconds (0: global shutter)
};

/** Parses a frame log: columns frame and frame_start, and exposure and line_delay unless
`exposure` and `lineDelay` (seconds) give them for every frame (NaN: the column is required).
Throws cv::Exception naming the line for a missing column, a non-number, a frame index or start
that does not increase, or an exposure or line delay out of range. */
std::vector<FrameRecord> parseFrameLog(const std::string& text, const std::string& source, double exposure,
                                       double lineDelay);
std::vector<FrameRecord> readFrameLog(const std::string& path, double exposure, double lineDelay);
//! Writes a frame log with all four columns, atomically.
void writeFrameLog(const std::string& path, const std::vector<FrameRecord>& frames);

//! The actuator's switches: levels[i] from times[i] on; before times[0] the plant rests at levels[0].
struct CommandLog
{
    std::vector<double> times;  //!< seconds, actuator clock, strictly increasing
    std::vector<int> levels;    //!< cells

    /** The commands that move the plant during [from, to] (seconds): the switches from a settle
    time before `from` (the plant has come to rest from anything earlier) to `to`, starting from the
    level in force before them. */
    cv::dynblur::SwitchSchedule scheduleAround(double from, double to) const;
};

/** Parses a command log (columns t and level). Throws cv::Exception naming the line for a missing
column, a non-number, a non-integer level or a time that does not increase, and for an empty log. */
CommandLog parseCommandLog(const std::string& text, const std::string& source);
CommandLog readCommandLog(const std::string& path);
//! Writes a command log atomically.
void writeCommandLog(const std::string& path, const CommandLog& log);

}  // namespace dynblur_samples

#endif
