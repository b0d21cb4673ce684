// SPDX-License-Identifier: Apache-2.0
// CameraMotion from samples: the gyroscope integrator against exact and dense references, the
// orientation spline against a known motion, fromPlant against its own velocity, and bad input.
#include "test_common.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/dynblur.hpp>

#include <opencv2/core/quaternion.hpp>

#include <functional>

using namespace cv;
using namespace cv::dynblur;

namespace {

const double kDeg = CV_PI / 180.0;

//! Angle of the rotation Aᵀ·B, radians: how far apart two orientations are (atan2 of sin and cos:
//! acos of the trace alone cannot resolve angles below ~1e-8).
double angleBetween(const Matx33d& A, const Matx33d& B)
{
    const Matx33d D = A.t() * B;
    const double s = 0.5 * norm(Vec3d(D(2, 1) - D(1, 2), D(0, 2) - D(2, 0), D(1, 0) - D(0, 1)));
    return std::atan2(s, 0.5 * (D(0, 0) + D(1, 1) + D(2, 2) - 1.0));
}

Matx33d rotationAbout(const Vec3d& unitAxis, double angle)
{
    Matx33d R;
    Rodrigues(unitAxis * angle, R);
    return R;
}

//! Shake-like body rates: per axis a sum of four sines between 1 and 20 Hz, |ω_i| ≤ 30 °/s.
Vec3d shakeRate(double t)
{
    static const double freq[3][4] = {{1.3, 4.1, 9.7, 19.2}, {1.9, 5.3, 12.1, 17.5}, {1.1, 3.7, 7.9, 15.4}};
    static const double phase[3][4] = {{0.2, 1.1, 2.3, 0.7}, {2.9, 0.4, 1.7, 2.2}, {1.5, 2.6, 0.1, 1.9}};
    Vec3d w;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j)
            w[i] += (30.0 * kDeg / 4) * std::sin(2 * CV_PI * freq[i][j] * t + phase[i][j]);
    return w;
}

/** Q(t) on a dense grid of step `dt` from Q(t0) = I, solving dQ/dt = Q·[ω(t)]× by classical RK4 on
    the quaternion (q' = ½·q ⊗ (0, ω)), renormalised every step. */
struct DenseReference
{
    double t0, dt;
    std::vector<Vec4d> q;

