// The physical forward model (DESIGN §2): a rolling-shutter frame recorded while the positioner
// moves, by time integration of warped views. Ground truth for PsfGenerator: it shares no code
// with psf.cpp (it warps images; psf.cpp splats paths).
#include "precomp.hpp"

#include <random>

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

void checkShutterForCamera(const RollingShutter& shutter, const Size& imageSize, const char* where)
{
    if (!std::isfinite(shutter.frameStart))
        CV_Error_(Error::StsBadArg, ("%s: shutter.frameStart must be finite (seconds)", where));
    if (!(std::isfinite(shutter.exposure) && shutter.exposure >= 0))
        CV_Error_(Error::StsBadArg, ("%s: shutter.exposure=%g must be finite and >= 0 (seconds)", where,
                                     shutter.exposure));
    if (!(std::isfinite(shutter.lineDelay) && shutter.lineDelay >= 0))
        CV_Error_(Error::StsBadArg, ("%s: shutter.lineDelay=%g must be finite and >= 0 (seconds)", where,
                                     shutter.lineDelay));
    if (shutter.rows != imageSize.height)
        CV_Error_(Error::StsBadArg, ("%s: shutter.rows=%d must equal the camera's image height %d", where,
                                     shutter.rows, imageSize.height));
}

//! Bilinear sample of `src` (type T, CN channels) at (x, y), borders by borderMode; adds w·value to acc.
template <typename T, int CN>
inline void addBilinear(const Mat& src, double x, double y, int borderMode, T w, T* acc)
{
    const int x0 = cvFloor(x), y0 = cvFloor(y);
    const int W = src.cols, H = src.rows;
    if (x0 >= 0 && y0 >= 0 && x0 + 1 < W && y0 + 1 < H)
    {
        const T ax = (T)(x - x0), ay = (T)(y - y0);
        const T* r0 = src.ptr<T>(y0) + x0 * CN;
        const T* r1 = src.ptr<T>(y0 + 1) + x0 * CN;
        const T w00 = w * (1 - ax) * (1 - ay), w01 = w * ax * (1 - ay), w10 = w * (1 - ax) * ay, w11 = w * ax * ay;
        for (int c = 0; c < CN; c++)
            acc[c] += w00 * r0[c] + w01 * r0[c + CN] + w10 * r1[c] + w11 * r1[c + CN];
        return;
    }
    if (!(std::isfinite(x) && std::isfinite(y)))
        return;  // a ray behind the reference camera: contributes black
    const double ax = x - x0, ay = y - y0;
    const double wx[2] = {1 - ax, ax}, wy[2] = {1 - ay, ay};
    for (int j = 0; j < 2; j++)
    {
        if (wy[j] == 0)
            continue;
        const int yy = borderInterpolate(y0 + j, H, borderMode);
        for (int i = 0; i < 2; i++)
        {
            if (wx[i] == 0)
                continue;
            const int xx = borderInterpolate(x0 + i, W, borderMode);
            if (xx < 0 || yy < 0)
                continue;  // BORDER_CONSTANT: zero
            const T* p = src.ptr<T>(yy) + xx * CN;
            for (int c = 0; c < CN; c++)
                acc[c] += (T)(w * wx[i] * wy[j] * p[c]);
        }
    }
}

//! acc rows [r0, r1) += rowWeight[r] · sharp(q(x, r)). q is known at the columns `cols` of each row
//! (2-channel doubles, one row per image row) and linear in between.
template <typename T, int CN>
void warpAccumulate(const Mat& sharp, const Mat& coarse, const std::vector<int>& cols, int r0, int r1,
                    const std::vector<double>& rowWeight, Point2d offset, int borderMode, Mat& acc)
{
    parallel_for_(Range(r0, r1), [&](const Range& rr) {
        for (int r = rr.start; r < rr.end; r++)
        {
            const T w = (T)rowWeight[r];
            if (w <= 0)
                continue;
            const Point2d* q = coarse.ptr<Point2d>(r - r0);
            T* a = acc.ptr<T>(r);
            for (size_t s = 0; s + 1 < cols.size(); s++)
            {
                const int xa = cols[s], xb = cols[s + 1];
                const Point2d qa = q[s] + offset, dq = (q[s + 1] - q[s]) * (1.0 / (xb - xa));
                const int xEnd = s + 2 == cols.size() ? xb + 1 : xb;
                for (int x = xa; x < xEnd; x++)
                {
                    const double t = x - xa;
                    addBilinear<T, CN>(sharp, qa.x + t * dq.x, qa.y + t * dq.y, borderMode, w, a + x * CN);
                }
            }
        }
    });
}

