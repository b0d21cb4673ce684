// SPDX-License-Identifier: Apache-2.0
// The extension module dynblur._dynblur: cv::dynblur for Python (see python/README.md).
#include "bindings.hpp"

#include <opencv2/core.hpp>

namespace dynblur_py {

thread_local std::exception_ptr pendingCallbackError;

namespace {

//! Class raised for cv::Exception; dynblur/__init__.py replaces it (a cv2.error subclass when cv2 imports).
PyObject* errorClass = nullptr;

void raiseCvError(const cv::Exception& e)
{
    py::gil_scoped_acquire gil;
    py::handle cls(errorClass);
    py::object exc = cls(e.what());
    exc.attr("code") = e.code;
    exc.attr("err") = e.err;
    exc.attr("func") = e.func;
    exc.attr("file") = e.file;
    exc.attr("line") = e.line;
    exc.attr("msg") = e.msg;
    PyErr_SetObject(errorClass, exc.ptr());
}

}  // namespace

}  // namespace dynblur_py

PYBIND11_MODULE(_dynblur, m)
{
    using namespace dynblur_py;
    m.doc() = "cv::dynblur bindings (use the package `dynblur` or `cv2.dynblur`).";
    errorClass = PyErr_NewExceptionWithDoc("dynblur.error", "An error reported by the C++ library (cv::Exception).",
                                           PyExc_Exception, nullptr);
    m.attr("error") = py::handle(errorClass);
    m.def("_set_error_class", [](py::object cls) {
        Py_XDECREF(errorClass);
        errorClass = cls.inc_ref().ptr();
    });
    py::register_exception_translator([](std::exception_ptr p) {
        try
        {
            if (p)
                std::rethrow_exception(p);
        }
        catch (const cv::Exception& e)
        {
            raiseCvError(e);
        }
    });
    m.attr("__opencv_version__") = CV_VERSION;
    // Test hooks for the converters: an array through cv::Mat and back, and how it was seen.
    m.def("_roundtrip", [](py::handle a) { return fromMat(toMat(a, "a").mat.clone()); }, py::arg("a"));
    m.def("_matInfo", [](py::handle a) {
        cv::Mat mat = toMat(a, "a").mat;
        return py::make_tuple(mat.rows, mat.cols, mat.channels(), mat.depth());
    }, py::arg("a"));
    // In bindings.hpp's order: each type is registered before a binding that uses it.
    bindSchedule(m);
    bindPlant(m);
    bindPlanner(m);
    bindShutter(m);
    bindCameraMotion(m);
    bindMount(m);
    bindGyroLog(m);
    bindCamera(m);
    bindMountPlanner(m);
    bindRefinement(m);
    bindClipTiming(m);
    bindRender(m);
    bindPsf(m);
    bindDeconv(m);
    bindDeblurrer(m);
    bindCalibration(m);
    bindBus(m);
}
