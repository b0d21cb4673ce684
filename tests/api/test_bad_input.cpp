// SPDX-License-Identifier: Apache-2.0
// Bad inputs on every public entry point (docs/reliability.md): empty, wrong type / channels / depth, wrong
// size, NaN/Inf pixels and parameters, negative / zero / huge sizes, non-normalised or negative
// kernels, truncated or garbage files. Each must be refused with a cv::Exception (or the documented
// error) whose message names the argument and, for a number, its allowed range — never a crash, a
// hang or a silent garbage result.
//
// The per-idea tests already refuse many of these (expectErrorNaming in test_psf.cpp and
// test_render.cpp, the schedule/plant/bus checks of test_plant.cpp, test_planner.cpp, test_bus.cpp,
// programs/test_plant_identification.cpp); this file holds the rest, one table row per input, and checks the
// message of those the per-idea tests only check for an exception. Rows print as
// "[ refused ] entry point | input | message" lines: docs/reliability.md's table is built from them.
#include "bad_input_rows.hpp"
#include "test_common.hpp"

#include <opencv2/dynblur.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

using namespace cv;
using namespace cv::dynblur;
using namespace dynblur_test;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();
const double kDeg = CV_PI / 180.0;

SwitchSchedule saccade()
{
    return SwitchSchedule({0.0, 0.0113, 0.0262, 0.040}, {4, 10, 7, 10}, 0);
}

Mat nanAt(Mat m, double value = kNaN)
{
    m = m.clone();
    m.at<float>(m.rows / 2, (m.cols * m.channels()) / 2) = static_cast<float>(value);
    return m;
}

PsfBank oneKernelBank(Size size, const Mat& k)
{
    PsfBank b;
    b.model = PSF_UNIFORM;
    b.imageSize = size;
    b.nodeRows = {(size.height - 1) / 2.0};
    b.nodeCols = {(size.width - 1) / 2.0};
    b.kernels = {k};
    b.shifts = {Point()};
    return b;
}

}  // namespace

TEST(BadInput, Plant)
{
    const Ptr<Plant> plant = Plant::create(14.4, 0.12, kDeg);
    const Mat t = (Mat_<double>(1, 3) << 0.0, 0.01, 0.02);
    Mat out;
    refuseAll({
        {"Plant::create", "naturalFreqHz = 0", [] { Plant::create(0.0, 0.12, kDeg); }, {"naturalFreqHz", "> 0"}},
        {"Plant::create", "naturalFreqHz = NaN", [] { Plant::create(kNaN, 0.12, kDeg); }, {"naturalFreqHz"}},
        {"Plant::create", "naturalFreqHz = -Inf", [] { Plant::create(-kInf, 0.12, kDeg); }, {"naturalFreqHz"}},
        {"Plant::create", "dampingRatio = 1", [] { Plant::create(14.4, 1.0, kDeg); }, {"dampingRatio", "(0, 1)"}},
        {"Plant::create", "dampingRatio = NaN", [] { Plant::create(14.4, kNaN, kDeg); }, {"dampingRatio"}},
        {"Plant::create", "gain = 0", [] { Plant::create(14.4, 0.12, 0.0); }, {"gain"}},
        {"Plant::create", "gain = NaN", [] { Plant::create(14.4, 0.12, kNaN); }, {"gain"}},
        {"Plant::response", "t holds NaN", [&] { plant->response(saccade(), Mat((Mat_<double>(1, 2) << 0.0, kNaN)), out); }, {"'t'[1]", "not finite"}},
        {"Plant::response", "t is CV_8U", [&] { plant->response(saccade(), Mat(1, 2, CV_8U, Scalar(0)), out); }, {"'t'", "CV_64F or CV_32F"}},
        {"Plant::response", "t is 2-channel", [&] { plant->response(saccade(), Mat(1, 2, CV_64FC2, Scalar(0)), out); }, {"'t'", "one-channel"}},
        {"Plant::response", "schedule: levels shorter than times",
         [&] { plant->response(SwitchSchedule({0.0, 0.01}, {1}), t, out); }, {"levels"}},
        {"Plant::response", "schedule: times[1] = Inf",
         [&] { plant->response(SwitchSchedule({0.0, kInf}, {1, 2}), t, out); }, {"times"}},
        {"Plant::velocity", "t holds Inf", [&] { plant->velocity(saccade(), Mat((Mat_<double>(1, 2) << 0.0, kInf)), out); }, {"'t'[1]", "not finite"}},
        {"Plant::identify", "theta holds NaN",
         [&] {
             Mat tt(1, 50, CV_64F), th(1, 50, CV_64F);
             for (int i = 0; i < 50; ++i)
             {
                 tt.at<double>(i) = 0.001 * i;
                 th.at<double>(i) = 0.01 * i;
             }
             th.at<double>(20) = kNaN;
             Plant::identify(tt, th, SwitchSchedule({0.0}, {10}));
         },
         {"theta"}},
        {"Plant::identify", "t is empty", [&] { Plant::identify(Mat(), Mat(), SwitchSchedule({0.0}, {10})); }, {"'t'", "at least 8"}},
        {"OdePlant::createLinear", "dampingRatio = 1.5", [] { OdePlant::createLinear(14.4, 1.5, kDeg); }, {"dampingRatio"}},
        {"OdePlant::create", "stateSize = 1",
         [] {
             OdePlant::create([](double, const double*, double, double* d) { d[0] = 0; }, 1,
                              [](int) { return std::vector<double>{0.0}; }, 14.4, 0.12, kDeg);
         },
         {"stateSize", "2"}},
        {"OdePlant::create", "rhs empty",
         [] { OdePlant::create(OdePlant::RightHandSide(), 2, [](int) { return std::vector<double>{0, 0}; }, 14.4, 0.12, kDeg); },
         {"rhs"}},
        {"OdePlant::create", "relTol = 0",
         [] {
             OdePlant::create([](double, const double*, double, double* d) { d[0] = d[1] = 0; }, 2,
                              [](int) { return std::vector<double>{0.0, 0.0}; }, 14.4, 0.12, kDeg, 0.0);
         },
         {"relTol"}},
        {"residualVibration", "naturalFreqHz = 0", [] { residualVibration(saccade(), 0.0, 0.12); }, {"naturalFreqHz"}},
        {"residualVibration", "dampingRatio = NaN", [] { residualVibration(saccade(), 14.4, kNaN); }, {"dampingRatio"}},
    });
}

