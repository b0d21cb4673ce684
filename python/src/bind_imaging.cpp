// SPDX-License-Identifier: Apache-2.0
// Bindings of camera.hpp, render.hpp, psf.hpp, deconv.hpp and deblurrer.hpp.
#include "bindings.hpp"

#include <opencv2/dynblur/camera.hpp>
#include <opencv2/dynblur/camera_motion.hpp>
#include <opencv2/dynblur/deblurrer.hpp>
#include <opencv2/dynblur/deconv.hpp>
#include <opencv2/dynblur/psf.hpp>
#include <opencv2/dynblur/render.hpp>

#include <memory>
#include <sstream>

namespace dynblur_py {

using namespace cv::dynblur;

namespace {

//! Points of shape (..., 2) → N×2 CV_64F, call, and back to the input's shape.
template <typename View>
py::array viewToReference(const CameraModel& cam, py::handle points, const View& view)
{
    auto a = toDoubleArray(points, "points");
    if (a.ndim() < 1 || a.shape(a.ndim() - 1) != 2)
        throw py::value_error("argument 'points' must have shape (..., 2): pixel (x, y) pairs");
    std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim());
    cv::Mat in(int(a.size() / 2), 2, CV_64F, const_cast<double*>(a.data())), out;
    {
        py::gil_scoped_release release;
        cam.viewToReference(in, view, out);
    }
    out = out.reshape(1, int(a.size() / 2));
    py::array_t<double> result(shape);
    CV_Assert(out.total() == size_t(result.size()) && out.depth() == CV_64F && out.isContinuous());
    std::copy(out.ptr<double>(), out.ptr<double>() + out.total(), result.mutable_data());
    return result;
}

/* DynamicDeblurrer::deblur of `frame` with `motion` (a schedule or a CameraMotion) without the GIL:
   restored, or (restored, validMask) when `returnMask`. */
template <typename Motion>
py::object deblurFrame(DynamicDeblurrer& db, py::handle frame, const Motion& motion, const RollingShutter& shutter,
                       double reference, bool returnMask)
{
    bool wasDouble = false;
    MatIn f = toFrame(frame, "frame", &wasDouble);
    cv::Mat out, mask;
    {
        py::gil_scoped_release release;
        if (returnMask)
            db.deblur(f.mat, motion, shutter, out, reference, mask);
        else
            db.deblur(f.mat, motion, shutter, out, reference);
    }
    if (returnMask)
        return py::make_tuple(fromFrame(out, wasDouble), fromMat(mask));
    return fromFrame(out, wasDouble);
}

std::string repr(const RLParams& p)
{
    std::ostringstream o;
    o << "RLParams(iterations=" << p.iterations << ", damping=" << p.damping << ", tvWeight=" << p.tvWeight
      << ", boundary=" << p.boundary << ", accelerate=" << (p.accelerate ? "True" : "False")
      << ", tolerance=" << p.tolerance << ", colorIterations=" << p.colorIterations
      << ", blurPrecision=" << p.blurPrecision << ")";
    return o.str();
}

}  // namespace

