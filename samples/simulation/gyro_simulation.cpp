// SPDX-License-Identifier: Apache-2.0
// A rendered hand-held recording with its gyro log (gyro_simulation.hpp): a small clip of the hand-held
// clip simulator, written as an image sequence with a frame log that states the nominal line delay.
#include "gyro_simulation.hpp"

#include "clip_writer.hpp"

#include <opencv2/core/utils/filesystem.hpp>

#include <cmath>

namespace dynblur_samples {

using namespace cv;

int simulateGyroRecording(const std::string& dir, const GyroSimulation& truth)
{
    const double kDeg = CV_PI / 180, toldReadout = 0.030;
    HandHeldClip clip;
    clip.frameSize = Size(320, 240);
    clip.focalPx = 300;
    clip.fps = 30;
    clip.exposure = 0.010;
    clip.readoutTime = toldReadout * truth.lineDelayScale;
    clip.frames = std::max(1, int(std::ceil(truth.seconds * clip.fps)) - 1);
    clip.rotation.lowHz = 2;
    clip.rotation.highHz = 17;
    clip.rotation.peakRate = 40 * kDeg;
    clip.stretches.stillSeconds = 0.3;
    clip.stretches.shakySeconds = 0.5;
    clip.gyro.rateHz = 200;
    clip.gyro.noise = 0.1 * kDeg;
    clip.gyro.bias = truth.bias;
    clip.gyro.timeOffset = truth.timeOffset;
    clip.seed = 20261204;
    const HandHeldSimulator simulator(clip);

    utils::fs::createDirectories(dir);
    ClipFiles files;
    files.video = "frame_%04d.png";
    files.frameLogLineDelay = toldReadout / clip.frameSize.height;
    writeClip(simulator, dir, files);
    return clip.frames;
}

}  // namespace dynblur_samples
