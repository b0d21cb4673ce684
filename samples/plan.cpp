// dynblur_plan: plans one point-to-point move as an integer-level switching schedule, prints it,
// and writes the predicted trajectory (PREFIX.csv) and a plot of it (PREFIX.png).
//
//     dynblur_plan --deg --from=0 --to=10 --mode=robust --out=move10
#include "option_check.hpp"
#include "plot.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/dynblur.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

using namespace cv;
using namespace cv::dynblur;

static const char* const kKeys =
    "{help h usage ? |        | print this help                                              }"
    "{from           | 0      | start angle, radians (degrees with --deg)                    }"
    "{to             | <none> | target angle, radians (degrees with --deg)                   }"
    "{deg            |        | read --from and --to in degrees                              }"
    "{mode           | fast   | fast (shortest settle) or robust (tolerates +-10% error in wn) }"
    "{hz             | 14.4   | plant natural frequency, Hz                                  }"
    "{zeta           | 0.12   | plant damping ratio                                          }"
    "{gain-deg       | 1      | plant static gain, degrees per level (one cell)              }"
    "{max-level      | 16     | largest |level|, cells                                       }"
    "{min-dwell      | 0.002  | shortest time between two switches, seconds                  }"
    "{start          | 0      | time of the first switch, seconds                            }"
    "{out            | plan   | output prefix: writes PREFIX.csv and PREFIX.png              }";

static int fail(const std::string& message)
{
    std::cerr << "error: " << message << "\n";
    return 2;
}

