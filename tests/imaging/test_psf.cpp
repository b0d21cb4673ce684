// SPDX-License-Identifier: Apache-2.0
// PsfBank / PsfGenerator, cross-checked against the independent forward model renderBlurred.
#include "test_common.hpp"

#include <opencv2/dynblur.hpp>

#include <cstdio>

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


//! A kernel in the bank's convention: weights around the centre element, plus an integer shift.
struct ShiftedKernel
{
    Mat k;  // CV_64F
    Point shift;
};

/** The straightforward computation of one node's kernel, independent of PsfGenerator's numerics:
the node's path d(t) = p − viewToReference(p, θ(t) − θ_ref) sampled uniformly in time (the plant's
own response at every sample) so that consecutive samples are at most `stepPx` apart, splatted
bilinearly with trapezoid (dwell-time) weights and normalised; shift and extents from the samples'
bounding box, as documented for PsfBank. */
ShiftedKernel referenceKernel(const Ptr<Plant>& plant, const SwitchSchedule& sched, const Ptr<CameraModel>& cam,
                              const RollingShutter& rs, double thetaRef, Point2d pixel, double stepPx)
{
    const double a = rs.frameStart + pixel.y * rs.lineDelay, b = a + rs.exposure;
    auto path = [&](int n, std::vector<Point2d>& d) {
        Mat t(1, n + 1, CV_64F), theta;
        for (int i = 0; i <= n; i++)
            t.at<double>(i) = n == 0 ? a : a + (b - a) * i / n;
        plant->response(sched, t, theta);
        d.resize(n + 1);
        for (int i = 0; i <= n; i++)
            d[i] = pixel - cam->viewToReference(pixel, theta.at<double>(i) - thetaRef);
    };
    std::vector<Point2d> d;
    int n = b > a ? 256 : 0;
    path(n, d);
    double longest = 0;
    for (int i = 1; i <= n; i++)
        longest = std::max(longest, norm(d[i] - d[i - 1]));
    if (longest > stepPx)
    {
        n = (int)std::min(4.0e5, std::ceil(n * longest / stepPx) * 1.2);
        path(n, d);
    }
    double x0 = d[0].x, x1 = x0, y0 = d[0].y, y1 = y0;
    for (const Point2d& p : d)
    {
        x0 = std::min(x0, p.x);
        x1 = std::max(x1, p.x);
        y0 = std::min(y0, p.y);
        y1 = std::max(y1, p.y);
    }
    ShiftedKernel r;
    r.shift = Point(cvRound(0.5 * (x0 + x1)), cvRound(0.5 * (y0 + y1)));
    const int hx = std::max(0, (int)std::ceil(std::max(x1 - r.shift.x, r.shift.x - x0) - 1e-6));
    const int hy = std::max(0, (int)std::ceil(std::max(y1 - r.shift.y, r.shift.y - y0) - 1e-6));
    r.k = Mat::zeros(2 * hy + 1, 2 * hx + 1, CV_64F);
    for (int i = 0; i <= n; i++)
    {
        const double w = n == 0 ? 1.0 : (i == 0 || i == n ? 0.5 : 1.0);
        const double u = std::min((double)hx, std::max((double)-hx, d[i].x - r.shift.x));
        const double v = std::min((double)hy, std::max((double)-hy, d[i].y - r.shift.y));
        const int iu = std::min(hx - (hx > 0 ? 1 : 0), cvFloor(u)), iv = std::min(hy - (hy > 0 ? 1 : 0), cvFloor(v));
        const double fu = u - iu, fv = v - iv;
        for (int j = 0; j < 2; j++)
            for (int i2 = 0; i2 < 2; i2++)
            {
                const double wk = w * (j ? fv : 1 - fv) * (i2 ? fu : 1 - fu);
                if (wk != 0)
                    r.k.at<double>(iv + j + hy, iu + i2 + hx) += wk;
            }
    }
    r.k /= sum(r.k)[0];
    return r;
}

//! Σ|a − b| of two kernels with the same shift, each around its centre element.
double kernelL1(const Mat& a, const Mat& b)
{
    const int hx = std::max(a.cols, b.cols) / 2, hy = std::max(a.rows, b.rows) / 2;
    Mat ca = Mat::zeros(2 * hy + 1, 2 * hx + 1, CV_64F), cb = ca.clone();
    Mat a64, b64;
    a.convertTo(a64, CV_64F);
    b.convertTo(b64, CV_64F);
    a64.copyTo(ca(Rect(hx - a.cols / 2, hy - a.rows / 2, a.cols, a.rows)));
    b64.copyTo(cb(Rect(hx - b.cols / 2, hy - b.rows / 2, b.cols, b.rows)));
    return norm(ca, cb, NORM_L1);
}

