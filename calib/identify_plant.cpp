// SPDX-License-Identifier: Apache-2.0
// dynblur_identify_plant: natural frequency, damping ratio and gain of the camera positioner from a
// logged step response (format: samples/support/response_log.hpp, calib/README.md).
//
//     dynblur_identify_plant response.csv --out plant.yml
//     dynblur_identify_plant response.csv --schedule move.yml --out plant.yml
//     dynblur_identify_plant --simulate sim.csv --hz 12 --zeta 0.1 --delay 0.0123   (a test log)
//
// Writes the plant file (naturalFreqHz, dampingRatio, gain, maxLevel; atomically) and a plot of the
// measured and fitted angle and the residual (PLANT_fit.png).
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

static const char* const kUsage =
    "Usage: dynblur_identify_plant [options] LOG.csv\n"
    "Identifies the positioner's natural frequency, damping ratio and gain (theta'' + 2 zeta wn theta' +\n"
    "wn^2 theta = wn^2 g u) from a logged step response, by a least-squares fit of the closed form.\n"
    "\n"
    "LOG.csv: a header line naming the columns, then one sample per line: t (s), theta (rad) and,\n"
    "optionally, level (the commanded level in force, integer cells). Lines starting with # are comments.\n"
    "Options (--name value or --name=value):\n"
    "  --schedule FILE.yml  the command as a SwitchSchedule file (SwitchSchedule::save); needed when the\n"
    "                       log has no level column, and used instead of it when given\n"
    "  --known-start        the log's clock is the command's clock: do not fit a delay (by default a\n"
    "                       constant delay between command and motion is fitted and reported)\n"
    "  --unknown-start      fit the delay (the default; accepted for clarity)\n"
    "  --out FILE.yml       plant file to write (default plant.yml)\n"
    "  --max-level N        largest |level| the actuator holds, written to the plant file (default 16)\n"
    "  --plot FILE.png      plot of measured vs fitted theta and the residual (default: FILE_fit.png)\n"
    "  --no-png             do not write the plot\n"
    "  --help               this help\n"
    "Simulation (writes a test log and exits; nothing is identified):\n"
    "  --simulate FILE.csv  noisy step response of the linear plant: level 0 -> --step-level at --delay s\n"
    "  --hz F --zeta Z --gain-deg G --step-level N --delay S --latency S --noise-deg N --duration S\n"
    "  --rate HZ --seed K   (defaults 14.4, 0.12, 1, 4, 0.05, 0, 0.01, 1.0, 1000, 1); --latency: the plant\n"
    "                       moves that long after the switch the level column shows (an unknown start)\n"
    "Exit status: 0 identified, 1 bad or unusable log (the message says why), 2 bad usage.\n";

static int usageError(const std::string& message)
{
    std::cerr << "error: " << message << "\n(see dynblur_identify_plant --help)\n";
    return 2;
}


static double deg(double rad)
{
    return rad * 180.0 / CV_PI;
}

static int simulate(const dynblur_samples::CliArgs& args, const std::string& path)
{
    const double hz = args.num("hz", 14.4), zeta = args.num("zeta", 0.12);
    const double gain = args.num("gain-deg", 1.0) * CV_PI / 180.0;
    const int stepLevel = args.integer("step-level", 4);
    const double delay = args.num("delay", 0.05), noise = args.num("noise-deg", 0.01) * CV_PI / 180.0;
    const double duration = args.num("duration", 1.0), rate = args.num("rate", 1000.0);
    const int seed = args.integer("seed", 1);
    const double latency = args.num("latency", 0.0);
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
        dynblur_samples::CliArgs args(argc, argv,
                                      {"schedule", "out", "max-level", "plot", "simulate", "hz", "zeta", "gain-deg",
                                       "step-level", "delay", "latency", "noise-deg", "duration", "rate", "seed"},
                                      {"help", "known-start", "unknown-start", "no-png"}, true);
        if (args.has("help"))
        {
            std::cout << kUsage;
            return 0;
        }
        if (args.has("simulate"))
        {
            if (!args.positional().empty())
                return usageError("--simulate writes a log; give no input file");
            return simulate(args, args.str("simulate", ""));
        }
        if (args.positional().size() != 1)
            return usageError(args.positional().empty() ? "no log file given" : "give exactly one log file");
        const std::string logPath = args.positional()[0];
        const std::string out = args.str("out", "plant.yml");
        const std::string plotPath = args.str("plot", pathStem(out) + "_fit.png");
        const int maxLevel = args.integer("max-level", 16);
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
                schedule = SwitchSchedule::load(args.str("schedule", ""));
                commandSource = "schedule " + args.str("schedule", "");
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
            savePlantFile(out, *plant, maxLevel, comment);
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
