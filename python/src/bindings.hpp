// Shared by the binding translation units of the dynblur extension.
#pragma once

#include "convert.hpp"

#include <exception>

namespace dynblur_py {

void bindMotion(py::module_& m);
void bindImaging(py::module_& m);
void bindCalibration(py::module_& m);
void bindRefinement(py::module_& m);

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