TEST(BadInput, Schedule)
{
    const std::string good = tempPath("good.yml");
    saccade().save(good);
    refuseAll(brokenFileRows("SwitchSchedule::load", "schedule.yml", readText(good),
                             [](const std::string& path) { SwitchSchedule::load(path); }));
    refuseAll({
        {"SwitchSchedule::validate", "empty", [] { SwitchSchedule().validate(); }, {"times", "empty"}},
        {"SwitchSchedule::validate", "levels shorter than times", [] { SwitchSchedule({0.0, 0.01}, {1}).validate(); }, {"levels"}},
        {"SwitchSchedule::validate", "times not increasing", [] { SwitchSchedule({0.01, 0.01}, {1, 2}).validate(); }, {"times"}},
        {"SwitchSchedule::validate", "times[0] = NaN", [] { SwitchSchedule({kNaN}, {1}).validate(); }, {"times"}},
        {"SwitchSchedule::validate", "levels[1] = 17 with maxLevel 16",
         [] { SwitchSchedule({0.0, 0.01}, {1, 17}).validate(16); }, {"levels[1]", "16"}},
        {"SwitchSchedule::validate", "initialLevel = -17 with maxLevel 16",
         [] { SwitchSchedule({0.0}, {1}, -17).validate(16); }, {"initialLevel", "16"}},
        {"SwitchSchedule::validate", "maxLevel = -1", [] { saccade().validate(-1); }, {"maxLevel"}},
        {"SwitchSchedule::levelAt", "t = NaN", [] { saccade().levelAt(kNaN); }, {"t = nan", "must be finite"}},
        {"SwitchSchedule::load", "times as a string",
         [] { SwitchSchedule::load(writeFile("str.yml", "%YAML:1.0\n---\ntimes: \"soon\"\nlevels: [1]\n")); }, {"times"}},
        {"SwitchSchedule::load", "levels of reals",
         [] { SwitchSchedule::load(writeFile("real.yml", "%YAML:1.0\n---\ntimes: [0.0, 0.01]\nlevels: [1.5, 2]\n")); }, {"levels"}},
        {"SwitchSchedule::load", "times with .nan",
         [] { SwitchSchedule::load(writeFile("nan.yml", "%YAML:1.0\n---\ntimes: [0.0, .nan]\nlevels: [1, 2]\n")); }, {"times"}},
        {"SwitchSchedule::load", "levels missing",
         [] { SwitchSchedule::load(writeFile("nolevels.yml", "%YAML:1.0\n---\ntimes: [0.0]\n")); }, {"levels"}},
        {"SwitchSchedule::load", "initialLevel a string",
         [] {
             SwitchSchedule::load(writeFile("init.yml", "%YAML:1.0\n---\ntimes: [0.0]\nlevels: [1]\ninitialLevel: \"x\"\n"));
         },
         {"initialLevel"}},
        {"SwitchSchedule::save", "unwritable path", [] { saccade().save("/nonexistent-dir/s.yml"); }, {"/nonexistent-dir/s.yml"}},
    });
}

TEST(BadInput, Planner)
{
    const Ptr<Plant> plant = Plant::create(14.4, 0.12, kDeg);
    const Ptr<SwitchPlanner> planner = SwitchPlanner::create(plant, 16);
    refuseAll({
        {"SwitchPlanner::create", "plant empty", [] { SwitchPlanner::create(Ptr<Plant>(), 16); }, {"plant"}},
        {"SwitchPlanner::create", "maxLevel = 0", [&] { SwitchPlanner::create(plant, 0); }, {"maxLevel"}},
        {"SwitchPlanner::create", "mode = 2", [&] { SwitchPlanner::create(plant, 16, 2); }, {"mode"}},
        {"SwitchPlanner::create", "minDwell = -0.001", [&] { SwitchPlanner::create(plant, 16, PLAN_FAST, -0.001); }, {"minDwell"}},
        {"SwitchPlanner::create", "minDwell = NaN", [&] { SwitchPlanner::create(plant, 16, PLAN_FAST, kNaN); }, {"minDwell"}},
        {"SwitchPlanner::plan", "fromAngle = NaN", [&] { planner->plan(kNaN, 0.1); }, {"fromAngle"}},
        {"SwitchPlanner::plan", "toAngle = Inf", [&] { planner->plan(0.0, kInf); }, {"toAngle"}},
        {"SwitchPlanner::plan", "startTime = NaN", [&] { planner->plan(0.0, 0.1, kNaN); }, {"startTime"}},
        {"SwitchPlanner::plan", "toAngle beyond maxLevel * gain", [&] { planner->plan(0.0, 16.5 * kDeg); }, {"toAngle"}},
        {"SwitchPlanner::setMaxLevel", "0", [&] { planner->setMaxLevel(0); }, {"maxLevel"}},
        {"SwitchPlanner::setMode", "7", [&] { planner->setMode(7); }, {"mode"}},
        {"SwitchPlanner::setMinDwell", "-1", [&] { planner->setMinDwell(-1); }, {"minDwell"}},
        {"SwitchPlanner::setSettleBand", "0", [&] { planner->setSettleBand(0); }, {"band"}},
        {"SwitchPlanner::setSettleBand", "NaN", [&] { planner->setSettleBand(kNaN); }, {"band"}},
        {"SwitchPlanner::setRobustRange", "-0.1", [&] { planner->setRobustRange(-0.1); }, {"range"}},
        {"SwitchPlanner::setRobustTolerance", "0", [&] { planner->setRobustTolerance(0); }, {"tolerance"}},
    });
}

