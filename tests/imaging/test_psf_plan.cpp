// SPDX-License-Identifier: Apache-2.0
// PSF_AUTO: the plan (PsfPlan) chooses per band of rows the cheapest model within the tolerance, and
// never one the motion makes wrong: checked against a dense tile bank on a roll, a shake and a saccade.
#include "test_common.hpp"

#include "rotation_motion.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>

using namespace cv;
using namespace cv::dynblur;
using dynblur_test::Wave;
using dynblur_test::WaveMotion;

namespace {

const Size kSize(640, 480);

Ptr<CameraModel> testCamera() { return CameraModel::create(600, 600, 319.5, 239.5, kSize.width, kSize.height); }

//! A roll about the optical axis at `rateDegPerSec` (one sinusoid of 5 Hz peaking at that rate).
Ptr<CameraMotion> roll(double rateDegPerSec)
{
    const double rate = rateDegPerSec * CV_PI / 180;
    return makePtr<WaveMotion>(std::vector<Wave>{}, std::vector<Wave>{},
                               std::vector<Wave>{Wave{rate / (2 * CV_PI * 5.0), 5.0, 0.0}});
}

//! The mean displacement of node n of `bank` (its kernel's centroid from its centre, plus its shift), pixels.
Point2d meanDisplacement(const PsfBank& bank, size_t n)
{
    const Mat& k = bank.kernels[n];
    const Moments m = moments(k);
    return Point2d(m.m10 / m.m00 - (k.cols - 1) / 2.0, m.m01 / m.m00 - (k.rows - 1) / 2.0) + Point2d(bank.shifts[n]);
}

/* Every band the plan gives rows (or the frame one kernel) holds at every node row of a 64-column
   tile bank (the same node rows) kernels whose mean displacements stay within the tolerance of the
   centre column's (the frame centre's for PSF_UNIFORM); returns the worst such distance. */
double worstWhereCheaper(const PsfPlan& plan, const PsfBank& dense)
{
    const size_t nx = dense.nodeCols.size(), ny = dense.nodeRows.size();
    EXPECT_EQ(ny, plan.bandStart.size());
    double worst = 0;
    const Point2d frameCentre = meanDisplacement(dense, (ny / 2) * nx + nx / 2);
    for (size_t j = 0; j < std::min(ny, plan.bandStart.size()); j++)
    {
        if (plan.bandModel[j] == PSF_TILES)
            continue;
        const Point2d centre =
            plan.bandModel[j] == PSF_UNIFORM ? frameCentre : meanDisplacement(dense, j * nx + nx / 2);
        for (size_t i = 0; i < nx; i++)
            worst = std::max(worst, norm(meanDisplacement(dense, j * nx + i) - centre));
    }
    return worst;
}

}  // namespace

TEST(PsfPlan, RollAboutTheOpticalAxisNeverGetsRows)
{
    // A roll turns each row: its ends move apart by about the width times the roll's angle.
    Ptr<PsfGenerator> generator = PsfGenerator::create(testCamera());
    const RollingShutter shutter(0.01, 0.02, 62.5e-6, kSize.height);
    const PsfPlan plan = generator->plan(roll(30), shutter);
    ASSERT_FALSE(plan.bandStart.empty());
    EXPECT_EQ(plan.model, PSF_TILES);
    EXPECT_EQ(plan.rowShare(PSF_TILES), 1.0);
    for (size_t j = 0; j < plan.rowsError.size(); j++)
        EXPECT_GT(plan.rowsError[j], plan.tolerance) << "band " << j;
    const PsfBank bank = generator->generate(PSF_AUTO, roll(30), shutter);
    EXPECT_EQ(bank.model, PSF_TILES);
    EXPECT_GE(bank.nodeCols.size(), 8u);

    // A roll too slow to move anything by the tolerance takes one kernel for the frame.
    const PsfPlan slow = generator->plan(roll(0.05), shutter);
    std::printf("[ measured ] roll 30 deg/s: rows error %.2f-%.2f px; roll 0.05 deg/s: uniform error %.3f px\n",
                *std::min_element(plan.rowsError.begin(), plan.rowsError.end()),
                *std::max_element(plan.rowsError.begin(), plan.rowsError.end()), slow.uniformError);
    EXPECT_EQ(slow.model, PSF_UNIFORM);
    EXPECT_EQ(slow.rowShare(PSF_UNIFORM), 1.0);
    const PsfBank one = generator->generate(PSF_AUTO, roll(0.05), shutter);
    EXPECT_EQ(one.model, PSF_UNIFORM);
    EXPECT_EQ(one.kernels.size(), 1u);
}

