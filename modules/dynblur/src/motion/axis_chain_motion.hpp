// SPDX-License-Identifier: Apache-2.0
// Private: a mount's CameraMotion (Mount::motion) as the refinement sees it: its axes' plants and
// schedules, which a correction scales axis by axis.
#ifndef OPENCV_DYNBLUR_MOTION_AXIS_CHAIN_MOTION_HPP
#define OPENCV_DYNBLUR_MOTION_AXIS_CHAIN_MOTION_HPP

#include "opencv2/dynblur/camera_motion.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief Q(t) = R_{a₁}(q₁(t))·R_{a₂}(q₂(t))⋯ with each qᵢ a plant's response to its own schedule
(Mount::motion): the pipelines recognise it to treat a mount as plant-driven (its stills at rest, its
plants refined) rather than as a measured motion. */
class AxisChainMotion : public CameraMotion
{
public:
    //! The number of axes, base first.
    virtual int axisCount() const = 0;
    //! The plant of axis `axis` (0 ≤ axis < axisCount()).
    virtual Ptr<Plant> axisPlant(int axis) const = 0;
    //! The schedule axis `axis` follows.
    virtual const SwitchSchedule& axisSchedule(int axis) const = 0;
    //! The same chain and schedules with axis i driven by plants[i] (one per axis).
    virtual Ptr<CameraMotion> withPlants(const std::vector<Ptr<Plant>>& plants) const = 0;
    /** The chain at every axis's resting angle before the move (initial levels; `final` false) or
        after it (final levels): where the mount's stills are taken. Only the gains decide it. */
    virtual Matx33d restOrientation(bool final) const = 0;

    //! Whether axis `axis` moves: its schedule switches to a level other than its initial one.
    bool axisMoves(int axis) const
    {
        const SwitchSchedule& s = axisSchedule(axis);
        for (int level : s.levels)
            if (level != s.initialLevel)
                return true;
        return false;
    }
};

//! The motion as an AxisChainMotion (a mount's), or null when it is not one.
inline const AxisChainMotion* asAxisChainMotion(const CameraMotion& motion)
{
    return dynamic_cast<const AxisChainMotion*>(&motion);
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
