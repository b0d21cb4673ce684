// SPDX-License-Identifier: Apache-2.0
// Band-limited hand motion, its homographies and the blur it puts into a frame (hand_motion.hpp).
#include "hand_motion.hpp"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>

namespace dynblur_samples {

using namespace cv;
using namespace cv::dynblur;

namespace {

//! 0 → 1 over [0, width] as a raised cosine.
double raisedCosine(double u, double width)
{
    if (u <= 0)
        return 0;
    if (u >= width)
        return 1;
    return 0.5 - 0.5 * std::cos(CV_PI * u / width);
}

//! The fade-in from the home view at the motion's start, seconds: the still instant renderBlurred's tRef names.
const double kFadeIn = 0.1;

//! The probe pixels of a frame: three columns, five rows.
std::vector<Point2d> probePixels(const Size& size)
{
    std::vector<Point2d> probes;
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 3; j++)
            probes.emplace_back(0.5 * j * (size.width - 1), 0.25 * i * (size.height - 1));
    return probes;
}

Point2d apply(const Matx33d& H, const Point2d& p)
{
    const Vec3d q = H * Vec3d(p.x, p.y, 1);
    return Point2d(q[0] / q[2], q[1] / q[2]);
}

}  // namespace

double ShakeStretches::envelope(double t) const
{
    if (stillSeconds <= 0)
        return 1;
    const double period = stillSeconds + shakySeconds;
    const double u = t - std::floor(t / period) * period - stillSeconds;  // time into the shaky stretch
    if (u < 0)
        return 0;
    return std::min(raisedCosine(u, rampSeconds), raisedCosine(shakySeconds - u, rampSeconds));
}

Vec3d CameraPath::position(double t) const
{
    if (positions.empty())
        return Vec3d();
    const double x = std::min(std::max((t - start) * sampleRateHz, 0.0), positions.rows - 1.0);
    const int k = std::min(int(x), positions.rows - 2);
    const double a = x - k;
    const double* p0 = positions.ptr<double>(k);
    const double* p1 = positions.ptr<double>(k + 1);
    return Vec3d((1 - a) * p0[0] + a * p1[0], (1 - a) * p0[1] + a * p1[1], (1 - a) * p0[2] + a * p1[2]);
}

Matx33d CameraPath::homeFromView(double t, const Matx33d& K, bool rotationOnly) const
{
    Matx33d M = rotation->orientation(t);
    if (!rotationOnly && !positions.empty())
    {
        // A ray of the view meets the plane n·X = d at X = λ·Q·K⁻¹p + c; its home pixel is K·X.
        const Vec3d c = position(t);
        const Matx33d shift(1, 0, c[0] / (planeDepth - c[2]), 0, 1, c[1] / (planeDepth - c[2]), 0, 0,
                            1 + c[2] / (planeDepth - c[2]));
        M = shift * M;
    }
    return K * M * K.inv();
}

double frameBlurPx(const CameraPath& path, const Matx33d& K, const Size& size, const RollingShutter& shutter,
                   bool rotationOnly)
{
    if (shutter.exposure <= 0)
        return 0;
    const int kTimes = 17;
    double blur = 0;
    const std::vector<Point2d> probes = probePixels(size);
    for (size_t i = 0; i < probes.size(); i += 3)  // one row of probes: one interval
    {
        const Vec2d interval = shutter.rowInterval(int(std::lround(probes[i].y)));
        std::vector<Matx33d> H(kTimes);
        for (int k = 0; k < kTimes; k++)
            H[k] = path.homeFromView(interval[0] + (interval[1] - interval[0]) * k / (kTimes - 1), K, rotationOnly);
        for (size_t j = i; j < i + 3; j++)
        {
            std::vector<Point2d> q(kTimes);
            for (int k = 0; k < kTimes; k++)
                q[k] = apply(H[k], probes[j]);
            for (int a = 0; a < kTimes; a++)
                for (int b = a + 1; b < kTimes; b++)
                    blur = std::max(blur, norm(q[a] - q[b]));
        }
    }
    return blur;
}

