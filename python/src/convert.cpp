// SPDX-License-Identifier: Apache-2.0
// numpy ⇄ cv::Mat conversion (see convert.hpp for the rules).
#include "convert.hpp"

#include <sstream>

namespace dynblur_py {

namespace {

py::module_ numpy() { return py::module_::import("numpy"); }

std::string describe(py::handle obj)
{
    return py::str(py::type::of(obj).attr("__name__")).cast<std::string>();
}

int depthOf(const py::dtype& dt, const char* name)
{
    const char kind = dt.kind();
    const auto size = dt.itemsize();
    switch (kind)
    {
    case 'b': return CV_8U;
    case 'u':
        if (size == 1) return CV_8U;
        if (size == 2) return CV_16U;
        break;
    case 'i':
        if (size == 1) return CV_8S;
        if (size == 2) return CV_16S;
        if (size == 4) return CV_32S;
        break;
    case 'f':
        if (size == 2) return CV_16F;
        if (size == 4) return CV_32F;
        if (size == 8) return CV_64F;
        break;
    default: break;
    }
    std::ostringstream msg;
    msg << "argument '" << name << "': dtype " << py::str(dt).cast<std::string>()
        << " is not supported (use uint8, int8, uint16, int16, int32, float16, float32 or float64)";
    throw py::value_error(msg.str());
}

py::dtype dtypeOf(int depth)
{
    switch (depth)
    {
    case CV_8U: return py::dtype("uint8");
    case CV_8S: return py::dtype("int8");
    case CV_16U: return py::dtype("uint16");
    case CV_16S: return py::dtype("int16");
    case CV_32S: return py::dtype("int32");
    case CV_16F: return py::dtype("float16");
    case CV_32F: return py::dtype("float32");
    case CV_64F: return py::dtype("float64");
    default: throw std::runtime_error("dynblur: unsupported cv::Mat depth " + std::to_string(depth));
    }
}

//! A C-contiguous, aligned, native-endian numpy array for obj (no copy when it already is one).
py::array asArray(py::handle obj, const char* name)
{
    if (obj.is_none())
        throw py::value_error(std::string("argument '") + name + "' is None, expected an array");
    py::array a;
    if (py::isinstance<py::array>(obj))
        a = py::reinterpret_borrow<py::array>(obj);
    else
    {
        try
        {
            a = numpy().attr("asarray")(obj);
        }
        catch (py::error_already_set& e)
        {
            throw py::value_error(std::string("argument '") + name + "' (" + describe(obj) +
                                  ") cannot be converted to an array: " + e.what());
        }
    }
    if (a.dtype().kind() == 'O')
        throw py::value_error(std::string("argument '") + name +
                              "': object arrays are not supported, expected a numeric array");
    if (a.dtype().byteorder() == '>')  // big-endian on this (little-endian) machine
        a = a.attr("astype")(a.dtype().attr("newbyteorder")("="));
    const int flags = a.flags();
    if (!(flags & py::array::c_style) || !(flags & py::detail::npy_api::NPY_ARRAY_ALIGNED_))
        a = numpy().attr("ascontiguousarray")(a);  // slices, negative strides, unaligned: copied
    return a;
}

}  // namespace

MatIn toMat(py::handle obj, const char* name, bool copy)
{
    py::array a = asArray(obj, name);
    const int depth = depthOf(a.dtype(), name);
    const auto nd = a.ndim();
    if (nd < 1 || nd > 3)
    {
        std::ostringstream msg;
        msg << "argument '" << name << "' has " << nd
            << " dimensions, expected 1 (N), 2 (H×W) or 3 (H×W×C)";
        throw py::value_error(msg.str());
    }
    const int rows = int(a.shape(0));
    const int cols = nd >= 2 ? int(a.shape(1)) : 1;
    const int channels = nd == 3 ? int(a.shape(2)) : 1;
    if (channels < 1 || channels > 4)
    {
        std::ostringstream msg;
        msg << "argument '" << name << "' has " << channels
            << " channels (last dimension of an H×W×C array), expected 1 to 4";
        throw py::value_error(msg.str());
    }
    MatIn in;
    in.owner = a;
    const size_t step = size_t(cols) * size_t(channels) * size_t(a.itemsize());
    in.mat = cv::Mat(rows, cols, CV_MAKETYPE(depth, channels), const_cast<void*>(a.data()),
                     rows > 0 ? step : size_t(cv::Mat::AUTO_STEP));
    if (copy)
    {
        in.mat = in.mat.clone();
        in.owner = py::none();
    }
    return in;
}

MatIn toFrame(py::handle obj, const char* name, bool* wasDouble)
{
    MatIn in = toMat(obj, name);
    const int depth = in.mat.depth();
    if (wasDouble)
        *wasDouble = depth == CV_64F;
    if (depth == CV_64F)
    {
        cv::Mat single;
        in.mat.convertTo(single, CV_32F);
        in.mat = single;
        in.owner = py::none();
    }
    else if (depth != CV_8U && depth != CV_32F)
        throw py::value_error(std::string("argument '") + name + "': dtype " +
                              py::str(py::array::ensure(obj).dtype()).cast<std::string>() +
                              " is not a frame's (use uint8 for sRGB, float32 or float64 for linear values in [0, 1])");
    return in;
}

py::array fromFrame(const cv::Mat& m, bool asDouble)
{
    if (!asDouble || m.depth() != CV_32F)
        return fromMat(m);
    cv::Mat wide;
    m.convertTo(wide, CV_64F);
    return fromMat(wide);
}

py::array fromMat(const cv::Mat& src)
{
    cv::Mat m = src;
    if (m.dims > 2)
        throw std::runtime_error("dynblur: cannot return a cv::Mat with more than 2 dimensions");
    if (!m.empty() && (!m.isContinuous() || m.u == nullptr))
        m = m.clone();  // foreign memory (an argument's buffer) or a strided view: own a copy
    const py::dtype dt = dtypeOf(m.depth());
    const py::ssize_t rows = m.rows, cols = m.cols, ch = m.channels();
    const py::ssize_t es1 = py::ssize_t(m.elemSize1());
    std::vector<py::ssize_t> shape{rows, cols}, strides{cols * ch * es1, ch * es1};
    if (ch > 1)
    {
        shape.push_back(ch);
        strides.push_back(es1);
    }
    if (m.empty())
        return py::array(dt, shape, strides);
    auto* keep = new cv::Mat(m);
    py::capsule owner(keep, [](void* p) { delete static_cast<cv::Mat*>(p); });
    return py::array(dt, shape, strides, m.data, owner);
}

py::array_t<double, py::array::c_style> toDoubleArray(py::handle obj, const char* name)
{
    py::array a = asArray(obj, name);
    const char kind = a.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b')
        throw py::value_error(std::string("argument '") + name + "': dtype " +
                              py::str(a.dtype()).cast<std::string>() + " is not numeric");
    return numpy().attr("ascontiguousarray")(a, py::arg("dtype") = "float64");
}

cv::Mat timesArg(py::handle obj, Doubles& keep, const char* name)
{
    keep = toDoubleArray(obj, name);
    if (keep.ndim() != 1)
        throw py::value_error(std::string("argument '") + name + "' must have shape (N,): sample times, seconds");
    return cv::Mat(int(keep.shape(0)), 1, CV_64F, keep.mutable_data());
}

/** Per-sample rows of shape (N, C), C in `columns` (or (N, 3, 3) when 9 is allowed: matrices), as an
    N×C Mat over `keep`'s data. */
cv::Mat rowsArg(py::handle obj, Doubles& keep, const char* name, std::initializer_list<int> columns,
                const char* allowed)
{
    keep = toDoubleArray(obj, name);
    int cols = -1;
    if (keep.ndim() == 2)
        cols = int(keep.shape(1));
    else if (keep.ndim() == 3 && keep.shape(1) == 3 && keep.shape(2) == 3)
        cols = 9;
    bool ok = false;
    for (int c : columns)
        ok = ok || c == cols;
    if (!ok)
        throw py::value_error(std::string("argument '") + name + "' must have shape " + allowed);
    return cv::Mat(int(keep.shape(0)), cols, CV_64F, keep.mutable_data());
}

//! A list of frames → Mats that own no Python memory past the call (copied when needed).
std::vector<cv::Mat> toMats(py::handle list, const char* name)
{
    std::vector<cv::Mat> mats;
    size_t index = 0;
    for (py::handle item : py::iter(list))
    {
        const std::string itemName = std::string(name) + "[" + std::to_string(index++) + "]";
        mats.push_back(toFrame(item, itemName.c_str()).mat.clone());
    }
    return mats;
}

}  // namespace dynblur_py
