// SPDX-License-Identifier: Apache-2.0
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

#include "cli_args.hpp"
#include "commanded_motion.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/videoio.hpp>

#include <limits>
#include <string>
#include <vector>

namespace dynblur_samples {

/** @brief The files of a recording kept in one folder, as `dynblur_calibrate_timing --simulate`
writes them: frames.avi (or frame_%04d.png), frames.csv, commands.csv, camera.xml, plant.yml (one
axis) or mount.yml (a mount's), and timing.yml once calibrated. A name is empty when its file is absent (frames.csv and commands.csv
must be there: a folder without them throws, naming it). */
struct RecordingFolder
{
    std::string video, frames, commands, camera, plant, mount, timing;
};
RecordingFolder findRecording(const std::string& folder);

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
that does not increase, or an exposure or line delay out of range, and naming the unit for a frame
period over 1 s (frame_start in ms) or an exposure longer than the frame period. */
std::vector<FrameRecord> parseFrameLog(const std::string& text, const std::string& source, double exposure,
                                       double lineDelay);
std::vector<FrameRecord> readFrameLog(const std::string& path, double exposure, double lineDelay);
//! Writes a frame log with all four columns, atomically.
void writeFrameLog(const std::string& path, const std::vector<FrameRecord>& frames);

/** @brief The actuators' switches: from times[i] on, axis a is at levels[a][i]; before times[0] each
axis rests at its first level. One axis (column `level`) or a mount's axes (columns `level0`,
`level1`, ..., base first). */
struct CommandLog
{
    std::vector<double> times;             //!< seconds, actuator clock, strictly increasing
    std::vector<std::vector<int>> levels;  //!< levels[axis][i], cells; one row per axis, each as long as times

    //! The number of axes the log commands.
    int axisCount() const { return int(levels.size()); }
    //! Whether any axis's level changes.
    bool moves() const;
    /** Appends a move: the union of the schedules' switch times, offset by `offset` seconds, each with
    every axis's level in force (an axis whose schedule is empty holds its last level).
    @param schedules one per axis. @param offset seconds added to the schedules' times. */
    void appendMove(const std::vector<cv::dynblur::SwitchSchedule>& schedules, double offset);

    /** The commands that move axis `axis` during [from, to] (seconds): the switches from a settle
    time before `from` (the plant has come to rest from anything earlier) to `to`, starting from the
    level in force before them. With `restSince` (seconds, finite), the axis is known at rest at that
    instant (a still frame): the switches start from the level in force then, so the schedule's initial
    resting angle is that still's. */
    cv::dynblur::SwitchSchedule scheduleAround(double from, double to, int axis = 0,
                                               double restSince = std::numeric_limits<double>::quiet_NaN()) const;
    //! scheduleAround() of every axis.
    std::vector<cv::dynblur::SwitchSchedule>
    schedulesAround(double from, double to, double restSince = std::numeric_limits<double>::quiet_NaN()) const;
};

/** Parses a command log (columns t and level, or t and level0, level1, ... for a mount). Throws
cv::Exception naming the line for a missing column, a non-number, a non-integer level or a time that
does not increase, and for an empty log. */
CommandLog parseCommandLog(const std::string& text, const std::string& source);
CommandLog readCommandLog(const std::string& path);
//! Writes a command log atomically: column level for one axis, level0, level1, ... for several.
void writeCommandLog(const std::string& path, const CommandLog& log);

/** Throws cv::Exception for a recording whose logs cannot belong together: a command log whose axes
are not `motion`'s (`commandsPath` and `mountPath` named), a frame read out (`rows` rows) in longer
than the frame period, or a command log that moves the plant while no frame sees a move (both logs'
time spans in the message: one in ms, or on another epoch). */
void checkFramesMeetCommands(const std::vector<FrameRecord>& frames, const CommandLog& commands,
                             const CommandedMotion& motion, int rows, const std::string& commandsPath = "--commands",
                             const std::string& mountPath = "");

/** @brief The options that name a recording: --recording, --video, --frames, --commands, --camera,
--plant, --mount, --exposure, --line-delay, --readout. */
CliOptionGroup recordingOptions();

/** @brief The line delay the command line tells, seconds: --line-delay, or --readout over `rows`;
NaN when neither is given. Throws std::runtime_error naming the options when both are given or the
readout is out of [0, 1) s. */
double toldLineDelay(const CliArgs& args, int rows);

/** @brief A recording opened by a program: its logs, camera and nominal plant, from `--recording DIR`
and/or the options of recordingOptions() and `--timing` where the program declares it (an option
given beside --recording wins). A default camera or plant is announced on stderr. Throws cv::Exception naming what is missing, malformed or cannot be opened, and for logs
that cannot belong together (checkFramesMeetCommands). */
struct OpenedRecording
{
    std::vector<FrameRecord> log;
    CommandLog commands;
    cv::Ptr<cv::dynblur::CameraModel> camera;  //!< default: calib/c270_nominal.xml
    std::string cameraPath;                    //!< the file it was read from
    std::string videoOption;                   //!< "--video" or "--recording", for messages
    cv::Ptr<cv::dynblur::Plant> plant;         //!< default: the seed's 14.4 Hz, ζ 0.12, 1°/level
    cv::Ptr<cv::dynblur::Mount> mount;         //!< a mount's recording (--mount or mount.yml); empty: one axis
    std::string timingPath;                    //!< "" when none was given or found
    cv::VideoCapture video;
    int position = 0;                          //!< frames read from the video so far

    /** @param defaultCameraPath the camera file used when none is given. */
    static void open(const CliArgs& args, const std::string& defaultCameraPath, OpenedRecording& recording);
    //! The motion the command log drives: the mount's, or the plant's.
    CommandedMotion commanded() const { return CommandedMotion(plant, mount); }
    //! Whether the options name a recording (--recording, or all of --video, --frames and --commands).
    static bool named(const CliArgs& args);
    /** The image of `record`, read after those of the previous records; throws naming a frame the
    video does not hold, or one of another size than the camera's. */
    cv::Mat read(const FrameRecord& record);
};

/** @brief MotionRefinement flags from a list such as "offset,line-delay": the refinement's parameter
names (cv::dynblur::refinementFlags: offset, line-delay, plant, bias, all, none); false when it names
an unknown parameter or one whose flag is not among `allowed`. */
bool parseRefinementList(const std::string& list, int allowed, int& flags);

}  // namespace dynblur_samples

#endif
