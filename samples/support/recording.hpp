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

#include <opencv2/dynblur.hpp>
#include <opencv2/videoio.hpp>

#include <string>
#include <vector>

namespace dynblur_samples {

/** @brief The files of a recording kept in one folder, as `dynblur_calibrate_timing --simulate`
writes them: frames.avi (or frame_%04d.png), frames.csv, commands.csv, camera.xml, plant.yml, and
timing.yml once calibrated. A name is empty when its file is absent (frames.csv and commands.csv
must be there: a folder without them throws, naming it). */
struct RecordingFolder
{
    std::string video, frames, commands, camera, plant, timing;
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

/** Throws cv::Exception for a recording whose logs cannot belong together: a frame read out (`rows`
rows) in longer than the frame period, or a command log that moves the plant while no frame sees
a move (both logs' time spans in the message: one in ms, or on another epoch). */
void checkFramesMeetCommands(const std::vector<FrameRecord>& frames, const CommandLog& commands,
                             const cv::Ptr<cv::dynblur::Plant>& plant, int rows);

/** @brief The options that name a recording: --recording, --video, --frames, --commands, --camera,
--plant, --exposure, --line-delay, --readout. */
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
    std::string timingPath;                    //!< "" when none was given or found
    cv::VideoCapture video;
    int position = 0;                          //!< frames read from the video so far

    /** @param defaultCameraPath the camera file used when none is given. */
    static void open(const CliArgs& args, const std::string& defaultCameraPath, OpenedRecording& recording);
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

/** @brief Streams a recording's frames and pairs each frame taken during a move with the still frame
that saw what its moving rows see: the last still frame before it when the frame starts at rest
(window I), the first still frame after it otherwise, unless another switch comes between (then,
and when more than `maxPending` frames wait, the last still frame before it). Frames come back in
their order, as soon as their reference is known: memory holds at most `maxPending` frames. Each
moving frame also carries the stills on both sides of its move (`before`, `after`) for
DynamicDeblurrer::setReferenceFrames, which chooses per frame: a frame that waits for the still after
its move comes back when that still arrives (the latency of a stream: the rest of the move and one
frame), or at finish() without one.

"Still" is what a restoration cannot tell from still: the image moves by less than a quarter pixel
(and by less than that during the exposure), with the clock off by as much as `maxOffset` either
way, so a plant's slow residual vibration is not a move. */
class ReferencePairing
{
public:
    struct Item
    {
        FrameRecord record;
        cv::Mat image;
        cv::dynblur::SwitchSchedule schedule;  //!< the commands around the frame
        cv::dynblur::RollingShutter shutter;   //!< as the frame log reports it
        int window = 0;                        //!< exposure window under the model as given
        bool still = false;
        cv::Mat reference;                     //!< the moving frame's still frame (empty: none known)
        double referenceAngle = 0;             //!< its angle, radians
        cv::Mat before, after;                 //!< the stills before and after its move (empty: none)
        double angleBefore = 0, angleAfter = 0;  //!< their angles, radians
    };

    /** @param plant the nominal plant. @param camera the camera. @param commands the command log.
    @param correction the model's correction (a calibration; MotionCorrection() for none).
    @param maxOffset how far off the clock may be, seconds. @param maxPending frames held at most. */
    ReferencePairing(const cv::Ptr<cv::dynblur::Plant>& plant, const cv::Ptr<cv::dynblur::CameraModel>& camera,
                     const CommandLog& commands, const cv::dynblur::MotionCorrection& correction, double maxOffset,
                     size_t maxPending = 32);

    //! Takes the next frame; returns the frames whose reference is now known, in order.
    std::vector<Item> push(const FrameRecord& record, const cv::Mat& image);
    //! At the end of the recording: the frames still waiting (with the last still frame before them).
    std::vector<Item> finish();
    //! Whether push() calls the frame still, read out by `rows` rows (what a progress count needs ahead).
    bool isStill(const FrameRecord& record, int rows) const;
    //! Frames held until the still after their move arrives.
    size_t pending() const { return waiting_.size(); }

private:
    void release(std::vector<Item>& ready, const cv::Mat& reference, double angle, double stillStart);
    //! The commands around a frame read out as `corrected` (the calibrated shutter), ±maxOffset.
    cv::dynblur::SwitchSchedule scheduleFor(const cv::dynblur::RollingShutter& corrected) const;
    //! At rest under `schedule` whether the clock is early, right or late by maxOffset.
    bool stillUnder(const cv::dynblur::RollingShutter& corrected, const cv::dynblur::SwitchSchedule& schedule) const;

    cv::Ptr<cv::dynblur::Plant> plant_, correctedPlant_;
    cv::Ptr<cv::dynblur::CameraModel> camera_;
    const CommandLog& commands_;
    cv::dynblur::MotionCorrection correction_;
    double maxOffset_;
    size_t maxPending_;
    std::vector<Item> waiting_;
    cv::Mat lastStill_;
    double lastStillAngle_ = 0;
};

}  // namespace dynblur_samples

#endif
