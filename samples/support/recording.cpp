// SPDX-License-Identifier: Apache-2.0
#include "recording.hpp"

#include "atomic_file.hpp"
#include "cli_args.hpp"
#include "csv_fields.hpp"
#include "plant_file.hpp"
#include "video_clip.hpp"

#include <opencv2/core/utils/filesystem.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

namespace dynblur_samples {

using namespace csv;

namespace {

/* After this long the seed's plant (ζ ωn = 10.9 /s) has come to rest from any earlier switch to
   within e^-30 of the move: older commands are left out of a frame's schedule. */
const double kSettleSeconds = 3.0;

//! A CSV log as rows of fields, with the columns named in its header found by (lower-case) name.
struct Table
{
    std::map<std::string, size_t> column;
    std::vector<std::vector<std::string>> rows;
    std::vector<size_t> lines;  // 1-based line of each row
};

Table parseTable(const std::string& text, const std::string& source)
{
    Table table;
    std::istringstream in(text);
    std::string line;
    size_t number = 0;
    bool header = true;
    while (std::getline(in, line))
    {
        number++;
        const std::string content = trim(line);
        if (content.empty() || content[0] == '#')
            continue;
        const std::vector<std::string> fields = splitFields(content);
        if (header)
        {
            for (size_t i = 0; i < fields.size(); i++)
                if (!table.column.emplace(lower(fields[i]), i).second)
                    parseError(source, number, "the header names the column '" + fields[i] + "' twice");
            header = false;
            continue;
        }
        if (fields.size() != table.column.size())
            parseError(source, number,
                       "expected " + std::to_string(table.column.size()) + " fields as in the header, found " +
                           std::to_string(fields.size()));
        table.rows.push_back(fields);
        table.lines.push_back(number);
    }
    if (header)
        parseError(source, number, "no header line (the column names)");
    return table;
}

double number(const Table& t, size_t row, const std::string& name, const std::string& source)
{
    double value = 0;
    if (!toDouble(t.rows[row][t.column.at(name)], value))
        parseError(source, t.lines[row], "'" + name + "' is not a finite number: '" + t.rows[row][t.column.at(name)] + "'");
    return value;
}

int integer(const Table& t, size_t row, const std::string& name, const std::string& source)
{
    const double value = number(t, row, name, source);
    if (value != std::floor(value) || std::abs(value) > 1e9)
        parseError(source, t.lines[row], "'" + name + "' must be an integer");
    return static_cast<int>(value);
}

void requireColumn(const Table& t, const std::string& name, const std::string& source, const std::string& why)
{
    if (!t.column.count(name))
        CV_Error(cv::Error::StsParseError, source + ": the header has no column '" + name + "' (" + why + ")");
}

/* The frame period (the median step of frame_start per frame) bounds the exposure; a period over a
   second is frame_start in milliseconds. */
void checkFramePeriod(const std::vector<FrameRecord>& frames, const std::string& source)
{
    if (frames.size() < 2)
        return;
    std::vector<double> steps;
    for (size_t i = 1; i < frames.size(); i++)
        steps.push_back((frames[i].frameStart - frames[i - 1].frameStart) / (frames[i].frame - frames[i - 1].frame));
    std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
    const double period = steps[steps.size() / 2];
    if (period > 1.0)
        CV_Error_(cv::Error::StsOutOfRange,
                  ("%s: 'frame_start' steps by %g per frame, a frame period over 1 s: seconds expected (is it in ms? "
                   "33.3 ms is 0.0333)", source.c_str(), period));
    for (const FrameRecord& f : frames)
        if (f.exposure > period)
            CV_Error_(cv::Error::StsOutOfRange,
                      ("%s: frame %d: 'exposure' = %g s is longer than the frame period %g s: seconds expected (is it "
                       "in ms? 8 ms is 0.008)", source.c_str(), f.frame, f.exposure, period));
}

}  // namespace

/* The frames of the log that see the plant move under `commands` (exposure windows I–III), read out
   by `rows` rows. */
static int movingFrames(const std::vector<FrameRecord>& frames, const CommandLog& commands,
                        const CommandedMotion& motion, int rows)
{
    int moving = 0;
    for (const FrameRecord& f : frames)
    {
        const cv::dynblur::RollingShutter shutter(f.frameStart, f.exposure, f.lineDelay, rows);
        const cv::Vec2d readout = shutter.readoutInterval();
        moving += motion.classify(commands.schedulesAround(readout[0], readout[1]), shutter) != cv::dynblur::EXPOSURE_IV;
    }
    return moving;
}

void checkFramesMeetCommands(const std::vector<FrameRecord>& frames, const CommandLog& commands,
                             const CommandedMotion& motion, int rows, const std::string& commandsPath,
                             const std::string& mountPath)
{
    if (commands.axisCount() != motion.axisCount())
        CV_Error(cv::Error::StsBadArg,
                 motion.isMount()
                     ? cv::format("%s: the command log has %d level column(s) but the mount '%s' (--mount) has %d axes: "
                                  "a mount's log has one column per axis, level0, level1, ... (docs/recording-format.md)",
                                  commandsPath.c_str(), commands.axisCount(), mountPath.c_str(), motion.axisCount())
                     : cv::format("%s: the command log has %d axes (level0, level1, ...) but no mount was given: give "
                                  "the mount file with --mount (or mount.yml in the recording)",
                                  commandsPath.c_str(), commands.axisCount()));
    const FrameRecord& last = frames.back();
    const double period = frames.size() > 1 ? (last.frameStart - frames.front().frameStart) /
                                                  std::max(1, last.frame - frames.front().frame)
                                            : HUGE_VAL;
    for (const FrameRecord& f : frames)
        if ((rows - 1) * f.lineDelay > period * 1.01)  // a sensor reads out within its frame period
            CV_Error_(cv::Error::StsOutOfRange,
                      ("--frames: frame %d: 'line_delay' = %g s reads the %d rows out in %g s, longer than the frame "
                       "period %g s: seconds expected (is it in us? 62.5 us is 62.5e-6)",
                       f.frame, f.lineDelay, rows, (rows - 1) * f.lineDelay, period));
    if (!commands.moves())
        return;  // no move to see
    if (movingFrames(frames, commands, motion, rows) > 0)
        return;
    CV_Error_(cv::Error::StsBadArg,
              ("no frame overlaps a move: the frames span %.6g to %.6g s (camera clock) and the commands %.6g to %.6g s "
               "(actuator clock); both logs are in seconds, on clocks that agree to within a frame (is one in ms, "
               "or on another epoch?)",
               frames.front().frameStart, last.frameStart + last.exposure + (rows - 1) * last.lineDelay,
               commands.times.front(), commands.times.back()));
}

RecordingFolder findRecording(const std::string& folder)
{
    const auto present = [&](const std::string& name) {
        const std::string path = folder + "/" + name;
        return std::ifstream(path).good() ? path : std::string();
    };
    RecordingFolder r;
    r.video = present("frames.avi");
    if (r.video.empty() && !present("frame_0000.png").empty())
        r.video = folder + "/frame_%04d.png";
    r.frames = present("frames.csv");
    r.commands = present("commands.csv");
    r.camera = present("camera.xml");
    r.plant = present("plant.yml");
    r.mount = present("mount.yml");
    r.timing = present("timing.yml");
    std::string missing;
    for (const auto& part : {std::make_pair(&r.video, "frames.avi or frame_0000.png... (the frames)"),
                             std::make_pair(&r.frames, "frames.csv (the frame log)"),
                             std::make_pair(&r.commands, "commands.csv (the command log)")})
        if (part.first->empty())
            missing += (missing.empty() ? "" : ", ") + std::string(part.second);
    if (!missing.empty())
        CV_Error(cv::Error::StsError, cv::utils::fs::isDirectory(folder)
                                          ? "--recording: '" + folder + "' lacks " + missing
                                          : "--recording: the folder '" + folder + "' does not exist");
    return r;
}

CliOptionGroup recordingOptions()
{
    return {"", "",
            {{"recording", "DIR", "",
              "a recording folder (frames.avi or frame_%04d.png, frames.csv, commands.csv, camera.xml, plant.yml, "
              "and timing.yml once calibrated)"},
             {"video", "V", "", "the frames: a video file or an image sequence (frame_%04d.png), as cv::VideoCapture reads them"},
             {"frames", "FILE.csv", "", "frame log: frame,frame_start[,exposure,line_delay] (docs/recording-format.md)"},
             {"commands", "FILE.csv", "", "command log: t,level on the actuator's clock"},
             {"camera", "FILE.xml", "", "camera (ViSP XML); default: the recording's camera.xml, else calib/c270_nominal.xml"},
             {"plant", "FILE.yml", "",
              "nominal plant file; default: the recording's plant.yml, else the seed's (14.4 Hz, zeta 0.12, 1 deg per "
              "level)"},
             {"mount", "FILE.yml", "",
              "a mount's file (Mount::save): the command log carries one level column per axis; default: the "
              "recording's mount.yml, else one axis"},
             {"exposure", "S", "", "exposure of one row, seconds, when the frame log has no exposure column"},
             {"line-delay", "S", "", "line delay, seconds, when the frame log has no line_delay column"},
             {"readout", "S", "", "the readout of a whole frame, seconds, in place of --line-delay (line delay = S / rows)"}}};
}

double toldLineDelay(const CliArgs& args, int rows)
{
    if (args.has("line-delay") && args.has("readout"))
        throw std::runtime_error("--line-delay and --readout both tell the line delay: give one");
    if (args.has("readout"))
    {
        const double readout = args.num("readout");
        if (!(readout >= 0 && readout < 1))
            throw std::runtime_error(cv::format("--readout %g must be in [0, 1) s (seconds: 20 ms is 0.02)", readout));
        return readout / rows;
    }
    return args.num("line-delay", NAN);
}

bool OpenedRecording::named(const CliArgs& args)
{
    return args.has("recording") || (args.has("video") && args.has("frames") && args.has("commands"));
}

void OpenedRecording::open(const CliArgs& args, const std::string& defaultCameraPath, OpenedRecording& r)
{
    const RecordingFolder folder = args.has("recording") ? findRecording(args.str("recording", "")) : RecordingFolder();
    // A default is said aloud: a recording without its camera or plant is restored with the wrong blur.
    r.cameraPath = args.str("camera", folder.camera);
    if (r.cameraPath.empty())
    {
        r.cameraPath = defaultCameraPath;
        std::fprintf(stderr, "note: no --camera%s: using the default camera '%s'\n",
                     args.has("recording") ? " and no camera.xml in the recording" : "", defaultCameraPath.c_str());
    }
    r.camera = cv::dynblur::CameraModel::load(r.cameraPath);
    r.log = readFrameLog(args.str("frames", folder.frames), args.num("exposure", NAN),
                         toldLineDelay(args, r.camera->getImageSize().height));
    const std::string commandsPath = args.str("commands", folder.commands);
    r.commands = readCommandLog(commandsPath);
    const std::string mountPath = args.str("mount", folder.mount);
    r.mount = mountPath.empty() ? cv::Ptr<cv::dynblur::Mount>() : cv::dynblur::Mount::load(mountPath);
    const std::string plant = args.str("plant", folder.plant);
    if (plant.empty() && r.mount.empty())
        std::fprintf(stderr, "note: no --plant%s: using the seed's plant (14.4 Hz, zeta 0.12, 1 deg per level)\n",
                     args.has("recording") ? " and no plant.yml in the recording" : "");
    r.plant = plant.empty() ? cv::dynblur::Plant::create(14.4, 0.12, CV_PI / 180) : loadPlantFile(plant).plant;
    r.timingPath = args.declares("timing") ? args.str("timing", folder.timing) : folder.timing;
    const std::string video = args.str("video", folder.video);
    r.videoOption = args.has("video") ? "--video" : "--recording";  // what the user typed
    openVideo(r.video, video, r.videoOption);
    r.position = 0;
    const cv::Size size = r.camera->getImageSize();
    const int width = int(r.video.get(cv::CAP_PROP_FRAME_WIDTH)), height = int(r.video.get(cv::CAP_PROP_FRAME_HEIGHT));
    if (width > 0 && height > 0 && cv::Size(width, height) != size)
        CV_Error(cv::Error::StsBadSize,
                 cv::format("%s: frames are %dx%d but the camera '%s' is %dx%d (give the camera that took the "
                            "video: --camera)",
                            r.videoOption.c_str(), width, height, r.cameraPath.c_str(), size.width, size.height));
    checkFramesMeetCommands(r.log, r.commands, r.commanded(), size.height, commandsPath, mountPath);
}

cv::Mat OpenedRecording::read(const FrameRecord& record)
{
    cv::Mat image;
    while (position <= record.frame)
    {
        if (!video.read(image))
            CV_Error(cv::Error::StsBadArg, cv::format("--frames: line for frame %d, but the video ends after %d frames",
                                                      record.frame, position));
        position++;
    }
    const cv::Size size = camera->getImageSize();
    if (image.size() != size)
        CV_Error(cv::Error::StsBadSize,
                 cv::format("%s: frame %d is %dx%d but the camera '%s' is %dx%d (give the camera that took the "
                            "video: --camera)",
                            videoOption.c_str(), record.frame, image.cols, image.rows, cameraPath.c_str(), size.width,
                            size.height));
    return image;
}

bool parseRefinementList(const std::string& list, int allowed, int& flags)
{
    try
    {
        flags = cv::dynblur::refinementFlags(list);
    }
    catch (const cv::Exception&)
    {
        return false;
    }
    return (flags & ~allowed) == 0;
}

std::vector<FrameRecord> parseFrameLog(const std::string& text, const std::string& source, double exposure,
                                       double lineDelay)
{
    const Table t = parseTable(text, source);
    requireColumn(t, "frame", source, "index of the frame in the video");
    requireColumn(t, "frame_start", source, "start of row 0's exposure, seconds");
    if (std::isnan(exposure))
        requireColumn(t, "exposure", source, "or give the exposure for every frame");
    if (std::isnan(lineDelay))
        requireColumn(t, "line_delay", source, "or give the line delay for every frame");
    std::vector<FrameRecord> frames;
    for (size_t r = 0; r < t.rows.size(); r++)
    {
        FrameRecord f;
        f.frame = integer(t, r, "frame", source);
        f.frameStart = number(t, r, "frame_start", source);
        f.exposure = t.column.count("exposure") ? number(t, r, "exposure", source) : exposure;
        f.lineDelay = t.column.count("line_delay") ? number(t, r, "line_delay", source) : lineDelay;
        if (f.frame < 0 || (!frames.empty() && f.frame <= frames.back().frame))
            parseError(source, t.lines[r], "'frame' must be >= 0 and increase from line to line");
        if (!frames.empty() && f.frameStart <= frames.back().frameStart)
            parseError(source, t.lines[r], "'frame_start' must increase from line to line");
        if (!(f.exposure > 0 && f.exposure < 10))
            parseError(source, t.lines[r],
                       cv::format("'exposure' = %g must be in (0, 10) s: seconds expected (is it in ms? 8 ms is 0.008)",
                                  f.exposure));
        if (!(f.lineDelay >= 0 && f.lineDelay < 0.01))
            parseError(source, t.lines[r],
                       cv::format("'line_delay' = %g must be in [0, 0.01) s: seconds expected (is it in us? 62.5 us is "
                                  "62.5e-6)", f.lineDelay));
        frames.push_back(f);
    }
    if (frames.empty())
        CV_Error(cv::Error::StsParseError, source + ": no frames");
    checkFramePeriod(frames, source);
    return frames;
}

std::vector<FrameRecord> readFrameLog(const std::string& path, double exposure, double lineDelay)
{
    return parseFrameLog(readTextFile(path, "frame log"), path, exposure, lineDelay);
}

void writeFrameLog(const std::string& path, const std::vector<FrameRecord>& frames)
{
    std::ostringstream out;
    out << "# dynblur frame log: frame index in the video, start of row 0's exposure (s, camera clock),\n"
           "# exposure of one row (s), row-to-row readout delay (s)\nframe,frame_start,exposure,line_delay\n";
    char line[160];
    for (const FrameRecord& f : frames)
    {
        std::snprintf(line, sizeof line, "%d,%.9f,%.9g,%.9g\n", f.frame, f.frameStart, f.exposure, f.lineDelay);
        out << line;
    }
    writeTextFile(path, out.str());
}

bool CommandLog::moves() const
{
    for (const std::vector<int>& axis : levels)
        if (std::any_of(axis.begin(), axis.end(), [&](int l) { return l != axis[0]; }))
            return true;
    return false;
}

void CommandLog::appendMove(const std::vector<cv::dynblur::SwitchSchedule>& schedules, double offset)
{
    CV_Assert(int(schedules.size()) == axisCount() && !times.empty());
    std::vector<double> instants;
    for (const cv::dynblur::SwitchSchedule& s : schedules)
        instants.insert(instants.end(), s.times.begin(), s.times.end());
    std::sort(instants.begin(), instants.end());
    instants.erase(std::unique(instants.begin(), instants.end()), instants.end());
    for (double t : instants)
    {
        times.push_back(t + offset);
        for (size_t a = 0; a < schedules.size(); a++)
            levels[a].push_back(schedules[a].times.empty() ? levels[a].back() : schedules[a].levelAt(t));
    }
}

cv::dynblur::SwitchSchedule CommandLog::scheduleAround(double from, double to, int axis, double restSince) const
{
    CV_Assert(!times.empty() && axis >= 0 && axis < axisCount());
    const std::vector<int>& level = levels[size_t(axis)];
    const double horizon = std::isfinite(restSince) ? restSince : from - kSettleSeconds;
    size_t first = 0;
    while (first + 1 < times.size() && times[first + 1] <= horizon)
        first++;  // the last switch at or before the horizon sets the level in force
    cv::dynblur::SwitchSchedule schedule;
    schedule.initialLevel = level[first];
    for (size_t i = first; i < times.size() && times[i] <= to; i++)
    {
        schedule.times.push_back(times[i]);
        schedule.levels.push_back(level[i]);
    }
    if (schedule.times.empty())  // everything starts after the interval: the plant rests at the first level
    {
        schedule.times.push_back(times[0]);
        schedule.levels.push_back(level[0]);
    }
    return schedule;
}

std::vector<cv::dynblur::SwitchSchedule> CommandLog::schedulesAround(double from, double to, double restSince) const
{
    std::vector<cv::dynblur::SwitchSchedule> schedules;
    for (int a = 0; a < axisCount(); a++)
        schedules.push_back(scheduleAround(from, to, a, restSince));
    return schedules;
}

namespace {

//! The level columns of a command log: {"level"} for one axis, {"level0", "level1", ...} for a mount.
std::vector<std::string> levelColumns(const Table& t, const std::string& source)
{
    if (t.column.count("level") && t.column.count("level0"))
        CV_Error(cv::Error::StsParseError, source + ": the header names both 'level' (one axis) and 'level0' (a "
                                                    "mount's axes): give one");
    if (t.column.count("level"))
        return {"level"};
    std::vector<std::string> columns;
    while (t.column.count("level" + std::to_string(columns.size())))
        columns.push_back("level" + std::to_string(columns.size()));
    if (columns.empty())
        CV_Error(cv::Error::StsParseError, source + ": the header has no column 'level' (one axis: level switched "
                                                    "on, integer cells) nor 'level0', 'level1', ... (a mount: one per "
                                                    "axis, base first)");
    return columns;
}

}  // namespace

CommandLog parseCommandLog(const std::string& text, const std::string& source)
{
    const Table t = parseTable(text, source);
    requireColumn(t, "t", source, "switching instant, seconds, actuator clock");
    const std::vector<std::string> columns = levelColumns(t, source);
    CommandLog log;
    log.levels.resize(columns.size());
    for (size_t r = 0; r < t.rows.size(); r++)
    {
        const double time = number(t, r, "t", source);
        if (!log.times.empty() && time <= log.times.back())
            parseError(source, t.lines[r], "'t' must increase from line to line");
        log.times.push_back(time);
        for (size_t a = 0; a < columns.size(); a++)
            log.levels[a].push_back(integer(t, r, columns[a], source));
    }
    if (log.times.empty())
        CV_Error(cv::Error::StsParseError, source + ": no commands");
    return log;
}

CommandLog readCommandLog(const std::string& path)
{
    return parseCommandLog(readTextFile(path, "command log"), path);
}

void writeCommandLog(const std::string& path, const CommandLog& log)
{
    std::ostringstream out;
    const bool oneAxis = log.axisCount() == 1;
    out << "# dynblur command log: from t (s, actuator clock) on, the level (cells)"
        << (oneAxis ? "" : " of each axis, base first") << "; before the first line\n# "
        << (oneAxis ? "the plant rests at the first line's level\nt,level" : "each axis rests at its first line's level\nt");
    for (int a = 0; !oneAxis && a < log.axisCount(); a++)
        out << ",level" << a;
    out << "\n";
    char field[32];
    for (size_t i = 0; i < log.times.size(); i++)
    {
        std::snprintf(field, sizeof field, "%.9f", log.times[i]);
        out << field;
        for (const std::vector<int>& axis : log.levels)
            out << ',' << axis[i];
        out << '\n';
    }
    writeTextFile(path, out.str());
}

}  // namespace dynblur_samples
