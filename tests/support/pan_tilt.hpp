// SPDX-License-Identifier: Apache-2.0
// Test support: a pan-tilt head (Mount) and a planned move of each of its axes.
#ifndef DYNBLUR_TEST_PAN_TILT_HPP
#define DYNBLUR_TEST_PAN_TILT_HPP

#include <opencv2/dynblur.hpp>

#include <algorithm>
#include <vector>

namespace dynblur_test {

//! A pan-tilt head: pan about y (base), tilt about x, piezo-like plants of 0.2° and 0.25° per level.
inline cv::Ptr<cv::dynblur::Mount> panTilt()
{
    cv::Ptr<cv::dynblur::Mount> mount = cv::dynblur::Mount::create();
    mount->addAxis(cv::Vec3d(0, 1, 0), cv::dynblur::Plant::create(14.4, 0.12, 0.2 * CV_PI / 180), -200, 200);
    mount->addAxis(cv::Vec3d(1, 0, 0), cv::dynblur::Plant::create(11.0, 0.15, 0.25 * CV_PI / 180), -120, 120);
    return mount;
}

/* The pan-tilt head: pan about y (base) carries tilt about x, each the seed's positioner (ζ 0.12,
   1° per level, levels ±16) at `panHz` and `tiltHz`. */
inline cv::Ptr<cv::dynblur::Mount> seedPanTilt(double panHz, double tiltHz)
{
    cv::Ptr<cv::dynblur::Mount> mount = cv::dynblur::Mount::create();
    mount->addAxis(cv::Vec3d(0, 1, 0), cv::dynblur::Plant::create(panHz, 0.12, CV_PI / 180), -16, 16);
    mount->addAxis(cv::Vec3d(1, 0, 0), cv::dynblur::Plant::create(tiltHz, 0.12, CV_PI / 180), -16, 16);
    return mount;
}

//! A move planned for each axis of `mount` from rest at `fromDeg` to `toDeg` (degrees), starting at `start` s.
inline std::vector<cv::dynblur::SwitchSchedule> plannedMoves(const cv::Ptr<cv::dynblur::Mount>& mount,
                                                             const std::vector<double>& fromDeg,
                                                             const std::vector<double>& toDeg, double start)
{
    std::vector<cv::dynblur::SwitchSchedule> schedules;
    for (int i = 0; i < mount->getAxisCount(); i++)
    {
        const cv::Vec2i levels = mount->getLevelRange(i);
        cv::Ptr<cv::dynblur::SwitchPlanner> planner =
            cv::dynblur::SwitchPlanner::create(mount->getPlant(i), std::max(-levels[0], levels[1]));
        schedules.push_back(
            planner->plan(fromDeg[size_t(i)] * CV_PI / 180, toDeg[size_t(i)] * CV_PI / 180, start));
    }
    return schedules;
}

}  // namespace dynblur_test

#endif