int main(int argc, char** argv)
{
    CommandLineParser parser(argc, argv, kKeys);
    parser.about("Plans a vibration-free move of the piezo-driven camera positioner (dynblur).\n"
                 "Options take the form --name=value, e.g. --deg --from=-5 --to=5 --mode=robust");
    if (parser.has("help"))
    {
        parser.printMessage();
        return 0;
    }
    const std::string unknown = dynblur_samples::unknownOption(argc, argv, kKeys);
    if (!unknown.empty())
        return fail(unknown);
    const bool degrees = parser.has("deg");
    double from = parser.get<double>("from");
    double to = parser.get<double>("to");
    const std::string modeName = parser.get<std::string>("mode");
    const double hz = parser.get<double>("hz");
    const double zeta = parser.get<double>("zeta");
    const double gainDeg = parser.get<double>("gain-deg");
    const int maxLevel = parser.get<int>("max-level");
    const double minDwell = parser.get<double>("min-dwell");
    const double start = parser.get<double>("start");
    const std::string prefix = parser.get<std::string>("out");
    if (!parser.check())
    {
        parser.printErrors();
        return 2;
    }
    if (modeName != "fast" && modeName != "robust")
        return fail("--mode must be 'fast' or 'robust', not '" + modeName + "'");
    if (prefix.empty())
        return fail("--out must not be empty");
    const double degree = CV_PI / 180.0;
    if (degrees)
    {
        from *= degree;
        to *= degree;
    }

    Ptr<Plant> plant;
    Ptr<SwitchPlanner> planner;
    SwitchSchedule schedule;
    double planMs = 0;
    try
    {
        plant = Plant::create(hz, zeta, gainDeg * degree);
        planner = SwitchPlanner::create(plant, maxLevel, modeName == "robust" ? PLAN_ROBUST : PLAN_FAST, minDwell);
        const auto begin = std::chrono::steady_clock::now();
        schedule = planner->plan(from, to, start);
        planMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
    }
    catch (const cv::Exception& e)
    {
        return fail(e.err);
    }

    // --- The schedule and its predicted figures.
    const double gain = plant->getGain();
    const int move = schedule.finalLevel() - schedule.initialLevel;
    std::printf("move: level %d -> %d (%.3f -> %.3f deg), %s mode, planned in %.1f ms\n", schedule.initialLevel,
                schedule.finalLevel(), gain * schedule.initialLevel / degree, gain * schedule.finalLevel() / degree,
                modeName.c_str(), planMs);
    std::printf("plant: %.3f Hz, zeta %.3f, %.4f deg/level; max level %d, min dwell %.2f ms\n", hz, zeta, gainDeg,
                maxLevel, minDwell * 1e3);
    if (move == 0)
    {
        std::printf("nothing to do: already at the target level\n");
        return 0;
    }
    std::printf("%10s %8s\n", "t (ms)", "level");
    for (size_t i = 0; i < schedule.times.size(); ++i)
        std::printf("%10.3f %8d\n", schedule.times[i] * 1e3, schedule.levels[i]);
    std::printf("settle time (+-%.0f%% band): %.2f ms\n", planner->getSettleBand() * 100, schedule.settleTime * 1e3);
    std::printf("peak velocity: %.1f deg/s\n", schedule.peakVelocity / degree);
    std::printf("residual vibration: %.3g %% of the move\n", schedule.residualVibration * 100);
    if (modeName == "robust")
    {
        double worst = 0;
        const double range = planner->getRobustRange();
        for (int k = -20; k <= 20; ++k)
            worst = std::max(worst, residualVibration(schedule, hz * (1 + range * k / 20.0), zeta));
        std::printf("worst residual vibration for wn within +-%.0f%%: %.2f %%\n", range * 100, worst * 100);
    }

    // --- Trajectory, sampled every 0.1 ms from 10 ms before the move to a damped period after it.
    const double margin = 0.010;
    const double end = schedule.times.back() + std::max(margin, 1.0 / hz);
    std::vector<double> t;
    for (double x = start - margin; x <= end + 1e-12; x += 1e-4)
        t.push_back(x);
    Mat theta, omega;
    plant->response(schedule, t, theta);
    plant->velocity(schedule, t, omega);

    const std::string csvName = prefix + ".csv";
    std::ofstream csv(csvName);
    if (!csv)
        return fail("cannot write " + csvName);
    csv << "t,theta,omega,u\n";
    csv.precision(10);
    for (size_t i = 0; i < t.size(); ++i)
        csv << t[i] << ',' << theta.at<double>(static_cast<int>(i)) << ',' << omega.at<double>(static_cast<int>(i))
            << ',' << schedule.levelAt(t[i]) << '\n';
    if (!csv)
        return fail("cannot write " + csvName);

    // --- Plot: angle with the settle band, velocity, command levels; time in ms from the start.
    std::vector<double> timeMs(t.size()), thetaDeg(t.size()), omegaDeg(t.size()), level(t.size());
    for (size_t i = 0; i < t.size(); ++i)
    {
        timeMs[i] = (t[i] - start) * 1e3;
        thetaDeg[i] = theta.at<double>(static_cast<int>(i)) / degree;
        omegaDeg[i] = omega.at<double>(static_cast<int>(i)) / degree;
        level[i] = schedule.levelAt(t[i]);
    }
    const double targetDeg = gain * schedule.finalLevel() / degree;
    const double bandDeg = planner->getSettleBand() * std::abs(gain * move) / degree;
    const double settleMs = schedule.settleTime * 1e3;

    dynblur_plot::Figure figure(1000, format("%s move %.2f -> %.2f deg: settles in %.1f ms, peak %.0f deg/s",
                                             modeName.c_str(), gain * schedule.initialLevel / degree, targetDeg,
                                             settleMs, schedule.peakVelocity / degree));
    const std::string bandLabel = format("+-%.0f%% band", planner->getSettleBand() * 100);
    figure.addPanel("angle", "theta (deg)")
        .xSpan(0, settleMs, "settling", Scalar(235, 206, 135), 0.18)
        .yBand(targetDeg - bandDeg, targetDeg + bandDeg, bandLabel)
        .hLine(targetDeg, "target")
        .line(timeMs, thetaDeg, "theta", dynblur_plot::paletteColor(0));
    figure.addPanel("angular velocity", "omega (deg/s)")
        .xSpan(0, settleMs, "", Scalar(235, 206, 135), 0.18)
        .hLine(0)
        .line(timeMs, omegaDeg, "dtheta/dt", dynblur_plot::paletteColor(1));
    figure.addPanel("command", "u (levels)")
        .hLine(0)
        .line(timeMs, level, "active cells", dynblur_plot::paletteColor(2));
    figure.xLabel("time from the first switch (ms)");
    const std::string pngName = prefix + ".png";
    if (!figure.save(pngName))
        return fail("cannot write " + pngName);
    std::printf("wrote %s and %s\n", csvName.c_str(), pngName.c_str());
    return 0;
}