TEST(PsfPlan, CheaperModelsOnlyWhereADenseBankAgrees)
{
    /* A tilt saccade (the keystone grows with the move, so bands differ), a hand shake and a pan
       with a small roll: wherever the plan gives a band rows (or the frame one kernel), a dense
       bank's kernels agree with it to the tolerance plus the kernels' own sampling (0.1 px). */
    Ptr<CameraModel> camera = testCamera();
    const Ptr<Plant> plant = Plant::create(14.4, 0.12, CV_PI / 180);
    SwitchSchedule saccade;
    saccade.times = {0.0, 0.004, 0.007, 0.012};
    saccade.levels = {6, 3, 12, 10};
    struct Case
    {
        const char* name;
        Ptr<CameraMotion> motion;
        RollingShutter shutter;
    };
    const std::vector<Case> cases = {
        {"tilt saccade, window III rolling", CameraMotion::fromPlant(plant, saccade),
         RollingShutter(0.0, 0.008, 1.0 / 30 / 480, kSize.height)},
        {"tilt saccade, global", CameraMotion::fromPlant(plant, saccade), RollingShutter(0.012, 0.008, 0, kSize.height)},
        {"hand shake 30 deg/s", dynblur_test::handShake(30), RollingShutter(0.1, 0.02, 62.5e-6, kSize.height)},
        {"pan with a slow roll",
         makePtr<WaveMotion>(std::vector<Wave>{}, std::vector<Wave>{Wave{0.02, 4.0, 0.3}},
                             std::vector<Wave>{Wave{0.0005, 4.0, 0.3}}),
         RollingShutter(0.1, 0.01, 62.5e-6, kSize.height)},
    };
    int cheaperBands = 0;
    for (const Case& c : cases)
    {
        Ptr<PsfGenerator> generator = PsfGenerator::create(camera);
        generator->setAutoTolerance(0.5);  // twice the default: these frames then get rows bands to check
        const PsfPlan plan = generator->plan(c.motion, c.shutter);
        generator->setTileGrid(Size(64, 0));
        const PsfBank dense = generator->generate(PSF_TILES, c.motion, c.shutter);
        const double worst = worstWhereCheaper(plan, dense);
        std::printf("[ measured ] %s: operator %d, rows given uniform / rows / tiles %.0f / %.0f / %.0f %%, worst "
                    "mean-displacement difference where cheaper %.3f px\n",
                    c.name, plan.model, 100 * plan.rowShare(PSF_UNIFORM), 100 * plan.rowShare(PSF_ROWS),
                    100 * plan.rowShare(PSF_TILES), worst);
        EXPECT_LE(worst, plan.tolerance + 0.1) << c.name;
        for (int model : plan.bandModel)
            cheaperBands += model != PSF_TILES;
    }
    EXPECT_GT(cheaperBands, 0) << "no case gave a band a cheaper model: the check above checked nothing";
}

TEST(PsfPlan, MixedBankSharesOneKernelAcrossARowsBand)
{
    /* A saccade that leaves the last rows of a rolling frame nearly still: tiles above, rows there
       (at twice the default tolerance; the bank is built the same way at any). */
    Ptr<PsfGenerator> generator = PsfGenerator::create(testCamera());
    generator->setAutoTolerance(0.5);
    SwitchSchedule saccade;
    saccade.times = {0.0, 0.004, 0.007, 0.012};
    saccade.levels = {6, 3, 12, 10};
    const Ptr<CameraMotion> motion = CameraMotion::fromPlant(Plant::create(14.4, 0.12, CV_PI / 180), saccade);
    const RollingShutter shutter(0.0, 0.008, 1.0 / 30 / 480, kSize.height);
    const PsfPlan plan = generator->plan(motion, shutter);
    ASSERT_GT(plan.rowShare(PSF_ROWS), 0.0);
    ASSERT_GT(plan.rowShare(PSF_TILES), 0.0);
    const PsfBank bank = generator->generate(PSF_AUTO, motion, shutter);
    ASSERT_EQ(bank.model, PSF_TILES);
    bank.validate();
    ASSERT_EQ(bank.nodeRows.size(), plan.bandModel.size());
    const size_t nx = bank.nodeCols.size();
    int shared = 0;
    for (size_t j = 0; j < plan.bandModel.size(); j++)
        for (size_t i = 1; i < nx && plan.bandModel[j] == PSF_ROWS; i++, shared++)
        {
            EXPECT_EQ(bank.shifts[j * nx + i], bank.shifts[j * nx]);
            EXPECT_EQ(norm(bank.kernels[j * nx + i], bank.kernels[j * nx], NORM_INF), 0.0);
        }
    EXPECT_GT(shared, 0);
    // The bank restores: a frame it blurred comes back closer to the latent image.
    Mat latent(kSize, CV_32FC1), blurred, restored;
    randu(latent, 0.1, 0.9);
    GaussianBlur(latent, latent, Size(0, 0), 2);
    applyPsfBank(latent, bank, blurred);
    RLParams params;
    params.iterations = 10;
    richardsonLucyVariant(blurred, bank, restored, params);
    const Rect inner(40, 40, kSize.width - 80, kSize.height - 80);
    EXPECT_LT(norm(restored(inner), latent(inner), NORM_L1), 0.8 * norm(blurred(inner), latent(inner), NORM_L1));
}