/** Compares every `every`-th kernel of a bank (and the last) with referenceKernel: same shift, L1
difference at most `tol`. Prints the largest and mean L1. */
void expectMatchesReference(const PsfBank& bank, const Ptr<Plant>& plant, const SwitchSchedule& sched,
                            const Ptr<CameraModel>& cam, const RollingShutter& rs, int every, double tol,
                            const std::string& what)
{
    const double thetaRef = plant->restingAngle(sched.finalLevel());
    const int nx = (int)bank.nodeCols.size(), n = (int)bank.kernels.size();
    double worst = 0, mean = 0;
    int count = 0, spread = 0;
    for (int i = 0; i < n; i = (i + every < n || i == n - 1) ? i + every : n - 1)
    {
        const Point2d pixel(bank.nodeCols[i % nx], bank.nodeRows[i / nx]);
        const ShiftedKernel ref = referenceKernel(plant, sched, cam, rs, thetaRef, pixel, 0.01);
        EXPECT_EQ(bank.shifts[i], ref.shift) << what << ", kernel " << i << " at " << pixel;
        const double l1 = kernelL1(bank.kernels[i], ref.k);
        EXPECT_LE(l1, tol) << what << ", kernel " << i << " at " << pixel << ", " << bank.kernels[i].size()
                           << " vs reference " << ref.k.size();
        worst = std::max(worst, l1);
        mean += l1;
        count++;
        spread += ref.k.total() > 1;
        if (i == n - 1)
            break;
    }
    std::printf("[ measured ] kernels vs dense reference, %s: %d kernels (%d of more than one tap), L1 max %.2e, mean %.2e\n",
                what.c_str(), count, spread, worst, mean / std::max(1, count));
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
    int checked = 0;
    for (int row : {50, 300, 800})
    {
        const Point p(320, row);
        const Point q = latentFor(perRow, p);
        if (q.y < 0 || q.y >= 960)
            continue;
        ++checked;
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
    // Every point is checked (its latent point lies in the frame): a sweep that checked none would pass.
    EXPECT_EQ(checked, 3);
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
    int checked = 0;
    for (const Point p : {Point(20, 300), Point(620, 300)})
    {
        const Point q = latentFor(tiles, p);
        if (q.x < 0 || q.y < 0 || q.x >= 640 || q.y >= 480)
            continue;
        ++checked;
        const Mat blurred = renderPoint(seedPlant(), saccade(), cam, rs, q);
        const double eRows = spotError(blurred, rows, q);
        const double eTiles = spotError(blurred, tiles, q);
        std::cout << "[ INFO     ] corner " << p << ": L1 error rows " << eRows << ", tiles " << eTiles << std::endl;
        EXPECT_LT(eTiles, 0.15);
        EXPECT_GT(eRows, 3 * eTiles);
    }
    EXPECT_EQ(checked, 2) << "a corner's latent point fell outside the frame: the sweep checked fewer corners";
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
    dynblur_test::expectErrorNaming([&] { gen->generate(4, saccade(), rs); }, "model");
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

TEST(PsfGenerator, KernelsMatchADenseReference)
{
    // The generator's kernels (Hermite trajectory between exact plant samples, exact integration
    // of the bilinear splat along the path) against the plain computation: same shifts, L1 ≤ 1e-3.
    const double tol = 1e-3;
    const Ptr<Plant> plant = seedPlant();
    {
        // The benchmark's frames: the three-switch saccade from the frame start, and the robust
        // plan's window-III frame of the deblurring benchmark.
        Ptr<CameraModel> cam = CameraModel::create(1230, 1230, 640, 480, 1280, 960);
        const RollingShutter rs(0.0, 0.008, 1.0 / 30 / 960, 960);
        const PsfBank rows = PsfGenerator::create(plant, cam)->generate(PSF_ROWS, saccade(), rs);
        expectMatchesReference(rows, plant, saccade(), cam, rs, 24, tol, "saccade frame, rows");
    }
    {
        Ptr<CameraModel> cam = CameraModel::create(1230, 1230, 639.5, 479.5, 1280, 960);
        const SwitchSchedule robust = SwitchPlanner::create(plant, 16, PLAN_ROBUST)->plan(0.0, 10 * CV_PI / 180, 0.0);
        const RollingShutter rs(0.012, 0.008, 1.0 / 30 / 960, 960);
        ASSERT_EQ(classifyExposure(plant, robust, rs), EXPOSURE_III);
        Ptr<PsfGenerator> gen = PsfGenerator::create(plant, cam);
        expectMatchesReference(gen->generate(PSF_ROWS, robust, rs), plant, robust, cam, rs, 20, tol,
                               "window III frame, rows");
        expectMatchesReference(gen->generate(PSF_TILES, robust, rs), plant, robust, cam, rs, 331, tol,
                               "window III frame, tiles");
        expectMatchesReference(gen->generate(PSF_UNIFORM, robust, RollingShutter(0.02, 0.008, 0, 960)), plant,
                               robust, cam, RollingShutter(0.02, 0.008, 0, 960), 1, tol, "global shutter, uniform");
    }
    {
        // Window I (still rows far from the reference, rows turning round) with distortion and a
        // mount axis with a roll component, so that paths curve and vary across x.
        Ptr<CameraModel> cam = CameraModel::create(800, 800, 320, 240, 640, 480, -0.1, 0.1);
        cam->setMountAxis(Vec3d(1, 0, 0.6));
        const RollingShutter rs(-0.01, 0.008, 1.0 / 30 / 480, 480);
        Ptr<PsfGenerator> gen = PsfGenerator::create(plant, cam);
        expectMatchesReference(gen->generate(PSF_TILES, saccade(), rs), plant, saccade(), cam, rs, 97, tol,
                               "window I, distortion, tilted axis, tiles");
        // a long exposure: the path turns round inside it
        const RollingShutter slow(0.0, 0.05, 1.0 / 30 / 480, 480);
        gen->setMaxKernelSize(801);
        expectMatchesReference(gen->generate(PSF_ROWS, saccade(), slow), plant, saccade(), cam, slow, 40, tol,
                               "50 ms exposure, distortion, tilted axis, rows");
        // zero exposure: each kernel is the bilinear splat of one point (rolling: one instant per
        // row; global: one instant for the frame)
        const RollingShutter instant(0.01, 0.0, 1.0 / 30 / 480, 480), flash(0.01, 0.0, 0.0, 480);
        expectMatchesReference(gen->generate(PSF_TILES, saccade(), instant), plant, saccade(), cam, instant, 97, tol,
                               "zero exposure, rolling, tiles");
        expectMatchesReference(gen->generate(PSF_TILES, saccade(), flash), plant, saccade(), cam, flash, 97, tol,
                               "zero exposure, global, tiles");
    }
}