TEST(BadInput, Shutter)
{
    const Ptr<Plant> plant = Plant::create(14.4, 0.12, kDeg);
    refuseAll({
        {"RollingShutter::validate", "rows = 0", [] { RollingShutter(0, 0.008, 0, 0).validate(); }, {"rows"}},
        {"RollingShutter::validate", "exposure = -0.001", [] { RollingShutter(0, -0.001, 0, 10).validate(); }, {"exposure"}},
        {"RollingShutter::validate", "exposure = Inf", [] { RollingShutter(0, kInf, 0, 10).validate(); }, {"exposure"}},
        {"RollingShutter::validate", "lineDelay = -1e-6", [] { RollingShutter(0, 0.008, -1e-6, 10).validate(); }, {"lineDelay"}},
        {"RollingShutter::validate", "lineDelay = NaN", [] { RollingShutter(0, 0.008, kNaN, 10).validate(); }, {"lineDelay"}},
        {"RollingShutter::validate", "frameStart = NaN", [] { RollingShutter(kNaN, 0.008, 0, 10).validate(); }, {"frameStart"}},
        {"RollingShutter::rowInterval", "row = rows", [] { RollingShutter(0, 0.008, 0, 10).rowInterval(10); }, {"row"}},
        {"RollingShutter::rowInterval", "row = -1", [] { RollingShutter(0, 0.008, 0, 10).rowInterval(-1); }, {"row"}},
        {"classifyExposure", "plant empty", [] { classifyExposure(Ptr<Plant>(), saccade(), RollingShutter()); }, {"plant"}},
        {"classifyExposure", "angleTol = 0", [&] { classifyExposure(plant, saccade(), RollingShutter(), 0.0); }, {"angleTol"}},
        {"classifyExposure", "velocityTol = -1",
         [&] { classifyExposure(plant, saccade(), RollingShutter(), 1e-4, -1.0); }, {"velocityTol"}},
        {"classifyExposure", "velocityTol = NaN",
         [&] { classifyExposure(plant, saccade(), RollingShutter(), 1e-4, kNaN); }, {"velocityTol"}},
        {"classifyExposure", "schedule times not increasing",
         [&] { classifyExposure(plant, SwitchSchedule({0.0, 0.0}, {1, 2}), RollingShutter()); }, {"times"}},
        {"classifyExposure", "shutter rows = 0", [&] { classifyExposure(plant, saccade(), RollingShutter(0, 0.008, 0, 0)); }, {"rows"}},
    });
}

TEST(BadInput, Camera)
{
    const Ptr<CameraModel> cam = CameraModel::create(600, 600, 319.5, 239.5, 640, 480);
    const std::string goodXml = tempPath("cam.xml");
    cam->save(goodXml, "Cam");
    const std::string xml = readText(goodXml);
    refuseAll(brokenFileRows("CameraModel::load", "camera.xml", xml, [](const std::string& path) { CameraModel::load(path); }));
    std::string negativePx = xml;
    const size_t px = negativePx.find("<px>");
    ASSERT_NE(px, std::string::npos) << xml;
    negativePx.replace(px, 4, "<px>-");
    Mat out;
    refuseAll({
        {"CameraModel::create", "fx = 0", [] { CameraModel::create(0, 600, 319.5, 239.5, 640, 480); }, {"fx"}},
        {"CameraModel::create", "fy = NaN", [] { CameraModel::create(600, kNaN, 319.5, 239.5, 640, 480); }, {"fy"}},
        {"CameraModel::create", "cx = Inf", [] { CameraModel::create(600, 600, kInf, 239.5, 640, 480); }, {"cx"}},
        {"CameraModel::create", "width = 0", [] { CameraModel::create(600, 600, 319.5, 239.5, 0, 480); }, {"width"}},
        {"CameraModel::create", "height = -480", [] { CameraModel::create(600, 600, 319.5, 239.5, 640, -480); }, {"height"}},
        {"CameraModel::create", "kud = NaN", [] { CameraModel::create(600, 600, 319.5, 239.5, 640, 480, kNaN); }, {"kud"}},
        {"CameraModel::create", "kdu = Inf", [] { CameraModel::create(600, 600, 319.5, 239.5, 640, 480, 0, kInf); }, {"kdu"}},
        {"CameraModel::setMountAxis", "(0, 0, 0)", [&] { cam->setMountAxis(Vec3d(0, 0, 0)); }, {"axis"}},
        {"CameraModel::setMountAxis", "(NaN, 0, 1)", [&] { cam->setMountAxis(Vec3d(kNaN, 0, 1)); }, {"axis"}},
        {"CameraModel::viewToReference", "angle = NaN",
         [&] { cam->viewToReference(std::vector<Point2f>{Point2f(1, 1)}, kNaN, out); }, {"angle"}},
        {"CameraModel::viewToReference", "points of CV_8U",
         [&] { cam->viewToReference(Mat(1, 2, CV_8UC2, Scalar::all(1)), 0.01, out); }, {"points"}},
        {"CameraModel::load", "px negative", [&] { CameraModel::load(writeFile("negpx.xml", negativePx)); }, {"fx", "> 0"}},
        {"CameraModel::load", "cameraName not in the file", [&] { CameraModel::load(goodXml, "Nope"); }, {"Nope"}},
        {"CameraModel::load", "width = -1", [&] { CameraModel::load(goodXml, "", -1, 480); }, {"width"}},
        {"CameraModel::save", "unwritable path", [&] { cam->save("/nonexistent-dir/c.xml", "Cam"); }, {"/nonexistent-dir/c.xml"}},
    });
}