void bindImaging(py::module_& m)
{
    // ---------------------------------------------------------------- CameraModel
    py::class_<CameraModel, std::shared_ptr<CameraModel>>(m, "CameraModel", R"doc(Pinhole camera with ViSP's one-term radial distortion, mounted on the positioner.
u = cx + fx·x·(1 + kud·r²), v = cy + fy·y·(1 + kud·r²); a distorted pixel is undistorted with kdu.
Camera frame: x right, y down, z forward. The camera rotates about mountAxis (default +x: tilt);
the view at θ relative to θ_ref is I_θ(p) = I_ref(K·R_axis(θ − θ_ref)·K⁻¹·p).)doc")
        .def_static("create",
            [](double fx, double fy, double cx, double cy, int w, int h, double kud, double kdu) {
                return std::shared_ptr<CameraModel>(CameraModel::create(fx, fy, cx, cy, w, h, kud, kdu));
            },
            py::arg("fx"), py::arg("fy"), py::arg("cx"), py::arg("cy"), py::arg("width"), py::arg("height"),
            py::arg("kud") = 0.0, py::arg("kdu") = 0.0,
            R"doc(fx, fy: focal lengths, pixels, > 0; cx, cy: principal point, pixels; width, height: image
size, pixels; kud, kdu: ViSP's undistorted→distorted and distorted→undistorted radial coefficients.)doc")
        .def_static("load",
            [](const std::string& f, const std::string& name, int w, int h) {
                return std::shared_ptr<CameraModel>(CameraModel::load(f, name, w, h));
            },
            py::arg("filename"), py::arg("cameraName") = "", py::arg("width") = 0, py::arg("height") = 0,
            R"doc(Reads a ViSP camera XML file (vpXmlParserCamera format). cameraName: empty takes the first
camera; width, height: image size to select (0: any).)doc")
        .def("save", py::overload_cast<const cv::String&, const cv::String&>(&CameraModel::save, py::const_),
             py::arg("filename"), py::arg("cameraName") = "Camera",
             "Writes a ViSP camera XML file, with distortion when kud or kdu is non-zero.")
        .def("getFx", &CameraModel::getFx, "focal length along x, pixels")
        .def("getFy", &CameraModel::getFy, "focal length along y, pixels")
        .def("getCx", &CameraModel::getCx, "principal point x, pixels")
        .def("getCy", &CameraModel::getCy, "principal point y, pixels")
        .def("getKud", &CameraModel::getKud, "undistorted→distorted radial coefficient")
        .def("getKdu", &CameraModel::getKdu, "distorted→undistorted radial coefficient")
        .def("getImageSize", &CameraModel::getImageSize, "image size (width, height), pixels")
        .def("getMountAxis", &CameraModel::getMountAxis, "Rotation axis of the mount in the camera frame (unit vector).")
        .def("setMountAxis", &CameraModel::setMountAxis, py::arg("axis"),
             "axis: rotation axis in the camera frame, non-zero; it is normalised.")
        .def("cameraMatrix", &CameraModel::cameraMatrix, "The 3×3 intrinsic matrix K (float64 array).")
        .def("pixelToNormalized", &CameraModel::pixelToNormalized, py::arg("pixel"),
             "Undistorted normalised coordinates (x, y) of a (distorted) pixel (u, v).")
        .def("normalizedToPixel", &CameraModel::normalizedToPixel, py::arg("normalized"),
             "(Distorted) pixel (u, v) of undistorted normalised coordinates (x, y).")
        .def("viewToReference", &viewToReference<double>, py::arg("points"), py::arg("angle"),
             R"doc(Where pixels of the view at θ = θ_ref + angle see the reference view:
q = distort(K·R_axis(angle)·K⁻¹·undistort(p)). points: array of shape (..., 2), pixels;
angle: radians. Returns float64 pixel coordinates of the same shape (NaN for a ray behind the camera).)doc")
        .def("viewToReference", &viewToReference<cv::Matx33d>, py::arg("points"), py::arg("rotation"),
             R"doc(Where pixels of the view turned by any rotation R relative to the reference see the reference
view: q = distort(K·R·K⁻¹·undistort(p)) (R = Q_refᵀ·Q(t), CameraMotion.relativeRotation).
points: array of shape (..., 2), pixels; rotation: 3×3 rotation matrix. Returns float64 pixel
coordinates of the same shape.)doc");

    // ---------------------------------------------------------------- render.hpp
    m.def("renderBlurred",
        [](py::handle sharp, const std::shared_ptr<CameraMotion>& motion, const std::shared_ptr<CameraModel>& camera,
           const RollingShutter& shutter, double tRef, double maxStepPx, int borderMode) {
            MatIn in = toMat(sharp, "sharp");
            auto m = required(motion, "motion");
            auto c = required(camera, "camera");
            cv::Mat out;
            {
                py::gil_scoped_release release;
                renderBlurred(in.mat, m, c, shutter, out, tRef, maxStepPx, borderMode);
            }
            return fromMat(out);
        },
        py::arg("sharp"), py::arg("motion"), py::arg("camera"), py::arg("shutter"), py::arg("tRef") = kNaN,
        py::arg("maxStepPx") = 0.25, py::arg("borderMode") = int(cv::BORDER_REFLECT_101),
        R"doc(The physical forward model for any camera motion (CameraMotion): each row is the time average of
the sharp view turned by R(t) = Q_refᵀ·Q(t) over its own exposure. sharp: the view at Q(tRef) (as
for the plant form); tRef: seconds, NaN = the motion's default (a plant's final rest, a sampled
motion's mid-exposure). Returns the blurred frame.)doc");
    m.def("renderBlurred",
        [](py::handle sharp, const std::shared_ptr<Plant>& plant, const SwitchSchedule& schedule,
           const std::shared_ptr<CameraModel>& camera, const RollingShutter& shutter, double thetaRef,
           double maxStepPx, int borderMode) {
            MatIn in = toMat(sharp, "sharp");
            auto p = required(plant, "plant");
            auto c = required(camera, "camera");
            const SwitchSchedule s = schedule;
            cv::Mat out;
            {
                py::gil_scoped_release release;
                renderBlurred(in.mat, p, s, c, shutter, out, thetaRef, maxStepPx, borderMode);
            }
            return fromMat(out);
        },
        py::arg("sharp"), py::arg("plant"), py::arg("schedule"), py::arg("camera"), py::arg("shutter"),
        py::arg("thetaRef") = kNaN, py::arg("maxStepPx") = 0.25, py::arg("borderMode") = int(cv::BORDER_REFLECT_101),
        R"doc(The physical forward model: the frame a rolling-shutter sensor records while the positioner
follows a schedule. Each row is the time average, in linear intensity, of the view warped to the
camera's angle over its own exposure interval (uint8 input is taken as sRGB).

sharp: the motion-free view at θ_ref, the camera's image size or larger by the same margin on each
side, 1–4 channels, uint8/float32/float64; shutter.rows must equal the image height; thetaRef:
radians, NaN = the schedule's final resting angle; maxStepPx: largest image motion between time
samples, pixels, in (0, 1]; borderMode: cv2.BORDER_* used beyond sharp.
Returns the blurred frame (camera's image size, same dtype as sharp).)doc");

    m.def("addSensorNoise",
        [](py::handle linear, double fullWell, double readNoise, double dark, std::uint64_t seed) {
            MatIn in = toMat(linear, "linear");
            cv::Mat out;
            {
                py::gil_scoped_release release;
                addSensorNoise(in.mat, out, fullWell, readNoise, dark, seed);
            }
            return fromMat(out);
        },
        py::arg("linear"), py::arg("fullWellElectrons") = 4000.0, py::arg("readNoiseElectrons") = 8.0,
        py::arg("darkElectrons") = 5.0, py::arg("seed") = std::uint64_t(0x5eed),
        R"doc(Adds webcam sensor noise to a linear-intensity float32 image in [0, 1]: Poisson shot noise
(photons and dark current) and Gaussian read noise, then clips to [0, 1]. The same seed gives the
same noise. Returns float32.)doc");

    m.def("srgbToLinear",
        [](py::handle srgb) {
            MatIn in = toMat(srgb, "srgb");
            cv::Mat out;
            srgbToLinear(in.mat, out);
            return fromMat(out);
        },
        py::arg("srgb"), "sRGB (uint8 or [0,1] float) to linear intensity in [0, 1], float32, same channels.");
    m.def("linearToSrgb",
        [](py::handle linear, int depth) {
            MatIn in = toMat(linear, "linear");
            cv::Mat out;
            linearToSrgb(in.mat, out, depth);
            return fromMat(out);
        },
        py::arg("linear"), py::arg("depth") = int(CV_8U),
        "Linear intensity (float32) to sRGB of the requested depth (cv2.CV_8U = 0 or cv2.CV_32F = 5).");

    // ---------------------------------------------------------------- psf.hpp
    m.attr("PSF_UNIFORM") = int(PSF_UNIFORM);
    m.attr("PSF_ROWS") = int(PSF_ROWS);
    m.attr("PSF_TILES") = int(PSF_TILES);
    m.attr("PSF_AUTO") = int(PSF_AUTO);
    py::class_<PsfPlan>(m, "PsfPlan", R"doc(What PSF_AUTO chose for one frame: the operator (model) and, per band of rows (bandStart: first
row), PSF_UNIFORM, PSF_ROWS or PSF_TILES, with the displacement errors (pixels) of the cheaper models
it was chosen by. List fields are copies.)doc")
        .def(py::init<>())
        .def_readwrite("model", &PsfPlan::model, "the frame's operator: PSF_UNIFORM, PSF_ROWS or PSF_TILES")
        .def_readwrite("tolerance", &PsfPlan::tolerance, "tolerance it was chosen with, pixels")
        .def_readwrite("uniformError", &PsfPlan::uniformError, "PSF_UNIFORM's largest displacement error, pixels")
        .def_readwrite("bandStart", &PsfPlan::bandStart, "first frame row of each band")
        .def_readwrite("bandModel", &PsfPlan::bandModel, "per band: PSF_UNIFORM, PSF_ROWS or PSF_TILES")
        .def_readwrite("rowsError", &PsfPlan::rowsError, "per band: PSF_ROWS's largest displacement error, pixels")
        .def_readwrite("rows", &PsfPlan::rows, "frame rows")
        .def("rowShare", &PsfPlan::rowShare, py::arg("model"), "Share of the frame's rows given `model`, in [0, 1].");
    py::class_<PsfBank>(m, "PsfBank", R"doc(Spatially variant blur: kernels on a grid of nodes, blended with bilinear (partition of unity)
weights. Kernel n sits at node (nodeCols[n % nx], nodeRows[n // nx]); a latent point q spreads to
blurred pixels q + shifts[n] + (u − c) with weight kernels[n][u], c the kernel's centre element.
Kernels are float32, odd-sized, non-negative and sum to 1. List fields are copies: assign to change.)doc")
        .def(py::init<>())
        .def_readwrite("model", &PsfBank::model, "PsfModel that produced the bank")
        .def_readwrite("imageSize", &PsfBank::imageSize, "frame size (width, height), pixels")
        .def_readwrite("nodeRows", &PsfBank::nodeRows, "node y coordinates, pixels, increasing")
        .def_readwrite("nodeCols", &PsfBank::nodeCols, "node x coordinates, pixels, increasing")
        .def_property("kernels",
            [](const PsfBank& b) {
                py::list l;
                for (const auto& k : b.kernels)
                    l.append(fromMat(k));
                return l;
            },
            [](PsfBank& b, py::iterable kernels) {
                std::vector<cv::Mat> ks;
                int i = 0;
                for (auto k : kernels)
                {
                    const std::string name = "kernels[" + std::to_string(i++) + "]";
                    ks.push_back(toMat(k, name.c_str(), true).mat);
                }
                b.kernels = std::move(ks);
            },
            "kernels, row-major over the nodes (list of float32 arrays; a copy)")
        .def_readwrite("shifts", &PsfBank::shifts, "integer displacement (x, y) of each kernel's centre, pixels")
        .def("validate", &PsfBank::validate, "Raises dynblur.error when the bank is inconsistent (sizes, types, sums).")
        .def("maxKernelSize", &PsfBank::maxKernelSize, "Largest kernel (width, height) over the bank, pixels.")
        .def("isIdentity", &PsfBank::isIdentity,
             "True when every kernel is a one-tap kernel with zero shift (nothing to restore).");

    py::class_<PsfGenerator, std::shared_ptr<PsfGenerator>>(m, "PsfGenerator", R"doc(Predicts the blur of every pixel from the plant's trajectory and the shutter timing. For a
pixel p exposed over [t0, t1] the kernel is the path of p − q(t), q(t) = the reference point it
sees at θ(t), splatted bilinearly with weights ∝ dwell time and normalised to sum 1.)doc")
        .def_static("create",
            [](const std::shared_ptr<Plant>& plant, const std::shared_ptr<CameraModel>& camera) {
                return std::shared_ptr<PsfGenerator>(PsfGenerator::create(required(plant, "plant"), required(camera, "camera")));
            },
            py::arg("plant"), py::arg("camera"))
        .def_static("create",
            [](const std::shared_ptr<CameraModel>& camera) {
                return std::shared_ptr<PsfGenerator>(PsfGenerator::create(required(camera, "camera")));
            },
            py::arg("camera"), "A generator for a camera alone: it takes the motion with each frame.")
        .def("generate",
            [](const PsfGenerator& g, int model, const std::shared_ptr<CameraMotion>& motion,
               const RollingShutter& shutter, double tRef) {
                auto m = required(motion, "motion");
                py::gil_scoped_release release;
                return g.generate(model, m, shutter, tRef);
            },
            py::arg("model"), py::arg("motion"), py::arg("shutter"), py::arg("tRef") = kNaN,
            R"doc(Kernels for one frame of any camera motion (CameraMotion; its time span must cover the readout).
tRef: seconds, NaN = the motion's default reference. Returns a PsfBank.)doc")
        .def("generate",
            [](const PsfGenerator& g, int model, const SwitchSchedule& schedule, const RollingShutter& shutter,
               double thetaRef) {
                const SwitchSchedule s = schedule;
                py::gil_scoped_release release;
                return g.generate(model, s, shutter, thetaRef);
            },
            py::arg("model"), py::arg("schedule"), py::arg("shutter"), py::arg("thetaRef") = kNaN,
            R"doc(Kernels for one frame. model: PSF_UNIFORM, PSF_ROWS or PSF_TILES; shutter.rows must equal the
camera's image height; thetaRef: radians, NaN = the schedule's final resting angle. Returns a PsfBank.
PSF_AUTO: the model chosen per band of rows (the bank's model is the one chosen).)doc")
        .def("plan",
            [](const PsfGenerator& g, const std::shared_ptr<CameraMotion>& motion, const RollingShutter& shutter,
               double tRef) {
                auto m = required(motion, "motion");
                py::gil_scoped_release release;
                return g.plan(m, shutter, tRef);
            },
            py::arg("motion"), py::arg("shutter"), py::arg("tRef") = kNaN,
            "What PSF_AUTO chooses for one frame of `motion` (a PsfPlan).")
        .def("getAutoTolerance", &PsfGenerator::getAutoTolerance,
             "PSF_AUTO's largest displacement error of a cheaper model, pixels (default 0.25).")
        .def("setAutoTolerance", &PsfGenerator::setAutoTolerance, py::arg("pixels"))
        .def("getMaxKernelSize", &PsfGenerator::getMaxKernelSize,
             "Largest kernel extent allowed, pixels (default 401); a longer path is refused.")
        .def("setMaxKernelSize", &PsfGenerator::setMaxKernelSize, py::arg("pixels"))
        .def("getBandRows", &PsfGenerator::getBandRows,
             "Row-band height for PSF_ROWS, rows; 0 (default) chooses it from how fast the kernel changes.")
        .def("setBandRows", &PsfGenerator::setBandRows, py::arg("rows"))
        .def("getTileGrid", &PsfGenerator::getTileGrid,
             "Tile grid (columns, rows) of nodes for PSF_TILES; (0, 0) (default) chooses it.")
        .def("setTileGrid", &PsfGenerator::setTileGrid, py::arg("grid"));

    // ---------------------------------------------------------------- deconv.hpp
    m.attr("RL_BOUNDARY_ZERO") = int(RL_BOUNDARY_ZERO);
    m.attr("RL_BOUNDARY_PAD") = int(RL_BOUNDARY_PAD);
    m.attr("RL_BLUR_FLOAT32") = int(RL_BLUR_FLOAT32);
    m.attr("RL_BLUR_BFLOAT16") = int(RL_BLUR_BFLOAT16);
    const RLParams d;
    py::class_<RLParams>(m, "RLParams", "Options of Richardson–Lucy deconvolution.")
        .def(py::init([](int iterations, double damping, double tvWeight, int boundary, bool accelerate, double tolerance,
                         int colorIterations, int blurPrecision) {
                 RLParams p;
                 p.iterations = iterations;
                 p.damping = damping;
                 p.tvWeight = tvWeight;
                 p.boundary = boundary;
                 p.accelerate = accelerate;
                 p.tolerance = tolerance;
                 p.colorIterations = colorIterations;
                 p.blurPrecision = blurPrecision;
                 return p;
             }),
             py::arg("iterations") = d.iterations, py::arg("damping") = d.damping, py::arg("tvWeight") = d.tvWeight,
             py::arg("boundary") = d.boundary, py::arg("accelerate") = d.accelerate, py::arg("tolerance") = d.tolerance,
             py::arg("colorIterations") = d.colorIterations, py::arg("blurPrecision") = d.blurPrecision)
        .def_readwrite("iterations", &RLParams::iterations, "iterations, ≥ 1 (default 20)")
        .def_readwrite("damping", &RLParams::damping,
                       "DAMPAR of MATLAB's deconvlucy, linear intensity units, ≥ 0 (0: off); NaN: automatic, 3σ of the "
                       "frame's estimated noise (DynamicDeblurrer's default)")
        .def_readwrite("tvWeight", &RLParams::tvWeight, "total-variation regularisation weight λ, ≥ 0 (0: off)")
        .def_readwrite("boundary", &RLParams::boundary, "RL_BOUNDARY_ZERO or RL_BOUNDARY_PAD")
        .def_readwrite("accelerate", &RLParams::accelerate, "Biggs–Andrews vector extrapolation")
        .def_readwrite("tolerance", &RLParams::tolerance,
                       "stop a plane early when the relative change of its iteration falls below it, ≥ 0 (0: never)")
        .def_readwrite("colorIterations", &RLParams::colorIterations,
                       "iterations on every color plane of a 3–4 channel image, >= 0; the rest restore the luminance "
                       "alone and scale every plane by its change; -1 (default) or >= iterations: all")
        .def_readwrite("blurPrecision", &RLParams::blurPrecision,
                       "RL_BLUR_FLOAT32 (default) or RL_BLUR_BFLOAT16: the blurs of richardsonLucyVariant and "
                       "DynamicDeblurrer in bfloat16 (8 significant bits, float sums; two multiply-adds per "
                       "instruction with AVX512-BF16), a few hundredths of a dB from float")
        .def("__repr__", &repr);

    m.def("richardsonLucy",
        [](py::handle blurred, py::handle psf, const RLParams& params, py::handle initial) {
            MatIn b = toMat(blurred, "blurred"), k = toMat(psf, "psf");
            MatIn init;
            if (!initial.is_none())
                init = toMat(initial, "initial");
            cv::Mat out;
            {
                py::gil_scoped_release release;
                richardsonLucy(b.mat, k.mat, out, params, init.mat);
            }
            return fromMat(out);
        },
        py::arg("blurred"), py::arg("psf"), py::arg("params") = RLParams(), py::arg("initial") = py::none(),
        R"doc(Richardson–Lucy deconvolution with one kernel (FFTW, single precision, threaded).

blurred: float32, 1–4 channels, linear intensity, finite and >= 0 (clip noisy data at 0 first);
psf: float32/float64, one channel, odd size, non-negative (normalised here); params: RLParams;
initial: start estimate (same shape and dtype as blurred, >= 0), None = the blurred image. With RL_BOUNDARY_ZERO the update is scikit-image's
(richardson_lucy, clip=False) from the same start; RL_BOUNDARY_PAD extends the latent domain by
the kernel's half-size. Returns the latent image (same shape and dtype as blurred).)doc");

    m.def("richardsonLucyVariant",
        [](py::handle blurred, const PsfBank& bank, const RLParams& params, bool returnMask) -> py::object {
            MatIn b = toMat(blurred, "blurred");
            cv::Mat out, mask;
            {
                py::gil_scoped_release release;
                if (returnMask)
                    richardsonLucyVariant(b.mat, bank, out, params, mask);
                else
                    richardsonLucyVariant(b.mat, bank, out, params);
            }
            if (returnMask)
                return py::make_tuple(fromMat(out), fromMat(mask));
            return fromMat(out);
        },
        py::arg("blurred"), py::arg("bank"), py::arg("params") = RLParams(), py::arg("returnMask") = false,
        R"doc(Spatially variant Richardson–Lucy whose operator and adjoint are the bank's blended blur (no seams).

blurred: float32, 1–4 channels, linear intensity >= 0, the bank's image size. Returns latent (the view at θ_ref), or
(latent, validMask) with returnMask=True: validMask is uint8, 255 where the frame observed the
latent pixel (others hold the nearest observed value).)doc");

    m.def("applyPsfBank",
        [](py::handle latent, const PsfBank& bank) {
            MatIn l = toMat(latent, "latent");
            cv::Mat out;
            {
                py::gil_scoped_release release;
                applyPsfBank(l.mat, bank, out);
            }
            return fromMat(out);
        },
        py::arg("latent"), py::arg("bank"),
        "Applies the bank's forward blur B = A·L (float32, 1–4 channels, the bank's image size; zero outside the frame).");

    m.def("wienerDeconvolve",
        [](py::handle blurred, const PsfBank& bank, double nsr) {
            MatIn b = toMat(blurred, "blurred");
            cv::Mat out;
            {
                py::gil_scoped_release release;
                wienerDeconvolve(b.mat, bank, out, nsr);
            }
            return fromMat(out);
        },
        py::arg("blurred"), py::arg("bank"), py::arg("noiseToSignal") = 1e-2,
        R"doc(Wiener deconvolution, the non-iterative fast path: each node's kernel is inverted over its region
and the results blended with the bank's weights. noiseToSignal: noise-to-signal power ratio, > 0.)doc");

    // ---------------------------------------------------------------- deblurrer.hpp
    m.attr("DEBLUR_RICHARDSON_LUCY") = int(DEBLUR_RICHARDSON_LUCY);
    m.attr("DEBLUR_WIENER") = int(DEBLUR_WIENER);
    m.attr("DEBLUR_COLOR_FULL_RESOLUTION") = int(DEBLUR_COLOR_FULL_RESOLUTION);
    m.attr("DEBLUR_COLOR_HALF_RESOLUTION") = int(DEBLUR_COLOR_HALF_RESOLUTION);
    m.attr("DEBLUR_PRESET_DEFAULT") = int(DEBLUR_PRESET_DEFAULT);
    m.attr("DEBLUR_PRESET_FRAME_RATE") = int(DEBLUR_PRESET_FRAME_RATE);
    m.attr("UNOBSERVED_RECORDED") = int(UNOBSERVED_RECORDED);
    m.attr("UNOBSERVED_MARKED") = int(UNOBSERVED_MARKED);
    m.attr("UNOBSERVED_NEAREST") = int(UNOBSERVED_NEAREST);
    py::class_<DynamicDeblurrer, std::shared_ptr<DynamicDeblurrer>>(m, "DynamicDeblurrer", R"doc(Restores frames taken while the positioner moves: the blur of every pixel is predicted from the
plant and the commands, then undone. The result is the global-shutter, motion-free view at θ_ref.
One instance is not meant to be shared by threads running deblur() at the same time.)doc")
        .def_static("create",
            [](const std::shared_ptr<Plant>& plant, const std::shared_ptr<CameraModel>& camera) {
                return std::shared_ptr<DynamicDeblurrer>(DynamicDeblurrer::create(required(plant, "plant"), required(camera, "camera")));
            },
            py::arg("plant"), py::arg("camera"))
        .def_static("create",
            [](const std::shared_ptr<CameraModel>& camera) {
                return std::shared_ptr<DynamicDeblurrer>(DynamicDeblurrer::create(required(camera, "camera")));
            },
            py::arg("camera"), "A deblurrer for measured motion: no plant; deblur(frame, motion, shutter).")
        .def("deblur",
            [](DynamicDeblurrer& db, py::handle frame, const std::shared_ptr<CameraMotion>& motion,
               const RollingShutter& shutter, double tRef, bool returnMask) {
                return deblurFrame(db, frame, required(motion, "motion"), shutter, tRef, returnMask);
            },
            py::arg("frame"), py::arg("motion"), py::arg("shutter"), py::arg("tRef") = kNaN,
            py::arg("returnMask") = false,
            R"doc(Restores one frame of any camera motion (CameraMotion): the view at the orientation Q(tRef).
tRef: seconds, NaN = a plant's final rest or a sampled motion's mid-exposure. A plant's motion
(CameraMotion.fromPlant, the deblurrer's plant) is restored as deblur(frame, schedule, ...).
Returns restored, or (restored, validMask) with returnMask=True.)doc")
        .def("deblur",
            [](DynamicDeblurrer& db, py::handle frame, const SwitchSchedule& schedule, const RollingShutter& shutter,
               double thetaRef, bool returnMask) {
                return deblurFrame(db, frame, SwitchSchedule(schedule), shutter, thetaRef, returnMask);
            },
            py::arg("frame"), py::arg("schedule"), py::arg("shutter"), py::arg("thetaRef") = kNaN,
            py::arg("returnMask") = false,
            R"doc(Restores one frame.

frame: uint8 (sRGB) or float32 (linear, [0,1]; refused outside it), 1, 3 or 4 channels, the camera's image size;
schedule: the command in force around the frame; shutter: the frame's timing (rows = height);
thetaRef: radians, NaN = the schedule's final resting angle. Returns restored (same shape and
dtype; a window-IV frame comes back unchanged), or (restored, validMask) with returnMask=True
(uint8, 255 where the frame observed the restored pixel).)doc")
        .def("getPsfModel", &DynamicDeblurrer::getPsfModel,
             "PsfModel (default PSF_AUTO: per band of rows the cheapest model within the generator's auto tolerance)")
        .def("setPsfModel", &DynamicDeblurrer::setPsfModel, py::arg("model"))
        .def("setPreset", &DynamicDeblurrer::setPreset, py::arg("preset"),
             "Sets the PSF model, method, color resolution and RLParams of a DeblurPreset "
             "(DEBLUR_PRESET_DEFAULT or DEBLUR_PRESET_FRAME_RATE) together.")
        .def("getLastPlan", &DynamicDeblurrer::getLastPlan, "What PSF_AUTO chose for the last restored frame (PsfPlan).")
        .def("getMethod", &DynamicDeblurrer::getMethod, "DeblurMethod (DEBLUR_RICHARDSON_LUCY or DEBLUR_WIENER)")
        .def("setMethod", &DynamicDeblurrer::setMethod, py::arg("method"))
        .def("getColorResolution", &DynamicDeblurrer::getColorResolution,
             "DeblurColorResolution of the color iterations (RLParams.colorIterations in [0, iterations), 3-4 "
             "channels): DEBLUR_COLOR_FULL_RESOLUTION (default) or DEBLUR_COLOR_HALF_RESOLUTION (the frame halved, "
             "the luminance at full resolution with every iteration; needs an even image size)")
        .def("setColorResolution", &DynamicDeblurrer::setColorResolution, py::arg("resolution"))
        .def("getUnobservedFill", &DynamicDeblurrer::getUnobservedFill,
             "What the restored frame holds where the frame never saw the view: UNOBSERVED_RECORDED (the frame's "
             "pixel, default), UNOBSERVED_MARKED (black) or UNOBSERVED_NEAREST (the nearest observed pixel)")
        .def("setUnobservedFill", &DynamicDeblurrer::setUnobservedFill, py::arg("fill"))
        .def("getRLParams", &DynamicDeblurrer::getRLParams,
             "Restoration options; default RLParams() with automatic damping (NaN: 3σ of the frame's noise).")
        .def("setRLParams", &DynamicDeblurrer::setRLParams, py::arg("params"))
        .def("getLastExposureWindow", &DynamicDeblurrer::getLastExposureWindow,
             "Exposure window of the last frame passed to deblur() (0 before the first).")
        .def("getLastPsfBank", &DynamicDeblurrer::getLastPsfBank, "Kernels used for the last frame.")
        .def("getPsfGenerator", [](const DynamicDeblurrer& db) { return std::shared_ptr<PsfGenerator>(db.getPsfGenerator()); })
        .def("getRefinement", &DynamicDeblurrer::getRefinement,
             "MotionRefinement flags each frame's correction may change (default REFINE_ALL; runs while a reference "
             "frame is set)")
        .def("setRefinement", &DynamicDeblurrer::setRefinement, py::arg("flags"))
        .def("setReferenceFrame",
            [](DynamicDeblurrer& db, py::handle still, double angle) {
                MatIn s = toFrame(still, "still");
                py::gil_scoped_release release;
                db.setReferenceFrame(s.mat, angle);
            },
            py::arg("still"), py::arg("angle") = kNaN,
            R"doc(The still frame the next frames are compared with (same stream: dtype and channels), taken at
`angle` radians (NaN: each frame's schedule's initial resting angle).)doc")
        .def("setReferenceFrame",
            [](DynamicDeblurrer& db, py::handle still, const RollingShutter& stillShutter) {
                MatIn s = toMat(still, "still");
                py::gil_scoped_release release;
                db.setReferenceFrame(s.mat, stillShutter);
            },
            py::arg("still"), py::arg("stillShutter"),
            R"doc(The still frame for a measured motion's frames, placed by its capture time: the orientation at the
middle row's mid-exposure of stillShutter (the frames' clock, moved by the refined clock offset).)doc")
        .def("setReferenceFrames",
            [](DynamicDeblurrer& db, py::handle before, py::handle after, double angleBefore, double angleAfter) {
                MatIn b, a;
                if (!before.is_none())
                    b = toFrame(before, "before");
                if (!after.is_none())
                    a = toFrame(after, "after");
                py::gil_scoped_release release;
                db.setReferenceFrames(b.mat, a.mat, angleBefore, angleAfter);
            },
            py::arg("before"), py::arg("after"), py::arg("angleBefore") = kNaN, py::arg("angleAfter") = kNaN,
            R"doc(The still frames before and after a move (None: none on that side; not both); each frame is
compared with the one that observed its moving rows (window I: before; window III: after; window II: both).
Angles in radians; NaN: the schedule's initial (before) or final (after) resting angle.)doc")
        .def("setNoiseFrames",
            [](DynamicDeblurrer& db, py::handle stillA, py::handle stillB) {
                MatIn a, b;
                if (!stillA.is_none())
                    a = toFrame(stillA, "stillA");
                if (!stillB.is_none())
                    b = toFrame(stillB, "stillB");
                py::gil_scoped_release release;
                db.setNoiseFrames(a.mat, b.mat);
            },
            py::arg("stillA"), py::arg("stillB"),
            R"doc(Two consecutive stills at rest at the same view (same dtype, channels and size as the frames):
the noise refinement weighs its residuals by is measured from their difference at each scale the fit uses,
in place of Immerkær's estimate on the reference still. Identical stills are refused; None, None forgets
the measurement.)doc")
        .def("clearReferenceFrame", &DynamicDeblurrer::clearReferenceFrame)
        .def("getLastCorrection", &DynamicDeblurrer::getLastCorrection,
             "The MotionCorrection used for the last frame, its consistency, and whether it was applied.")
        .def("getCalibration", &DynamicDeblurrer::getCalibration,
             "The correction every frame starts from (a recording's calibrateTiming result).")
        .def("setCalibration", &DynamicDeblurrer::setCalibration, py::arg("correction"))
        .def("getConsistencyLimit", &DynamicDeblurrer::getConsistencyLimit,
             "Frames whose consistency exceeds it are returned unchanged (default 3, or 7.5 with noise frames; inf: no "
             "check)")
        .def("setConsistencyLimit", &DynamicDeblurrer::setConsistencyLimit, py::arg("limit"))
        .def("getBlindRefinement", &DynamicDeblurrer::getBlindRefinement,
             "Whether frames without a reference frame are refined blind (default False: the model as told)")
        .def("setBlindRefinement", &DynamicDeblurrer::setBlindRefinement, py::arg("enabled"))
        .def("getBlindConsistencyLimit", &DynamicDeblurrer::getBlindConsistencyLimit,
             "Blind frames whose criterion exceeds it are returned unchanged (default inf: no check)")
        .def("setBlindConsistencyLimit", &DynamicDeblurrer::setBlindConsistencyLimit, py::arg("limit"));
}

}  // namespace dynblur_py
