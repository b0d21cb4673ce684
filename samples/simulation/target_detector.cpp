// SPDX-License-Identifier: Apache-2.0
#include "target_detector.hpp"

#include <visp3/core/vpImage.h>
#include <visp3/detection/vpDetectorAprilTag.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace cv;

namespace dynblur_samples {

struct TargetDetector::Impl
{
    vpDetectorAprilTag detector{vpDetectorAprilTag::TAG_36h11};
};

TargetDetector::TargetDetector() : impl_(new Impl)
{
    impl_->detector.setAprilTagNbThreads(1);
}

TargetDetector::~TargetDetector() = default;

Detection TargetDetector::detect(const Mat& grey8, const std::vector<double>& tagOffsets)
{
    vpDetectorAprilTag& detector = impl_->detector;
    vpImage<unsigned char> image(static_cast<unsigned>(grey8.rows), static_cast<unsigned>(grey8.cols));
    for (int y = 0; y < grey8.rows; ++y)
        std::copy(grey8.ptr<uchar>(y), grey8.ptr<uchar>(y) + grey8.cols, image[static_cast<unsigned>(y)]);
    Detection detection;
    if (!detector.detect(image))
        return detection;
    std::vector<bool> seen(tagOffsets.size(), false);
    Point2d sum;
    for (size_t i = 0; i < detector.getNbObjects(); ++i)
    {
        int id = -1;
        if (std::sscanf(detector.getMessage(i).c_str(), "36h11 id: %d", &id) != 1 || id < 0 ||
            id >= static_cast<int>(tagOffsets.size()) || seen[static_cast<size_t>(id)])
            continue;
        std::vector<Point2d> corners;
        for (const vpImagePoint& p : detector.getPolygon(i))
            corners.emplace_back(p.get_u(), p.get_v());
        if (corners.size() != 4)
            continue;
        // The centre of a square seen in perspective is where its diagonals cross (the corners'
        // mean is off by a fraction of a pixel once the plane is tilted).
        const Point2d a = corners[0], b = corners[2], c = corners[1], d = corners[3];
        const Point2d r = b - a, q = d - c;
        const double denominator = r.x * q.y - r.y * q.x;
        if (std::abs(denominator) < 1e-9)
            continue;
        const double t = ((c - a).x * q.y - (c - a).y * q.x) / denominator;
        sum += a + t * r - Point2d(0, tagOffsets[static_cast<size_t>(id)]);
        seen[static_cast<size_t>(id)] = true;
        detection.corners.push_back(corners);
    }
    detection.tagsFound = static_cast<int>(detection.corners.size());
    detection.found = detection.tagsFound == static_cast<int>(tagOffsets.size());
    if (detection.tagsFound > 0)
        detection.centre = sum / detection.tagsFound;
    return detection;
}

}  // namespace dynblur_samples
