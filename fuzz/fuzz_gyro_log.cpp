// SPDX-License-Identifier: Apache-2.0
// Fuzzes GyroLog::load, the reader of gyro logs (Gyroflow's gcsv, CSV, phone apps' CSV), and what a
// restoration does with a log it accepted: the bias from still intervals, the integrated motion
// (CameraMotion::fromAngularVelocity) and its orientation and rates across the log's span, each of
// which must be a rotation and finite rates.
#include "fuzz_common.hpp"

#include <opencv2/dynblur.hpp>

#include <cmath>

using namespace cv::dynblur;

namespace {

void checkMotion(const CameraMotion& motion)
{
    const cv::Vec2d span = motion.getTimeSpan();
    for (double s : {0.0, 0.25, 0.5, 1.0})
    {
        const double t = s == 1.0 ? span[1] : span[0] + s * (span[1] - span[0]);
        if (!(t >= span[0] && t <= span[1]))
            continue;  // a span too wide for double arithmetic
        const cv::Matx33d Q = motion.orientation(t);
        const cv::Matx33d E = Q.t() * Q - cv::Matx33d::eye();
        for (int i = 0; i < 9; ++i)
            if (!(std::abs(E.val[i]) < 1e-9))
                std::abort();  // not a rotation
        const cv::Vec3d w = motion.angularVelocity(t);
        if (!std::isfinite(w[0] + w[1] + w[2]))
            std::abort();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string& path = dynblur_fuzz::writeScratchFile(data, size, "_gyro.gcsv");
    GyroLog log;
    try
    {
        log = GyroLog::load(path);
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
        return 0;
    }
    if (log.times.size() < 2 || log.rates.rows != int(log.times.size()) || log.rates.cols != 3)
        std::abort();  // load() promises at least two samples, one row of rates each
    try
    {
        log.estimateBias(0.05, 0.01);
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
    }
    try
    {
        checkMotion(*log.toMotion());
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
    }
    return 0;
}