    DenseReference(const std::function<Vec3d(double)>& rate, double start, double end, double step)
        : t0(start), dt(step)
    {
        auto derivative = [](const Vec4d& p, const Vec3d& w) {
            return 0.5 * Vec4d(-p[1] * w[0] - p[2] * w[1] - p[3] * w[2], p[0] * w[0] + p[2] * w[2] - p[3] * w[1],
                               p[0] * w[1] - p[1] * w[2] + p[3] * w[0], p[0] * w[2] + p[1] * w[1] - p[2] * w[0]);
        };
        const int steps = int(std::lround((end - start) / step));
        q.resize(size_t(steps) + 1);
        q[0] = Vec4d(1, 0, 0, 0);
        for (int k = 0; k < steps; ++k)
        {
            const double t = start + k * step;
            const Vec4d& p = q[size_t(k)];
            const Vec4d k1 = derivative(p, rate(t));
            const Vec4d k2 = derivative(p + 0.5 * step * k1, rate(t + 0.5 * step));
            const Vec4d k3 = derivative(p + 0.5 * step * k2, rate(t + 0.5 * step));
            const Vec4d k4 = derivative(p + step * k3, rate(t + step));
            Vec4d next = p + (step / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            q[size_t(k) + 1] = next * (1.0 / norm(next));
        }
    }
    double time(size_t i) const { return t0 + double(i) * dt; }
    Matx33d orientation(size_t i) const
    {
        const Vec4d& p = q[i];
        return Quatd(p[0], p[1], p[2], p[3]).toRotMat3x3();
    }
};

//! Samples of `rate` at `hz` on [start, end]: times N×1 and rates N×3.
void sampleRates(const std::function<Vec3d(double)>& rate, double start, double end, double hz, Mat& times, Mat& rates)
{
    const int n = int(std::lround((end - start) * hz)) + 1;
    times.create(n, 1, CV_64F);
    rates.create(n, 3, CV_64F);
    for (int k = 0; k < n; ++k)
    {
        const double t = start + k / hz;
        times.at<double>(k) = t;
        const Vec3d w = rate(t);
        for (int i = 0; i < 3; ++i)
            rates.at<double>(k, i) = w[i];
    }
}

//! The largest orientation error, radians, of `motion` against the reference at every `stride`-th grid point.
double worstOrientationError(const CameraMotion& motion, const DenseReference& ref, size_t stride)
{
    double worst = 0;
    for (size_t i = 0; i < ref.q.size(); i += stride)
        worst = std::max(worst, angleBetween(motion.orientation(ref.time(i)), ref.orientation(i)));
    return worst;
}

// ------------------------------------------------------------------------------------ fromAngularVelocity

TEST(CameraMotionGyro, ConstantAxisGivesTheAxisRotationExactly)
{
    // The rate's size varies along one fixed axis, quadratically in time: the interpolated rate is
    // the true one and the integrated angle its integral, so the orientation must be that axis
    // rotation to rounding, between samples too.
    const Vec3d axis = normalize(Vec3d(0.3, -0.5, 0.8));
    auto size = [](double t) { return 0.5 + 2.0 * t - 1.5 * t * t; };
    auto angle = [](double t) { return 0.5 * t + t * t - 0.5 * t * t * t; };
    Mat times, rates;
    sampleRates([&](double t) { return axis * size(t); }, 0.0, 2.0, 200, times, rates);
    const Ptr<CameraMotion> motion = CameraMotion::fromAngularVelocity(times, rates);
    double worst = 0, worstRate = 0;
    for (double t = 0; t <= 2.0; t += 0.00173)
    {
        worst = std::max(worst, norm(motion->orientation(t) - rotationAbout(axis, angle(t)), NORM_INF));
        worstRate = std::max(worstRate, norm(motion->angularVelocity(t) - axis * size(t)));
    }
    EXPECT_LT(worst, 1e-12);
    EXPECT_LT(worstRate, 1e-12);
    EXPECT_LT(norm(motion->orientation(2.0) - rotationAbout(axis, angle(2.0)), NORM_INF), 1e-12);
}

TEST(CameraMotionGyro, MagnusStepMatchesADenseSolutionOfTheSameRates)
{
    // The dense RK4 reference integrates the very rates the integrator assumes (its interpolant of
    // the 200 Hz samples), so only the Magnus step's own error remains. The commutator term with
    // the wrong sign leaves 1.7e-6 rad (docs/camera-motion.md).
    Mat times, rates;
    sampleRates(shakeRate, 0.0, 1.0, 200, times, rates);
    const Ptr<CameraMotion> motion = CameraMotion::fromAngularVelocity(times, rates);
    const DenseReference ref([&](double t) { return motion->angularVelocity(std::min(t, 1.0)); }, 0.0, 1.0, 1e-5);
    const double worst = worstOrientationError(*motion, ref, 37);
    std::printf("[ figure ] Magnus step vs dense RK4 of the same rates, 200 Hz shake, 1 s: worst %.3g rad\n", worst);
    EXPECT_LT(worst, 6e-9);
}

TEST(CameraMotionGyro, ShakeSampledAt200HzFollowsTheContinuousMotion)
{
    // The continuous 1–20 Hz shake against its 200 Hz samples: what remains is the cubic
    // interpolation of the rate between samples (docs/camera-motion.md states the figure).
    Mat times, rates;
    sampleRates(shakeRate, 0.0, 1.0, 200, times, rates);
    const Ptr<CameraMotion> motion = CameraMotion::fromAngularVelocity(times, rates);
    const DenseReference ref(shakeRate, 0.0, 1.0, 1e-5);
    const double worst = worstOrientationError(*motion, ref, 37);
    std::printf("[ figure ] gyro 200 Hz, 3-axis shake 1-20 Hz <= 30 deg/s, 1 s: worst orientation error %.3g rad\n",
                worst);
    EXPECT_LT(worst, 6.5e-6);
}

TEST(CameraMotionGyro, FromPlantAndItsOwnVelocityAt1kHzAgree)
{
    const Ptr<Plant> plant = Plant::create(14.4, 0.12, kDeg);
    const SwitchSchedule schedule({0.05, 0.12}, {10, 6}, 0);
    const Vec3d axis = normalize(Vec3d(1, 0.4, -0.2));
    const Ptr<CameraMotion> exact = CameraMotion::fromPlant(plant, schedule, axis);
    Mat times, rates;
    sampleRates([&](double t) { return exact->angularVelocity(t); }, 0.0, 0.6, 1000, times, rates);
    const Ptr<CameraMotion> gyro = CameraMotion::fromAngularVelocity(times, rates, exact->orientation(0.0));
    double worst = 0;
    for (double t = 0; t <= 0.6; t += 0.0007)
        worst = std::max(worst, angleBetween(gyro->orientation(t), exact->orientation(t)));
    std::printf("[ figure ] fromPlant vs fromAngularVelocity (1 kHz), 10-level saccade: worst %.3g rad\n", worst);
    // All of it arises at the two switches, where the plant's acceleration steps and the rate's
    // interpolant cannot follow the kink; it does not grow between them.
    EXPECT_LT(worst, 1.3e-4);
    EXPECT_FALSE(gyro->isPlantMotion());
}

TEST(CameraMotionGyro, DefaultReferenceIsTheMiddleOfTheExposure)
{
    Mat times, rates;
    sampleRates(shakeRate, 0.0, 0.2, 200, times, rates);
    const Matx33d Q0 = rotationAbout(Vec3d(0, 1, 0), 0.3);
    const Ptr<CameraMotion> motion = CameraMotion::fromAngularVelocity(times, rates, Q0);
    EXPECT_LT(norm(motion->orientation(0.0) - Q0, NORM_INF), 1e-15);
    const RollingShutter shutter(0.05, 0.01, 30e-3 / 479, 480);
    const double middle = 0.05 + 0.5 * 479 * shutter.lineDelay + 0.005;
    EXPECT_LT(norm(motion->referenceOrientation(NAN, shutter) - motion->orientation(middle), NORM_INF), 1e-15);
    EXPECT_LT(norm(motion->referenceOrientation(0.07, shutter) - motion->orientation(0.07), NORM_INF), 1e-15);
    const Vec2d span = motion->getTimeSpan();
    EXPECT_EQ(span[0], 0.0);
    EXPECT_DOUBLE_EQ(span[1], 0.2);
}

// ------------------------------------------------------------------------------------ fromOrientations

struct OrientationSamples
{
    Mat times, rotvecs, quats, matrices;
};

//! The shake motion's orientation at `hz` from the dense reference (grid step 1e-5 s).
OrientationSamples sampleOrientations(const DenseReference& ref, double hz)
{
    OrientationSamples s;
    const size_t stride = size_t(std::lround(1.0 / (hz * ref.dt)));
    const int n = int((ref.q.size() - 1) / stride) + 1;
    s.times.create(n, 1, CV_64F);
    s.rotvecs.create(n, 3, CV_64F);
    s.quats.create(n, 4, CV_64F);
    s.matrices.create(n, 9, CV_64F);
    for (int k = 0; k < n; ++k)
    {
        const size_t i = size_t(k) * stride;
        s.times.at<double>(k) = ref.time(i);
        const Matx33d R = ref.orientation(i);
        Vec3d r;
        Rodrigues(R, r);
        for (int j = 0; j < 3; ++j)
            s.rotvecs.at<double>(k, j) = r[j];
        for (int j = 0; j < 4; ++j)
            s.quats.at<double>(k, j) = ref.q[i][j];
        for (int j = 0; j < 9; ++j)
            s.matrices.at<double>(k, j) = R.val[j];
    }
    return s;
}

TEST(CameraMotionOrientations, ReproducesAKnownSmoothMotion)
{
    const DenseReference ref(shakeRate, 0.0, 1.0, 1e-5);
    const OrientationSamples s = sampleOrientations(ref, 200);
    const Ptr<CameraMotion> motion = CameraMotion::fromOrientations(s.times, s.quats);
    double worstAngle = 0, worstRate = 0;
    for (size_t i = 0; i < ref.q.size(); i += 37)
    {
        worstAngle = std::max(worstAngle, angleBetween(motion->orientation(ref.time(i)), ref.orientation(i)));
        worstRate = std::max(worstRate, norm(motion->angularVelocity(ref.time(i)) - shakeRate(ref.time(i))));
    }
    std::printf("[ figure ] fromOrientations 200 Hz, 3-axis shake: worst orientation %.3g rad, worst rate %.3g rad/s "
                "(peak |w| %.3g rad/s)\n", worstAngle, worstRate, 30 * kDeg * std::sqrt(3.0));
    EXPECT_LT(worstAngle, 2.4e-5);
    EXPECT_LT(worstRate, 0.026);
}

TEST(CameraMotionOrientations, RotationVectorsQuaternionsAndMatricesGiveOneMotion)
{
    const DenseReference ref(shakeRate, 0.0, 0.3, 1e-4);
    const OrientationSamples s = sampleOrientations(ref, 100);
    const Ptr<CameraMotion> a = CameraMotion::fromOrientations(s.times, s.rotvecs);
    const Ptr<CameraMotion> b = CameraMotion::fromOrientations(s.times, s.quats);
    const Ptr<CameraMotion> c = CameraMotion::fromOrientations(s.times, s.matrices);
    for (double t = 0; t <= 0.3; t += 0.0031)
    {
        EXPECT_LT(norm(a->orientation(t) - b->orientation(t), NORM_INF), 1e-12) << t;
        EXPECT_LT(norm(c->orientation(t) - b->orientation(t), NORM_INF), 1e-12) << t;
        EXPECT_LT(norm(a->angularVelocity(t) - b->angularVelocity(t)), 1e-10) << t;
    }
    // At the samples the spline passes through them.
    for (int k = 0; k < s.times.rows; ++k)
        EXPECT_LT(norm(b->orientation(s.times.at<double>(k)) - Matx33d(s.matrices.ptr<double>(k)), NORM_INF), 1e-12);
}

TEST(CameraMotionOrientations, RateIsTheDerivativeOfTheOrientation)
{
    // Few, uneven samples of a large motion (up to ~80° between samples): the rate must still be
    // the body-frame derivative of orientation(t), and continuous across samples (C¹).
    Mat times = (Mat_<double>(5, 1) << 0.0, 0.1, 0.25, 0.3, 0.5);
    Mat rotvecs = (Mat_<double>(5, 3) << 0, 0, 0, 0.5, -0.3, 0.2, 1.2, 0.4, -0.5, 1.0, 1.1, -0.2, 0.2, 1.5, 0.9);
    const Ptr<CameraMotion> motion = CameraMotion::fromOrientations(times, rotvecs);
    const double eps = 1e-6;
    for (double t = 0.001; t < 0.499; t += 0.0123)
    {
        // vee((D − Dᵀ)/2) = sin θ·axis: the small rotation's vector to 1e-10 (cv::Rodrigues goes through acos).
        const Matx33d D = motion->orientation(t - eps).t() * motion->orientation(t + eps);
        const Vec3d numeric(0.5 * (D(2, 1) - D(1, 2)), 0.5 * (D(0, 2) - D(2, 0)), 0.5 * (D(1, 0) - D(0, 1)));
        EXPECT_LT(norm(numeric / (2 * eps) - motion->angularVelocity(t)), 1e-6) << t;
    }
    for (double tk : {0.1, 0.25, 0.3})
        EXPECT_LT(norm(motion->angularVelocity(tk - 1e-9) - motion->angularVelocity(tk + 1e-9)), 1e-6) << tk;
}

TEST(CameraMotionOrientations, TwoSamplesTurnAtAConstantRate)
{
    Mat times = (Mat_<double>(2, 1) << 1.0, 1.5);
    Mat rotvecs = (Mat_<double>(2, 3) << 0, 0, 0, 0, 0.4, 0);
    const Ptr<CameraMotion> motion = CameraMotion::fromOrientations(times, rotvecs);
    EXPECT_LT(norm(motion->angularVelocity(1.2) - Vec3d(0, 0.8, 0)), 1e-12);
    EXPECT_LT(norm(motion->orientation(1.25) - rotationAbout(Vec3d(0, 1, 0), 0.2), NORM_INF), 1e-12);
}

// ------------------------------------------------------------------------------------ bad input

using dynblur_test::expectErrorNaming;

Mat column(std::initializer_list<double> values)
{
    return Mat(std::vector<double>(values), true);
}

Mat zeros3(int n)
{
    return Mat::zeros(n, 3, CV_64F);
}

TEST(CameraMotionBadInput, Times)
{
    auto gyro = [](const Mat& t) { return [t] { CameraMotion::fromAngularVelocity(t, zeros3(t.rows)); }; };
    expectErrorNaming(gyro(column({0.0, 0.02, 0.01, 0.03})), "strictly increasing");
    expectErrorNaming(gyro(column({0.0, 0.01, 0.01, 0.02})), "times[2]");
    expectErrorNaming(gyro(column({0.0, 0.01, 0.02, 0.03, 0.07, 0.08})), "gap");
    expectErrorNaming(gyro(column({0.0, NAN, 0.02})), "times[1]");
    expectErrorNaming(gyro(column({0.0, 0.01, INFINITY})), "not finite");
    expectErrorNaming(gyro(column({0.5})), "at least 2");
    expectErrorNaming([] { CameraMotion::fromAngularVelocity(Mat::zeros(2, 2, CV_64F), zeros3(2)); }, "'times'");
    expectErrorNaming([] { CameraMotion::fromOrientations(column({0.0, 0.01, 0.0}), zeros3(3)); },
                      "fromOrientations");
    // A gap of three median intervals is allowed.
    EXPECT_NO_THROW(CameraMotion::fromAngularVelocity(column({0.0, 0.01, 0.02, 0.05, 0.06}), zeros3(5)));
}

TEST(CameraMotionBadInput, RatesAndRotations)
{
    const Mat t = column({0.0, 0.01, 0.02});
    expectErrorNaming([&] { CameraMotion::fromAngularVelocity(t, Mat::zeros(3, 2, CV_64F)); }, "N×3 body rates");
    expectErrorNaming([&] { CameraMotion::fromAngularVelocity(t, zeros3(4)); }, "has 4 rows");
    expectErrorNaming([&] { CameraMotion::fromAngularVelocity(t, Mat::zeros(3, 3, CV_32S)); }, "'rates'");
    Mat bad = zeros3(3);
    bad.at<double>(1, 2) = NAN;
    expectErrorNaming([&] { CameraMotion::fromAngularVelocity(t, bad); }, "rates[1][2]");
    expectErrorNaming([&] { CameraMotion::fromOrientations(t, Mat::zeros(3, 5, CV_64F)); }, "N×4 unit quaternions");
    bad.at<double>(1, 2) = INFINITY;
    expectErrorNaming([&] { CameraMotion::fromOrientations(t, bad); }, "rotations[1][2]");
    const Matx33d mirror(1, 0, 0, 0, 1, 0, 0, 0, -1);
    expectErrorNaming([&] { CameraMotion::fromAngularVelocity(t, zeros3(3), mirror); }, "initialOrientation");
    Mat matrices(3, 9, CV_64F);
    for (int k = 0; k < 3; ++k)
        Mat(Matx33d::eye()).reshape(1, 1).copyTo(matrices.row(k));
    matrices.at<double>(2, 8) = -1;  // a reflection: det = −1
    expectErrorNaming([&] { CameraMotion::fromOrientations(t, matrices); }, "rotations[2] is not a rotation");
    matrices.at<double>(2, 8) = 1.0004;  // within 1e-3 of a rotation: accepted and projected
    EXPECT_NO_THROW(CameraMotion::fromOrientations(t, matrices));
    matrices.at<double>(2, 1) = 0.2;  // det = +1 but not orthonormal
    expectErrorNaming([&] { CameraMotion::fromOrientations(t, matrices); }, "rotations[2] is not a rotation");
    Mat quats = (Mat_<double>(3, 4) << 1, 0, 0, 0, 0.9995, 0, 0, 0, 0.5, 0.5, 0.5, 0.6);
    expectErrorNaming([&] { CameraMotion::fromOrientations(t, quats); }, "rotations[2]");
    quats.at<double>(2, 3) = 0.5;
    EXPECT_NO_THROW(CameraMotion::fromOrientations(t, quats));
}

TEST(CameraMotionBadInput, TimeOutsideTheSpan)
{
    const Ptr<CameraMotion> gyro = CameraMotion::fromAngularVelocity(column({1.0, 1.01, 1.02}), zeros3(3));
    const Ptr<CameraMotion> poses = CameraMotion::fromOrientations(column({1.0, 1.01, 1.02}), zeros3(3));
    for (const Ptr<CameraMotion>& m : {gyro, poses})
    {
        expectErrorNaming([&] { m->orientation(0.99); }, "outside the motion's time span");
        expectErrorNaming([&] { m->angularVelocity(1.03); }, "t = 1.03");
        expectErrorNaming([&] { m->orientation(NAN); }, "outside");
        expectErrorNaming([&] { m->referenceOrientation(NAN, RollingShutter(1.01, 0.04, 0, 10)); },
                          "referenceOrientation");
        expectErrorNaming([&] { m->referenceOrientation(INFINITY, RollingShutter(1.0, 0.01, 0, 10)); }, "tRef");
        EXPECT_NO_THROW(m->orientation(1.02));
    }
}

}  // namespace
