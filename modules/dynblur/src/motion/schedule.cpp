// SPDX-License-Identifier: Apache-2.0
// SwitchSchedule: the staircase command, its checks and its file form.
#include "precomp.hpp"

namespace cv {
namespace dynblur {

SwitchSchedule::SwitchSchedule()
    : initialLevel(0),
      settleTime(std::numeric_limits<double>::quiet_NaN()),
      peakVelocity(std::numeric_limits<double>::quiet_NaN()),
      residualVibration(std::numeric_limits<double>::quiet_NaN())
{
}

SwitchSchedule::SwitchSchedule(const std::vector<double>& times_, const std::vector<int>& levels_, int initialLevel_)
    : SwitchSchedule()
{
    times = times_;
    levels = levels_;
    initialLevel = initialLevel_;
}

int SwitchSchedule::finalLevel() const
{
    return levels.empty() ? initialLevel : levels.back();
}

int SwitchSchedule::levelAt(double t) const
{
    if (!std::isfinite(t))
        CV_Error(Error::StsBadArg, format("SwitchSchedule::levelAt: t = %g must be finite (seconds)", t));
    // Level i holds on [times[i], times[i+1]): the last switch at or before t wins.
    const auto after = std::upper_bound(times.begin(), times.end(), t);
    const size_t switched = static_cast<size_t>(after - times.begin());
    return switched == 0 ? initialLevel : levels[std::min(switched, levels.size()) - 1];
}

void SwitchSchedule::validate(int maxLevel) const
{
    CV_Check(maxLevel, maxLevel >= 0, "maxLevel must be >= 0");
    if (times.empty())
        CV_Error(Error::StsBadArg, "SwitchSchedule: 'times' is empty; a schedule needs at least one switch");
    if (times.size() != levels.size())
        CV_Error(Error::StsBadArg,
                 format("SwitchSchedule: 'times' has %zu entries but 'levels' has %zu; they must match",
                        times.size(), levels.size()));
    for (size_t i = 0; i < times.size(); ++i)
    {
        if (!std::isfinite(times[i]))
            CV_Error(Error::StsBadArg, format("SwitchSchedule: times[%zu] is not finite", i));
        if (i > 0 && !(times[i] > times[i - 1]))
            CV_Error(Error::StsBadArg,
                     format("SwitchSchedule: 'times' must be strictly increasing, but times[%zu] = %.9g s "
                            "<= times[%zu] = %.9g s", i, times[i], i - 1, times[i - 1]));
    }
    // The entry's name is only written when it is refused: plants validate on every response.
    auto checkLevel = [maxLevel](int level, const char* name, size_t index) {
        if (level < -maxLevel || level > maxLevel)
            CV_Error(Error::StsOutOfRange,
                     format("SwitchSchedule: %s = %d is outside the allowed range [-%d, %d]",
                            index == size_t(-1) ? name : format("%s[%zu]", name, index).c_str(), level, maxLevel,
                            maxLevel));
    };
    checkLevel(initialLevel, "initialLevel", size_t(-1));
    for (size_t i = 0; i < levels.size(); ++i)
        checkLevel(levels[i], "levels", i);
}

void SwitchSchedule::save(const String& filename) const
{
    validate();
    FileStorage fs(filename, FileStorage::WRITE);
    if (!fs.isOpened())
        CV_Error(Error::StsError, "SwitchSchedule::save: cannot open '" + filename + "' for writing");
    fs << "times" << times << "levels" << levels << "initialLevel" << initialLevel;
}

SwitchSchedule SwitchSchedule::load(const String& filename)
{
    // Not cv::FileStorage: its readers trust their input (see ParameterFile).
    const ParameterFile file = ParameterFile::load(filename, "SwitchSchedule::load: schedule file");
    if (!file.has("times") || !file.has("levels"))
        CV_Error(Error::StsParseError,
                 "SwitchSchedule::load: '" + filename + "' needs sequences 'times' (seconds) and 'levels' (integers)");
    SwitchSchedule schedule;
    schedule.times = file.reals("times");
    schedule.levels = file.integers("levels");
    if (file.has("initialLevel"))
        schedule.initialLevel = file.integer("initialLevel");
    schedule.validate();
    return schedule;
}

}  // namespace dynblur
}  // namespace cv
