// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_MOUNT_HPP
#define OPENCV_DYNBLUR_MOUNT_HPP

#include <opencv2/core.hpp>
#include <opencv2/dynblur/camera_motion.hpp>
#include <opencv2/dynblur/plant.hpp>
#include <opencv2/dynblur/schedule.hpp>

#include <vector>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_motion
//! @{

/** @brief A chain of rotation axes, each turned by its own plant: a pan-tilt head, a gimbal, an
eye-in-hand wrist.

The axes are unit vectors in the camera frame at rest (x right, y down, z forward), listed from the
base: the first carries the second, which carries the third (pan carries tilt carries roll). With
joint angles q₁, q₂, … the camera's orientation in the base frame is
\f[Q(q) = R_{a_1}(q_1)\,R_{a_2}(q_2)\cdots\f]
(DESIGN §2, Rotation), and during a move each qᵢ(t) is its plant's response to its own schedule,
all on the camera's clock. The body rates follow from the chain,
\f[\omega = \sum_i (R_{a_{i+1}}\cdots R_{a_n})^\top a_i\,\dot q_i ,\f]
so motion() is exact at every instant, as CameraMotion::fromPlant is for one axis. An axis reaches the
angles its levels do: gain × [minLevel, maxLevel].

Pointing: pointing() is the optical axis Q(q)·(0, 0, 1) in the base frame; anglesFor() inverts it for the
first two axes (a pan and a tilt), the others held. Plan each axis's move from the angles it holds
to the ones anglesFor() returns with a SwitchPlanner for its plant.
*/
class CV_EXPORTS_W Mount : public Algorithm
{
public:
    /** @brief An empty chain: add its axes with addAxis(), base first. */
    CV_WRAP static Ptr<Mount> create();

    /** @brief Appends an axis carried by the previous ones.
    @param axis the rotation axis in the camera frame at rest, finite and non-zero (normalised);
           e.g. (0, 1, 0) pans, (1, 0, 0) tilts, (0, 0, 1) rolls. It must not be parallel (or
           antiparallel) to an axis already added, within 1e-6 rad: two such axes turn the camera
           alike, so no angle would tell them apart.
    @param plant the axis's positioner: its response to the axis's schedule is the joint angle,
           radians (positive turns right-handed about `axis`).
    @param minLevel the lowest level the axis's actuator takes.
    @param maxLevel the highest, ≥ minLevel. */
    CV_WRAP virtual void addAxis(const Vec3d& axis, const Ptr<Plant>& plant, int minLevel, int maxLevel) = 0;

    /** @brief Writes the mount as a parameter file (flat YAML, XML or JSON by the extension, as
    cv::FileStorage writes): `axisCount`, then per axis i `axis<i>` ([x, y, z], unit, camera frame
    at rest), `axis<i>_naturalFreqHz` (Hz), `axis<i>_dampingRatio`, `axis<i>_gain` (rad per level)
    and `axis<i>_levels` ([min, max]). Written beside the target and renamed over it, so no reader
    sees half a file. Every axis's plant must be the linear second-order one of Plant::create (an
    OdePlant's dynamics have no file form).
    @param filename the file to write. */
    CV_WRAP void save(const String& filename) const CV_OVERRIDE;

    /** @brief Reads a mount written by save(), with ParameterFile (never cv::FileStorage's reader).
    Refuses, naming the file and the entry: a missing or malformed entry, an axis whose norm is off 1
    by more than 1e-6, two parallel axes, a level range upside down, a plant parameter out of
    Plant::create's range, and an `axisCount` that does not match the `axis<i>` entries.
    @param filename the file to read. */
    CV_WRAP static Ptr<Mount> load(const String& filename);

    /** @brief The number of axes. */
    CV_WRAP virtual int getAxisCount() const = 0;
    /** @brief The unit axis `index` (0 = base) in the camera frame at rest.
    @param index 0 ≤ index < getAxisCount(). */
    CV_WRAP virtual Vec3d getAxis(int index) const = 0;
    /** @brief The plant of axis `index`.
    @param index 0 ≤ index < getAxisCount(). */
    CV_WRAP virtual Ptr<Plant> getPlant(int index) const = 0;
    /** @brief The levels axis `index` takes, (minLevel, maxLevel).
    @param index 0 ≤ index < getAxisCount(). */
    CV_WRAP virtual Vec2i getLevelRange(int index) const = 0;
    /** @brief The joint angles axis `index` reaches, radians (lowest, highest): its plant's resting
    angles at the two ends of its level range.
    @param index 0 ≤ index < getAxisCount(). */
    CV_WRAP virtual Vec2d getAngleRange(int index) const = 0;

    /** @brief Q(q) = R_{a₁}(q₁)·R_{a₂}(q₂)⋯, the camera frame in the base frame.
    @param angles one joint angle per axis, radians. */
    CV_WRAP virtual Matx33d orientation(const std::vector<double>& angles) const = 0;

    /** @brief The optical axis Q(q)·(0, 0, 1) in the base frame, a unit vector.
    @param angles one joint angle per axis, radians. */
    CV_WRAP virtual Vec3d pointing(const std::vector<double>& angles) const = 0;

    /** @brief The joint angles that point the optical axis along `direction`.

    The first two axes are solved in closed form (two rotations that take one vector to another,
    as a pan and a tilt do; there are at most two solutions), the others keep their angles from
    `current`. Of the solutions whose angles every axis reaches (getAngleRange), the one nearest to
    `current` is returned. A chain of one axis points only along a cone: the solution is the angle
    that comes nearest, and `direction` must lie on the cone within 1e-6 rad.
    @param direction where to point, in the base frame; finite and non-zero (normalised).
    @param current the angles held now, radians, one per axis; empty: all 0.
    @return one angle per axis, radians. Throws cv::Exception naming the direction and the axes'
            ranges when no reachable solution points there. */
    CV_WRAP virtual std::vector<double> anglesFor(const Vec3d& direction,
                                                  const std::vector<double>& current = std::vector<double>()) const = 0;

    /** @brief The camera's motion while each axis follows its own schedule (times on the camera's
    clock): Q(t) = Q(q(t)) with qᵢ(t) plant i's response, exact at every instant. The reference view
    for a NaN tRef (CameraMotion::referenceOrientation) is the chain at every axis's final resting
    angle. Pipelines take the general (3-axis) path for it; a one-axis mount's motion is the same
    rotation as CameraMotion::fromPlant's, which takes the one-axis path.
    @param schedules one schedule per axis, levels within each axis's range. */
    CV_WRAP virtual Ptr<CameraMotion> motion(const std::vector<SwitchSchedule>& schedules) const = 0;
};

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
