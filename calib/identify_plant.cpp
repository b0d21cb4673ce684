// SPDX-License-Identifier: Apache-2.0
// dynblur_identify_plant: natural frequency, damping ratio and gain of the camera positioner from a
// logged step response (format: samples/support/response_log.hpp, calib/README.md).
//
//     dynblur_identify_plant response.csv --out plant.yml
//     dynblur_identify_plant response.csv --schedule move.yml --out plant.yml
//     dynblur_identify_plant tilt.csv --mount pan_tilt.yml --axis 1
//     dynblur_identify_plant --simulate sim.csv --hz 12 --zeta 0.1 --delay 0.0123   (a test log)
//
// Writes the plant file (naturalFreqHz, dampingRatio, gain, maxLevel; atomically), or axis I's plant
// into the mount file, and a plot of the measured and fitted angle and the residual (PLANT_fit.png).
#include "atomic_file.hpp"  // samples/support
#include "cli_args.hpp"
#include "plant_file.hpp"
#include "plot.hpp"
#include "response_log.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/dynblur.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

using namespace cv;
using namespace cv::dynblur;
using namespace dynblur_samples;

static CliOptions identifyPlantOptions()
{
    CliOptions options("dynblur_identify_plant");
    options.synopsis("[options] LOG.csv")
        .synopsis("--simulate FILE.csv [simulation options]")
        .description("Identifies the positioner's natural frequency, damping ratio and gain (theta'' + 2 zeta wn theta' "
                     "+ wn^2 theta = wn^2 g u) from a logged step response, by a least-squares fit of the closed form.")
        .description("LOG.csv: a header line naming the columns, then one sample per line: t (s), theta (rad) and, "
                     "optionally, level (the commanded level in force, integer cells). Lines starting with # are "
                     "comments. Options take --name value or --name=value.")
        .option("schedule", "FILE.yml", "",
                "the command as a SwitchSchedule file (SwitchSchedule::save); needed when the log has no level "
                "column, and used instead of it when given")
        .flag("known-start", "the log's clock is the command's clock: do not fit a delay (by default a constant "
                             "delay between command and motion is fitted and reported)")
        .flag("unknown-start", "fit the delay (the default; accepted for clarity)")
        .option("out", "FILE.yml", "plant.yml", "plant file to write")
        .option("mount", "FILE.yml", "",
                "a mount file (Mount::save): the log is axis --axis's step response, and that axis's plant is "
                "written back into the file (atomically; the other axes and every level range untouched) instead "
                "of a plant file")
        .option("axis", "I", "", "the axis of --mount the log belongs to, 0 = the base")
        .option("max-level", "N", "16", "largest |level| the actuator holds, written to the plant file")
        .option("plot", "FILE.png", "", "plot of measured vs fitted theta and the residual (default: OUT_fit.png)")
        .flag("no-png", "do not write the plot")
        .heading("Simulation (writes a test log and exits; nothing is identified):")
        .option("simulate", "FILE.csv", "", "noisy step response of the linear plant: level 0 -> --step-level at --delay s")
        .option("hz", "F", "14.4", "natural frequency, Hz")
        .option("zeta", "Z", "0.12", "damping ratio")
        .option("gain-deg", "G", "1", "gain, degrees per level")
        .option("step-level", "N", "4", "the level stepped to")
        .option("delay", "S", "0.05", "time of the switch the level column shows, seconds")
        .option("latency", "S", "0",
                "the plant moves that long after the switch the level column shows (an unknown start), seconds")
        .option("noise-deg", "N", "0.01", "noise of theta, degrees (standard deviation)")
        .option("duration", "S", "1.0", "length of the log, seconds")
        .option("rate", "HZ", "1000", "samples per second")
        .option("seed", "K", "1", "seed of the noise")
        .positional()
        .footer("Exit status: 0 identified, 1 bad or unusable log (the message says why), 2 bad usage.");
    return options;
}

//! A mount file and the axis of it being identified.
struct MountAxis
{
    Ptr<Mount> mount;
    int index = -1;
};

static MountAxis loadMountAxis(const std::string& path, int index)
{
    MountAxis axis{Mount::load(path), index};
    if (index < 0 || index >= axis.mount->getAxisCount())
        CV_Error_(Error::StsOutOfRange, ("--axis %d must lie in [0, %d) (the axes of the mount file '%s')", index,
                                         axis.mount->getAxisCount(), path.c_str()));
    return axis;
}

//! The mount with axis `axis.index`'s plant replaced by `plant`; every other axis as it was.
static Ptr<Mount> withPlant(const MountAxis& axis, const Ptr<Plant>& plant)
{
    Ptr<Mount> mount = Mount::create();
    for (int i = 0; i < axis.mount->getAxisCount(); i++)
    {
        const Vec2i levels = axis.mount->getLevelRange(i);
        mount->addAxis(axis.mount->getAxis(i), i == axis.index ? plant : axis.mount->getPlant(i), levels[0],
                       levels[1]);
    }
    return mount;
}

