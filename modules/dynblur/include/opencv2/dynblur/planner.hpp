// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_PLANNER_HPP
#define OPENCV_DYNBLUR_PLANNER_HPP

#include <opencv2/dynblur/plant.hpp>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_motion
//! @{

//! What the planner optimises for.
enum PlannerMode
{
    PLAN_FAST = 0,    //!< shortest settle time; vibration cancelled at the nominal plant
    PLAN_ROBUST = 1   //!< also insensitive to an error in ωn (zero derivative of the vibration)
};

/** @brief Plans point-to-point moves as integer-level switching schedules that leave no
residual vibration.

The actuator can only hold integer levels, so amplitudes are fixed integers and the switching
instants are the unknowns: the steps are phasors \f$a_i e^{(\sigma + j\omega_d) t_i}\f$ and the
instants are solved so that they close into a polygon (zero residual vibration,
@cite Singer1990Preshaping), which rounding a ZV/ZVD shaper's amplitudes to integers cannot do.
Robust mode also zeroes the derivative with respect to ωn. Levels may overshoot the target
(and pass through 0): that buys speed. A minimum dwell between switches and the level limits are
hard constraints.
*/
class CV_EXPORTS_W SwitchPlanner : public Algorithm
{
public:
    /** @param plant the plant to plan for (its nominal ωn, ζ and gain are used).
        @param maxLevel largest |level|, cells, ≥ 1 (seed: 16 cells).
        @param mode PLAN_FAST or PLAN_ROBUST.
        @param minDwell shortest time between two switches, seconds, ≥ 0 (default 2 ms). */
    CV_WRAP static Ptr<SwitchPlanner> create(const Ptr<Plant>& plant, int maxLevel = 16,
                                             int mode = PLAN_FAST, double minDwell = 0.002);

    /** @brief Plans a move.
    @param fromAngle start angle, radians; rounded to the nearest level, which must lie in
           [-maxLevel, maxLevel].
    @param toAngle target angle, radians; rounded to the nearest level in [-maxLevel, maxLevel].
    @param startTime time of the first switch, seconds.
    @return the schedule with settleTime, peakVelocity and residualVibration filled in
            (predicted on the planner's plant). A zero move returns an empty schedule at the
            start level. */
    CV_WRAP virtual SwitchSchedule plan(double fromAngle, double toAngle, double startTime = 0.0) const = 0;

    CV_WRAP virtual int getMaxLevel() const = 0;
    CV_WRAP virtual void setMaxLevel(int maxLevel) = 0;
    CV_WRAP virtual int getMode() const = 0;
    CV_WRAP virtual void setMode(int mode) = 0;
    /** @brief Minimum dwell between switches, seconds. */
    CV_WRAP virtual double getMinDwell() const = 0;
    CV_WRAP virtual void setMinDwell(double minDwell) = 0;
    /** @brief Half-width of the band that defines the settle time, fraction of the move
    (default 0.02). */
    CV_WRAP virtual double getSettleBand() const = 0;
    CV_WRAP virtual void setSettleBand(double band) = 0;
    /** @brief Relative ωn error robust mode is designed for (default 0.10 = ±10%). */
    CV_WRAP virtual double getRobustRange() const = 0;
    CV_WRAP virtual void setRobustRange(double range) = 0;
    /** @brief Largest residual vibration, fraction of the move, a robust plan may leave anywhere
    in the robust range (default 0.025). A zero ωn-derivative alone does not bound the vibration at
    ±10%: aggressive schedules curve faster, so every robust candidate is checked against this. */
    CV_WRAP virtual double getRobustTolerance() const = 0;
    CV_WRAP virtual void setRobustTolerance(double tolerance) = 0;
    CV_WRAP virtual Ptr<Plant> getPlant() const = 0;
};

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
