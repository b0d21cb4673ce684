// The physical forward model (DESIGN §2): a rolling-shutter frame recorded while the positioner
// moves, by time integration of warped views. Ground truth for PsfGenerator: it shares no code
// with psf.cpp (it warps images; psf.cpp splats paths).
#include "precomp.hpp"

namespace cv {
namespace dynblur {

namespace {

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
