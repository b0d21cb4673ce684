// SPDX-License-Identifier: Apache-2.0
// Mount: a chain of plant-driven axes, its orientation, pointing and the camera motion of one
// schedule per axis.
#include "precomp.hpp"

#include "motion/axis_chain_motion.hpp"
#include "motion/axis_rotation.hpp"
#include "motion/camera_motion.hpp"

#include "opencv2/dynblur/mount.hpp"

namespace cv {
namespace dynblur {

namespace {

struct Axis
{
    Vec3d unit;
    Ptr<Plant> plant;
    int minLevel, maxLevel;
    Vec2d angleRange;  // radians, (lowest, highest)
};

Matx33d chainOrientation(const std::vector<Axis>& axes, const std::vector<double>& angles)
{
    Matx33d q = Matx33d::eye();
    for (size_t i = 0; i < axes.size(); i++)
        q = q * axisRotation(axes[i].unit, angles[i]);
    return q;
}

//! The angle that turns `from` to `to` about the unit `axis`, both seen in the plane normal to it;
//! NaN when either lies along the axis (any angle does).
double angleAbout(const Vec3d& axis, const Vec3d& from, const Vec3d& to)
{
    const Vec3d f = from - axis * axis.dot(from), g = to - axis * axis.dot(to);
    if (norm(f) < 1e-12 || norm(g) < 1e-12)
        return std::numeric_limits<double>::quiet_NaN();
    return std::atan2(axis.dot(f.cross(g)), f.dot(g));
}

//! `angle` plus the whole turns that bring it nearest to `near` within `range`; NaN when no turn of it lies there.
double nearestWithin(double angle, double near, const Vec2d& range)
{
    const double turn = 2 * CV_PI;
    double best = std::numeric_limits<double>::quiet_NaN();
    const double k0 = std::round((near - angle) / turn);
    for (double k = k0 - 2; k <= k0 + 2; k++)
    {
        const double a = angle + k * turn;
        if (a >= range[0] - 1e-12 && a <= range[1] + 1e-12 && !(std::abs(a - near) >= std::abs(best - near)))
            best = a;
    }
    return best;
}

//! Q(t) = Q(q(t)) for a mount whose axes follow their schedules (Mount::motion).
class MountMotion CV_FINAL : public detail::AxisChainMotion
{
public:
    MountMotion(const std::vector<Axis>& axes, const std::vector<SwitchSchedule>& schedules)
        : axes_(axes), schedules_(schedules)
    {
    }
    Matx33d orientation(double t) const CV_OVERRIDE { return chainOrientation(axes_, jointAngles(t)); }
    Vec3d angularVelocity(double t) const CV_OVERRIDE
    {
        // ω = Σ (R_{i+1}⋯R_n)ᵀ aᵢ q̇ᵢ, the product built from the last axis back.
        Matx33d carried = Matx33d::eye();
        Vec3d omega(0, 0, 0);
        for (size_t i = axes_.size(); i-- > 0;)
        {
            const Plant& plant = *axes_[i].plant;
            omega += carried.t() * (axes_[i].unit * detail::sampleAt(&Plant::velocity, plant, schedules_[i], t));
            carried = axisRotation(axes_[i].unit, detail::sampleAt(&Plant::response, plant, schedules_[i], t)) * carried;
        }
        return omega;
    }
    Vec2d getTimeSpan() const CV_OVERRIDE
    {
        return Vec2d(-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
    }
    Matx33d referenceOrientation(double tRef, const RollingShutter&) const CV_OVERRIDE
    {
        if (std::isinf(tRef))
            CV_Error(Error::StsBadArg, "CameraMotion::referenceOrientation: tRef must be finite (seconds) or NaN "
                                       "(the mount's final rest)");
        return std::isnan(tRef) ? restOrientation(true) : orientation(tRef);
    }
    bool isPlantMotion() const CV_OVERRIDE { return false; }
    String getDefaultName() const CV_OVERRIDE { return "dynblur.CameraMotion.Mount"; }

    int axisCount() const CV_OVERRIDE { return int(axes_.size()); }
    Ptr<Plant> axisPlant(int axis) const CV_OVERRIDE { return axes_[size_t(axis)].plant; }
    const SwitchSchedule& axisSchedule(int axis) const CV_OVERRIDE { return schedules_[size_t(axis)]; }
    Ptr<CameraMotion> withPlants(const std::vector<Ptr<Plant>>& plants) const CV_OVERRIDE
    {
        std::vector<Axis> axes = axes_;
        for (size_t i = 0; i < axes.size(); i++)
            axes[i].plant = plants[i];
        return makePtr<MountMotion>(axes, schedules_);
    }
    Matx33d restOrientation(bool final) const CV_OVERRIDE
    {
        std::vector<double> rest(axes_.size());
        for (size_t i = 0; i < axes_.size(); i++)
            rest[i] = axes_[i].plant->restingAngle(final ? schedules_[i].finalLevel() : schedules_[i].initialLevel);
        return chainOrientation(axes_, rest);
    }

private:
    std::vector<double> jointAngles(double t) const
    {
        std::vector<double> q(axes_.size());
        for (size_t i = 0; i < axes_.size(); i++)
            q[i] = detail::sampleAt(&Plant::response, *axes_[i].plant, schedules_[i], t);
        return q;
    }

    std::vector<Axis> axes_;
    std::vector<SwitchSchedule> schedules_;
};

class MountImpl CV_FINAL : public Mount
{
public:
    void addAxis(const Vec3d& axis, const Ptr<Plant>& plant, int minLevel, int maxLevel) CV_OVERRIDE
    {
        const double length = norm(axis);
        if (!(length > 1e-12) || !std::isfinite(length))
            CV_Error_(Error::StsBadArg, ("Mount::addAxis: axis (%g, %g, %g) must be a finite non-zero vector (the "
                                         "rotation axis in the camera frame at rest)",
                                         axis[0], axis[1], axis[2]));
        if (plant.empty())
            CV_Error(Error::StsNullPtr, "Mount::addAxis: plant is empty");
        if (minLevel > maxLevel)
            CV_Error_(Error::StsBadArg,
                      ("Mount::addAxis: minLevel = %d must be <= maxLevel = %d (the actuator's levels)", minLevel,
                       maxLevel));
        const Vec3d unit = axis * (1 / length);
        for (size_t i = 0; i < axes_.size(); i++)
            if (norm(unit.cross(axes_[i].unit)) < 1e-6)  // sin of the angle between them
                CV_Error_(Error::StsBadArg,
                          ("Mount::addAxis: axis (%g, %g, %g) is parallel to axis %zu (%g, %g, %g) within 1e-6 rad; "
                           "the axes of a mount must differ in direction",
                           axis[0], axis[1], axis[2], i, axes_[i].unit[0], axes_[i].unit[1], axes_[i].unit[2]));
        const double a = plant->restingAngle(minLevel), b = plant->restingAngle(maxLevel);
        axes_.push_back(Axis{unit, plant, minLevel, maxLevel, Vec2d(std::min(a, b), std::max(a, b))});
    }
    int getAxisCount() const CV_OVERRIDE { return int(axes_.size()); }
    Vec3d getAxis(int index) const CV_OVERRIDE { return axisAt(index, "getAxis").unit; }
    Ptr<Plant> getPlant(int index) const CV_OVERRIDE { return axisAt(index, "getPlant").plant; }
    Vec2i getLevelRange(int index) const CV_OVERRIDE
    {
        const Axis& a = axisAt(index, "getLevelRange");
        return Vec2i(a.minLevel, a.maxLevel);
    }
    Vec2d getAngleRange(int index) const CV_OVERRIDE { return axisAt(index, "getAngleRange").angleRange; }

