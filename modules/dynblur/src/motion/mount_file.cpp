// SPDX-License-Identifier: Apache-2.0
// Mount::save and Mount::load: a mount's axes, plants and level ranges as a flat parameter file.
#include "precomp.hpp"

#include "opencv2/dynblur/mount.hpp"
#include "io/whole_file.hpp"

#include <cstdio>

namespace cv {
namespace dynblur {

namespace {

//! How far the norm of an axis in a file may be off 1: the file states unit vectors.
const double kUnitTolerance = 1e-6;

String key(size_t axis, const char* field)
{
    return format("axis%zu%s", axis, field);
}

//! The entry `name` read by `read`, its message prefixed with the file; a missing entry named.
template <typename Read>
auto entry(const ParameterFile& file, const String& filename, const String& name, Read read) -> decltype(read(name))
{
    if (!file.has(name))
        CV_Error(Error::StsParseError, "Mount::load: mount file '" + filename + "' has no entry '" + name + "'");
    return read(name);
}

Vec3d readAxis(const ParameterFile& file, const String& filename, size_t i)
{
    const String name = key(i, "");
    const std::vector<double> v = entry(file, filename, name, [&](const String& n) { return file.reals(n); });
    if (v.size() != 3)
        CV_Error_(Error::StsParseError, ("Mount::load: mount file '%s': %s has %zu values; 3 are expected "
                                         "([x, y, z], a unit vector in the camera frame at rest)",
                                         filename.c_str(), name.c_str(), v.size()));
    const Vec3d axis(v[0], v[1], v[2]);
    if (!(std::abs(norm(axis) - 1) <= kUnitTolerance))
        CV_Error_(Error::StsOutOfRange, ("Mount::load: mount file '%s': %s = [%g, %g, %g] has norm %.9g; a unit "
                                         "vector (norm 1 within %g) is expected",
                                         filename.c_str(), name.c_str(), v[0], v[1], v[2], norm(axis),
                                         kUnitTolerance));
    return axis;
}

Vec2i readLevels(const ParameterFile& file, const String& filename, size_t i)
{
    const String name = key(i, "_levels");
    const std::vector<int> v = entry(file, filename, name, [&](const String& n) { return file.integers(n); });
    if (v.size() != 2 || v[0] > v[1])
        CV_Error_(Error::StsOutOfRange, ("Mount::load: mount file '%s': %s must be [min, max] with min <= max "
                                         "(the actuator's integer levels)",
                                         filename.c_str(), name.c_str()));
    return Vec2i(v[0], v[1]);
}

Ptr<Plant> readPlant(const ParameterFile& file, const String& filename, size_t i)
{
    auto real = [&](const char* field) {
        return entry(file, filename, key(i, field), [&](const String& n) { return file.real(n); });
    };
    const double hz = real("_naturalFreqHz"), zeta = real("_dampingRatio"), gain = real("_gain");
    try
    {
        return Plant::create(hz, zeta, gain);
    }
    catch (const Exception& e)
    {
        CV_Error(e.code, format("Mount::load: mount file '%s', axis %zu's plant: ", filename.c_str(), i) + e.err);
    }
}

}  // namespace

void Mount::save(const String& filename) const
{
    const int count = getAxisCount();
    if (count == 0)
        CV_Error(Error::StsBadArg, "Mount::save: the mount has no axis (add them with addAxis)");
    for (int i = 0; i < count; i++)
        if (getPlant(i)->getDefaultName() != "dynblur.Plant")
            CV_Error_(Error::StsBadArg, ("Mount::save: axis %d's plant (%s) has no file form; only the linear "
                                         "second-order Plant::create has",
                                         i, getPlant(i)->getDefaultName().c_str()));
    // Written beside the target and renamed over it: a reader never sees half a file.
    detail::saveWhole(filename, "Mount::save", [&](FileStorage& fs) {
        fs.writeComment("dynblur mount: axes base first (unit vectors, camera frame at rest), each axis's plant "
                        "(Hz, damping ratio, rad per level) and level range");
        fs << "axisCount" << count;
        for (int i = 0; i < count; i++)
        {
            const Vec3d a = getAxis(i);
            const Ptr<Plant> plant = getPlant(i);
            const Vec2i levels = getLevelRange(i);
            fs << key(size_t(i), "") << std::vector<double>{a[0], a[1], a[2]};
            fs << key(size_t(i), "_naturalFreqHz") << plant->getNaturalFreqHz();
            fs << key(size_t(i), "_dampingRatio") << plant->getDampingRatio();
            fs << key(size_t(i), "_gain") << plant->getGain();
            fs << key(size_t(i), "_levels") << std::vector<int>{levels[0], levels[1]};
        }
    });
}

Ptr<Mount> Mount::load(const String& filename)
{
    // Not cv::FileStorage: its readers trust their input (see ParameterFile).
    const ParameterFile file = ParameterFile::load(filename, "Mount::load: mount file");
    const int count = entry(file, filename, "axisCount", [&](const String& n) { return file.integer(n); });
    if (count < 1 || count > 16)
        CV_Error_(Error::StsOutOfRange,
                  ("Mount::load: mount file '%s': axisCount = %d must lie in [1, 16]", filename.c_str(), count));
    if (file.has(key(size_t(count), "")))
        CV_Error_(Error::StsParseError, ("Mount::load: mount file '%s': axisCount = %d but the file has an entry "
                                         "'%s'; axisCount must match the axis<i> entries",
                                         filename.c_str(), count, key(size_t(count), "").c_str()));
    Ptr<Mount> mount = Mount::create();
    for (size_t i = 0; i < size_t(count); i++)
    {
        if (!file.has(key(i, "")))
            CV_Error_(Error::StsParseError, ("Mount::load: mount file '%s': axisCount = %d but the file has no entry "
                                             "'%s'; axisCount must match the axis<i> entries",
                                             filename.c_str(), count, key(i, "").c_str()));
        const Vec3d axis = readAxis(file, filename, i);
        const Ptr<Plant> plant = readPlant(file, filename, i);
        const Vec2i levels = readLevels(file, filename, i);
        try
        {
            mount->addAxis(axis, plant, levels[0], levels[1]);
        }
        catch (const Exception& e)
        {
            CV_Error(e.code,
                     format("Mount::load: mount file '%s', %s: ", filename.c_str(), key(i, "").c_str()) + e.err);
        }
    }
    return mount;
}

}  // namespace dynblur
}  // namespace cv
