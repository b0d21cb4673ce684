// SPDX-License-Identifier: Apache-2.0
// A rendered hand-held recording with its gyro log (gyro_simulation.hpp).
#include "gyro_simulation.hpp"

#include "recording.hpp"
#include "scene.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sys/stat.h>

namespace dynblur_samples {

using namespace cv;
using namespace cv::dynblur;

namespace {

const double kDeg = CV_PI / 180;

/* The hand's body rates at t, rad/s: two sines per axis (as tests/support/rotation_motion.hpp's handShake),
   faded out for 0.3 s in every 0.8 s by raised-cosine ramps of 50 ms: the hand held still. */
Vec3d handRates(double t)
{
    static const double hz[3][2] = {{3.1, 11.0}, {2.3, 7.7}, {4.4, 16.5}};
    static const double phase[3][2] = {{0.4, 2.0}, {1.3, 0.2}, {2.9, 1.1}};
    const double peak = 15 * kDeg;  // each sine's peak rate: about 30 deg/s together
    const double u = std::fmod(t, 0.8), ramp = 0.05;
    double envelope = u < 0.3 ? 0 : u < 0.3 + ramp ? 0.5 - 0.5 * std::cos(CV_PI * (u - 0.3) / ramp)
                              : u > 0.8 - ramp   ? 0.5 - 0.5 * std::cos(CV_PI * (0.8 - u) / ramp)
                                                 : 1;
    Vec3d w;
    for (int i = 0; i < 3; i++)
        w[i] = envelope * peak * (std::cos(2 * CV_PI * hz[i][0] * t + phase[i][0]) +
                                  std::cos(2 * CV_PI * hz[i][1] * t + phase[i][1]));
    return w;
}

}  // namespace

int simulateGyroRecording(const std::string& dir, const GyroSimulation& truth)
{
    ::mkdir(dir.c_str(), 0755);
    const Ptr<CameraModel> camera = CameraModel::create(300, 300, 159.5, 119.5, 320, 240);
    // The true motion: the rates at 1 kHz, integrated (within 1e-6 rad of the continuous motion).
    const double start = -0.1, end = truth.seconds + 0.1;
    const int dense = int(std::lround((end - start) * 1000)) + 1;
    Mat times(dense, 1, CV_64F), rates(dense, 3, CV_64F);
    for (int k = 0; k < dense; k++)
    {
        times.at<double>(k) = start + k / 1000.0;
        const Vec3d w = handRates(times.at<double>(k));
        for (int i = 0; i < 3; i++)
            rates.at<double>(k, i) = w[i];
    }
    const Ptr<CameraMotion> motion = CameraMotion::fromAngularVelocity(times, rates);

    // The gyro log: 200 Hz on its own clock (truth.timeOffset ahead), bias and noise, in deg/s and ms.
    const std::string logPath = dir + "/gyro.gcsv";
    std::ofstream log(logPath);
    log << "GYROFLOW IMU LOG\nversion,1.3\nid,dynblur_simulation\norientation,XYZ\ntscale,0.001\n"
        << format("gscale,%.12g\n", kDeg) << "t,gx,gy,gz\n";
    RNG rng(20261204);
    for (int k = 0; k <= int(std::lround(truth.seconds * 200)); k++)
    {
        const double tau = k / 200.0;
        const Vec3d w = handRates(tau - truth.timeOffset) + truth.bias;
        log << format("%.3f,%.5f,%.5f,%.5f\n", tau * 1e3, (w[0] + rng.gaussian(0.1 * kDeg)) / kDeg,
                      (w[1] + rng.gaussian(0.1 * kDeg)) / kDeg, (w[2] + rng.gaussian(0.1 * kDeg)) / kDeg);
    }
    log.close();
    if (!log)
        CV_Error(Error::StsError, "cannot write '" + logPath + "'");

    // The scene is the view at t = 0, wider than the frame by the hand's reach.
    const int margin = 48;
    Mat scene;
    srgbToLinear(makeScene(Size(320 + 2 * margin, 240 + 2 * margin)), scene);
    const double exposure = 0.010, toldLineDelay = 0.030 / 240;
    std::vector<FrameRecord> frames;
    for (int k = 0; (k + 1) / 30.0 + 0.01 < truth.seconds; k++)
    {
        FrameRecord f;
        f.frame = k;
        f.frameStart = 0.01 + k / 30.0;
        f.exposure = exposure;
        f.lineDelay = toldLineDelay;
        const RollingShutter happened(f.frameStart, exposure, toldLineDelay * truth.lineDelayScale, 240);
        Mat blurred, noisy, frame;
        renderBlurred(scene, motion, camera, happened, blurred, 0.0);
        addSensorNoise(blurred, noisy, 4000.0, 8.0, 5.0, 3000 + uint64(k));
        linearToSrgb(noisy, frame, CV_8U);
        char name[64];
        std::snprintf(name, sizeof name, "/frame_%04d.png", k);
        if (!imwrite(dir + name, frame))
            CV_Error(Error::StsError, "cannot write '" + dir + name + "'");
        frames.push_back(f);
    }
    writeFrameLog(dir + "/frames.csv", frames);
    camera->save(dir + "/camera.xml");
    return int(frames.size());
}

}  // namespace dynblur_samples
