// SPDX-License-Identifier: Apache-2.0
// Bindings of deconv.hpp: RLParams, Richardson–Lucy, the bank's forward blur, Wiener.
#include "bindings.hpp"

#include <opencv2/dynblur/deconv.hpp>

#include <sstream>
#include <string>

namespace dynblur_py {

using namespace cv::dynblur;

namespace {

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

void bindDeconv(py::module_& m)
{
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
}

}  // namespace dynblur_py
