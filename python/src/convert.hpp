// SPDX-License-Identifier: Apache-2.0
// numpy ⇄ cv::Mat and small OpenCV value types ⇄ Python, for the dynblur extension.
//
// Inputs: any array-like becomes a cv::Mat header over a C-contiguous, aligned, native-endian
// numpy array (copied only when the original is not one: slices, negative strides, big-endian,
// lists). The header is valid while the MatIn that holds it lives. Outputs: every returned array
// owns its data (a capsule keeps the cv::Mat alive), and a Mat that points at foreign memory (an
// input's buffer) is cloned first, so no result aliases a temporary or an argument.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <opencv2/core.hpp>

#include <initializer_list>
#include <string>

namespace dynblur_py {

namespace py = pybind11;

//! A cv::Mat viewing a numpy array, with the array kept alive beside it.
struct MatIn
{
    cv::Mat mat;
    py::object owner;
};

/** @brief Converts an array-like argument to a Mat: 1-D → N×1, 2-D → H×W one channel,
3-D → H×W×C with 1 ≤ C ≤ 4. Supported dtypes: uint8, int8, uint16, int16, int32, float16,
float32, float64 (bool is taken as uint8). Throws ValueError naming `name` otherwise.
@param copy the Mat owns a copy of the data (for values stored beyond the call). */
MatIn toMat(py::handle obj, const char* name, bool copy = false);

/** @brief A camera frame for the restoration: uint8 (sRGB) and float32 (linear, in [0, 1]) as they
are, float64 converted to float32 (`wasDouble` tells), any other dtype a ValueError naming `name` and
the dtypes allowed. The frame's values are checked by the C++ call. */
MatIn toFrame(py::handle obj, const char* name, bool* wasDouble = nullptr);

/** @brief A restored frame in its input's type: float64 when the input was (`asDouble`), else as is. */
py::array fromFrame(const cv::Mat& m, bool asDouble);

/** @brief A numpy array with the Mat's data: H×W for one channel, H×W×C otherwise. The array keeps
the Mat alive; a Mat over memory OpenCV does not own (or non-continuous) is cloned. */
py::array fromMat(const cv::Mat& m);

//! Float64 numpy array of any shape from an array-like argument (ValueError naming it otherwise).
py::array_t<double, py::array::c_style> toDoubleArray(py::handle obj, const char* name);

//! A float64 C-contiguous numpy array: what keeps the data of timesArg's and rowsArg's Mats alive.
using Doubles = py::array_t<double, py::array::c_style>;

//! Sample times of shape (N,) as an N×1 Mat over `keep`'s data.
cv::Mat timesArg(py::handle obj, Doubles& keep, const char* name = "times");

/** Per-sample rows of shape (N, C), C in `columns` (or (N, 3, 3) when 9 is allowed: matrices), as an
    N×C Mat over `keep`'s data. */
cv::Mat rowsArg(py::handle obj, Doubles& keep, const char* name, std::initializer_list<int> columns,
                const char* allowed);

//! A list of frames (toFrame each, named `name`[i]) → Mats that own no Python memory past the call.
std::vector<cv::Mat> toMats(py::handle list, const char* name);

}  // namespace dynblur_py

namespace pybind11 {
namespace detail {

//! Fixed-size numeric OpenCV types as Python tuples (any length-N sequence on input).
template <typename T, typename Elem, int N, typename Access>
struct fixed_tuple_caster
{
    PYBIND11_TYPE_CASTER(T, const_name("tuple"));

    bool load(handle src, bool convert)
    {
        if (!src || isinstance<str>(src) || !PySequence_Check(src.ptr()))
            return false;
        auto seq = reinterpret_borrow<sequence>(src);
        if (seq.size() != size_t(N))
            return false;
        for (int i = 0; i < N; ++i)
        {
            make_caster<Elem> c;
            if (!c.load(seq[size_t(i)], convert))
                return false;
            Access::at(value, i) = cast_op<Elem>(c);
        }
        return true;
    }

    static handle cast(const T& v, return_value_policy, handle)
    {
        tuple t(N);
        for (int i = 0; i < N; ++i)
            t[size_t(i)] = pybind11::cast(Access::at(const_cast<T&>(v), i));
        return t.release();
    }
};

template <typename V> struct VecAccess { static auto& at(V& v, int i) { return v[i]; } };
template <typename P> struct PointAccess { static auto& at(P& p, int i) { return i == 0 ? p.x : p.y; } };
template <typename S> struct SizeAccess { static auto& at(S& s, int i) { return i == 0 ? s.width : s.height; } };

template <typename E, int N>
struct type_caster<cv::Vec<E, N>> : fixed_tuple_caster<cv::Vec<E, N>, E, N, VecAccess<cv::Vec<E, N>>> {};
template <typename E>
struct type_caster<cv::Point_<E>> : fixed_tuple_caster<cv::Point_<E>, E, 2, PointAccess<cv::Point_<E>>> {};
template <typename E>
struct type_caster<cv::Size_<E>> : fixed_tuple_caster<cv::Size_<E>, E, 2, SizeAccess<cv::Size_<E>>> {};

//! 3×3 double matrices as float64 numpy arrays.
template <>
struct type_caster<cv::Matx33d>
{
    PYBIND11_TYPE_CASTER(cv::Matx33d, const_name("numpy.ndarray"));
    bool load(handle src, bool)
    {
        try
        {
            auto a = dynblur_py::toDoubleArray(src, "matrix");
            if (a.size() != 9)
                return false;
            for (int i = 0; i < 9; ++i)
                value.val[i] = a.data()[i];
            return true;
        }
        catch (const std::exception&)
        {
            return false;
        }
    }
    static handle cast(const cv::Matx33d& m, return_value_policy, handle)
    {
        array_t<double> a({3, 3});
        for (int i = 0; i < 9; ++i)
            a.mutable_data()[i] = m.val[i];
        return a.release();
    }
};

}  // namespace detail
}  // namespace pybind11
