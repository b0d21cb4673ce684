// PsfBank / PsfGenerator, cross-checked against the independent forward model renderBlurred.
#include "test_common.hpp"

#include <opencv2/dynblur.hpp>

using namespace cv;
using namespace cv::dynblur;

namespace {

SwitchSchedule saccade() { return SwitchSchedule({0.0, 0.0127, 0.0296}, {16, 4, 10}, 0); }
Ptr<Plant> seedPlant() { return Plant::create(14.4, 0.12, CV_PI / 180.0); }

//! Blurred value at pixel p of a unit point at latent pixel q, from the bank's blending formula
//! B(p) = Σ_n w_n(p) k_n(p − q − s_n + c_n).
double bankPointSpread(const PsfBank& bank, Point q, Point p)
{
    auto bracket = [](const std::vector<double>& nodes, double v, int& i0, int& i1, double& t) {
        const int n = (int)nodes.size();
        if (n == 1 || v <= nodes[0])
        {
            i0 = i1 = 0;
            t = 0;
            return;
        }
        if (v >= nodes[n - 1])
        {
            i0 = i1 = n - 1;
            t = 0;
            return;
        }
        i0 = (int)(std::upper_bound(nodes.begin(), nodes.end(), v) - nodes.begin()) - 1;
        i1 = i0 + 1;
        t = (v - nodes[i0]) / (nodes[i1] - nodes[i0]);
    };
    int r0, r1, c0, c1;
    double ty, tx;
    bracket(bank.nodeRows, p.y, r0, r1, ty);
    bracket(bank.nodeCols, p.x, c0, c1, tx);
    const int nx = (int)bank.nodeCols.size();
    double v = 0;
    const int rs[2] = {r0, r1}, cs[2] = {c0, c1};
    const double wy[2] = {1 - ty, ty}, wx[2] = {1 - tx, tx};
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++)
        {
            const double w = wy[j] * wx[i];
            if (w == 0)
                continue;
            const int n = rs[j] * nx + cs[i];
            const Mat& k = bank.kernels[n];
            const Point u = p - q - bank.shifts[n] + Point((k.cols - 1) / 2, (k.rows - 1) / 2);
            if (u.x >= 0 && u.y >= 0 && u.x < k.cols && u.y < k.rows)
                v += w * k.at<float>(u.y, u.x);
        }
    return v;
}

//! The renderer's spot of a unit point at latent pixel q.
Mat renderPoint(const Ptr<Plant>& plant, const SwitchSchedule& sched, const Ptr<CameraModel>& cam,
                const RollingShutter& rs, Point q)
{
    Mat sharp(cam->getImageSize(), CV_64F, Scalar(0)), blurred;
    sharp.at<double>(q) = 1.0;
    renderBlurred(sharp, plant, sched, cam, rs, blurred, NAN, 0.1, BORDER_CONSTANT);
    return blurred;
}

//! Relative L1 difference between a rendered spot and the bank's prediction, over the window
//! where either is non-zero.
double spotError(const Mat& blurred, const PsfBank& bank, Point q, Rect* spot = nullptr,
                 double* centroidError = nullptr)
{
    double diff = 0, total = 0, totalE = 0;
    Point2d cs(0, 0), ce(0, 0);
    Rect box;
    for (int y = 0; y < blurred.rows; y++)
        for (int x = 0; x < blurred.cols; x++)
        {
            const double s = blurred.at<double>(y, x);
            const double e = bankPointSpread(bank, q, Point(x, y));
            if (s == 0 && e == 0)
                continue;
            box |= Rect(x, y, 1, 1);
            diff += std::abs(s - e);
            total += s;
            totalE += e;
            cs += s * Point2d(x, y);
            ce += e * Point2d(x, y);
        }
    if (spot)
        *spot = box;
    if (centroidError)
        *centroidError = total > 0 && totalE > 0 ? norm(cs * (1 / total) - ce * (1 / totalE)) : 1e9;
    return total > 0 ? diff / total : 1.0;
}

//! A point q whose blurred spot, under kernel n, is centred at pixel p: q = p − shift.
Point latentFor(const PsfBank& bank, Point p)
{
    double best = 1e30;
    int n0 = 0;
    const int nx = (int)bank.nodeCols.size();
    for (int n = 0; n < (int)bank.kernels.size(); n++)
    {
        const double d = std::abs(bank.nodeRows[n / nx] - p.y) + std::abs(bank.nodeCols[n % nx] - p.x);
        if (d < best)
        {
            best = d;
            n0 = n;
        }
    }
    return p - bank.shifts[n0];
}

