// SPDX-License-Identifier: Apache-2.0
// CameraModel: ViSP distortion formulas, ViSP XML files, the rotation mapping and its sign.
#include "test_common.hpp"

#include <opencv2/dynblur.hpp>

#include <cstdio>
#include <fstream>
#include <unistd.h>

using namespace cv;
using namespace cv::dynblur;

namespace {

std::string tempPath(const std::string& name)
{
    return std::string(::testing::TempDir()) + "dynblur_" + std::to_string(::getpid()) + "_" + name;
}

Ptr<CameraModel> c270(double kud = 0.0, double kdu = 0.0)
{
    return CameraModel::create(1230.0, 1228.0, 640.0, 480.0, 1280, 960, kud, kdu);
}

}  // namespace

TEST(CameraModel, GettersAndMatrix)
{
    Ptr<CameraModel> cam = c270(-0.05, 0.051);
    EXPECT_EQ(cam->getImageSize(), Size(1280, 960));
    EXPECT_DOUBLE_EQ(cam->getFx(), 1230.0);
    EXPECT_DOUBLE_EQ(cam->getFy(), 1228.0);
    EXPECT_DOUBLE_EQ(cam->getKud(), -0.05);
    EXPECT_DOUBLE_EQ(cam->getKdu(), 0.051);
    const Matx33d K = cam->cameraMatrix();
    EXPECT_DOUBLE_EQ(K(0, 0), 1230.0);
    EXPECT_DOUBLE_EQ(K(1, 2), 480.0);
    EXPECT_DOUBLE_EQ(K(2, 2), 1.0);
    EXPECT_EQ(cam->getMountAxis(), Vec3d(1, 0, 0));
    cam->setMountAxis(Vec3d(0, 3, 4));
    EXPECT_NEAR(cam->getMountAxis()[1], 0.6, 1e-15);
    EXPECT_NEAR(cam->getMountAxis()[2], 0.8, 1e-15);
}

TEST(CameraModel, BadArgumentsNameTheArgument)
{
    auto expectError = [](const std::function<void()>& f, const std::string& word) {
        try
        {
            f();
            ADD_FAILURE() << "no exception, expected one naming " << word;
        }
        catch (const cv::Exception& e)
        {
            EXPECT_NE(e.what(), std::string()) << word;
            EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
        }
    };
    expectError([] { CameraModel::create(0, 1000, 1, 1, 10, 10); }, "fx");
    expectError([] { CameraModel::create(1000, -1, 1, 1, 10, 10); }, "fy");
    expectError([] { CameraModel::create(1000, 1000, NAN, 1, 10, 10); }, "cx");
    expectError([] { CameraModel::create(1000, 1000, 1, 1, 0, 10); }, "width");
    expectError([] { CameraModel::create(1000, 1000, 1, 1, 10, -2); }, "height");
    expectError([] { c270()->setMountAxis(Vec3d(0, 0, 0)); }, "axis");
    expectError([] { CameraModel::load("/nonexistent/camera.xml"); }, "cannot open");
}

TEST(CameraModel, DistortionFormulasAreViSPs)
{
    const double kud = -0.19, kdu = 0.2;
    Ptr<CameraModel> cam = CameraModel::create(1089.9, 1090.1, 326.1, 230.5, 640, 480, kud, kdu);
    // vpMeterPixelConversion: u = u0 + px·x·(1 + kud·r²)
    const Point2d m(0.21, -0.13);
    const double r2 = m.x * m.x + m.y * m.y;
    const Point2d u = cam->normalizedToPixel(m);
    EXPECT_NEAR(u.x, 326.1 + 1089.9 * m.x * (1 + kud * r2), 1e-12);
    EXPECT_NEAR(u.y, 230.5 + 1090.1 * m.y * (1 + kud * r2), 1e-12);
    // vpPixelMeterConversion: x = (u − u0)/px · (1 + kdu·r²), r² from the distorted pixel
    const Point2d p(600.0, 40.0);
    const double xd = (p.x - 326.1) / 1089.9, yd = (p.y - 230.5) / 1090.1;
    const Point2d n = cam->pixelToNormalized(p);
    EXPECT_NEAR(n.x, xd * (1 + kdu * (xd * xd + yd * yd)), 1e-15);
    EXPECT_NEAR(n.y, yd * (1 + kdu * (xd * xd + yd * yd)), 1e-15);
}

