// SPDX-License-Identifier: Apache-2.0
// Bindings of deblurrer.hpp: DynamicDeblurrer and its options.
#include "bindings.hpp"

#include <opencv2/dynblur/deblurrer.hpp>

#include <memory>

namespace dynblur_py {

using namespace cv::dynblur;

namespace {

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

}  // namespace

void bindDeblurrer(py::module_& m)
{
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
dtype; a window-IV frame comes back unchanged, a sharp one is not deconvolved: getSharpThreshold), or
(restored, validMask) with returnMask=True (uint8, 255 where the frame observed the restored pixel).)doc")
        .def("getSharpThreshold", &DynamicDeblurrer::getSharpThreshold,
             "Pixels (default 1; 0: none): a frame whose blur and shift from the reference view both stay below "
             "it is not deconvolved; it comes back as it was, or with its rows moved back to the reference view "
             "(getLastCorrection().reason starts with 'sharp:')")
        .def("setSharpThreshold", &DynamicDeblurrer::setSharpThreshold, py::arg("px"))
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
        .def("setNeighbourFrame",
            [](DynamicDeblurrer& db, py::handle frame, const RollingShutter& shutter) {
                MatIn f;
                if (!frame.is_none())
                    f = toFrame(frame, "frame");
                py::gil_scoped_release release;
                db.setNeighbourFrame(f.mat, shutter);
            },
            py::arg("frame"), py::arg("shutter"),
            R"doc(A neighbouring frame of the next one of a measured motion's stream (None: forget it): with no still
set, the next frame is checked against it (the motion must carry its content onto the frame) and
returned unchanged when it does not.)doc")
        .def("getNeighbourLimit", &DynamicDeblurrer::getNeighbourLimit,
             "The blur error, pixels, the neighbour check accepts whatever the frame's blur (default 1).")
        .def("setNeighbourLimit", &DynamicDeblurrer::setNeighbourLimit, py::arg("limitPx"))
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