static int usageError(const std::string& message)
{
    std::cerr << "error: " << message << "\n(see dynblur_identify_plant --help)\n";
    return 2;
}


static double deg(double rad)
{
    return rad * 180.0 / CV_PI;
}

static int simulate(const CliArgs& args, const std::string& path)
{
    const double hz = args.num("hz"), zeta = args.num("zeta");
    const double gain = args.num("gain-deg") * CV_PI / 180.0;
    const int stepLevel = args.integer("step-level");
    const double delay = args.num("delay"), noise = args.num("noise-deg") * CV_PI / 180.0;
    const double duration = args.num("duration"), rate = args.num("rate");
    const int seed = args.integer("seed");
    const double latency = args.num("latency");
    if (!(duration > 0 && rate > 0 && duration * rate >= 2 && duration * rate < 1e7))
        return usageError("--duration and --rate must be > 0 and give 2 to 1e7 samples");
    if (!(noise >= 0))
        return usageError("--noise-deg must be >= 0");
    Ptr<Plant> plant = Plant::create(hz, zeta, gain);
    // The plant moves `latency` seconds after the logged switch (a command-to-motion delay that
    // the log does not show, as on a real bus).
    const SwitchSchedule logged({delay}, {stepLevel}, 0);
    const SwitchSchedule schedule({delay + latency}, {stepLevel}, 0);
    ResponseLog log;
    const int n = static_cast<int>(std::round(duration * rate));
    for (int i = 0; i < n; ++i)
        log.t.push_back(i / rate);
    Mat theta;
    plant->response(schedule, log.t, theta);
    RNG rng(static_cast<uint64>(seed));
    for (int i = 0; i < n; ++i)
    {
        log.theta.push_back(theta.at<double>(i) + rng.gaussian(noise));
        log.level.push_back(logged.levelAt(log.t[static_cast<size_t>(i)]));
    }
    writeResponseLog(path, log);
    std::printf("Wrote %s: %d samples at %g Hz, plant %.4g Hz, zeta %.4g, gain %.4g deg/level, step 0 -> %d at "
                "%.4g s (motion %.4g s later), noise %.3g deg\n",
                path.c_str(), n, rate, hz, zeta, deg(gain), stepLevel, delay, latency, deg(noise));
    return 0;
}