TEST(CameraModel, DistortionRoundTrip)
{
    // kdu is ViSP's first-order inverse of kud: kdu ≈ −kud/(1 + kud·r²)... to first order −kud.
    // The round trip undistort∘distort is then identity up to O(kud²·r⁴) of the normalised radius.
    const double kud = -0.05, kdu = 0.05;
    Ptr<CameraModel> cam = c270(kud, kdu);
    double worst = 0;
    for (int y = 0; y < 960; y += 60)
        for (int x = 0; x < 1280; x += 80)
        {
            const Point2d p(x, y);
            const Point2d back = cam->normalizedToPixel(cam->pixelToNormalized(p));
            const double r2 = std::pow((x - 640.0) / 1230.0, 2) + std::pow((y - 480.0) / 1228.0, 2);
            // bound: fx · r · (3·kud²·r⁴) with margin
            EXPECT_LE(norm(back - p), 1230.0 * std::sqrt(r2) * 4 * kud * kud * r2 * r2 + 1e-9) << p;
            worst = std::max(worst, norm(back - p));
        }
    EXPECT_LT(worst, 1.5);  // ≈ 1.1 px at the corners of a C270 with kud = −0.05
    // Without distortion the round trip is exact.
    Ptr<CameraModel> pin = c270();
    const Point2d p(17.25, 911.5);
    EXPECT_NEAR(norm(pin->normalizedToPixel(pin->pixelToNormalized(p)) - p), 0.0, 1e-10);
}

TEST(CameraModel, ZeroAngleIsIdentityEvenWithDistortion)
{
    for (double k : {0.0, -0.08})
    {
        Ptr<CameraModel> cam = c270(k, -k);
        for (const Point2d& p : {Point2d(0, 0), Point2d(640, 480), Point2d(1279, 959), Point2d(100.5, 800.25)})
            EXPECT_NEAR(norm(cam->viewToReference(p, 0.0) - p), 0.0, 1e-9) << p;
    }
}

TEST(CameraModel, ViewToReferenceMatchesDesignFormula)
{
    // No distortion: q = K·R_x(a)·K⁻¹·p exactly, R_x(a) = [[1,0,0],[0,c,−s],[0,s,c]].
    Ptr<CameraModel> cam = c270();
    const Matx33d K = cam->cameraMatrix();
    const double a = 0.07;
    const Matx33d R(1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a));
    for (const Point2d& p : {Point2d(640, 480), Point2d(10, 20), Point2d(1200, 900)})
    {
        const Vec3d h = K * R * K.inv() * Vec3d(p.x, p.y, 1.0);
        const Point2d expect(h[0] / h[2], h[1] / h[2]);
        EXPECT_NEAR(norm(cam->viewToReference(p, a) - expect), 0.0, 1e-9) << p;
    }
    // Array form agrees with the scalar form, for Nx2 and 1xN 2-channel inputs.
    Mat pts = (Mat_<double>(3, 2) << 640, 480, 10, 20, 1200, 900), out;
    cam->viewToReference(pts, a, out);
    ASSERT_EQ(out.size(), Size(2, 3));
    for (int i = 0; i < 3; i++)
    {
        const Point2d q = cam->viewToReference(Point2d(pts.at<double>(i, 0), pts.at<double>(i, 1)), a);
        EXPECT_NEAR(out.at<double>(i, 0), q.x, 1e-12);
        EXPECT_NEAR(out.at<double>(i, 1), q.y, 1e-12);
    }
    std::vector<Point2f> v{Point2f(640, 480), Point2f(10, 20)};
    Mat out2;
    cam->viewToReference(v, a, out2);
    EXPECT_EQ(out2.type(), CV_64FC2);
    EXPECT_EQ(out2.total(), 2u);
}

TEST(CameraModel, PositiveAngleMovesContentDown)
{
    // DESIGN §2: I_θ(p) = I_ref(q), q = K·R(θ − θ_ref)·K⁻¹·p. A positive step of θ: the centre pixel
    // of the new view sees the reference point above it (q.y < p.y), so the content that was at
    // q is now at p, lower in the image: scene content moves toward +y.
    Ptr<CameraModel> cam = c270();
    const Point2d c(640, 480);
    const double a = 1.0 * CV_PI / 180.0;
    const Point2d q = cam->viewToReference(c, a);
    EXPECT_LT(q.y, c.y);
    EXPECT_NEAR(q.y, 480 - 1228.0 * std::tan(a), 1e-9);
    EXPECT_NEAR(q.x, 640.0, 1e-9);
    EXPECT_GT(cam->viewToReference(c, -a).y, c.y);
    // ≈ 21 px per degree at the C270's focal length
    EXPECT_NEAR(c.y - q.y, 21.4, 0.2);
}