TEST(BadInput, PsfGenerator)
{
    const Ptr<Plant> plant = Plant::create(14.4, 0.12, kDeg);
    const Ptr<CameraModel> cam = CameraModel::create(120, 120, 31.5, 23.5, 64, 48);
    const Ptr<PsfGenerator> gen = PsfGenerator::create(plant, cam);
    const RollingShutter rs(0.0, 0.008, 4e-4, 48);
    PsfBank good = oneKernelBank(Size(64, 48), Mat::ones(1, 3, CV_32F) / 3.0);
    auto with = [&](std::function<void(PsfBank&)> change) {
        PsfBank b = good;
        b.kernels = {good.kernels[0].clone()};
        change(b);
        return b;
    };
    refuseAll({
        {"PsfGenerator::create", "plant empty", [&] { PsfGenerator::create(Ptr<Plant>(), cam); }, {"plant"}},
        {"PsfGenerator::create", "camera empty", [&] { PsfGenerator::create(plant, Ptr<CameraModel>()); }, {"camera"}},
        {"PsfGenerator::setTileGrid", "(100000, 100000) for a 64x48 camera",
         [&] { gen->setTileGrid(Size(100000, 100000)); }, {"grid", "64"}},
        {"PsfGenerator::generate", "shutter exposure = NaN",
         [&] { gen->generate(PSF_ROWS, saccade(), RollingShutter(0.0, kNaN, 4e-4, 48)); }, {"exposure"}},
        {"PsfGenerator::generate", "schedule times not increasing",
         [&] { gen->generate(PSF_ROWS, SwitchSchedule({0.01, 0.0}, {1, 2}), rs); }, {"times"}},
        {"PsfGenerator::generate", "path longer than maxKernelSize",
         [&] {
             Ptr<PsfGenerator> g = PsfGenerator::create(plant, cam);
             g->setMaxKernelSize(3);
             g->generate(PSF_UNIFORM, saccade(), RollingShutter(0.005, 0.008, 4e-4, 48));
         },
         {"MaxKernelSize", "limit of 3 pixels"}},
        {"PsfBank::validate", "model = 7", [&] { with([](PsfBank& b) { b.model = 7; }).validate(); }, {"model"}},
        {"PsfBank::validate", "imageSize 0x48", [&] { with([](PsfBank& b) { b.imageSize = Size(0, 48); }).validate(); }, {"imageSize"}},
        {"PsfBank::validate", "kernel with a negative element",
         [&] { with([](PsfBank& b) { b.kernels[0] = (Mat_<float>(1, 3) << -0.5f, 1.0f, 0.5f); }).validate(); }, {"negative"}},
        {"PsfBank::validate", "kernel with NaN",
         [&] { with([](PsfBank& b) { b.kernels[0].at<float>(0, 1) = NAN; }).validate(); }, {"non-finite"}},
        {"PsfBank::validate", "kernel CV_64F",
         [&] { with([](PsfBank& b) { b.kernels[0].convertTo(b.kernels[0], CV_64F); }).validate(); }, {"CV_32FC1"}},
        {"PsfBank::validate", "nodeCols NaN", [&] { with([](PsfBank& b) { b.nodeCols = {kNaN}; }).validate(); }, {"nodeCols"}},
    });
}

