// SPDX-License-Identifier: Apache-2.0
// The sRGB transfer curve (IEC 61966-2-1): exact conversions both ways and the table-driven 8-bit
// encoder and decoder the restoration's color path uses.
#include "precomp.hpp"
#include "imaging/srgb.hpp"

namespace cv {
namespace dynblur {

namespace {

inline double srgbToLinear1(double c)
{
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

inline double linearToSrgb1(double l)
{
    l = std::min(1.0, std::max(0.0, l));
    return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
}

}  // namespace

//! `src` as CV_32F (same channels) with `fn` applied to every element, rows in parallel.
template <typename Fn>
static Mat mapToFloat(const Mat& src, Fn fn)
{
    Mat f;
    src.convertTo(f, CV_32F);
    Mat f1 = f.reshape(1);
    parallel_for_(Range(0, f1.rows), [&](const Range& r) {
        for (int y = r.start; y < r.end; y++)
        {
            float* d = f1.ptr<float>(y);
            for (int x = 0; x < f1.cols; x++)
                d[x] = fn(d[x]);
        }
    });
    return f;
}

namespace {

/* 8-bit sRGB by tables: code k covers the linear values from codeStart[k], the sRGB curve's
   inverse at (k − 0.5) / 255 (the smallest float at or above it), up to codeStart[k + 1], so a
   value's code is 255·srgb(v) rounded to nearest. bucketCode[i] is the code of i / 4096; the curve
   never rises faster than 12.92 · 255 ≈ 3294 codes per unit (at black), so a bucket of 1/4096
   holds at most one step and one comparison finishes the code, where pow per value would be a
   pass of transcendental calls over every frame (BM_DeblurFrame8Bit against BM_DeblurFrame in
   perf/perf_deblurrer.cpp times the 8-bit path). */
struct SrgbEncoder
{
    static constexpr int kBuckets = 4096;
    float codeStart[257];
    uchar bucketCode[kBuckets + 1];

    SrgbEncoder()
    {
        codeStart[0] = -std::numeric_limits<float>::infinity();
        for (int k = 1; k < 256; k++)
        {
            const double linear = srgbToLinear1((k - 0.5) / 255.0);
            float start = (float)linear;
            if ((double)start < linear)
                start = std::nextafter(start, 2.f);
            codeStart[k] = start;
        }
        codeStart[256] = std::numeric_limits<float>::infinity();
        for (int i = 0, k = 0; i <= kBuckets; i++)
        {
            const float v = (float)i / kBuckets;
            while (v >= codeStart[k + 1])
                k++;
            bucketCode[i] = (uchar)k;
        }
    }

    static const SrgbEncoder& instance()
    {
        static const SrgbEncoder encoder;
        return encoder;
    }
};

}  // namespace

const float* detail::srgbDecodingTable()
{
    static const std::vector<float> table = [] {
        std::vector<float> t(256);
        for (int i = 0; i < 256; i++)
            t[size_t(i)] = (float)srgbToLinear1(i / 255.0);
        return t;
    }();
    return table.data();
}

/* Clamped to [0, 1] first (a NaN to 0, as std::max(0, NaN) gives 0). The multiply by a power of
   two is exact, so the bucket starts at or below the value. */
void detail::encodeSrgbRow(const float* __restrict linear, int n, uchar* __restrict out)
{
    const SrgbEncoder& e = SrgbEncoder::instance();
    for (int x = 0; x < n; x++)
    {
        const float v = std::min(std::max(0.f, linear[x]), 1.f);
        const int code = e.bucketCode[(int)(v * SrgbEncoder::kBuckets)];
        out[x] = (uchar)(code + (v >= e.codeStart[code + 1]));
    }
}

void srgbToLinear(InputArray _srgb, OutputArray _linear)
{
    Mat src = _srgb.getMat();
    if (src.empty())
        CV_Error(Error::StsBadArg, "srgbToLinear: 'srgb' is empty");
    const int depth = src.depth();
    if (depth == CV_8U)
    {
        const float* lut = detail::srgbDecodingTable();
        _linear.create(src.size(), CV_MAKETYPE(CV_32F, src.channels()));
        Mat out = _linear.getMat();
        const int n = src.cols * src.channels();
        parallel_for_(Range(0, src.rows), [&](const Range& rows) {
            for (int y = rows.start; y < rows.end; y++)
            {
                const uchar* s = src.ptr<uchar>(y);
                float* d = out.ptr<float>(y);
                for (int x = 0; x < n; x++)
                    d[x] = lut[s[x]];
            }
        });
        return;
    }
    CV_CheckType(src.type(), depth == CV_32F || depth == CV_64F, "srgbToLinear: srgb must be CV_8U, CV_32F or CV_64F");
    mapToFloat(src, [](float v) { return (float)srgbToLinear1(std::min(1.0, std::max(0.0, (double)v))); }).copyTo(_linear);
}

void linearToSrgb(InputArray _linear, OutputArray _srgb, int depth)
{
    Mat src = _linear.getMat();
    if (src.empty())
        CV_Error(Error::StsBadArg, "linearToSrgb: 'linear' is empty");
    CV_CheckType(src.type(), src.depth() == CV_32F || src.depth() == CV_64F,
                 "linearToSrgb: linear must be CV_32F (or CV_64F)");
    if (depth != CV_8U && depth != CV_32F)
        CV_Error_(Error::StsBadArg, ("linearToSrgb: depth=%d must be CV_8U or CV_32F", depth));
    if (depth == CV_8U)
    {
        Mat single = src;
        if (src.depth() != CV_32F)
            src.convertTo(single, CV_32F);
        _srgb.create(src.size(), CV_MAKETYPE(CV_8U, src.channels()));
        Mat out = _srgb.getMat();
        const int n = src.cols * src.channels();
        parallel_for_(Range(0, src.rows), [&](const Range& rows) {
            for (int y = rows.start; y < rows.end; y++)
                detail::encodeSrgbRow(single.ptr<float>(y), n, out.ptr<uchar>(y));
        });
        return;
    }
    mapToFloat(src, [](float v) { return (float)linearToSrgb1(v); }).copyTo(_srgb);
}

}  // namespace dynblur
}  // namespace cv