void expectWellFormed(const PsfBank& bank)
{
    EXPECT_NO_THROW(bank.validate());
    for (const Mat& k : bank.kernels)
    {
        ASSERT_EQ(k.type(), CV_32F);
        EXPECT_EQ(k.rows % 2, 1);
        EXPECT_EQ(k.cols % 2, 1);
        double mn;
        minMaxLoc(k, &mn);
        EXPECT_GE(mn, 0.0);
        EXPECT_NEAR(sum(k)[0], 1.0, 1e-5);
    }
}

}  // namespace

TEST(PsfBank, ValidateCatchesInconsistency)
{
    PsfBank b;
    b.imageSize = Size(10, 10);
    b.nodeRows = {4.5};
    b.nodeCols = {4.5};
    b.kernels = {Mat(1, 1, CV_32F, Scalar(1))};
    b.shifts = {Point(0, 0)};
    EXPECT_NO_THROW(b.validate());
    EXPECT_TRUE(b.isIdentity());
    EXPECT_EQ(b.maxKernelSize(), Size(1, 1));
    b.shifts[0] = Point(1, 0);
    EXPECT_FALSE(b.isIdentity());
    PsfBank c = b;
    c.kernels[0] = Mat(2, 1, CV_32F, Scalar(0.5));
    dynblur_test::expectErrorNaming([&] { c.validate(); }, "odd");
    c = b;
    c.kernels[0] = Mat(1, 1, CV_32F, Scalar(0.5));
    dynblur_test::expectErrorNaming([&] { c.validate(); }, "sum");
    c = b;
    c.shifts.clear();
    dynblur_test::expectErrorNaming([&] { c.validate(); }, "shifts");
    c = b;
    c.nodeRows = {4.5, 2.0};
    dynblur_test::expectErrorNaming([&] { c.validate(); }, "nodeRows");
}

TEST(PsfGenerator, StillFrameIsIdentity)
{
    Ptr<CameraModel> cam = CameraModel::create(1230, 1230, 640, 480, 1280, 960, -0.05, 0.05);
    Ptr<PsfGenerator> gen = PsfGenerator::create(seedPlant(), cam);
    const RollingShutter late(3.0, 0.008, 1.0 / 30 / 960, 960);
    for (int model : {PSF_UNIFORM, PSF_ROWS, PSF_TILES})
    {
        const PsfBank bank = gen->generate(model, saccade(), late);
        expectWellFormed(bank);
        EXPECT_TRUE(bank.isIdentity()) << model;
        EXPECT_EQ(bank.nodeRows.size(), 1u) << "a still frame needs one band";
    }
    // Also an empty schedule
    EXPECT_TRUE(gen->generate(PSF_ROWS, SwitchSchedule(), RollingShutter(0, 0.008, 3e-5, 960)).isIdentity());
}

TEST(PsfGenerator, KernelsAreWellFormedAndBandsFollowTheMotion)
{
    Ptr<CameraModel> cam = CameraModel::create(1230, 1230, 640, 480, 1280, 960);
    Ptr<PsfGenerator> gen = PsfGenerator::create(seedPlant(), cam);
    const RollingShutter rs(0.0, 0.008, 1.0 / 30 / 960, 960);
    const PsfBank uni = gen->generate(PSF_UNIFORM, saccade(), rs);
    ASSERT_EQ(uni.kernels.size(), 1u);
    EXPECT_DOUBLE_EQ(uni.nodeRows[0], 479.5);
    EXPECT_DOUBLE_EQ(uni.nodeCols[0], 639.5);
    expectWellFormed(uni);
    EXPECT_FALSE(uni.isIdentity());

    const PsfBank rows = gen->generate(PSF_ROWS, saccade(), rs);
    expectWellFormed(rows);
    EXPECT_EQ(rows.nodeCols.size(), 1u);
    EXPECT_GT(rows.nodeRows.size(), 20u);
    std::cout << "[ INFO     ] automatic row bands during a saccade: " << rows.nodeRows.size() << " for 960 rows"
              << std::endl;
    // adjacent kernels: path ends within the band tolerance → centroids close
    gen->setBandRows(16);
    EXPECT_EQ(gen->generate(PSF_ROWS, saccade(), rs).nodeRows.size(), 60u);
    gen->setBandRows(1);
    const PsfBank perRow = gen->generate(PSF_ROWS, saccade(), rs);
    EXPECT_EQ(perRow.nodeRows.size(), 960u);
    EXPECT_DOUBLE_EQ(perRow.nodeRows[17], 17.0);
    gen->setBandRows(0);

    const PsfBank tiles = gen->generate(PSF_TILES, saccade(), rs);
    expectWellFormed(tiles);
    EXPECT_GE(tiles.nodeCols.size(), 8u);
    EXPECT_LE(tiles.nodeCols.size(), 64u);
    std::cout << "[ INFO     ] automatic tile grid: " << tiles.nodeCols.size() << " x " << tiles.nodeRows.size()
              << std::endl;
    gen->setTileGrid(Size(4, 3));
    const PsfBank grid = gen->generate(PSF_TILES, saccade(), rs);
    EXPECT_EQ(grid.nodeCols.size(), 4u);
    EXPECT_EQ(grid.nodeRows.size(), 3u);
    EXPECT_EQ(grid.kernels.size(), 12u);
    EXPECT_DOUBLE_EQ(grid.nodeCols[0], 159.5);

    // NaN thetaRef is the final resting angle
    const PsfBank explicitRef = gen->generate(PSF_UNIFORM, saccade(), rs, 10 * CV_PI / 180);
    EXPECT_EQ(explicitRef.shifts[0], uni.shifts[0]);
    EXPECT_EQ(norm(explicitRef.kernels[0], uni.kernels[0], NORM_INF), 0.0);
}

