// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_SHUTTER_HPP
#define OPENCV_DYNBLUR_SHUTTER_HPP

#include <opencv2/dynblur/plant.hpp>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_motion
//! @{

/** @brief When each sensor row integrates light.

Row r integrates over [frameStart + r·lineDelay, frameStart + r·lineDelay + exposure]
(seconds, the schedule's clock) @cite Meingast2005Rolling. lineDelay = 0 is a global shutter.
*/
struct CV_EXPORTS_W_SIMPLE RollingShutter
{
    /** @param frameStart start of row 0's exposure, seconds.
        @param exposure exposure of each row, seconds, in [0, 1] (more is taken for milliseconds).
        @param lineDelay delay between the starts of two consecutive rows, seconds, ≥ 0, with the
        readout (rows − 1)·lineDelay at most 1 s (more is taken for microseconds).
        @param rows number of sensor rows, > 0. */
    CV_WRAP RollingShutter(double frameStart = 0.0, double exposure = 0.008, double lineDelay = 0.0,
                           int rows = 1);

    CV_PROP_RW double frameStart;  //!< start of row 0's exposure, seconds
    CV_PROP_RW double exposure;    //!< exposure of one row, seconds
    CV_PROP_RW double lineDelay;   //!< row-to-row readout delay, seconds (0: global shutter)
    CV_PROP_RW int rows;           //!< number of sensor rows

    /** @brief Exposure interval of row r (start, end), seconds. @param row 0 ≤ row < rows. */
    CV_WRAP Vec2d rowInterval(int row) const;
    /** @brief Exposure interval (start, end), seconds, of the sensor position `row` rows below row
    0: start = frameStart + row·lineDelay, end = start + exposure. Unlike rowInterval() it takes a
    fractional position (a band's centre row) and checks nothing, for loops over a shutter already
    validated. @param row position down the sensor, rows (pixels). */
    CV_WRAP Vec2d intervalAt(double row) const;
    /** @brief The rows whose exposure may overlap the time span [start, end] (seconds): every row
    that does, plus at most one more at each end (all rows for a global shutter). Checks nothing,
    as intervalAt(). @param start, end the span, seconds. */
    Range rowsOverlapping(double start, double end) const;
    /** @brief Start of the first row's exposure and end of the last one's, seconds. */
    CV_WRAP Vec2d readoutInterval() const;
    /** @brief Throws cv::Exception naming the field when a value is out of range (an exposure or a
    readout over 1 s with a hint at the unit). */
    CV_WRAP void validate() const;
};

//! Exposure windows of the seed's Fig. 5, generalised to the whole frame readout.
enum ExposureWindow
{
    EXPOSURE_I = 1,    //!< still at the start of the readout, moving later
    EXPOSURE_II = 2,   //!< moving at the start and at the end
    EXPOSURE_III = 3,  //!< moving at the start, still before the end (the seed's case)
    EXPOSURE_IV = 4    //!< still throughout
};

/** @brief Which exposure window a frame falls in (DESIGN §2) @cite DynblurSeed.

"Moving" at time t means: t is at or after the schedule's first switch and
|dθ/dt| > velocityTol, or θ(t) farther than angleTol from both θ_final and θ_rest(t), the resting
angle of the level in force at t (a schedule that holds earlier moves, as a recording's does, rests
between them). Before the first switch the plant rests.
A move that starts and ends inside one readout is window I.
@param plant the plant.
@param schedule the command (may be empty: still throughout).
@param shutter the frame's timing.
@param angleTol angle tolerance, radians, > 0 (default 2e-4 rad ≈ 0.25 px at fx = 1230 px).
@param velocityTol velocity tolerance, rad/s, > 0 (default 0.02 rad/s ≈ 0.2 px over 8 ms).
*/
CV_EXPORTS_W int classifyExposure(const Ptr<Plant>& plant, const SwitchSchedule& schedule,
                                  const RollingShutter& shutter, double angleTol = 2e-4,
                                  double velocityTol = 0.02);

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
