// SPDX-License-Identifier: Apache-2.0
#include "precomp.hpp"

#include "motion/half_shutter.hpp"
#include "motion/shutter_check.hpp"

namespace cv {
namespace dynblur {

//! The longest exposure, and the longest readout, a frame is believed to take (seconds).
static const double kMaxFrameSeconds = 1.0;

RollingShutter::RollingShutter(double frameStart_, double exposure_, double lineDelay_, int rows_)
    : frameStart(frameStart_), exposure(exposure_), lineDelay(lineDelay_), rows(rows_)
{
}

void detail::checkShutter(const RollingShutter& shutter, const char* where, const char* prefix, int imageRows)
{
    if (!std::isfinite(shutter.frameStart))
        CV_Error(Error::StsBadArg,
                 format("%s: %sframeStart = %g must be finite (seconds)", where, prefix, shutter.frameStart));
    if (!(std::isfinite(shutter.exposure) && shutter.exposure >= 0))
        CV_Error(Error::StsOutOfRange, format("%s: %sexposure = %g must be finite and >= 0 (seconds)", where, prefix,
                                              shutter.exposure));
    if (!(std::isfinite(shutter.lineDelay) && shutter.lineDelay >= 0))
        CV_Error(Error::StsOutOfRange,
                 format("%s: %slineDelay = %g must be finite and >= 0 (seconds; 0 = global shutter)", where, prefix,
                        shutter.lineDelay));
    if (shutter.rows <= 0)
        CV_Error(Error::StsOutOfRange, format("%s: %srows = %d must be > 0", where, prefix, shutter.rows));
    // A camera frame is exposed and read out within a second; more is a unit mistake (milliseconds or
    // microseconds where seconds are meant), which would otherwise cost minutes of kernels per frame.
    if (shutter.exposure > kMaxFrameSeconds)
        CV_Error(Error::StsOutOfRange,
                 format("%s: %sexposure = %g s is longer than %g s: seconds expected (is it in ms? 8 ms is 0.008)",
                        where, prefix, shutter.exposure, kMaxFrameSeconds));
    if ((shutter.rows - 1) * shutter.lineDelay > kMaxFrameSeconds)
        CV_Error(Error::StsOutOfRange,
                 format("%s: %slineDelay = %g s reads %d rows out in %g s, longer than %g s: seconds expected "
                        "(is it in us? 62.5 us is 62.5e-6)",
                        where, prefix, shutter.lineDelay, shutter.rows, (shutter.rows - 1) * shutter.lineDelay,
                        kMaxFrameSeconds));
    if (imageRows > 0 && shutter.rows != imageRows)
        CV_Error(Error::StsBadArg, format("%s: %srows = %d must equal the image's height %d", where, prefix,
                                          shutter.rows, imageRows));
}

void RollingShutter::validate() const
{
    detail::checkShutter(*this, "RollingShutter", "");
}

Vec2d RollingShutter::rowInterval(int row) const
{
    validate();
    if (row < 0 || row >= rows)
        CV_Error(Error::StsOutOfRange, format("RollingShutter::rowInterval: row = %d is outside [0, %d]", row, rows - 1));
    return intervalAt(row);
}

Vec2d RollingShutter::intervalAt(double row) const
{
    const double start = frameStart + row * lineDelay;
    return Vec2d(start, start + exposure);
}

Range RollingShutter::rowsOverlapping(double start, double end) const
{
    if (!(lineDelay > 0))
        return Range(0, rows);
    // row r starts at frameStart + r·lineDelay and ends exposure later
    const int first = std::max(0, (int)std::floor((start - exposure - frameStart) / lineDelay));
    const int last = std::min(rows - 1, (int)std::ceil((end - frameStart) / lineDelay));
    return Range(first, last + 1);
}

Vec2d RollingShutter::readoutInterval() const
{
    validate();
    return Vec2d(frameStart, intervalAt(rows - 1)[1]);
}

int classifyExposure(const Ptr<Plant>& plant, const SwitchSchedule& schedule, const RollingShutter& shutter,
                     double angleTol, double velocityTol)
{
    CV_Assert(!plant.empty() && "classifyExposure: 'plant' is null");
    shutter.validate();
    if (!(angleTol > 0 && std::isfinite(angleTol)))
        CV_Error(Error::StsOutOfRange, format("classifyExposure: angleTol = %g must be finite and > 0 (radians)", angleTol));
    if (!(velocityTol > 0 && std::isfinite(velocityTol)))
        CV_Error(Error::StsOutOfRange,
                 format("classifyExposure: velocityTol = %g must be finite and > 0 (rad/s)", velocityTol));
    if (schedule.times.empty() && schedule.levels.empty())
        return EXPOSURE_IV;
    schedule.validate();

    const Vec2d readout = shutter.readoutInterval();
    const double firstSwitch = schedule.times.front();
    if (readout[1] < firstSwitch)
        return EXPOSURE_IV;  // the whole readout happens before the move starts

    // Sample the part of the readout after the first switch finely enough (1/100 of a natural
    // period) that no swing through the tolerance band is missed.
    const double from = std::max(readout[0], firstSwitch);
    const double step = 1.0 / (100.0 * plant->getNaturalFreqHz());
    const int samples = std::max(2, static_cast<int>(std::ceil((readout[1] - from) / step)) + 1);
    Mat t(1, samples, CV_64F);
    for (int i = 0; i < samples; ++i)
        t.at<double>(i) = samples == 1 ? from : from + (readout[1] - from) * i / (samples - 1);
    Mat theta, omega;
    plant->response(schedule, t, theta);
    plant->velocity(schedule, t, omega);
    /* Still means at rest at the final angle, or at the level in force: a recording's schedule holds
       the earlier moves of its log, and the plant rests between them. A shaped move may reach its
       final angle before its last switch; it is still there, as a single move's frames always were. */
    const double finalAngle = plant->restingAngle(schedule.finalLevel());
    auto moving = [&](int i) {
        const double angle = theta.at<double>(i);
        const bool atRest = std::abs(angle - finalAngle) <= angleTol ||
                            std::abs(angle - plant->restingAngle(schedule.levelAt(t.at<double>(i)))) <= angleTol;
        return !atRest || std::abs(omega.at<double>(i)) > velocityTol;
    };

    bool movingAnywhere = false;
    for (int i = 0; i < samples && !movingAnywhere; ++i)
        movingAnywhere = moving(i);
    if (!movingAnywhere)
        return EXPOSURE_IV;
    const bool movingAtStart = readout[0] >= firstSwitch && moving(0);
    const bool movingAtEnd = moving(samples - 1);
    if (movingAtStart)
        return movingAtEnd ? EXPOSURE_II : EXPOSURE_III;
    return EXPOSURE_I;
}

namespace detail {

RollingShutter halfResolutionShutter(const RollingShutter& shutter)
{
    CV_Assert(shutter.rows % 2 == 0);
    return RollingShutter(shutter.frameStart + shutter.lineDelay / 2, shutter.exposure, 2 * shutter.lineDelay,
                          shutter.rows / 2);
}

}  // namespace detail

}  // namespace dynblur
}  // namespace cv