TEST(PsfPlan, BadInputIsRefused)
{
    Ptr<PsfGenerator> generator = PsfGenerator::create(testCamera());
    for (double bad : {0.0, -0.5, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()})
        dynblur_test::expectErrorNaming([&] { generator->setAutoTolerance(bad); }, "pixels");
    EXPECT_EQ(generator->getAutoTolerance(), 0.25);
    dynblur_test::expectErrorNaming([&] { generator->generate(4, roll(30), RollingShutter(0.01, 0.02, 0, 480)); },
                                    "PSF_AUTO");
    dynblur_test::expectErrorNaming([&] { generator->plan(roll(30), RollingShutter(0.01, 0.02, 0, 479)); }, "rows");
    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(testCamera());
    EXPECT_EQ(deblurrer->getPsfModel(), PSF_AUTO);
    dynblur_test::expectErrorNaming([&] { deblurrer->setPreset(2); }, "DEBLUR_PRESET_FRAME_RATE");
    dynblur_test::expectErrorNaming([&] { deblurrer->setPsfModel(4); }, "PSF_AUTO");
    RLParams params;
    params.iterations = 0;
    dynblur_test::expectErrorNaming([&] { deblurrer->setRLParams(params); }, "iterations");
}

TEST(PsfPlan, DeblurrerReportsThePlanOfARoll)
{
    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(testCamera());
    const RollingShutter shutter(0.01, 0.02, 62.5e-6, kSize.height);
    Mat frame(kSize, CV_32FC1, Scalar(0.5)), restored;
    randu(frame, 0.2, 0.8);
    deblurrer->deblur(frame, roll(30), shutter, restored);
    const PsfPlan plan = deblurrer->getLastPlan();
    EXPECT_EQ(plan.model, PSF_TILES);
    EXPECT_EQ(plan.rowShare(PSF_TILES), 1.0);
    EXPECT_EQ(deblurrer->getLastPsfBank().model, PSF_TILES);

    deblurrer->setPsfModel(PSF_ROWS);  // a fixed model: only the model is reported
    deblurrer->deblur(frame, roll(30), shutter, restored);
    EXPECT_EQ(deblurrer->getLastPlan().model, PSF_ROWS);
    EXPECT_TRUE(deblurrer->getLastPlan().bandStart.empty());

    deblurrer->setPreset(DEBLUR_PRESET_FRAME_RATE);
    EXPECT_EQ(deblurrer->getPsfModel(), PSF_AUTO);
    EXPECT_EQ(deblurrer->getRLParams().blurPrecision, RL_BLUR_BFLOAT16);
    EXPECT_GT(deblurrer->getRLParams().tolerance, 0.0);
    EXPECT_EQ(deblurrer->getColorResolution(), DEBLUR_COLOR_HALF_RESOLUTION);
    deblurrer->setPreset(DEBLUR_PRESET_DEFAULT);
    EXPECT_EQ(deblurrer->getRLParams().iterations, 20);
    EXPECT_EQ(deblurrer->getColorResolution(), DEBLUR_COLOR_FULL_RESOLUTION);
    EXPECT_TRUE(std::isnan(deblurrer->getRLParams().damping));
}