TEST(PsfGenerator, PointSourceMatchesRendererGlobalShutter)
{
    // Global shutter, seed's window III-like frame: the uniform kernel is exact at the centre.
    Ptr<CameraModel> cam = CameraModel::create(1230, 1230, 160, 120, 320, 240);
    Ptr<PsfGenerator> gen = PsfGenerator::create(seedPlant(), cam);
    const RollingShutter gs(0.030, 0.008, 0.0, 240);
    const PsfBank bank = gen->generate(PSF_UNIFORM, saccade(), gs);
    ASSERT_GT(bank.maxKernelSize().area(), 9);
    const Point q = latentFor(bank, Point(160, 120));
    const double err = spotError(renderPoint(seedPlant(), saccade(), cam, gs, q), bank, q);
    std::cout << "[ INFO     ] point source, uniform, global shutter: L1 error " << err << std::endl;
    EXPECT_LT(err, 0.03);
}

TEST(PsfGenerator, PointSourceMatchesRendererRollingShutter)
{
    // Window I: rows above ~115 are exposed before the move (shift of the whole move, ≈ −214 px),
    // rows below in motion. Per-row kernels (band 1) and automatic bands against the renderer.
    // Odd width: the row model's node column is the integer column 320.
    Ptr<CameraModel> cam = CameraModel::create(1230, 1230, 320, 480, 641, 960);
    const RollingShutter rs(-0.012, 0.008, 1.0 / 30 / 960, 960);
    ASSERT_EQ(classifyExposure(seedPlant(), saccade(), rs), EXPOSURE_I);
    Ptr<PsfGenerator> gen = PsfGenerator::create(seedPlant(), cam);
    gen->setBandRows(1);
    const PsfBank perRow = gen->generate(PSF_ROWS, saccade(), rs);
    gen->setBandRows(0);
    const PsfBank autoRows = gen->generate(PSF_ROWS, saccade(), rs);
    // Blending neighbouring tiles whose integer shifts differ (the keystone of a 10° offset) spreads
    // a point source; at a 10 px column spacing the spot stays close. The automatic grid uses
    // fewer columns, which costs images < 0.1 dB (DeblurQuality) but not a single point.
    gen->setTileGrid(Size(64, 0));
    const PsfBank tiles = gen->generate(PSF_TILES, saccade(), rs);
    gen->setTileGrid(Size(0, 0));
    expectWellFormed(perRow);
    expectWellFormed(autoRows);
    expectWellFormed(tiles);

    // Still row: a one-tap kernel far away.
    EXPECT_LE(perRow.kernels[50].total(), 9u);
    EXPECT_LT(perRow.shifts[50].y, -200);
    EXPECT_EQ(perRow.shifts[50].x, 0);

    // Row 50 is still but sees the whole move: besides the 214 px shift, the view is magnified by
    // ≈ 9% across x (keystone of a 10° tilt), which no shift-invariant kernel represents at the
    // one-pixel scale of a point; the spot's centroid must still agree.
    for (int row : {50, 300, 800})
    {
        const Point p(320, row);
        const Point q = latentFor(perRow, p);
        if (q.y < 0 || q.y >= 960)
            continue;
        Rect spot;
        double c1, c2, c3;
        const Mat blurred = renderPoint(seedPlant(), saccade(), cam, rs, q);
        const double e1 = spotError(blurred, perRow, q, &spot, &c1);
        const double e2 = spotError(blurred, autoRows, q, nullptr, &c2);
        const double e3 = spotError(blurred, tiles, q, nullptr, &c3);
        std::cout << "[ INFO     ] point source at latent " << q << " (spot " << spot << "): L1 error per-row " << e1
                  << ", auto rows " << e2 << ", tiles " << e3 << "; centroid error " << c1 << ", " << c2 << ", "
                  << c3 << " px" << std::endl;
        const double tol = row == 50 ? 0.15 : 0.07;
        EXPECT_LT(e1, tol) << row;
        EXPECT_LT(e2, tol) << row;
        EXPECT_LT(e3, 3 * tol) << row;  // blending kernels of neighbouring columns (keystone)
        if (row == 50)
        {
            // a compact spot: its centroid is a sharp test of the large shift
            EXPECT_LT(c1, 0.05) << row;
            EXPECT_LT(c2, 0.05) << row;
            EXPECT_LT(c3, 0.05) << row;
        }
    }
}