TEST(BadInput, Deconvolution)
{
    const Size size(30, 20);
    const Mat image(size, CV_32F, Scalar(0.5));
    const Mat kernel = Mat::ones(1, 3, CV_32F) / 3.0;
    const PsfBank bank = oneKernelBank(size, kernel);
    Mat out;
    auto withParams = [](std::function<void(RLParams&)> change) {
        RLParams p;
        change(p);
        return p;
    };
    auto shiftedBank = [&](int shift) {
        PsfBank b = oneKernelBank(size, Mat::ones(1, 1, CV_32F));
        b.shifts = {Point(shift, 0)};
        return b;
    };
    refuseAll({
        {"richardsonLucy", "blurred empty", [&] { richardsonLucy(Mat(), kernel, out); }, {"blurred"}},
        {"richardsonLucy", "blurred CV_8U", [&] { richardsonLucy(Mat(size, CV_8U, Scalar(1)), kernel, out); }, {"blurred", "CV_32F"}},
        {"richardsonLucy", "blurred CV_64F", [&] { richardsonLucy(Mat(size, CV_64F, Scalar(1)), kernel, out); }, {"blurred", "CV_32F"}},
        {"richardsonLucy", "blurred holds a pixel of -0.5", [&] { richardsonLucy(nanAt(image, -0.5), kernel, out); },
         {"blurred", ">= 0"}},
        {"richardsonLucy", "initial holds a pixel of -0.5",
         [&] { richardsonLucy(image, kernel, out, RLParams(), nanAt(image, -0.5)); }, {"initial", ">= 0"}},
        {"richardsonLucy", "blurred with 5 channels",
         [&] {
             Mat five(size, CV_32FC(5));
             five.reshape(1).setTo(1);  // a Scalar holds 4 values: fill it as one channel
             richardsonLucy(five, kernel, out);
         },
         {"blurred", "4"}},
        {"richardsonLucy", "blurred holds NaN", [&] { richardsonLucy(nanAt(image), kernel, out); }, {"blurred", "finite"}},
        {"richardsonLucy", "blurred holds -Inf", [&] { richardsonLucy(nanAt(image, -kInf), kernel, out); }, {"blurred", "finite"}},
        {"richardsonLucy", "psf empty", [&] { richardsonLucy(image, Mat(), out); }, {"psf"}},
        {"richardsonLucy", "psf 4x3 (even)", [&] { richardsonLucy(image, Mat(4, 3, CV_32F, Scalar(1)), out); }, {"psf", "odd"}},
        {"richardsonLucy", "psf with a negative element",
         [&] { richardsonLucy(image, Mat((Mat_<float>(1, 3) << -1.f, 2.f, 1.f)), out); }, {"psf", "negative"}},
        {"richardsonLucy", "psf all zero", [&] { richardsonLucy(image, Mat::zeros(3, 3, CV_32F), out); }, {"psf"}},
        {"richardsonLucy", "psf holds NaN", [&] { richardsonLucy(image, nanAt(Mat::ones(3, 3, CV_32F)), out); }, {"psf"}},
        {"richardsonLucy", "psf 2 channels", [&] { richardsonLucy(image, Mat(3, 3, CV_32FC2, Scalar::all(1)), out); }, {"psf"}},
        {"richardsonLucy", "psf CV_8U", [&] { richardsonLucy(image, Mat(3, 3, CV_8U, Scalar(1)), out); }, {"psf"}},
        {"richardsonLucy", "initial of another size",
         [&] { richardsonLucy(image, kernel, out, RLParams(), Mat(10, 10, CV_32F, Scalar(1))); }, {"initial"}},
        {"richardsonLucy", "iterations = 0", [&] { richardsonLucy(image, kernel, out, withParams([](RLParams& p) { p.iterations = 0; })); },
         {"iterations"}},
        {"richardsonLucy", "damping = -1", [&] { richardsonLucy(image, kernel, out, withParams([](RLParams& p) { p.damping = -1; })); },
         {"damping"}},
        {"richardsonLucy", "tvWeight = NaN",
         [&] { richardsonLucy(image, kernel, out, withParams([](RLParams& p) { p.tvWeight = kNaN; })); }, {"tvWeight"}},
        {"richardsonLucy", "boundary = 5", [&] { richardsonLucy(image, kernel, out, withParams([](RLParams& p) { p.boundary = 5; })); },
         {"boundary"}},
        {"richardsonLucy", "tolerance = -1",
         [&] { richardsonLucy(image, kernel, out, withParams([](RLParams& p) { p.tolerance = -1; })); }, {"tolerance"}},
        {"richardsonLucyVariant", "blurred holds NaN", [&] { richardsonLucyVariant(nanAt(image), bank, out); }, {"blurred"}},
        {"richardsonLucyVariant", "blurred holds a pixel of -0.5",
         [&] { richardsonLucyVariant(nanAt(image, -0.5), bank, out); }, {"blurred", ">= 0"}},
        {"richardsonLucyVariant", "blurred CV_8UC3", [&] { richardsonLucyVariant(Mat(size, CV_8UC3), bank, out); }, {"blurred"}},
        {"richardsonLucyVariant", "bank of another image size",
         [&] { richardsonLucyVariant(image, oneKernelBank(Size(31, 20), kernel), out); }, {"bank", "31x20"}},
        {"richardsonLucyVariant", "bank kernel not normalised",
         [&] { richardsonLucyVariant(image, oneKernelBank(size, Mat::ones(1, 3, CV_32F)), out); }, {"sum"}},
        {"richardsonLucyVariant", "bank without kernels",
         [&] {
             PsfBank b = bank;
             b.kernels.clear();
             richardsonLucyVariant(image, b, out);
         },
         {"kernels"}},
        {"applyPsfBank", "latent CV_8UC3", [&] { applyPsfBank(Mat(size, CV_8UC3), bank, out); }, {"latent"}},
        {"applyPsfBank", "latent holds NaN", [&] { applyPsfBank(nanAt(image), bank, out); }, {"latent"}},
        {"applyPsfBank", "bank with an even kernel",
         [&] { applyPsfBank(image, oneKernelBank(size, Mat::ones(2, 3, CV_32F) / 6.0), out); }, {"odd"}},
        {"wienerDeconvolve", "noiseToSignal = 0", [&] { wienerDeconvolve(image, bank, out, 0.0); }, {"noiseToSignal"}},
        {"wienerDeconvolve", "noiseToSignal = NaN", [&] { wienerDeconvolve(image, bank, out, kNaN); }, {"noiseToSignal"}},
        {"wienerDeconvolve", "noiseToSignal = Inf", [&] { wienerDeconvolve(image, bank, out, kInf); }, {"noiseToSignal"}},
        {"wienerDeconvolve", "blurred holds Inf", [&] { wienerDeconvolve(nanAt(image, kInf), bank, out); }, {"blurred"}},
        {"wienerDeconvolve", "blurred empty", [&] { wienerDeconvolve(Mat(), bank, out); }, {"blurred"}},
        {"wienerDeconvolve", "blurred of another size",
         [&] { wienerDeconvolve(Mat(21, 30, CV_32F, Scalar(0)), bank, out); }, {"bank", "30x21"}},
        {"richardsonLucyVariant", "bank shift 2^30 px (would allocate 86 GB)",
         [&] { richardsonLucyVariant(image, shiftedBank(1 << 30), out); }, {"shifts", "1024"}},
        {"richardsonLucyVariant", "bank shift INT_MAX",
         [&] { richardsonLucyVariant(image, shiftedBank(std::numeric_limits<int>::max()), out); }, {"shifts"}},
        {"PsfBank::validate", "shift -INT_MAX", [&] { shiftedBank(-std::numeric_limits<int>::max()).validate(); },
         {"shifts"}},
        {"richardsonLucy", "params.iterations = 2^30",
         [&] { richardsonLucy(image, kernel, out, withParams([](RLParams& p) { p.iterations = 1 << 30; })); },
         {"params.iterations", "100000"}},
    });
}

