// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_SCHEDULE_HPP
#define OPENCV_DYNBLUR_SCHEDULE_HPP

#include <opencv2/core.hpp>

#include <vector>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_motion
//! @{

/** @brief A staircase command: integer actuator levels switched at chosen instants.

The level `levels[i]` is held from `times[i]` to `times[i+1]` (the last one forever). Before
`times[0]` the level `initialLevel` is in force and the plant rests at `gain * initialLevel`.
One level is one active piezoelectric cell @cite DynblurSeed.

The planner fills the three reported figures; they are NaN for a hand-made schedule.
*/
struct CV_EXPORTS_W_SIMPLE SwitchSchedule
{
    CV_WRAP SwitchSchedule();
    /** @param times switching instants, seconds, strictly increasing.
        @param levels level switched on at each instant (cells), same length as times.
        @param initialLevel level in force before times[0] (cells). */
    CV_WRAP SwitchSchedule(const std::vector<double>& times, const std::vector<int>& levels,
                           int initialLevel = 0);

    CV_PROP_RW std::vector<double> times;   //!< switching instants, seconds, strictly increasing
    CV_PROP_RW std::vector<int> levels;     //!< level from each instant on, cells
    CV_PROP_RW int initialLevel;            //!< level before times[0], cells
    CV_PROP_RW double settleTime;           //!< predicted time from times[0] until the angle stays in the settle band, seconds
    CV_PROP_RW double peakVelocity;         //!< predicted peak |dθ/dt|, rad/s
    CV_PROP_RW double residualVibration;    //!< vibration left after the last switch, fraction of the move

    /** @brief Level in force after the last switch (initialLevel when the schedule is empty). */
    CV_WRAP int finalLevel() const;
    /** @brief Level in force at time t, seconds. */
    CV_WRAP int levelAt(double t) const;

    /** @brief Throws cv::Exception naming the offending field when the schedule is malformed:
    empty, lengths differ, non-finite or non-increasing times, or a level outside
    [-maxLevel, maxLevel].
    @param maxLevel largest allowed |level|, cells. */
    CV_WRAP void validate(int maxLevel = 1 << 20) const;

    /** @brief Writes the schedule to a cv::FileStorage file (YAML, XML or JSON by extension). */
    CV_WRAP void save(const String& filename) const;
    /** @brief Reads a schedule written by save(); checks it with validate(). */
    CV_WRAP static SwitchSchedule load(const String& filename);
};

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
