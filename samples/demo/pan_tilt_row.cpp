// SPDX-License-Identifier: Apache-2.0
// The demo's pan-tilt row: a diagonal saccade of a two-axis head, restored from the head's exact motion.
#include "demo_panels.hpp"

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdio>
#include <limits>

using namespace cv;
using namespace cv::dynblur;

namespace dynblur_demo {

namespace {

const double kDeg = CV_PI / 180.0;

/* The frame with the path each of a 4 × 3 grid of its points blurs along, in yellow through the point
   (white dot): the streak a point source there leaves, −(q(t) − q̄) about the point, q(t) = K·R(t)·K⁻¹·p
   being where the point's row looked in the reference view during its exposure (R(t) = Q_refᵀ·Q(t))
   and q̄ its mean (the shift the restoration takes back into the reference view). */
Mat drawBlurPaths(const Mat& frame, const Ptr<CameraMotion>& motion, const Ptr<CameraModel>& camera,
                  const RollingShutter& shutter)
{
    Mat drawn = frame.clone();
    const Matx33d reference = motion->referenceOrientation(std::numeric_limits<double>::quiet_NaN(), shutter);
    for (int gy = 1; gy <= 3; gy++)
        for (int gx = 1; gx <= 4; gx++)
        {
            const Point2d p(frame.cols * gx / 5.0, frame.rows * gy / 4.0);
            const Vec2d interval = shutter.rowInterval(int(p.y));
            std::vector<Point2d> seen;
            Point2d mean(0, 0);
            for (int k = 0; k <= 40; k++)
            {
                const double t = interval[0] + (interval[1] - interval[0]) * k / 40.0;
                seen.push_back(camera->viewToReference(p, motion->relativeRotation(t, reference)));
                mean += seen.back() / 41.0;
            }
            std::vector<Point> path;
            for (const Point2d& q : seen)
                path.push_back(Point(cvRound(p.x - (q.x - mean.x)), cvRound(p.y - (q.y - mean.y))));
            polylines(drawn, path, false, Scalar(0, 220, 255), 3, LINE_AA);
            circle(drawn, Point(cvRound(p.x), cvRound(p.y)), 5, Scalar(255, 255, 255), FILLED, LINE_AA);
        }
    return drawn;
}

}  // namespace

void runPanTilt(const Ptr<CameraModel>& camera, const Mat& scene, double exposure, double lineDelay,
                const RLParams& params, std::vector<Mat>& panelRows, std::vector<std::string>& tableRows)
{
    Ptr<Mount> mount = Mount::create();
    mount->addAxis(Vec3d(0, 1, 0), Plant::create(14.4, 0.12, kDeg), -16, 16);
    mount->addAxis(Vec3d(1, 0, 0), Plant::create(14.4, 0.12, kDeg), -16, 16);
    const MountMove move = MountPlanner::create(mount, PLAN_ROBUST)->plan({0, 0}, {10 * kDeg, 6 * kDeg});
    std::printf("[demo] pan-tilt head: 10 deg pan + 6 deg tilt together, settles in %.1f ms, peak %.0f deg/s, the "
                "path %.2f deg off a straight image line; rendering, restoring...\n",
                1e3 * move.settleTime, move.peakRate / kDeg, move.pathDeviation / kDeg);
    std::fflush(stdout);
    const Ptr<CameraMotion> motion = mount->motion(move.schedules);

    // The view at rest after the move, wide enough for every view the move passes through.
    const Size frameSize = camera->getImageSize();
    const int marginX = int(std::ceil(camera->getFx() * std::tan(10 * kDeg))) + 40,
              marginY = int(std::ceil(camera->getFy() * std::tan(6 * kDeg))) + 40;
    Mat wide, wideLinear;
    resize(scene, wide, Size(frameSize.width + 2 * marginX, frameSize.height + 2 * marginY), 0, 0, INTER_AREA);
    srgbToLinear(wide, wideLinear);
    const Mat truth = wide(Rect(marginX, marginY, frameSize.width, frameSize.height));
    // Every row exposed while the head turns: the frame starts as the move does.
    const RollingShutter shutter(0.002, exposure, lineDelay, frameSize.height);

    Mat blurred, noisy, frame;
    renderBlurred(wideLinear, motion, camera, shutter, blurred);
    addSensorNoise(blurred, noisy, 4000.0, 8.0, 5.0, 91);
    linearToSrgb(noisy, frame, CV_8U);

    const BothRestorations r = restoreBothWays(frame, motion, camera, shutter, params);
    tableRows.push_back(tableRow("pan-tilt, 10+6 deg", r.window, truth, frame, r.uniform, r.variant,
                                 judgedPixels(r.valid), r.uniformMs, r.variantMs));
    const int cellWidth = 400;
    std::vector<Mat> cells{labelled(drawBlurPaths(frame, motion, camera, shutter), "pan-tilt: blurred, its blur paths",
                                    cellWidth),
                           labelled(shadeUnobserved(r.uniform, r.valid), "single PSF (seed)", cellWidth),
                           labelled(shadeUnobserved(r.variant, r.valid), "restored from the head's motion", cellWidth),
                           labelled(truth, "truth (view at rest after the move)", cellWidth)};
    Mat row;
    hconcat(cells, row);
    panelRows.push_back(row);
}

}  // namespace dynblur_demo
