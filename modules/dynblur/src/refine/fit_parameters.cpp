// SPDX-License-Identifier: Apache-2.0
// The fit parameters' table read as vectors, flags and messages; refinementParameters() for callers.
#include "precomp.hpp"

#include "refine/fit_parameters.hpp"

namespace cv {
namespace dynblur {
namespace detail {

FitVector toFitUnits(const MotionCorrection& c)
{
    FitVector q;
    for (int j = 0; j < kFitParameters; j++)
    {
        const FitParameter& p = kFitTable[j];
        const double value = p.get(c);
        q[j] = (p.quantity == FIT_SCALE ? value - 1 : value) / p.unit;  // a scale: its departure from 1
    }
    return q;
}

MotionCorrection fromFitUnits(const FitVector& q, const MotionCorrection& like)
{
    MotionCorrection c = like;
    for (int j = 0; j < kFitParameters; j++)
    {
        const FitParameter& p = kFitTable[j];
        const double value = q[j] * p.unit;
        p.set(c, p.quantity == FIT_SCALE ? 1 + value : value);
    }
    return c;
}

std::vector<int> flaggedParameters(int flags, int motion, bool rolling, int axes)
{
    std::vector<int> active;
    for (int j = 0; j < kFitParameters; j++)
    {
        const FitParameter& p = kFitTable[j];
        if ((flags & p.flag) && (p.motions & motion) && (rolling || !p.rollingOnly) && p.axis < axes)
            active.push_back(j);
    }
    return active;
}

int flagsOfParameters(int bits)
{
    int flags = 0;
    for (int j = 0; j < kFitParameters; j++)
        if (bits & (1 << j))
            flags |= kFitTable[j].flag;
    return flags;
}

int allRefinementFlags()
{
    return refinementFlagsFor(FIT_ANY_MOTION);
}

int refinementFlagsFor(int motion)
{
    int flags = 0;
    for (const FitParameter& p : kFitTable)
        if (p.motions & motion)
            flags |= p.flag;
    return flags;
}

namespace {

//! One value per flag among `flags`, in the table's order, as `text` gives it for the flag's first parameter.
std::vector<String> perFlag(int flags, String (*text)(const FitParameter&))
{
    std::vector<String> items;
    int seen = 0;
    for (const FitParameter& p : kFitTable)
        if ((flags & p.flag) && !(seen & p.flag))
            items.push_back(text(p)), seen |= p.flag;
    return items;
}

//! "a, b and c".
String joined(const std::vector<String>& items)
{
    String text;
    for (size_t k = 0; k < items.size(); k++)
        text += (k == 0 ? "" : k + 1 == items.size() ? " and " : ", ") + items[k];
    return text;
}

}  // namespace

String refinementFlagNames(int flags)
{
    return joined(perFlag(flags, [](const FitParameter& p) { return String(p.group); }));
}

String refinementFlagList(int flags)
{
    return joined(perFlag(flags, [](const FitParameter& p) { return format("%s (%d)", p.flagName, p.flag); }));
}

String parameterNames(int bits)
{
    std::vector<String> names;
    for (int j = 0; j < kFitParameters; j++)
        if (bits & (1 << j))
            names.push_back(kFitTable[j].name);
    return joined(names);
}

String pinnedNote(int j, double value, double start, double maxTimeOffset)
{
    const FitParameter& p = kFitTable[j];
    const double bound = p.searchHalfWidth * p.unit;
    switch (p.quantity)
    {
    case FIT_CLOCK_OFFSET:
        return format("%s %+.2f ms at its search bound (%.2f ms either side of %+.2f ms)", p.name, value * 1e3,
                      maxTimeOffset * 1e3, start * 1e3);
    case FIT_SCALE:
        return format("%s x%.3f at its search bound (x%.2f to x%.2f)", p.name, value, 1 - bound, 1 + bound);
    default:
        return format("%s %+.2f deg/s at its search bound (%.2f deg/s either side of 0)", p.name,
                      value * 180 / CV_PI, bound * 180 / CV_PI);
    }
}

}  // namespace detail

RefinementParameter::RefinementParameter()
    : flag(0), searchHalfWidth(0), plantMotion(false), mountMotion(false), measuredMotion(false), mountAxis(-1),
      rollingShutterOnly(false), inRefineAll(false)
{
}

std::vector<RefinementParameter> refinementParameters()
{
    std::vector<RefinementParameter> parameters;
    for (const detail::FitParameter& p : detail::kFitTable)
    {
        RefinementParameter r;
        r.name = p.name;
        r.group = p.group;
        r.key = p.key;
        r.flagName = p.flagName;
        r.flag = p.flag;
        r.unit = p.quantity == detail::FIT_CLOCK_OFFSET ? "s" : p.quantity == detail::FIT_SCALE ? "" : "rad/s";
        r.searchHalfWidth = p.searchHalfWidth * p.unit;
        r.plantMotion = (p.motions & detail::FIT_PLANT_MOTION) != 0;
        r.mountMotion = (p.motions & detail::FIT_MOUNT_MOTION) != 0;
        r.measuredMotion = (p.motions & detail::FIT_MEASURED_MOTION) != 0;
        r.mountAxis = p.axis;
        r.rollingShutterOnly = p.rollingOnly;
        r.inRefineAll = p.inRefineAll;
        parameters.push_back(r);
    }
    return parameters;
}

int refinementFlags(const String& names)
{
    int flags = 0;
    String keys;
    for (const String& key : detail::perFlag(detail::allRefinementFlags(),
                                             [](const detail::FitParameter& p) { return String(p.key); }))
        keys += key + ", ";
    for (size_t start = 0; start <= names.size();)
    {
        const size_t end = std::min(names.find(',', start), names.size());
        const String item = names.substr(start, end - start);
        start = end + 1;
        int flag = item == "all" ? REFINE_ALL : item == "none" ? REFINE_NONE : -1;
        for (const detail::FitParameter& p : detail::kFitTable)
            if (item == p.key)
                flag = p.flag;
        if (flag < 0)
            CV_Error(Error::StsBadArg,
                     format("refinementFlags: '%s' in '%s' is not a parameter's name; use %sall or none, "
                            "comma-separated",
                            item.c_str(), names.c_str(), keys.c_str()));
        flags |= flag;
    }
    return flags;
}

}  // namespace dynblur
}  // namespace cv