int main(int argc, char** argv)
{
    try
    {
        const CliOptions options = identifyPlantOptions();
        const CliArgs args = options.parse(argc, argv);
        if (options.printHelp(args))
            return 0;
        if (args.has("simulate"))
        {
            if (!args.positional().empty())
                return usageError("--simulate writes a log; give no input file");
            return simulate(args, args.str("simulate"));
        }
        if (args.positional().size() != 1)
            return usageError(args.positional().empty() ? "no log file given" : "give exactly one log file");
        const std::string logPath = args.positional()[0];
        if (args.has("mount") != args.has("axis"))
            return usageError("--mount and --axis go together (the mount file and the axis the log belongs to)");
        if (args.has("mount") && (args.has("out") || args.has("max-level")))
            return usageError("--out and --max-level do not apply to --mount: the identified plant goes into the "
                              "mount file, whose level ranges are kept");
        MountAxis mountAxis;
        if (args.has("mount"))
        {
            try
            {
                mountAxis = loadMountAxis(args.str("mount"), args.integer("axis"));
            }
            catch (const cv::Exception& e)
            {
                std::cerr << "error: " << e.err << "\n";
                return 1;
            }
        }
        const std::string out = args.has("mount") ? args.str("mount") : args.str("out");
        const std::string plotPath = args.str(
            "plot", pathStem(out) + (args.has("mount") ? format("_axis%d", mountAxis.index) : String()) + "_fit.png");
        const int maxLevel = args.integer("max-level");
        if (maxLevel < 1)
            return usageError("--max-level must be >= 1");
        if (args.has("known-start") && args.has("unknown-start"))
            return usageError("--known-start and --unknown-start contradict each other");
        const bool estimateDelay = !args.has("known-start");

        ResponseLog log;
        SwitchSchedule schedule;
        std::string commandSource;
        try
        {
            std::printf("Reading %s...\n", logPath.c_str());
            std::fflush(stdout);
            log = readResponseLog(logPath);
            checkResponseLog(log);
            if (args.has("schedule"))
            {
                schedule = SwitchSchedule::load(args.str("schedule"));
                commandSource = "schedule " + args.str("schedule");
            }
            else if (log.hasLevel())
            {
                schedule = scheduleFromLevels(log);
                commandSource = "the log's level column";
            }
            else
                CV_Error(Error::StsBadArg, "the log has no 'level' column: give the command with --schedule FILE.yml");
        }
        catch (const cv::Exception& e)
        {
            std::cerr << "error: " << e.err << "\n";
            return 1;
        }
        std::printf("%zu samples over %.4g s (%.4g Hz); command from %s: level %d", log.t.size(),
                    log.t.back() - log.t.front(), (log.t.size() - 1) / (log.t.back() - log.t.front()),
                    commandSource.c_str(), schedule.initialLevel);
        for (size_t i = 0; i < schedule.times.size(); ++i)
            std::printf(", %d at %.4g s", schedule.levels[i], schedule.times[i]);
        std::printf("\nFitting wn, zeta, gain%s...\n", estimateDelay ? " and the command-to-motion delay" : "");
        std::fflush(stdout);

        double rms = 0, delay = 0;
        Ptr<Plant> plant;
        try
        {
            plant = Plant::identify(log.t, log.theta, schedule, estimateDelay, &rms, &delay);
        }
        catch (const cv::Exception& e)
        {
            std::cerr << "error: " << e.err << "\n";
            return 1;
        }
        std::printf("\nnatural frequency  %.4f Hz (wn = %.3f rad/s)\n", plant->getNaturalFreqHz(),
                    2 * CV_PI * plant->getNaturalFreqHz());
        std::printf("damping ratio      %.4f\n", plant->getDampingRatio());
        std::printf("gain               %.6g rad/level (%.5f deg/level)\n", plant->getGain(), deg(plant->getGain()));
        std::printf("delay              %.2f ms%s\n", delay * 1e3, estimateDelay ? "" : " (not fitted: --known-start)");
        std::printf("fit residual       %.4g rad RMS (%.4f deg)\n", rms, deg(rms));

        const std::string comment = "identified by dynblur_identify_plant from " + logPath +
                                    format(": residual %.3g rad RMS, delay %.2f ms", rms, delay * 1e3);
        try
        {
            if (mountAxis.mount.empty())
                savePlantFile(out, *plant, maxLevel, comment);
            else
                withPlant(mountAxis, plant)->save(out);
        }
        catch (const cv::Exception& e)
        {
            std::cerr << "error: " << e.err << "\n";
            return 1;
        }
        std::printf("Wrote %s", out.c_str());

        if (!args.has("no-png"))
        {
            SwitchSchedule shifted = schedule;
            for (double& t : shifted.times)
                t += delay;
            Mat fitted;
            plant->response(shifted, log.t, fitted);
            std::vector<double> measuredDeg, fittedDeg, residualDeg, levels;
            for (size_t i = 0; i < log.t.size(); ++i)
            {
                measuredDeg.push_back(deg(log.theta[i]));
                fittedDeg.push_back(deg(fitted.at<double>(static_cast<int>(i))));
                residualDeg.push_back(measuredDeg.back() - fittedDeg.back());
                levels.push_back(shifted.levelAt(log.t[i]));
            }
            dynblur_plot::Figure figure(1100, format("Plant identification: %.3f Hz, zeta %.3f, gain %.4f deg/level, "
                                                     "delay %.1f ms",
                                                     plant->getNaturalFreqHz(), plant->getDampingRatio(),
                                                     deg(plant->getGain()), delay * 1e3));
            figure.addPanel("measured and fitted angle", "theta (deg)")
                .line(log.t, fittedDeg, "fitted", dynblur_plot::paletteColor(1), 3)
                .line(log.t, measuredDeg, "measured", dynblur_plot::paletteColor(0), 1);
            figure.addPanel(format("residual (RMS %.4f deg)", deg(rms)), "deg")
                .hLine(0.0)
                .line(log.t, residualDeg, "measured - fitted", dynblur_plot::paletteColor(2), 1);
            figure.addPanel("command (shifted by the fitted delay)", "level").line(log.t, levels, "level",
                                                                                dynblur_plot::paletteColor(3), 2);
            figure.xLabel("time (s)");
            const std::string temporary = temporaryPathFor(plotPath);
            if (!figure.save(temporary) || std::rename(temporary.c_str(), plotPath.c_str()) != 0)
            {
                std::remove(temporary.c_str());
                std::cerr << "\nerror: cannot write the plot '" << plotPath << "'\n";
                return 1;
            }
            std::printf(", %s", plotPath.c_str());
        }
        std::printf("\n");
        return 0;
    }
    catch (const std::runtime_error& e)
    {
        return usageError(e.what());
    }
    catch (const cv::Exception& e)
    {
        std::cerr << "error: " << e.err << "\n";
        return 1;
    }
}
