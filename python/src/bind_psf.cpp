// SPDX-License-Identifier: Apache-2.0
// Bindings of psf.hpp: PsfPlan, PsfBank, PsfGenerator and the PSF models.
#include "bindings.hpp"

#include <opencv2/dynblur/psf.hpp>

#include <memory>
#include <string>
#include <vector>

namespace dynblur_py {

using namespace cv::dynblur;

void bindPsf(py::module_& m)
{
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
}

}  // namespace dynblur_py