template <typename T>
void warpAccumulateCn(const Mat& sharp, const Mat& coarse, const std::vector<int>& cols, int r0, int r1,
                      const std::vector<double>& rowWeight, Point2d offset, int borderMode, Mat& acc)
{
    switch (sharp.channels())
    {
    case 1: warpAccumulate<T, 1>(sharp, coarse, cols, r0, r1, rowWeight, offset, borderMode, acc); break;
    case 2: warpAccumulate<T, 2>(sharp, coarse, cols, r0, r1, rowWeight, offset, borderMode, acc); break;
    case 3: warpAccumulate<T, 3>(sharp, coarse, cols, r0, r1, rowWeight, offset, borderMode, acc); break;
    default: warpAccumulate<T, 4>(sharp, coarse, cols, r0, r1, rowWeight, offset, borderMode, acc); break;
    }
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

void addSensorNoise(InputArray _linear, OutputArray _noisy, double fullWellElectrons, double readNoiseElectrons,
                    double darkElectrons, uint64 seed)
{
    Mat src = _linear.getMat();
    if (src.empty())
        CV_Error(Error::StsBadArg, "addSensorNoise: 'linear' is empty");
    CV_CheckType(src.type(), src.depth() == CV_32F, "addSensorNoise: linear must be CV_32F");
    if (!checkRange(src))
        CV_Error(Error::StsBadArg, "addSensorNoise: 'linear' holds NaN or Inf; it must be finite");
    if (!(std::isfinite(fullWellElectrons) && fullWellElectrons > 0))
        CV_Error_(Error::StsBadArg, ("addSensorNoise: fullWellElectrons=%g must be finite and > 0", fullWellElectrons));
    if (!(std::isfinite(readNoiseElectrons) && readNoiseElectrons >= 0))
        CV_Error_(Error::StsBadArg,
                  ("addSensorNoise: readNoiseElectrons=%g must be finite and >= 0", readNoiseElectrons));
    if (!(std::isfinite(darkElectrons) && darkElectrons >= 0))
        CV_Error_(Error::StsBadArg, ("addSensorNoise: darkElectrons=%g must be finite and >= 0", darkElectrons));
    Mat out = src.clone();
    std::mt19937_64 engine(seed);
    std::normal_distribution<double> read(0.0, 1.0);
    for (int y = 0; y < out.rows; y++)
    {
        float* d = out.ptr<float>(y);
        const int n = out.cols * out.channels();
        for (int x = 0; x < n; x++)
        {
            // Photo-electrons plus dark electrons are Poisson; the camera subtracts the mean dark
            // level (black clamp), so the result is unbiased before clipping.
            const double mean = std::max(0.0, (double)d[x]) * fullWellElectrons + darkElectrons;
            double e = 0.0;
            if (mean > 0)
            {
                std::poisson_distribution<long long> shot(mean);
                e = (double)shot(engine);
            }
            e += readNoiseElectrons * read(engine) - darkElectrons;
            d[x] = (float)std::min(1.0, std::max(0.0, e / fullWellElectrons));
        }
    }
    out.copyTo(_noisy);
}

void renderBlurred(InputArray _sharp, const Ptr<Plant>& plant, const SwitchSchedule& schedule,
                   const Ptr<CameraModel>& camera, const RollingShutter& shutter, OutputArray _blurred,
                   double thetaRef, double maxStepPx, int borderMode)
{
    static const char* where = "renderBlurred";
    CV_Assert(plant && "renderBlurred: plant must not be null");
    CV_Assert(camera && "renderBlurred: camera must not be null");
    Mat sharp = _sharp.getMat();
    if (sharp.empty())
        CV_Error(Error::StsBadArg, "renderBlurred: sharp is empty");
    const int depth = sharp.depth(), cn = sharp.channels();
    if (!(depth == CV_8U || depth == CV_32F || depth == CV_64F) || cn < 1 || cn > 4)
        CV_Error_(Error::StsUnsupportedFormat,
                  ("renderBlurred: sharp must be CV_8U, CV_32F or CV_64F with 1-4 channels (got depth %d, %d channels)",
                   depth, cn));
    const Size size = camera->getImageSize();
    const int W = size.width, H = size.height;
    const int dx = sharp.cols - W, dy = sharp.rows - H;
    if (dx < 0 || dy < 0 || (dx % 2) != 0 || (dy % 2) != 0)
        CV_Error_(Error::StsBadArg,
                  ("renderBlurred: sharp is %dx%d; it must be the camera's %dx%d or larger by the same margin on "
                   "each side (even difference)",
                   sharp.cols, sharp.rows, W, H));
    const Point2d offset(dx / 2, dy / 2);
    checkShutterForCamera(shutter, size, where);
    if (std::isinf(thetaRef))
        CV_Error(Error::StsBadArg, "renderBlurred: thetaRef must be finite (radians) or NaN (final resting angle)");
    if (!(maxStepPx > 0 && maxStepPx <= 1))
        CV_Error_(Error::StsBadArg, ("renderBlurred: maxStepPx=%g must be in (0, 1] (pixels)", maxStepPx));
    if (!(borderMode == BORDER_CONSTANT || borderMode == BORDER_REPLICATE || borderMode == BORDER_REFLECT ||
          borderMode == BORDER_WRAP || borderMode == BORDER_REFLECT_101))
        CV_Error_(Error::StsBadArg,
                  ("renderBlurred: borderMode=%d must be BORDER_CONSTANT, _REPLICATE, _REFLECT, _WRAP or _REFLECT_101",
                   borderMode));
    if (!(schedule.times.empty() && schedule.levels.empty()))
        schedule.validate();
    if (std::isnan(thetaRef))
        thetaRef = plant->restingAngle(schedule.finalLevel());

    const double T0 = shutter.frameStart;
    const double T1 = T0 + (H - 1) * shutter.lineDelay + shutter.exposure;
    const double exposure = shutter.exposure, ld = shutter.lineDelay;

    // ---- Trajectory on a fine uniform grid: angle range and peak speed.
    auto evalTheta = [&](const std::vector<double>& t, std::vector<double>& th) {
        Mat out;
        plant->response(schedule, Mat(t), out);
        th.assign(out.ptr<double>(), out.ptr<double>() + t.size());
    };
    auto uniformGrid = [&](int n) {
        std::vector<double> t(n);
        for (int i = 0; i < n; i++)
            t[i] = (n == 1) ? T0 : T0 + (T1 - T0) * i / (n - 1);
        return t;
    };
    std::vector<double> tg = uniformGrid(T1 > T0 ? 2001 : 1), thg;
    evalTheta(tg, thg);
    double aMin = thg[0] - thetaRef, aMax = aMin, dMax = 0;
    for (size_t i = 0; i < thg.size(); i++)
    {
        aMin = std::min(aMin, thg[i] - thetaRef);
        aMax = std::max(aMax, thg[i] - thetaRef);
        if (i > 0)
            dMax = std::max(dMax, std::abs(thg[i] - thg[i - 1]));
    }
    // Pixels per radian: numeric derivative of the mapping at probe pixels (the image border and
    // centre, where a rotation moves pixels fastest) and angles over the range; sizes the fine grid.
    const double xs[3] = {0, (W - 1) * 0.5, W - 1.0}, ys[3] = {0, (H - 1) * 0.5, H - 1.0};
    double pxPerRad = 0;
    {
        const double eps = 1e-4;
        const double as[3] = {aMin, 0.5 * (aMin + aMax), aMax};
        for (double a : as)
            for (double x : xs)
                for (double y : ys)
                {
                    const Point2d p1 = camera->viewToReference(Point2d(x, y), a + eps);
                    const Point2d p0 = camera->viewToReference(Point2d(x, y), a - eps);
                    const double s = norm(p1 - p0) / (2 * eps);
                    if (std::isfinite(s))
                        pxPerRad = std::max(pxPerRad, s);
                }
        pxPerRad *= 1.25;  // margin for pixels between the probes
    }

    Mat sharpLin;
    if (depth == CV_8U)
        srgbToLinear(sharp, sharpLin);
    else
        sharpLin = sharp;
    const int accType = CV_MAKETYPE(sharpLin.depth(), cn);

    // The map q(p) = camera.viewToReference(p, angle) is evaluated at every kMapStep-th column
    // (and the last) of each warped row and is linear in between: a rotation's map is smooth, the
    // interpolation error is far below 0.01 px, and it saves most of the mapping cost.
    const int kMapStep = 8;
    std::vector<int> cols;
    for (int x = 0; x < W - 1; x += kMapStep)
        cols.push_back(x);
    cols.push_back(W - 1);
    const int nc = (int)cols.size();
    Mat grid(H, nc, CV_64FC2);
    for (int y = 0; y < H; y++)
    {
        Point2d* g = grid.ptr<Point2d>(y);
        for (int c = 0; c < nc; c++)
            g[c] = Point2d(cols[c], y);
    }

    Mat acc = Mat::zeros(H, W, accType);
    std::vector<double> rowWeight(H, 0.0), rowSum(H, 0.0);
    Mat coarse;
    auto accumulate = [&](double angle, int r0, int r1) {
        camera->viewToReference(grid.rowRange(r0, r1).reshape(2, 1), angle, coarse);
        coarse = coarse.reshape(2, r1 - r0);
        if (accType == CV_MAKETYPE(CV_32F, cn))
            warpAccumulateCn<float>(sharpLin, coarse, cols, r0, r1, rowWeight, offset, borderMode, acc);
        else
            warpAccumulateCn<double>(sharpLin, coarse, cols, r0, r1, rowWeight, offset, borderMode, acc);
        for (int r = r0; r < r1; r++)
            rowSum[r] += rowWeight[r];
    };

    const bool stillAtReference = std::max(std::abs(aMin), std::abs(aMax)) * pxPerRad < 1e-6;
    if (stillAtReference)
    {
        // Still throughout at the reference angle: the frame is the centre of the sharp view.
        sharp(Rect((int)offset.x, (int)offset.y, W, H)).copyTo(_blurred);
        return;
    }
    if (exposure <= 0)
    {
        // Instantaneous rows: row r is the view at its start time.
        std::vector<double> tr(H), thr;
        for (int r = 0; r < H; r++)
            tr[r] = T0 + r * ld;
        evalTheta(tr, thr);
        for (int r = 0; r < H; r++)
        {
            rowWeight[r] = 1.0;
            accumulate(thr[r] - thetaRef, r, r + 1);
            rowWeight[r] = 0.0;
        }
    }
    else
    {
        // ---- Adaptive time samples: consecutive samples differ by < maxStepPx of image motion.
        // Fine grid with steps of at most maxStepPx/4 of motion, then greedy merging.
        const double peakStepPx = dMax * pxPerRad;  // motion per coarse step
        int nFine = (int)std::min(4.0e6, std::max(2001.0, std::ceil((tg.size() - 1) * peakStepPx * 4.0 / maxStepPx) + 1));
        std::vector<double> tf = nFine == (int)tg.size() ? tg : uniformGrid(nFine), thf;
        if (nFine == (int)tg.size())
            thf = thg;
        else
            evalTheta(tf, thf);
        // Motion of each fine step, measured at the probe pixels (+10% for pixels between them).
        std::vector<Point2d> probes;
        for (double x : xs)
            for (double y : ys)
                probes.push_back(Point2d(x, y));
        Mat probeMat(1, (int)probes.size(), CV_64FC2, probes.data()), qPrev, qCur;
        camera->viewToReference(probeMat, thf[0] - thetaRef, qPrev);
        std::vector<int> sampleIdx;
        sampleIdx.push_back(0);
        double moved = 0;
        for (int k = 1; k < nFine; k++)
        {
            double step = 0;
            if (thf[k] != thf[k - 1])
            {
                camera->viewToReference(probeMat, thf[k] - thetaRef, qCur);
                for (int i = 0; i < (int)probes.size(); i++)
                {
                    const double d = norm(qCur.at<Point2d>(i) - qPrev.at<Point2d>(i));
                    step = std::max(step, std::isfinite(d) ? d : maxStepPx);
                }
                step *= 1.1;
                std::swap(qPrev, qCur);
            }
            if (moved + step > maxStepPx)
            {
                if (sampleIdx.back() != k - 1)
                    sampleIdx.push_back(k - 1);
                moved = 0;
            }
            moved += step;
        }
        if (sampleIdx.back() != nFine - 1)
            sampleIdx.push_back(nFine - 1);

        // ---- Each sample stands for the time cell between the midpoints to its neighbours; it
        // adds its view to each row with the exact overlap of that cell and the row's interval.
        const int ns = (int)sampleIdx.size();
        for (int j = 0; j < ns; j++)
        {
            const double ts = tf[sampleIdx[j]];
            const double c0 = j == 0 ? T0 : 0.5 * (tf[sampleIdx[j - 1]] + ts);
            const double c1 = j == ns - 1 ? T1 : 0.5 * (ts + tf[sampleIdx[j + 1]]);
            if (c1 <= c0)
                continue;
            int ra = 0, rb = H - 1;
            if (ld > 0)
            {
                ra = std::max(0, (int)std::floor((c0 - exposure - T0) / ld));
                rb = std::min(H - 1, (int)std::ceil((c1 - T0) / ld));
            }
            int first = -1, last = -1;
            for (int r = ra; r <= rb; r++)
            {
                const double s = T0 + r * ld, e = s + exposure;
                const double w = std::min(c1, e) - std::max(c0, s);
                rowWeight[r] = w > 0 ? w : 0.0;
                if (w > 0)
                {
                    if (first < 0)
                        first = r;
                    last = r;
                }
            }
            if (first >= 0)
                accumulate(thf[sampleIdx[j]] - thetaRef, first, last + 1);
            for (int r = ra; r <= rb; r++)
                rowWeight[r] = 0.0;
        }
    }

    // ---- Time average of each row over its own interval.
    for (int r = 0; r < H; r++)
    {
        CV_Assert(rowSum[r] > 0);
        acc.row(r) *= 1.0 / rowSum[r];
    }
    if (depth == CV_8U)
        linearToSrgb(acc, _blurred, CV_8U);
    else
        acc.copyTo(_blurred);
}

}  // namespace dynblur
}  // namespace cv