    Matx33d orientation(const std::vector<double>& angles) const CV_OVERRIDE
    {
        checkAngles(angles, "orientation", "angles");
        return chainOrientation(axes_, angles);
    }
    Vec3d pointing(const std::vector<double>& angles) const CV_OVERRIDE
    {
        checkAngles(angles, "pointing", "angles");
        return chainOrientation(axes_, angles) * Vec3d(0, 0, 1);
    }

    std::vector<double> anglesFor(const Vec3d& direction, const std::vector<double>& current) const CV_OVERRIDE
    {
        checkNotEmpty("anglesFor");
        const double length = norm(direction);
        if (!(length > 1e-12) || !std::isfinite(length))
            CV_Error_(Error::StsBadArg, ("Mount::anglesFor: direction (%g, %g, %g) must be a finite non-zero vector "
                                         "(where to point, in the base frame)",
                                         direction[0], direction[1], direction[2]));
        const std::vector<double> from = current.empty() ? std::vector<double>(axes_.size(), 0.0) : current;
        checkAngles(from, "anglesFor", "current");
        const Vec3d d = direction * (1 / length);
        // The optical axis as the axes beyond the first two carry it.
        Matx33d beyond = Matx33d::eye();
        for (size_t i = std::min<size_t>(2, axes_.size()); i < axes_.size(); i++)
            beyond = beyond * axisRotation(axes_[i].unit, from[i]);
        const Vec3d p = beyond * Vec3d(0, 0, 1);

        std::vector<std::vector<double>> candidates;
        const Vec3d a1 = axes_[0].unit;
        if (axes_.size() == 1)
        {
            // One axis: a turn about a₁ only (addAxis refuses a second axis parallel to it).
            std::vector<double> q = from;
            const double q1 = angleAbout(a1, p, d);
            q[0] = std::isnan(q1) ? from[0] : q1;
            if (norm(axisRotation(a1, q[0]) * p - d) <= 1e-6)
                candidates.push_back(q);
        }
        else
        {
            // c = R_{a₂}(q₂)·p = R_{a₁}(−q₁)·d lies on both circles: a₁·c = a₁·d, a₂·c = a₂·p, |c| = 1.
            const Vec3d a2 = axes_[1].unit, n = a1.cross(a2);
            const double k = a1.dot(a2), u = a1.dot(d), v = a2.dot(p), det = 1 - k * k;
            const double alpha = (u - k * v) / det, beta = (v - k * u) / det;
            const double gamma2 = (1 - alpha * alpha - beta * beta - 2 * alpha * beta * k) / n.dot(n);
            if (gamma2 > -1e-12)
                for (const double sign : {1.0, -1.0})
                {
                    const Vec3d c = alpha * a1 + beta * a2 + sign * std::sqrt(std::max(0.0, gamma2)) * n;
                    std::vector<double> q = from;
                    const double q2 = angleAbout(a2, p, c), q1 = angleAbout(a1, c, d);
                    q[1] = std::isnan(q2) ? from[1] : q2;
                    q[0] = std::isnan(q1) ? from[0] : q1;
                    candidates.push_back(q);
                }
        }
        std::vector<double> best;
        double bestDistance = std::numeric_limits<double>::infinity();
        for (std::vector<double>& q : candidates)
        {
            double distance = 0;
            for (size_t i = 0; i < std::min<size_t>(2, q.size()); i++)
            {
                q[i] = nearestWithin(q[i], from[i], axes_[i].angleRange);
                distance += std::abs(q[i] - from[i]);
            }
            if (distance < bestDistance)  // false for NaN: a solution out of reach
                best = q, bestDistance = distance;
        }
        if (best.empty())
        {
            String ranges;
            for (size_t i = 0; i < axes_.size(); i++)
                ranges += format("%saxis %zu: [%.4f, %.4f] rad (levels %d to %d)", i ? "; " : "", i,
                                 axes_[i].angleRange[0], axes_[i].angleRange[1], axes_[i].minLevel,
                                 axes_[i].maxLevel);
            CV_Error_(Error::StsOutOfRange,
                      ("Mount::anglesFor: no joint angles the axes reach point the optical axis along direction "
                       "(%.4f, %.4f, %.4f) (base frame); %s",
                       d[0], d[1], d[2], ranges.c_str()));
        }
        return best;
    }

