// SPDX-License-Identifier: Apache-2.0
// Shared by the refinement tests: frames blurred by a truth that differs from what the deblurrer is
// told (drifts), the still frames beside them, and the wrong schedules an inconsistent frame is told.
#ifndef DYNBLUR_TEST_REFINEMENT_CASES_HPP
#define DYNBLUR_TEST_REFINEMENT_CASES_HPP

#include "saccade_scene.hpp"

#include <opencv2/dynblur.hpp>

#include <functional>
#include <vector>

namespace dynblur_test {

using namespace cv;
using namespace cv::dynblur;

const double kNaN = std::numeric_limits<double>::quiet_NaN();

//! How the hardware differs from the nominal model (the truth the frame is rendered with).
struct Drift
{
    const char* name;
    double timeOffset;        // s, added to the reported frame start
    double lineDelayScale;
    double naturalFreqScale;
    double dampingScale;

    //! The drift as the correction that takes the nominal model to the truth.
    MotionCorrection correction() const
    {
        MotionCorrection c;
        c.timeOffset = timeOffset;
        c.lineDelayScale = lineDelayScale;
        c.naturalFreqScale = naturalFreqScale;
        c.dampingScale = dampingScale;
        return c;
    }
    Ptr<Plant> plant(const SaccadeScene& s) const { return correction().correctPlant(s.plant); }
    RollingShutter shutter(const RollingShutter& told) const { return correction().correctShutter(told); }
};

//! A frame of the scene in `window`, blurred by `drift`'s truth, and the still frame before the move.
struct DriftedFrame
{
    RollingShutter told;
    Mat frame, still;
    double stillAngle = 0;  // radians
};

/* The still frame that saw what the frame's moving rows see: the one before the move for a frame
   that starts at rest (window I), the one after it for a frame that ends at rest (III). */
inline DriftedFrame captureDrifted(const SaccadeScene& s, int window, double lineDelay, const Drift& drift, uint64 seed)
{
    DriftedFrame d;
    d.told = s.shutterInWindow(window, lineDelay);
    d.frame = s.capture(drift.shutter(d.told), seed, drift.plant(s));
    const bool after = window != EXPOSURE_I;
    d.still = s.capture(RollingShutter(after ? 1.0 : -0.2, d.told.exposure, d.told.lineDelay, d.told.rows), seed + 1);
    d.stillAngle = s.plant->restingAngle(after ? s.schedule.finalLevel() : s.schedule.initialLevel);
    return d;
}

struct WindowCase
{
    int window;
    double lineDelay;  // s
    const char* name;
};

const WindowCase kWindows[] = {{EXPOSURE_I, 1.0 / 30 / 480, "I"},
                               {EXPOSURE_III, 1.0 / 30 / 480, "III"},
                               {EXPOSURE_III, 0.0, "III global"}};

// The ranges: δt within ±2 ms, ωn ±5 %, ζ ±20 %, line delay ±10 %, one at a time and combined.
const Drift kDrifts[] = {{"none", 0, 1, 1, 1},
                         {"dt +2 ms", 2e-3, 1, 1, 1},
                         {"dt -2 ms", -2e-3, 1, 1, 1},
                         {"dt +0.7 ms", 0.7e-3, 1, 1, 1},
                         {"wn +5 %", 0, 1, 1.05, 1},
                         {"wn -5 %", 0, 1, 0.95, 1},
                         {"zeta +20 %", 0, 1, 1, 1.2},
                         {"zeta -20 %", 0, 1, 1, 0.8},
                         {"ld +10 %", 0, 1.1, 1, 1},
                         {"ld -10 %", 0, 0.9, 1, 1},
                         {"combined A", 1.2e-3, 0.93, 1.035, 1.15},
                         {"combined B", -1.5e-3, 1.06, 0.96, 0.88}};

//! Rows a window's figure is judged on: the most blurred third of a rolling window III frame, else all.
inline Range judgedRows(const SaccadeScene& s, const WindowCase& w, const RollingShutter& told)
{
    return w.window == EXPOSURE_III && w.lineDelay > 0 ? s.mostBlurredRows(told, 480 / 3) : Range(0, 480);
}


//! A frame in which something moves that the reference never saw: a bright bar streaked across it.
inline Mat withMovingObject(const Mat& frame)
{
    Mat linear, streak = Mat::zeros(frame.size(), CV_32FC3);
    srgbToLinear(frame, linear);
    rectangle(streak, Rect(frame.cols / 3, frame.rows / 2, frame.cols / 4, frame.rows / 6), Scalar::all(0.9), FILLED);
    blur(streak, streak, Size(41, 1));
    linear = max(linear, streak);
    Mat out;
    linearToSrgb(linear, out, CV_8U);
    return out;
}


/* The schedules the rejection tests tell a drifted frame instead of its own: the same one shifted
   by 10 ms, and another move's (6°). */
struct WrongSchedules
{
    explicit WrongSchedules(const SaccadeScene& s)
        : shifted(s.schedule), another(SwitchPlanner::create(s.plant, 16)->plan(0.0, 6 * kDeg, 0.0))
    {
        for (double& t : shifted.times)
            t += 0.010;
    }
    const Drift drift{"combined A", 1.2e-3, 0.93, 1.035, 1.15};
    SwitchSchedule shifted, another;
};

//! An 8-bit sRGB still moved by (dx, dy) pixels (a bumped camera), edges reflected.
inline Mat shifted(const Mat& still, double dx, double dy)
{
    const Matx23d move(1, 0, dx, 0, 1, dy);
    Mat out;
    warpAffine(still, out, move, still.size(), INTER_LINEAR, BORDER_REFLECT);
    return out;
}

//! An 8-bit sRGB still whose light is scaled by `gain` (the lighting changed, or the webcam's exposure).
inline Mat relit(const Mat& still, double gain)
{
    Mat linear, out;
    srgbToLinear(still, linear);
    linear = min(linear * gain, 1.0);
    linearToSrgb(linear, out, CV_8U);
    return out;
}

//! The schedule of the same move in the other direction.
inline SwitchSchedule otherSign(const SwitchSchedule& schedule)
{
    SwitchSchedule mirrored = schedule;
    for (int& level : mirrored.levels)
        level = -level;
    mirrored.initialLevel = -mirrored.initialLevel;
    return mirrored;
}

//! The same schedule `seconds` later.
inline SwitchSchedule late(const SwitchSchedule& schedule, double seconds)
{
    SwitchSchedule moved = schedule;
    for (double& t : moved.times)
        t += seconds;
    return moved;
}

//! A frame told a model that does not explain it: the schedule told, the frame and the still given.
struct WrongModel
{
    const char* name;
    SwitchSchedule schedule;
    Mat frame, still;
};

/* RefinementNeverWorse's eight wrong models of the drifted frame `d`: told another move, the move
   5, 10 or 20 ms late, or the move of the other sign; something moving in the frame; the still moved
   by 5 px or lit x0.8. `encode` takes each frame and still as the camera delivers it (a codec). */
inline std::vector<WrongModel> wrongModels(const SaccadeScene& s, const WrongSchedules& wrong, const DriftedFrame& d,
                                           const std::function<Mat(const Mat&)>& encode)
{
    const Mat frame = encode(d.frame), still = encode(d.still);
    return {{"another move (6 deg)", wrong.another, frame, still},
            {"5 ms late", late(s.schedule, 0.005), frame, still},
            {"10 ms late", late(s.schedule, 0.010), frame, still},
            {"20 ms late", late(s.schedule, 0.020), frame, still},
            {"the other sign", otherSign(s.schedule), frame, still},
            {"moving object", s.schedule, encode(withMovingObject(d.frame)), still},
            {"still shifted 5 px", s.schedule, frame, encode(shifted(d.still, 3, 4))},
            {"still lit x0.8", s.schedule, frame, encode(relit(d.still, 0.8))}};
}

}  // namespace dynblur_test

#endif