TEST(CameraModel, SaveLoadRoundTrip)
{
    for (double k : {0.0, -0.0712})
    {
        Ptr<CameraModel> cam = CameraModel::create(1231.5, 1229.25, 641.125, 479.5, 1280, 960, k, -1.02 * k);
        const std::string path = tempPath(k == 0 ? "nodist.xml" : "dist.xml");
        cam->save(path, "C270");
        cam->save(path, "C270");  // overwrites, no duplicate error
        Ptr<CameraModel> back = CameraModel::load(path, "C270");
        ASSERT_TRUE(back);
        EXPECT_NEAR(back->getFx(), 1231.5, 1e-6);
        EXPECT_NEAR(back->getFy(), 1229.25, 1e-6);
        EXPECT_NEAR(back->getCx(), 641.125, 1e-6);
        EXPECT_NEAR(back->getCy(), 479.5, 1e-6);
        EXPECT_NEAR(back->getKud(), k, 1e-9);
        EXPECT_NEAR(back->getKdu(), -1.02 * k, 1e-9);
        EXPECT_EQ(back->getImageSize(), Size(1280, 960));
        // empty name: the first camera of the file
        Ptr<CameraModel> first = CameraModel::load(path);
        EXPECT_NEAR(first->getFx(), 1231.5, 1e-6);
        // a name that is not there
        EXPECT_THROW(CameraModel::load(path, "Nope"), cv::Exception);
        std::remove(path.c_str());
    }
}

TEST(CameraModel, LoadsHandWrittenViSPFile)
{
    // The layout written by ViSP's calibration tools (vpXmlParserCamera), two cameras, one with
    // both projection models.
    const std::string path = tempPath("visp.xml");
    {
        std::ofstream f(path.c_str());
        f << "<?xml version=\"1.0\"?>\n"
             "<root>\n"
             "  <!--This file stores intrinsic camera parameters used\n"
             "   in the vpCameraParameters Class of ViSP available\n"
             "   at https://visp.inria.fr/download/ .\n"
             "   It can be read with the parse method of\n"
             "   the vpXmlParserCamera class.-->\n"
             "  <camera>\n"
             "    <!--Name of the camera-->\n"
             "    <name>Camera</name>\n"
             "    <!--Size of the image on which camera calibration was performed-->\n"
             "    <image_width>640</image_width>\n"
             "    <image_height>480</image_height>\n"
             "    <!--Intrinsic camera parameters computed for each projection model-->\n"
             "    <model>\n"
             "      <!--Projection model type-->\n"
             "      <type>perspectiveProjWithoutDistortion</type>\n"
             "      <!--Pixel ratio-->\n"
             "      <px>1129.0</px>\n"
             "      <py>1130.6</py>\n"
             "      <!--Principal point-->\n"
             "      <u0>317.9</u0>\n"
             "      <v0>229.1</v0>\n"
             "    </model>\n"
             "    <model>\n"
             "      <type>perspectiveProjWithDistortion</type>\n"
             "      <px>1089.9</px>\n"
             "      <py>1090.1</py>\n"
             "      <u0>326.1</u0>\n"
             "      <v0>230.5</v0>\n"
             "      <!--Undistorted to distorted distortion parameter-->\n"
             "      <kud>-0.196</kud>\n"
             "      <!--Distorted to undistorted distortion parameter-->\n"
             "      <kdu>0.204</kdu>\n"
             "    </model>\n"
             "  </camera>\n"
             "  <camera>\n"
             "    <name>Pinhole</name>\n"
             "    <image_width>1280</image_width>\n"
             "    <image_height>960</image_height>\n"
             "    <model>\n"
             "      <type>perspectiveProjWithoutDistortion</type>\n"
             "      <px>1230</px>\n"
             "      <py>1231</py>\n"
             "      <u0>640</u0>\n"
             "      <v0>480</v0>\n"
             "    </model>\n"
             "  </camera>\n"
             "</root>\n";
    }
    // With distortion (the model with distortion is preferred when both are present).
    Ptr<CameraModel> a = CameraModel::load(path, "Camera");
    EXPECT_NEAR(a->getFx(), 1089.9, 1e-9);
    EXPECT_NEAR(a->getFy(), 1090.1, 1e-9);
    EXPECT_NEAR(a->getCx(), 326.1, 1e-9);
    EXPECT_NEAR(a->getCy(), 230.5, 1e-9);
    EXPECT_NEAR(a->getKud(), -0.196, 1e-12);
    EXPECT_NEAR(a->getKdu(), 0.204, 1e-12);
    EXPECT_EQ(a->getImageSize(), Size(640, 480));
    // Empty name: the first camera.
    EXPECT_NEAR(CameraModel::load(path)->getKud(), -0.196, 1e-12);
    // Without distortion, selected by name and size.
    Ptr<CameraModel> b = CameraModel::load(path, "Pinhole", 1280, 960);
    EXPECT_NEAR(b->getFx(), 1230, 1e-9);
    EXPECT_NEAR(b->getFy(), 1231, 1e-9);
    EXPECT_EQ(b->getKud(), 0.0);
    EXPECT_EQ(b->getKdu(), 0.0);
    EXPECT_EQ(b->getImageSize(), Size(1280, 960));
    // Wrong size for that name.
    EXPECT_THROW(CameraModel::load(path, "Pinhole", 640, 480), cv::Exception);
    std::remove(path.c_str());
}
