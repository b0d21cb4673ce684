// SPDX-License-Identifier: Apache-2.0
// MountPlanner's coordination: an axis's schedule that follows a leading axis's motion scaled to
// its own move (mount_planner.hpp explains why).
#ifndef OPENCV_DYNBLUR_COORDINATED_AXIS_HPP
#define OPENCV_DYNBLUR_COORDINATED_AXIS_HPP

#include "opencv2/dynblur/planner.hpp"

namespace cv {
namespace dynblur {

/** The schedule of `planner`'s plant from `own`'s initial level to its final level that stays
nearest, at every instant, to the leader's motion scaled to this move, among the integer-level
schedules of the same number of switches as the leader's whose instants cancel the vibration (robust
in robust mode), started at once or delayed, that settle no later than the leader. `own` (the axis's own
plan, which must move) is a candidate, so the result is never farther from the scaled motion than it is.
@param planner the axis's planner (plant, level cap, mode, dwell, band, robustness).
@param own the axis's own plan of the move, starting with the leader's first switch.
@param leader the leading axis's plan, settleTime filled in.
@param leaderPlant the leading axis's plant. */
SwitchSchedule followLeader(const SwitchPlanner& planner, const SwitchSchedule& own, const SwitchSchedule& leader,
                            const Plant& leaderPlant);

}  // namespace dynblur
}  // namespace cv

#endif
