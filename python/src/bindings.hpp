// SPDX-License-Identifier: Apache-2.0
// Shared by the binding translation units of the dynblur extension.
#pragma once

#include "convert.hpp"

#include <exception>
#include <limits>
#include <memory>
#include <string>

namespace dynblur_py {

//! The object behind a required argument; ValueError naming it when it is None.
template <typename T>
cv::Ptr<T> required(const std::shared_ptr<T>& p, const char* name)
{
    if (!p)
        throw py::value_error(std::string("argument '") + name + "' is None");
    return cv::Ptr<T>(p);
}

//! NaN, the default of reference angles and times: the schedule's or the motion's own reference.
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

//! A library object as the shared_ptr its Python class holds.
template <typename T>
std::shared_ptr<T> shared(const cv::Ptr<T>& p)
{
    return std::shared_ptr<T>(p);
}

/* One function per bound public header, named for it (bind_<header>.cpp). module.cpp calls them in this
   order: a type is registered before any binding that takes, returns or defaults to it. */
void bindSchedule(py::module_& m);
void bindPlant(py::module_& m);
void bindPlanner(py::module_& m);
void bindShutter(py::module_& m);
void bindCameraMotion(py::module_& m);
void bindMount(py::module_& m);
void bindGyroLog(py::module_& m);
void bindCamera(py::module_& m);
void bindMountPlanner(py::module_& m);
void bindRefinement(py::module_& m);
void bindClipTiming(py::module_& m);
void bindRender(py::module_& m);
void bindPsf(py::module_& m);
void bindDeconv(py::module_& m);
void bindDeblurrer(py::module_& m);
void bindCalibration(py::module_& m);
void bindBus(py::module_& m);

//! First exception raised by a Python callback (OdePlant rhs) during the current call on this thread.
extern thread_local std::exception_ptr pendingCallbackError;
//! Rethrows and clears pendingCallbackError when set.
inline void rethrowCallbackError()
{
    if (pendingCallbackError)
    {
        std::exception_ptr e = pendingCallbackError;
        pendingCallbackError = nullptr;
        std::rethrow_exception(e);
    }
}

}  // namespace dynblur_py