TEST(BadInput, Deblurrer)
{
    const Ptr<Plant> plant = Plant::create(14.4, 0.12, kDeg);
    const Ptr<CameraModel> cam = CameraModel::create(120, 120, 31.5, 23.5, 64, 48);
    const Ptr<DynamicDeblurrer> d = DynamicDeblurrer::create(plant, cam);
    const RollingShutter rs(0.005, 0.008, 4e-4, 48);
    const Mat frame(48, 64, CV_32F, Scalar(0.5));
    // A still of the 64x48 camera with sensor noise drawn from `seed`.
    const auto noisy = [&](uint64 seed) {
        Mat still;
        addSensorNoise(frame, still, 4000.0, 8.0, 5.0, seed);
        return still;
    };
    Mat out;
    refuseAll({
        {"DynamicDeblurrer::create", "plant empty", [&] { DynamicDeblurrer::create(Ptr<Plant>(), cam); }, {"plant"}},
        {"DynamicDeblurrer::create", "camera empty", [&] { DynamicDeblurrer::create(plant, Ptr<CameraModel>()); }, {"camera"}},
        {"DynamicDeblurrer::deblur", "frame empty", [&] { d->deblur(Mat(), saccade(), rs, out); }, {"frame"}},
        {"DynamicDeblurrer::deblur", "frame CV_16UC3", [&] { d->deblur(Mat(48, 64, CV_16UC3, Scalar::all(0)), saccade(), rs, out); },
         {"frame", "CV_8U"}},
        {"DynamicDeblurrer::deblur", "frame with 2 channels", [&] { d->deblur(Mat(48, 64, CV_8UC2, Scalar::all(0)), saccade(), rs, out); },
         {"frame"}},
        {"DynamicDeblurrer::deblur", "frame 32x24 for a 64x48 camera",
         [&] { d->deblur(Mat(24, 32, CV_8UC3, Scalar::all(0)), saccade(), rs, out); }, {"frame", "64x48"}},
        {"DynamicDeblurrer::deblur", "frame holds NaN", [&] { d->deblur(nanAt(frame), saccade(), rs, out); }, {"frame"}},
        {"DynamicDeblurrer::deblur", "CV_32F frame value 2",
         [&] { d->deblur(Mat(48, 64, CV_32F, Scalar(2.0)), saccade(), rs, out); }, {"frame", "[0, 1]"}},
        {"DynamicDeblurrer::deblur", "CV_32F frame with a pixel of -0.01",
         [&] { d->deblur(nanAt(frame, -0.01), saccade(), rs, out); }, {"frame", "[0, 1]"}},
        {"DynamicDeblurrer::deblur", "shutter rows 47", [&] { d->deblur(frame, saccade(), RollingShutter(0.005, 0.008, 4e-4, 47), out); },
         {"rows"}},
        {"DynamicDeblurrer::deblur", "thetaRef = Inf",
         [&] { d->deblur(frame, saccade(), rs, out, kInf); }, {"thetaRef"}},
        {"DynamicDeblurrer::deblur", "schedule times not increasing",
         [&] { d->deblur(frame, SwitchSchedule({0.01, 0.0}, {1, 2}), rs, out); }, {"times"}},
        {"DynamicDeblurrer::setNoiseFrames", "stillA empty", [&] { d->setNoiseFrames(Mat(), noisy(1)); }, {"stillA"}},
        {"DynamicDeblurrer::setNoiseFrames", "stillB 32x24 for a 64x48 camera",
         [&] { d->setNoiseFrames(noisy(1), Mat(24, 32, CV_32F, Scalar(0.5))); }, {"stillB", "64x48"}},
        {"DynamicDeblurrer::setNoiseFrames", "stillB holds NaN", [&] { d->setNoiseFrames(noisy(1), nanAt(noisy(2))); },
         {"stillB"}},
        {"DynamicDeblurrer::setNoiseFrames", "stillA CV_32F, stillB CV_8U",
         [&] { d->setNoiseFrames(noisy(1), Mat(48, 64, CV_8U, Scalar(128))); }, {"stillA", "stillB", "CV_8U"}},
        {"DynamicDeblurrer::setNoiseFrames", "the same still twice",
         [&] { d->setNoiseFrames(noisy(1), noisy(1)); }, {"stillA", "stillB", "no noise"}},
        {"DynamicDeblurrer::deblur", "a CV_8U frame after CV_32F noise frames",
         [&] {
             const Ptr<DynamicDeblurrer> n = DynamicDeblurrer::create(plant, cam);
             n->setNoiseFrames(noisy(1), noisy(2));
             n->setReferenceFrame(Mat(48, 64, CV_8U, Scalar(128)), 0.0);
             n->deblur(Mat(48, 64, CV_8U, Scalar(128)), saccade(), RollingShutter(0.0, 0.008, 4e-4, 48), out);
         },
         {"frame", "noise frames"}},
        {"DynamicDeblurrer::setPsfModel", "7", [&] { d->setPsfModel(7); }, {"model"}},
        {"DynamicDeblurrer::setMethod", "-1", [&] { d->setMethod(-1); }, {"method"}},
        {"DynamicDeblurrer::setUnobservedFill", "3", [&] { d->setUnobservedFill(3); }, {"fill", "UNOBSERVED_RECORDED"}},
        {"DynamicDeblurrer::setSharpThreshold", "-0.5", [&] { d->setSharpThreshold(-0.5); }, {"px", ">= 0"}},
        {"DynamicDeblurrer::setSharpThreshold", "NaN", [&] { d->setSharpThreshold(kNaN); }, {"px", "finite"}},
        {"DynamicDeblurrer::setSharpThreshold", "Inf", [&] { d->setSharpThreshold(kInf); }, {"px", "finite"}},
        {"DynamicDeblurrer::setRLParams", "iterations = 0",
         [&] {
             RLParams p;
             p.iterations = 0;
             d->setRLParams(p);
         },
         {"iterations"}},
    });
}