TEST(PsfGenerator, TilesCaptureColumnVariation)
{
    // A mount axis with a roll component: the blur at the image corners differs from the centre
    // column's, which the row model cannot represent.
    Ptr<CameraModel> cam = CameraModel::create(800, 800, 320, 240, 640, 480, -0.1, 0.1);
    cam->setMountAxis(Vec3d(1, 0, 0.6));
    const RollingShutter rs(0.005, 0.008, 1.0 / 30 / 480, 480);
    Ptr<PsfGenerator> gen = PsfGenerator::create(seedPlant(), cam);
    const PsfBank rows = gen->generate(PSF_ROWS, saccade(), rs);
    gen->setTileGrid(Size(16, 0));
    const PsfBank tiles = gen->generate(PSF_TILES, saccade(), rs);
    for (const Point p : {Point(20, 300), Point(620, 300)})
    {
        const Point q = latentFor(tiles, p);
        if (q.x < 0 || q.y < 0 || q.x >= 640 || q.y >= 480)
            continue;
        const Mat blurred = renderPoint(seedPlant(), saccade(), cam, rs, q);
        const double eRows = spotError(blurred, rows, q);
        const double eTiles = spotError(blurred, tiles, q);
        std::cout << "[ INFO     ] corner " << p << ": L1 error rows " << eRows << ", tiles " << eTiles << std::endl;
        EXPECT_LT(eTiles, 0.15);
        EXPECT_GT(eRows, 3 * eTiles);
    }
}

TEST(PsfGenerator, MaxKernelSizeError)
{
    Ptr<CameraModel> cam = CameraModel::create(1230, 1230, 640, 480, 1280, 960);
    Ptr<PsfGenerator> gen = PsfGenerator::create(seedPlant(), cam);
    EXPECT_EQ(gen->getMaxKernelSize(), 401);
    gen->setMaxKernelSize(9);
    const RollingShutter rs(0.0, 0.008, 1.0 / 30 / 960, 960);
    try
    {
        gen->generate(PSF_UNIFORM, saccade(), rs);
        ADD_FAILURE() << "expected the kernel-size error";
    }
    catch (const cv::Exception& e)
    {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("limit of 9"), std::string::npos) << msg;
        EXPECT_NE(msg.find("raise it with PsfGenerator::setMaxKernelSize"), std::string::npos) << msg;
    }
    dynblur_test::expectErrorNaming([&] { gen->setMaxKernelSize(0); }, "pixels");
}

TEST(PsfGenerator, BadArgumentsNameTheArgument)
{
    Ptr<CameraModel> cam = CameraModel::create(300, 300, 80, 60, 160, 120);
    Ptr<PsfGenerator> gen = PsfGenerator::create(seedPlant(), cam);
    const RollingShutter rs(0.0, 0.008, 1e-4, 120);
    dynblur_test::expectErrorNaming([&] { gen->generate(3, saccade(), rs); }, "model");
    dynblur_test::expectErrorNaming([&] { gen->generate(PSF_ROWS, saccade(), RollingShutter(0, 0.008, 1e-4, 100)); },
                      "shutter.rows");
    dynblur_test::expectErrorNaming([&] { gen->generate(PSF_ROWS, saccade(), RollingShutter(0, -1, 1e-4, 120)); },
                      "shutter.exposure");
    dynblur_test::expectErrorNaming([&] { gen->generate(PSF_ROWS, saccade(), rs, INFINITY); }, "thetaRef");
    EXPECT_NO_THROW(gen->generate(PSF_ROWS, saccade(), rs, NAN));
    dynblur_test::expectErrorNaming([&] { gen->setBandRows(-1); }, "rows");
    dynblur_test::expectErrorNaming([&] { gen->setTileGrid(Size(-1, 2)); }, "grid");
    EXPECT_THROW(PsfGenerator::create(Ptr<Plant>(), cam), cv::Exception);
    EXPECT_THROW(PsfGenerator::create(seedPlant(), Ptr<CameraModel>()), cv::Exception);
}