double viewStrayPx(const CameraPath& path, const Matx33d& K, const Size& size, double from, double to)
{
    const double xs[3] = {0, 0.5 * (size.width - 1), size.width - 1.0};
    const double ys[3] = {0, 0.5 * (size.height - 1), size.height - 1.0};
    double stray = 0;
    const int steps = std::max(1, int(std::ceil((to - from) * 1000)));
    for (int k = 0; k <= steps; k++)
    {
        const Matx33d H = path.homeFromView(from + (to - from) * k / steps, K);
        for (double x : xs)
            for (double y : ys)
                if (x != xs[1] || y != ys[1])
                    stray = std::max(stray, norm(apply(H, Point2d(x, y)) - Point2d(x, y)));
    }
    return stray;
}

HandShake::HandShake(double start, double end, const ShakeStretches& stretches, uint64 seed)
    : start_(start), samples_(int(std::ceil((end - start) * kSampleRateHz)) + 1), seed_(seed), envelope_(samples_)
{
    for (int k = 0; k < samples_; k++)
    {
        const double t = start + k / kSampleRateHz;
        envelope_[size_t(k)] = stretches.envelope(t) * raisedCosine(t - start, kFadeIn);
    }
}

Mat HandShake::shape(double lowHz, double highHz, const Vec3d& weights, double scale, uint64 stream) const
{
    // White noise, filtered in the frequency domain: kept between lowHz and highHz, divided by the
    // frequency so that its derivative (the rate) has a flat spectrum there. The DFT's length is the
    // span or more, so the signal is not forced to be periodic over the span.
    const int n = getOptimalDFTSize(samples_);
    RNG rng(seed_ * 4 + stream);
    Mat out(samples_, 3, CV_64F);
    for (int axis = 0; axis < 3; axis++)
    {
        Mat noise(n, 1, CV_64F), spectrum;
        rng.fill(noise, RNG::NORMAL, 0.0, 1.0);
        dft(noise, spectrum, DFT_COMPLEX_OUTPUT);
        for (int k = 0; k < n; k++)
        {
            const double f = std::min(k, n - k) * kSampleRateHz / n;
            Vec2d& c = spectrum.at<Vec2d>(k);
            c = (f >= lowHz && f <= highHz) ? c * (1.0 / (2 * CV_PI * f)) : Vec2d();
        }
        Mat signal;
        idft(spectrum, signal, DFT_REAL_OUTPUT | DFT_SCALE);
        // Unit RMS of the derivative over the span, then the axis's weight and the scale.
        double sum = 0;
        for (int k = 1; k < samples_; k++)
        {
            const double d = (signal.at<double>(k) - signal.at<double>(k - 1)) * kSampleRateHz;
            sum += d * d;
        }
        const double rms = std::sqrt(sum / std::max(1, samples_ - 1));
        for (int k = 0; k < samples_; k++)
            out.at<double>(k, axis) =
                rms > 0 ? signal.at<double>(k) / rms * weights[axis] * scale * envelope_[size_t(k)] : 0.0;
    }
    return out;
}

Mat HandShake::rotationVectors(double lowHz, double highHz, const Vec3d& weights, double scale) const
{
    return shape(lowHz, highHz, weights, scale, 1);
}

Mat HandShake::positions(double lowHz, double highHz, const Vec3d& weights, double scale) const
{
    return shape(lowHz, highHz, weights, scale, 2);
}

CameraPath HandShake::path(const Mat& rotationVectors, const Mat& positions, double planeDepth) const
{
    Mat times(samples_, 1, CV_64F);
    for (int k = 0; k < samples_; k++)
        times.at<double>(k) = start_ + k / kSampleRateHz;
    CameraPath path;
    path.rotation = CameraMotion::fromOrientations(times, rotationVectors);
    path.positions = positions;
    path.start = start_;
    path.sampleRateHz = kSampleRateHz;
    path.planeDepth = planeDepth;
    return path;
}

}  // namespace dynblur_samples
