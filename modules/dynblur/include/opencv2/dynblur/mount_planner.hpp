// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_MOUNT_PLANNER_HPP
#define OPENCV_DYNBLUR_MOUNT_PLANNER_HPP

#include <opencv2/core.hpp>
#include <opencv2/dynblur/camera.hpp>
#include <opencv2/dynblur/mount.hpp>
#include <opencv2/dynblur/planner.hpp>
#include <opencv2/dynblur/schedule.hpp>

#include <vector>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_motion
//! @{

//! How the axes of a mount share a move.
enum MountCoordination
{
    MOUNT_COORDINATED = 0,  //!< the axes arrive together along a near-straight path (the default)
    MOUNT_INDEPENDENT = 1   //!< each axis as fast as it can on its own
};

/** @brief A planned move of every axis of a mount and what it does to the camera. Times are
seconds from the plan's startTime. */
struct CV_EXPORTS_W_SIMPLE MountMove
{
    CV_WRAP MountMove();

    CV_PROP_RW std::vector<SwitchSchedule> schedules;  //!< one per axis, base first (empty: the axis holds)
    CV_PROP_RW std::vector<double> fromAngles;         //!< the joint angles held at the start, rad (levels' rests)
    CV_PROP_RW std::vector<double> toAngles;           //!< the joint angles at the end, rad (levels' rests)
    CV_PROP_RW std::vector<double> axisSettleTimes;    //!< each axis's settle time into its band, s
    CV_PROP_RW std::vector<double> residualVibration;  //!< each axis's residual vibration, fraction of its move
    CV_PROP_RW double settleTime;      //!< the whole move's: the last axis settled, s
    CV_PROP_RW double peakRate;        //!< peak |ω| of the camera from the chain, rad/s
    CV_PROP_RW double pathDeviation;   //!< largest angle between the optical axis and the great circle
                                       //!< through its start and end directions, rad (0: a straight image path)
};

/** @brief Plans a move of every axis of a Mount: from the angles held to target angles, to a
direction, or to a pixel.

Each axis is one SwitchPlanner's problem (integer levels, free switching instants that cancel the
residual vibration, @cite Singer1990Preshaping). Planned independently (MOUNT_INDEPENDENT), a small
move on one axis ends long before a large one on another: the optical axis first runs along the
short axis, then along the long one (a bent path in the image), and the frames in between are
blurred along a direction that changes.

Coordinated (MOUNT_COORDINATED, the default) the axis whose own fastest move settles last leads: its
plan is SwitchPlanner's. Every other axis f follows the leader's motion scaled to its move,
q_f*(t) = q_f(0) + r·(q_L(t) − q_L(0)) with r = Δq_f/Δq_L, which keeps the optical axis on the great
circle between its end directions (a straight line in the image) for axes of one plant. Levels are
integers, so q_f* cannot be met exactly: among the schedules of the follower's plant with the same
number of switches as the leader's, levels within 2 of the leader's levels scaled by r, and instants
solved to cancel the follower's own vibration (and its ωn-derivative in robust mode), each started
at once or delayed by up to the time it would settle before the leader, the planner takes the one
nearest q_f* at every instant (the largest distance over the move) among those that settle no later
than the leader. A faster axis thus starts later and ends with the leader. The follower's own fastest
plan is always a candidate, so coordination never bends the path more than independent planning
does, and the whole move settles when the leader does. Scaling the leader's instants would need
fractional levels, and stretching a lower-level plan in time would leave vibration; the phasor solve
keeps both integer levels and zero vibration.

The levels an axis's planner uses are symmetric: ±min(−minLevel, maxLevel) of its range.
*/
class CV_EXPORTS_W MountPlanner : public Algorithm
{
public:
    /** @param mount the mount to plan for (its plants' nominal ωn, ζ and gains are used); every axis's
           level range must hold [−1, 1].
        @param mode PLAN_FAST or PLAN_ROBUST, for every axis (SwitchPlanner's modes).
        @param minDwell shortest time between two switches of an axis, seconds, ≥ 0.
        @param coordination MOUNT_COORDINATED or MOUNT_INDEPENDENT. */
    CV_WRAP static Ptr<MountPlanner> create(const Ptr<Mount>& mount, int mode = PLAN_FAST, double minDwell = 0.002,
                                            int coordination = MOUNT_COORDINATED);

    /** @brief Plans the move from `fromAngles` to `toAngles`.
    @param fromAngles the joint angles held, radians, one per axis, each within its axis's range.
    @param toAngles the target joint angles, radians, one per axis, each within its axis's range
           (rounded to the nearest level).
    @param startTime the time of the first switch, seconds (camera clock).
    @return the schedules and the report. */
    CV_WRAP virtual MountMove plan(const std::vector<double>& fromAngles, const std::vector<double>& toAngles,
                                   double startTime = 0.0) const = 0;

    /** @brief Plans the move that points the optical axis along `direction` (Mount::anglesFor).
    @param direction where to point, in the mount's base frame; finite and non-zero.
    @param fromAngles the joint angles held, radians, one per axis.
    @param startTime the time of the first switch, seconds. */
    CV_WRAP virtual MountMove planToDirection(const Vec3d& direction, const std::vector<double>& fromAngles,
                                              double startTime = 0.0) const = 0;

    /** @brief Plans the move that brings the scene point seen now at `pixel` to the optical axis
    (the ray through the pixel, undistorted with the camera's model, becomes the new pointing).
    @param camera the camera on the mount.
    @param pixel where the target is in the current image, pixels.
    @param fromAngles the joint angles held, radians, one per axis.
    @param startTime the time of the first switch, seconds. */
    CV_WRAP virtual MountMove planToPixel(const Ptr<CameraModel>& camera, const Point2d& pixel,
                                          const std::vector<double>& fromAngles, double startTime = 0.0) const = 0;

    /** @brief The mount planned for. */
    CV_WRAP virtual Ptr<Mount> getMount() const = 0;
    /** @brief PLAN_FAST or PLAN_ROBUST. */
    CV_WRAP virtual int getMode() const = 0;
    /** @brief Shortest time between two switches of an axis, seconds. */
    CV_WRAP virtual double getMinDwell() const = 0;
    /** @brief MOUNT_COORDINATED or MOUNT_INDEPENDENT. */
    CV_WRAP virtual int getCoordination() const = 0;
};

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