TEST(BadInput, Render)
{
    const Mat lin(20, 30, CV_32F, Scalar(0.5));
    Mat out;
    refuseAll({
        {"addSensorNoise", "linear CV_8U", [&] { addSensorNoise(Mat(20, 30, CV_8U, Scalar(1)), out); }, {"linear"}},
        {"addSensorNoise", "fullWellElectrons = NaN", [&] { addSensorNoise(lin, out, kNaN); }, {"fullWellElectrons"}},
        {"addSensorNoise", "fullWellElectrons = 0", [&] { addSensorNoise(lin, out, 0.0); }, {"fullWellElectrons"}},
        {"addSensorNoise", "readNoiseElectrons = -1", [&] { addSensorNoise(lin, out, 4000, -1); }, {"readNoiseElectrons"}},
        {"addSensorNoise", "darkElectrons = Inf", [&] { addSensorNoise(lin, out, 4000, 8, kInf); }, {"darkElectrons"}},
        {"srgbToLinear", "CV_16S", [&] { srgbToLinear(Mat(20, 30, CV_16S, Scalar(0)), out); }, {"srgb"}},
        {"linearToSrgb", "depth = CV_16U", [&] { linearToSrgb(lin, out, CV_16U); }, {"depth"}},
        {"linearToSrgb", "linear CV_8U", [&] { linearToSrgb(Mat(20, 30, CV_8U, Scalar(1)), out); }, {"linear"}},
        {"addSensorNoise", "linear empty", [&] { addSensorNoise(Mat(), out); }, {"linear"}},
        {"addSensorNoise", "linear holds NaN", [&] { addSensorNoise(nanAt(lin), out); }, {"linear", "finite"}},
        {"srgbToLinear", "srgb empty", [&] { srgbToLinear(Mat(), out); }, {"srgb"}},
        {"linearToSrgb", "linear empty", [&] { linearToSrgb(Mat(), out); }, {"linear"}},
    });
}

TEST(BadInput, Calibration)
{
    const Mat grey(48, 64, CV_8U, Scalar(128));
    Mat corners;
    const std::string junk = writeFile("junk.png", "not a png at all");
    refuseAll({
        {"detectChessboardCorners", "image empty", [&] { detectChessboardCorners(Mat(), Size(9, 6), corners); }, {"image"}},
        {"detectChessboardCorners", "image CV_32F", [&] { detectChessboardCorners(Mat(48, 64, CV_32F), Size(9, 6), corners); },
         {"image"}},
        {"detectChessboardCorners", "boardSize 1x6", [&] { detectChessboardCorners(grey, Size(1, 6), corners); }, {"boardSize"}},
        {"calibrateCameraViSP", "no image paths", [] { calibrateCameraViSP({}, Size(9, 6), 0.025); },
         {"0 of 0 views", "at least 3"}},
        {"calibrateCameraViSP", "squareSize = NaN", [&] { calibrateCameraViSP({junk, junk, junk}, Size(9, 6), kNaN); }, {"squareSize"}},
        {"calibrateCameraViSP", "boardSize 9x1", [&] { calibrateCameraViSP({junk, junk, junk}, Size(9, 1), 0.025); }, {"boardSize"}},
        {"calibrateCameraViSP", "outlierFactor = 0.5",
         [&] { calibrateCameraViSP({junk, junk, junk}, Size(9, 6), 0.025, 0.5); }, {"outlierFactor"}},
        {"calibrateCameraViSP", "three unreadable files",
         [&] { calibrateCameraViSP({junk, junk, junk}, Size(9, 6), 0.025); }, {"junk.png"}},
        {"calibrateCameraViSPImages", "images of CV_16U",
         [&] {
             calibrateCameraViSPImages(std::vector<Mat>(3, Mat(48, 64, CV_16U, Scalar(0))), {}, Size(9, 6), 0.025);
         },
         {"not 8-bit", "at least 3"}},
        {"calibrateCameraViSPImages", "viewNames of another length",
         [&] { calibrateCameraViSPImages(std::vector<Mat>(3, grey), {"a"}, Size(9, 6), 0.025); }, {"viewNames"}},
    });
}

