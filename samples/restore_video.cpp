// SPDX-License-Identifier: Apache-2.0
// dynblur_restore_video: restores a recording (frames, frame log, command log; docs/recording-format.md)
// frame by frame, streaming: each frame taken during a move is refined against the stills on both
// sides of its move (the deblurrer chooses the one that saw its moving rows) and restored; still
// frames pass through. A frame that ends its move at rest waits for the still after the move.
// Writes the restored video, a CSV of each frame's window, correction and consistency, and a contact
// sheet of the most blurred frames. With --truth (a rendered recording's sharp scene) each moving
// frame's gain over the recording is measured. The stages live in samples/restore_video/.
//
//     dynblur_restore_video --video rec/frame_%04d.png --frames rec/frames.csv --commands rec/commands.csv
//                           --camera rec/camera.xml --plant rec/plant.yml --timing rec/timing.yml
//     dynblur_restore_video --gyro Gyroscope.csv --video clip.mp4 --camera camera.xml --timing timing.yml
//                           --out restored.mp4                        (a hand-held clip: docs/hand-held.md)
#include "restore_video/restore_video.hpp"

#include "cli_args.hpp"  // samples/support
#include "gyro_recording.hpp"
#include "recording.hpp"
#include "restoration_options.hpp"

#include <iostream>
#include <string>

using namespace dynblur_samples;

static CliOptions restoreVideoOptions()
{
    CliOptions options("dynblur_restore_video");
    options.synopsis("--video V --frames FRAMES.csv --commands COMMANDS.csv [options]")
        .synopsis("--recording DIR [options]")
        .synopsis("--gyro LOG --video V [--frames FRAMES.csv] [options]")
        .description("Restores the frames of a recording that a move blurred, with the blur predicted from the plant "
                     "and the commands, corrected per frame against the still frame before the move (a frame that "
                     "starts at rest) or after it (one that ends at rest), in units of the noise measured from the "
                     "last two consecutive still frames. A frame no correction explains is written unchanged.")
        .description("Each frame is restored to the view at the angle of its middle row's mid-exposure. A frame that "
                     "needs the still after its move is held until that still arrives (the rest of the move and one "
                     "frame; the progress line shows how many frames wait).")
        .group(recordingOptions())
        .option("timing", "FILE.yml", "",
                "the recording's calibration (dynblur_calibrate_timing); each frame then refines its clock's jitter "
                "only, unless --refine says otherwise")
        .option("refine", "LIST", "",
                "offset, line-delay, plant, all or none, comma-separated (default: offset with --timing, all without)")
        .group(restorationOptions())
        .option("no-still-after", "WHAT", "as-told",
                "a frame that ends its move at rest (window III) but has no still after it (the recording ends, or "
                "another move starts) cannot be refined: as-told restores it with the model as told (and --timing), "
                "unchanged writes it as recorded; the tool lists those frames either way")
        .option("unobserved", "WHAT", "recorded",
                "where a frame never saw the restored view (content beyond its edges): recorded keeps the frame's "
                "pixels, marked paints them black, nearest repeats the nearest observed pixel (streaks across a wide "
                "band)")
        .option("truth", "DIR", "",
                "a rendered recording's truth (scene.png, truth.yml: dynblur_calibrate_timing --simulate writes "
                "them): each moving frame's PSNR against the view it is restored to, as recorded and restored, its "
                "true window, and a summary")
        .option("out", "FILE", "restored.avi",
                "restored video, the input's size and rate (a name ending .mp4: MPEG-4 in MP4; otherwise MJPG); "
                "beside it OUT_frames.png, the most blurred moving frames as recorded and restored")
        .option("csv", "FILE", "",
                "per-frame log (default: OUT's name with .csv); window is the frame's exposure window under the "
                "motion it was restored with, window_as_told under the model as given, blur_px the largest image "
                "motion during one row's exposure")
        .group(gyroLogOptions(
            "Gyro mode (--gyro):",
            "A clip whose motion is a gyro log (docs/hand-held.md): every frame is restored with the log's motion, on "
            "the clock, line delay, bias and axes of --timing (dynblur_calibrate_timing --gyro; without it, as the "
            "logs tell), to the view at its middle row's mid-exposure, once checked against the frame before (one "
            "whose motion from it the log does not explain is written as recorded); frames the log shows still pass "
            "through, frames it shows sharp are not deconvolved. "
            "Without --frames the frame times come from the video's container (its timestamps, else the frame "
            "index at its rate); the exposure from --exposure or --timing, the line delay from --timing (the one "
            "its calibration was told, which its scale corrects), --readout, --line-delay or a gcsv log's "
            "frame_readout_time. --camera, --preset, --model, --out and --csv as above; the CSV has the columns "
            "above, then frame_start_s, gyro_bias_x, _y, _z (rad/s) and rate_scale. A failure midway (a log shorter "
            "than the clip) keeps the frames written so far, closed."))
        .footer("Output is written to temporary files and renamed into place only when the whole recording is done "
                "(--gyro: or when it fails midway, as far as it was written).")
        .footer("Exit status: 0 restored, 1 bad or unusable recording (the message says why), 2 bad usage.");
    return options;
}

static int usageError(const std::string& message)
{
    std::cerr << "error: " << message << "\n(see dynblur_restore_video --help)\n";
    return 2;
}

int main(int argc, char** argv)
{
    try
    {
        const CliOptions options = restoreVideoOptions();
        const CliArgs args = options.parse(argc, argv);
        if (options.printHelp(args))
            return 0;
        const RestorationSettings settings(args);
        if (args.has("gyro"))
        {
            if (args.has("truth"))
                return usageError("--truth belongs to a recording with a command log, not to --gyro");
            return restoreGyroRecording(args, settings);
        }
        if (!OpenedRecording::named(args))
            return usageError("--recording DIR, or --video, --frames and --commands, are required");
        return restoreCommandedRecording(args, settings);
    }
    catch (const std::runtime_error& e)
    {
        return usageError(e.what());
    }
    catch (const cv::Exception& e)
    {
        // The stages have removed what they had begun to write.
        std::cerr << "\nerror: " << e.err << "\n";
        return 1;
    }
}
