// SPDX-License-Identifier: Apache-2.0
// A clip's fine calibration: the clock offset, line delay, gyro bias and rate scale under which the
// log's rotations carry tracked features from frame to frame.
#include "precomp.hpp"

#include "motion/so3.hpp"
#include "refine/track_fit.hpp"

#include <algorithm>
#include <map>

namespace cv {
namespace dynblur {
namespace detail {

namespace {

// Instants over an exposure at which a feature's path is sampled for its centroid.
const int kExposureSamples = 5;
// Pairs the fit evaluates at most: beyond, every k-th (a rotation per pair end, per evaluation).
const size_t kMaxPairs = 20000;
// Levenberg–Marquardt steps per round, and robust rounds.
const int kIterations = 12, kRounds = 3;
// A pair is left out beyond this many times the median error, and beyond kMinOutlierPx.
const double kOutlierFactor = 3, kMinOutlierPx = 1.0;

double median(std::vector<double> values)
{
    if (values.empty())
        return std::numeric_limits<double>::quiet_NaN();
    std::nth_element(values.begin(), values.begin() + long(values.size() / 2), values.end());
    return values[values.size() / 2];
}

/* The parameters' covariance with the tracks of one frame counted as one measurement: errors shared
   by a frame's tracks (its blur, the gyro's noise over its interval) move them together, so counting
   each track as independent would claim a precision the clip does not have. The sandwich estimate
   (JᵀJ)⁻¹·(Σ_f J_fᵀ·r_f·r_fᵀ·J_f)·(JᵀJ)⁻¹ over the frames f, Jacobians by forward differences. */
FitMatrix groupedCovariance(TrackResiduals& residuals, const std::vector<TrackPair>& pairs, const FitVector& q,
                            const std::vector<int>& active, const MotionCorrection& like)
{
    const int n = int(active.size());
    FitMatrix covariance = FitMatrix::zeros();
    if (n == 0)
        return covariance;
    std::vector<float> at, moved;
    residuals.residuals(fromFitUnits(q, like), at);
    std::vector<std::vector<float>> columns(static_cast<size_t>(n));
    for (int a = 0; a < n; a++)
    {
        const int j = active[size_t(a)];
        FitVector shifted = q;
        shifted[j] += kFitTable[j].step;
        moved.clear();
        residuals.residuals(fromFitUnits(shifted, like), moved);
        columns[size_t(a)].resize(at.size());
        for (size_t k = 0; k < at.size(); k++)
            columns[size_t(a)][k] = float((moved[k] - at[k]) / kFitTable[j].step);
    }
    Mat jtj = Mat::zeros(n, n, CV_64F), meat = Mat::zeros(n, n, CV_64F);
    std::map<int, Mat> scores;  // per frame: Σ J_kᵀ·r_k over its pairs' residuals
    const std::vector<int>& used = residuals.used();
    for (size_t k = 0; k < at.size(); k++)
    {
        Mat& score = scores[pairs[size_t(used[k / 2])].frameB];
        if (score.empty())
            score = Mat::zeros(n, 1, CV_64F);
        for (int a = 0; a < n; a++)
        {
            score.at<double>(a) += double(columns[size_t(a)][k]) * at[k];
            for (int b = 0; b < n; b++)
                jtj.at<double>(a, b) += double(columns[size_t(a)][k]) * columns[size_t(b)][k];
        }
    }
    for (const auto& frame : scores)
        meat += frame.second * frame.second.t();
    const Mat bread = jtj.inv(DECOMP_SVD), sandwich = bread * meat * bread;
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++)
            covariance(active[size_t(a)], active[size_t(b)]) = sandwich.at<double>(a, b);
    return covariance;
}

}  // namespace

TrackResiduals::TrackResiduals(const Ptr<CameraMotion>& motion, const Ptr<CameraModel>& camera,
                               const std::vector<TrackPair>& pairs, const std::vector<ClipFrame>& frames)
    : motion_(motion), camera_(camera), focal_(0.5 * (camera->getFx() + camera->getFy())), pairs_(pairs),
      frames_(frames)
{
    rays_.reserve(pairs.size());
    targets_.reserve(pairs.size());
    for (size_t k = 0; k < pairs.size(); k++)
    {
        const Point2d a = camera->pixelToNormalized(Point2d(pairs[k].a)), b = camera->pixelToNormalized(Point2d(pairs[k].b));
        rays_.emplace_back(a.x, a.y, 1.0);
        targets_.push_back(b);
        used_.push_back(int(k));
    }
}

bool TrackResiduals::predict(int k, const MotionCorrection& c, Point2d& predicted) const
{
    const TrackPair& pair = pairs_[size_t(k)];
    const ClipFrame &a = frames_[size_t(pair.frameA)], &b = frames_[size_t(pair.frameB)];
    const double ta = a.frameStart + pair.a.y * a.lineDelay * c.lineDelayScale + 0.5 * a.exposure + c.timeOffset;
    const double tb = b.frameStart + pair.b.y * b.lineDelay * c.lineDelayScale + 0.5 * b.exposure + c.timeOffset;
    const Vec2d span = motion_->getTimeSpan();
    if (!(ta - 0.5 * a.exposure >= span[0] && ta + 0.5 * a.exposure <= span[1] && tb - 0.5 * b.exposure >= span[0] &&
          tb + 0.5 * b.exposure <= span[1]))
        return false;
    // The view at t relative to t_a, with the bias's turn from t_a removed and the turn scaled, as
    // withCorrectedRates corrects a motion about t_a.
    const Matx33d start = motion_->orientation(ta);
    auto view = [&](double t) {
        Matx33d R = start.t() * motion_->orientation(t);
        if (c.gyroBias != Vec3d())
            R = R * so3::matrixFromQuat(so3::quatFromRotationVector(-c.gyroBias * (t - ta)));
        if (c.rateScale != 1)
            R = so3::matrixFromQuat(
                so3::quatFromRotationVector(c.rateScale * so3::rotationVectorFromQuat(so3::quatFromMatrix(R))));
        return R;
    };
    /* A blurred feature sits at the centroid of its path over the exposure, not where it was at
       mid-exposure (the two part by a few pixels at tens of pixels of accelerating blur): the point
       seen at p_a is carried by the difference of its centroids in the two frames. */
    const Vec3d& ray = rays_[size_t(k)];
    Point2d centroid[2];
    for (int frame = 0; frame < 2; frame++)
    {
        const double mid = frame == 0 ? ta : tb, exposure = frame == 0 ? a.exposure : b.exposure;
        for (int i = 0; i < kExposureSamples; i++)
        {
            const double t = mid + exposure * ((i + 0.5) / kExposureSamples - 0.5);
            const Vec3d d = view(t).t() * ray;
            if (!(d[2] > 0))
                return false;
            centroid[frame] += Point2d(d[0] / d[2], d[1] / d[2]) * (1.0 / kExposureSamples);
        }
    }
    predicted = Point2d(ray[0], ray[1]) + centroid[1] - centroid[0];
    return true;
}

void TrackResiduals::residuals(const MotionCorrection& c, std::vector<float>& out)
{
    for (int k : used_)
    {
        Point2d p;
        if (!predict(k, c, p))
        {
            out.push_back(0.f), out.push_back(0.f);  // the same count at every candidate
            continue;
        }
        out.push_back(float(focal_ * (p.x - targets_[size_t(k)].x)));
        out.push_back(float(focal_ * (p.y - targets_[size_t(k)].y)));
    }
}

std::vector<double> TrackResiduals::errors(const MotionCorrection& c)
{
    std::vector<double> e;
    e.reserve(used_.size());
    for (int k : used_)
    {
        Point2d p;
        e.push_back(predict(k, c, p) ? focal_ * norm(p - targets_[size_t(k)]) : std::numeric_limits<double>::quiet_NaN());
    }
    return e;
}

std::vector<Point2d> TrackResiduals::carried(const MotionCorrection& c)
{
    std::vector<Point2d> points;
    for (int k : used_)
    {
        Point2d p;
        points.push_back(predict(k, c, p) ? camera_->normalizedToPixel(p)
                                          : Point2d(std::numeric_limits<double>::quiet_NaN(), 0));
    }
    return points;
}

void TrackResiduals::select(const std::vector<bool>& keep)
{
    CV_Assert(keep.size() == used_.size());
    std::vector<int> kept;
    for (size_t i = 0; i < used_.size(); i++)
        if (keep[i])
            kept.push_back(used_[i]);
    used_.swap(kept);
}

TrackFit fitTracks(const Ptr<CameraMotion>& motion, const Ptr<CameraModel>& camera,
                   const std::vector<TrackPair>& pairs, const std::vector<ClipFrame>& frames,
                   const MotionCorrection& start, int flags, int holdable, double maxTimeOffset)
{
    TrackResiduals residuals(motion, camera, pairs, frames);
    // Only pairs the log covers wherever the offset may go, at most kMaxPairs of them, spread evenly.
    {
        MotionCorrection early = start, late = start;
        early.timeOffset -= maxTimeOffset, late.timeOffset += maxTimeOffset;
        const std::vector<double> a = residuals.errors(early), b = residuals.errors(late), c = residuals.errors(start);
        std::vector<bool> keep(a.size());
        size_t covered = 0;
        for (size_t i = 0; i < keep.size(); i++)
            covered += keep[i] = std::isfinite(a[i]) && std::isfinite(b[i]) && std::isfinite(c[i]);
        const size_t stride = std::max<size_t>(1, (covered + kMaxPairs - 1) / kMaxPairs);
        for (size_t i = 0, seen = 0; i < keep.size(); i++)
            if (keep[i])
                keep[i] = seen++ % stride == 0;
        residuals.select(keep);
    }
    TrackFit result;
    result.pairs = residuals.used().size();
    bool rolling = false;
    for (const ClipFrame& f : frames)
        rolling = rolling || f.lineDelay > 0;
    const FitBox box(start, maxTimeOffset);
    std::vector<int> active = flaggedParameters(flags, FIT_MEASURED_MOTION, rolling, 1);
    FitVector q = box.prior;
    FitMatrix covariance = FitMatrix::zeros();
    for (int round = 0; round < kRounds && !residuals.used().empty(); round++)
    {
        LevelFit fit(residuals, active, box);
        q = fit.run(q, kIterations, covariance, nullptr, false);
        if (round + 1 == kRounds)
        {
            covariance = groupedCovariance(residuals, pairs, q, active, start);
            // A parameter the tracks leave uncertain keeps its start: the noise would choose it.
            std::vector<int> observed;
            for (int j : active)
                if (!(kFitTable[j].flag & holdable) ||
                    std::sqrt(std::max(0.0, covariance(j, j))) <= kFitTable[j].observable)
                    observed.push_back(j);
                else
                    result.held |= kFitTable[j].flag, result.heldParameters |= 1 << j, q[j] = box.prior[j];
            if (observed.size() < active.size())
            {
                active.swap(observed);
                LevelFit held(residuals, active, box);
                q = held.run(q, kIterations, covariance, nullptr, false);
                covariance = groupedCovariance(residuals, pairs, q, active, start);
            }
            break;
        }
        const std::vector<double> e = residuals.errors(fromFitUnits(q, start));
        const double limit = std::max(kMinOutlierPx, kOutlierFactor * median(e));
        std::vector<bool> keep(e.size());
        for (size_t i = 0; i < e.size(); i++)
            keep[i] = e[i] <= limit;
        residuals.select(keep);
    }
    result.correction = fromFitUnits(q, start);
    for (int j = 0; j < kFitParameters; j++)
        result.deviation[j] = std::sqrt(std::max(0.0, covariance(j, j))) * kFitTable[j].unit;
    const std::vector<double> e = residuals.errors(result.correction);
    result.inliers = e.size();
    std::vector<double> sum(frames.size(), 0.0);
    std::vector<int> count(frames.size(), 0);
    double total = 0;
    for (size_t i = 0; i < e.size(); i++)
    {
        const int frame = pairs[size_t(residuals.used()[i])].frameB;
        sum[size_t(frame)] += e[i] * e[i], count[size_t(frame)]++;
        total += e[i] * e[i];
    }
    result.rms = e.empty() ? std::numeric_limits<double>::quiet_NaN() : std::sqrt(total / double(e.size()));
    for (size_t f = 0; f < frames.size(); f++)
        result.frameRms.push_back(count[f] ? std::sqrt(sum[f] / count[f]) : std::numeric_limits<double>::quiet_NaN());
    return result;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