TEST(BadInput, Bus)
{
    // No device behind these: every check happens before anything is sent.
    const Ptr<ActuatorBus> bus = ActuatorBus::create("tcp://127.0.0.1:9", 0.2, 0);
    auto driverWith = [&](std::function<void(ActuatorLimits&)> change) {
        ActuatorLimits l;
        change(l);
        ActuatorDriver::create(bus, l);
    };
    refuseAll({
        {"ActuatorBus::create", "uri udp://...", [] { ActuatorBus::create("udp://127.0.0.1:1"); }, {"uri", "tcp://"}},
        {"ActuatorBus::create", "uri without a port", [] { ActuatorBus::create("tcp://127.0.0.1"); }, {"tcp://HOST:PORT"}},
        {"ActuatorBus::create", "port 70000", [] { ActuatorBus::create("tcp://127.0.0.1:70000"); }, {"port", "[1, 65535]"}},
        {"ActuatorBus::create", "port 'x'", [] { ActuatorBus::create("tcp://127.0.0.1:x"); }, {"port"}},
        {"ActuatorBus::create", "baud 'x'", [] { ActuatorBus::create("rtu:/dev/null?baud=x"); }, {"baud"}},
        {"ActuatorBus::create", "baud 10", [] { ActuatorBus::create("rtu:/dev/null?baud=10"); }, {"baud", "[50, 4000000]"}},
        {"ActuatorBus::create", "parity X", [] { ActuatorBus::create("rtu:/dev/null?parity=X"); }, {"parity", "N, E or O"}},
        {"ActuatorBus::create", "unit 300", [] { ActuatorBus::create("tcp://127.0.0.1:1502?unit=300"); }, {"unit", "[0, 255]"}},
        {"ActuatorBus::create", "responseTimeout = 0", [] { ActuatorBus::create("tcp://127.0.0.1:1502", 0.0); },
         {"responseTimeout", "(0, 60]"}},
        {"ActuatorBus::create", "responseTimeout = NaN", [] { ActuatorBus::create("tcp://127.0.0.1:1502", kNaN); },
         {"responseTimeout", "(0, 60]"}},
        {"ActuatorBus::create", "retries = 11", [] { ActuatorBus::create("tcp://127.0.0.1:1502", 0.5, 11); }, {"retries", "[0, 10]"}},
        {"ActuatorBus::readInputRegisters", "count = 0", [&] { bus->readInputRegisters(0, 0); }, {"count", "[1, 125]"}},
        {"ActuatorBus::readHoldingRegisters", "count = 126", [&] { bus->readHoldingRegisters(0, 126); }, {"count", "[1, 125]"}},
        {"ActuatorBus::readInputRegisters", "address = -1", [&] { bus->readInputRegisters(-1, 1); }, {"address", "[0, 65535]"}},
        {"ActuatorBus::readHoldingRegisters", "address 65530 + 10", [&] { bus->readHoldingRegisters(65530, 10); }, {"count"}},
        {"ActuatorBus::writeRegisters", "no values", [&] { bus->writeRegisters(100, {}); }, {"count", "[1, 123]"}},
        {"ActuatorBus::writeRegisters", "value 70000", [&] { bus->writeRegisters(100, {1, 70000}); }, {"values[1]", "[-32768, 65535]"}},
        {"ActuatorBus::writeRegister", "value -40000", [&] { bus->writeRegister(100, -40000); }, {"value", "[-32768, 65535]"}},
        {"ActuatorBus::setResponseTimeout", "61", [&] { bus->setResponseTimeout(61); }, {"responseTimeout", "(0, 60]"}},
        {"ActuatorBus::setRetries", "-1", [&] { bus->setRetries(-1); }, {"retries", "[0, 10]"}},
        {"ActuatorDriver::create", "bus empty", [] { ActuatorDriver::create(Ptr<ActuatorBus>()); }, {"bus"}},
        {"ActuatorDriver::create", "limits.maxLevel = -1",
         [&] { driverWith([](ActuatorLimits& l) { l.maxLevel = -1; }); },
         {"limits.maxLevel", "[0, 32767]"}},
        {"ActuatorDriver::create", "limits.minDwell = NaN",
         [&] { driverWith([](ActuatorLimits& l) { l.minDwell = kNaN; }); },
         {"limits.minDwell", "[0, 1]"}},
        {"ActuatorDriver::create", "limits.maxEntries = 0",
         [&] { driverWith([](ActuatorLimits& l) { l.maxEntries = 0; }); },
         {"limits.maxEntries", "[1, 65535]"}},
        {"ActuatorDriver::create", "limits.safeLevel = 17 > maxLevel",
         [&] { driverWith([](ActuatorLimits& l) { l.safeLevel = 17; }); },
         {"limits.safeLevel", "maxLevel"}},
        {"ActuatorDriver::checkSchedule", "empty schedule", [&] { ActuatorDriver::create(bus)->checkSchedule(SwitchSchedule()); },
         {"times"}},
        {"ActuatorDriver::waitUntilDone", "timeout = -1", [&] { ActuatorDriver::create(bus)->waitUntilDone(-1); },
         {"timeout", "[0, 3600]"}},
        {"ActuatorDriver::waitUntilDone", "timeout = NaN", [&] { ActuatorDriver::create(bus)->waitUntilDone(kNaN); },
         {"timeout", "[0, 3600]"}},
        {"ActuatorDriver::start", "before any upload", [&] { ActuatorDriver::create(bus)->start(); }, {"upload"}},
        {"encodeSchedule", "levels[0] = 40000", [] { encodeSchedule(SwitchSchedule({0.0}, {40000})); }, {"levels"}},
        {"encodeSchedule", "span of 2 hours", [] { encodeSchedule(SwitchSchedule({0.0, 7200.0}, {1, 2})); }, {"2^32"}},
    });
}

// The likely unit mistakes: each refused at once (not minutes of kernels later), with a message that
// names the argument and suggests the unit.
TEST(BadInput, UnitMistakes)
{
    const Ptr<Plant> plant = Plant::create(14.4, 0.12, kDeg);
    const Ptr<CameraModel> cam = CameraModel::create(120, 120, 31.5, 23.5, 64, 48);
    const Ptr<DynamicDeblurrer> d = DynamicDeblurrer::create(plant, cam);
    const Mat frame(48, 64, CV_32F, Scalar(0.5));
    Mat out;
    refuseAll({
        {"DynamicDeblurrer::deblur", "exposure = 8 (ms)",
         [&] { d->deblur(frame, saccade(), RollingShutter(0.005, 8, 4e-4, 48), out); }, {"exposure", "seconds", "ms"}},
        {"DynamicDeblurrer::deblur", "lineDelay = 62.5 (us)",
         [&] { d->deblur(frame, saccade(), RollingShutter(0.005, 0.008, 62.5, 48), out); }, {"lineDelay", "seconds", "62.5e-6"}},
        {"renderBlurred", "exposure = 8 (ms)",
         [&] { renderBlurred(frame, plant, saccade(), cam, RollingShutter(0.005, 8, 4e-4, 48), out); }, {"exposure", "ms"}},
        {"Plant::create", "gain = 1 (rad per level, meant 1 deg)", [] { Plant::create(14.4, 0.12, 1.0); },
         {"gain", "radians per level", "degrees"}},
        {"Plant::identify", "theta in degrees",
         [&] {
             const SwitchSchedule step({0.01}, {10}, 0);
             std::vector<double> t, theta;
             for (int i = 0; i < 200; i++)
             {
                 t.push_back(i * 1e-3);
                 Mat th;
                 plant->response(step, Mat(1, 1, CV_64F, Scalar(t.back())), th);
                 theta.push_back(th.at<double>(0) / kDeg);
             }
             Plant::identify(t, theta, step);
         },
         {"theta", "radians expected", "degrees"}},
        {"Plant::create", "naturalFreqHz = 5000", [] { Plant::create(5000, 0.12, kDeg); }, {"naturalFreqHz", "Hz"}},
        {"SwitchPlanner::plan", "toAngle = 10 (deg)", [&] { SwitchPlanner::create(plant, 16)->plan(0.0, 10.0); },
         {"toAngle", "radians expected", "0.1745"}},
        {"DynamicDeblurrer::deblur", "thetaRef = 10 (deg)", [&] { d->deblur(frame, saccade(), RollingShutter(0.005, 0.008, 4e-4, 48), out, 10.0); },
         {"thetaRef", "radians expected"}},
        {"renderBlurred", "thetaRef = 10 (deg)",
         [&] { renderBlurred(frame, plant, saccade(), cam, RollingShutter(0.005, 0.008, 4e-4, 48), out, 10.0); },
         {"thetaRef", "radians expected"}},
    });
}