    Ptr<CameraMotion> motion(const std::vector<SwitchSchedule>& schedules) const CV_OVERRIDE
    {
        checkNotEmpty("motion");
        if (schedules.size() != axes_.size())
            CV_Error_(Error::StsBadSize, ("Mount::motion: %zu schedules given for %zu axes (one per axis, base first)",
                                          schedules.size(), axes_.size()));
        for (size_t i = 0; i < axes_.size(); i++)
        {
            schedules[i].validate();
            std::vector<int> levels = schedules[i].levels;
            levels.push_back(schedules[i].initialLevel);
            for (int level : levels)
                if (level < axes_[i].minLevel || level > axes_[i].maxLevel)
                    CV_Error_(Error::StsOutOfRange,
                              ("Mount::motion: schedules[%zu] takes level %d, outside axis %zu's range [%d, %d]", i,
                               level, i, axes_[i].minLevel, axes_[i].maxLevel));
        }
        return makePtr<MountMotion>(axes_, schedules);
    }

    String getDefaultName() const CV_OVERRIDE { return "dynblur.Mount"; }

private:
    const Axis& axisAt(int index, const char* function) const
    {
        if (index < 0 || index >= int(axes_.size()))
            CV_Error_(Error::StsOutOfRange,
                      ("Mount::%s: index = %d must be in [0, %d) (the mount's axes)", function, index, int(axes_.size())));
        return axes_[size_t(index)];
    }
    void checkNotEmpty(const char* function) const
    {
        if (axes_.empty())
            CV_Error_(Error::StsBadArg, ("Mount::%s: the mount has no axis (add them with addAxis)", function));
    }
    void checkAngles(const std::vector<double>& angles, const char* function, const char* name) const
    {
        checkNotEmpty(function);
        if (angles.size() != axes_.size())
            CV_Error_(Error::StsBadSize, ("Mount::%s: %s has %zu values for %zu axes (one angle per axis, radians)",
                                          function, name, angles.size(), axes_.size()));
        for (size_t i = 0; i < angles.size(); i++)
            if (!std::isfinite(angles[i]))
                CV_Error_(Error::StsBadArg,
                          ("Mount::%s: %s[%zu] = %g must be finite (radians)", function, name, i, angles[i]));
    }

    std::vector<Axis> axes_;
};

}  // namespace

Ptr<Mount> Mount::create()
{
    return makePtr<MountImpl>();
}

}  // namespace dynblur
}  // namespace cv
