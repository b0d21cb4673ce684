// SPDX-License-Identifier: Apache-2.0
// The physical forward model (DESIGN §2): a rolling-shutter frame recorded while the positioner
// moves, by time integration of warped views. Ground truth for PsfGenerator: it shares no code
// with the PSF generator (it warps images; the generator splats paths).
#include "precomp.hpp"

#include "motion/axis_rotation.hpp"
#include "imaging/trajectory.hpp"
#include "motion/camera_motion.hpp"
#include "motion/shutter_check.hpp"

namespace cv {
namespace dynblur {

namespace {

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


/** One frame of renderBlurred, as the stages of the forward model: the motion's extent over the
readout, the time samples that resolve it to maxStepPx, and each sample's view added to the rows
whose exposure overlaps the sample's time cell, in linear light; then each row's time average.
Each sample's view is the rotation R(t) relative to the reference (DESIGN §2, Rotation). */
class FrameRenderer
{
public:
    FrameRenderer(const Mat& sharpLinear, const detail::ViewMotion& motion, const Ptr<CameraModel>& camera,
                  const RollingShutter& shutter, int borderMode)
        : sharp_(sharpLinear), motion_(motion), camera_(camera), shutter_(shutter), borderMode_(borderMode),
          W_(camera->getImageSize().width), H_(camera->getImageSize().height),
          offset_((sharpLinear.cols - W_) / 2, (sharpLinear.rows - H_) / 2)
    {
        const Vec2d readout = shutter.readoutInterval();
        T0_ = readout[0];
        T1_ = readout[1];
    }

    /** How far the view strays from the reference and the largest image motion between two samples
    of a uniform grid over the readout, pixels. */
    void surveyMotion()
    {
        tGrid_ = uniformGrid(T1_ > T0_ ? 2001 : 1);
        if (motion_.oneAxis())
            surveyAngles();
        else
            surveyRotations();
    }

    //! True when the camera stays at the reference view to within 1e-6 px: the frame is the view.
    bool stillAtReference() const { return strayPx_ < 1e-6; }
    //! The sharp view's centre, the camera's frame size.
    Rect view() const { return Rect((int)offset_.x, (int)offset_.y, W_, H_); }

    //! Allocates the accumulator and the map's sampling grid.
    void prepare()
    {
        // The map q(p) = camera.viewToReference(p, R) is evaluated at every kMapStep-th column
        // (and the last) of each warped row and is linear in between: a rotation's map is smooth,
        // the interpolation error is far below 0.01 px, and it saves most of the mapping cost.
        const int kMapStep = 8;
        for (int x = 0; x < W_ - 1; x += kMapStep)
            cols_.push_back(x);
        cols_.push_back(W_ - 1);
        const int nc = (int)cols_.size();
        grid_.create(H_, nc, CV_64FC2);
        for (int y = 0; y < H_; y++)
        {
            Point2d* g = grid_.ptr<Point2d>(y);
            for (int c = 0; c < nc; c++)
                g[c] = Point2d(cols_[c], y);
        }
        acc_ = Mat::zeros(H_, W_, CV_MAKETYPE(sharp_.depth(), sharp_.channels()));
        rowWeight_.assign(H_, 0.0);
        rowSum_.assign(H_, 0.0);
    }

    //! Zero exposure: row r is the view at its start time.
    void exposeInstantRows()
    {
        std::vector<double> starts(H_);
        for (int r = 0; r < H_; r++)
            starts[r] = shutter_.intervalAt(r)[0];
        const std::vector<Matx33d> R = views(starts);
        for (int r = 0; r < H_; r++)
        {
            rowWeight_[r] = 1.0;
            accumulate(R[r], r, r + 1);
            rowWeight_[r] = 0.0;
        }
    }

    /** Time samples (and their views) between which the image moves by less than maxStepPx: a
    fine uniform grid with steps of at most maxStepPx/4 of motion, then greedy merging. */
    void adaptiveSamples(double maxStepPx, std::vector<double>& t, std::vector<Matx33d>& R) const
    {
        const int nFine = (int)std::min(
            4.0e6, std::max(2001.0, std::ceil((tGrid_.size() - 1) * peakStepPx_ * 4.0 / maxStepPx) + 1));
        const bool coarseSuffices = nFine == (int)tGrid_.size();
        const std::vector<double> tf = coarseSuffices ? tGrid_ : uniformGrid(nFine);
        const std::vector<Matx33d> Rf = coarseSuffices ? viewGrid_ : views(tf);
        // Motion of each fine step, measured at the probe pixels (+10% for pixels between them).
        std::vector<Point2d> probes = probePixels();
        Mat probeMat(1, (int)probes.size(), CV_64FC2, probes.data()), qPrev, qCur;
        camera_->viewToReference(probeMat, Rf[0], qPrev);
        std::vector<int> sampleIdx;
        sampleIdx.push_back(0);
        double moved = 0;
        for (int k = 1; k < nFine; k++)
        {
            double step = 0;
            if (Rf[k] != Rf[k - 1])
            {
                camera_->viewToReference(probeMat, Rf[k], qCur);
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
        t.resize(sampleIdx.size());
        R.resize(sampleIdx.size());
        for (size_t j = 0; j < sampleIdx.size(); j++)
        {
            t[j] = tf[sampleIdx[j]];
            R[j] = Rf[sampleIdx[j]];
        }
    }

    /** Each time sample stands for the time cell between the midpoints to its neighbours; it adds
    its view to each row with the exact overlap of that cell and the row's interval. */
    void exposeSamples(const std::vector<double>& t, const std::vector<Matx33d>& R)
    {
        const int ns = (int)t.size();
        for (int j = 0; j < ns; j++)
        {
            const double ts = t[j];
            const double c0 = j == 0 ? T0_ : 0.5 * (t[j - 1] + ts);
            const double c1 = j == ns - 1 ? T1_ : 0.5 * (ts + t[j + 1]);
            if (c1 <= c0)
                continue;
            const Range rows = shutter_.rowsOverlapping(c0, c1);
            int first = -1, last = -1;
            for (int r = rows.start; r < rows.end; r++)
            {
                const Vec2d interval = shutter_.intervalAt(r);
                const double w = std::min(c1, interval[1]) - std::max(c0, interval[0]);
                rowWeight_[r] = w > 0 ? w : 0.0;
                if (w > 0)
                {
                    if (first < 0)
                        first = r;
                    last = r;
                }
            }
            if (first >= 0)
                accumulate(R[j], first, last + 1);
            for (int r = rows.start; r < rows.end; r++)
                rowWeight_[r] = 0.0;
        }
    }

    //! Each row's sum divided by its total exposure: the time average over its own interval.
    Mat averageRows()
    {
        for (int r = 0; r < H_; r++)
        {
            CV_Assert(rowSum_[r] > 0);
            acc_.row(r) *= 1.0 / rowSum_[r];
        }
        return acc_;
    }

private:
    std::vector<double> uniformGrid(int n) const
    {
        std::vector<double> t(n);
        for (int i = 0; i < n; i++)
            t[i] = (n == 1) ? T0_ : T0_ + (T1_ - T0_) * i / (n - 1);
        return t;
    }

    //! One axis: θ at the times `t`, radians.
    std::vector<double> angles(const std::vector<double>& t) const
    {
        Mat out;
        motion_.plant->response(motion_.schedule, Mat(t), out);
        return std::vector<double>(out.ptr<double>(), out.ptr<double>() + t.size());
    }

    //! One axis: the view's rotation relative to the reference at the angles `theta`, radians.
    std::vector<Matx33d> viewsAt(const std::vector<double>& theta) const
    {
        std::vector<Matx33d> R(theta.size());
        for (size_t i = 0; i < theta.size(); i++)
            R[i] = axisRotation(motion_.axis, theta[i] - motion_.thetaRef);
        return R;
    }

    //! The view's rotation R(t) relative to the reference at the times `t`.
    std::vector<Matx33d> views(const std::vector<double>& t) const
    {
        if (motion_.oneAxis())
            return viewsAt(angles(t));
        std::vector<Matx33d> R(t.size());
        for (size_t i = 0; i < t.size(); i++)
            R[i] = motion_.reference.t() * motion_.motion->orientation(t[i]);
        return R;
    }

    /** One axis: the angle range relative to θ_ref and its largest step on the survey grid, scaled
    by the fastest image motion per radian over that range. */
    void surveyAngles()
    {
        const std::vector<double> theta = angles(tGrid_);
        viewGrid_ = viewsAt(theta);
        double aMin = theta[0] - motion_.thetaRef, aMax = aMin, dMax = 0;
        for (size_t i = 0; i < theta.size(); i++)
        {
            aMin = std::min(aMin, theta[i] - motion_.thetaRef);
            aMax = std::max(aMax, theta[i] - motion_.thetaRef);
            if (i > 0)
                dMax = std::max(dMax, std::abs(theta[i] - theta[i - 1]));
        }
        const double pxPerRad = pixelsPerRadian(aMin, aMax);
        strayPx_ = std::max(std::abs(aMin), std::abs(aMax)) * pxPerRad;
        peakStepPx_ = dMax * pxPerRad;
    }

    /** Any rotation: the probe pixels' largest distance from where the reference sees them, and
    their largest motion between two survey samples (+25 % for pixels between the probes). */
    void surveyRotations()
    {
        viewGrid_ = views(tGrid_);
        std::vector<Point2d> probes = probePixels();
        const Mat probeMat(1, (int)probes.size(), CV_64FC2, probes.data());
        Mat qPrev, qCur;
        strayPx_ = peakStepPx_ = 0;
        for (size_t k = 0; k < viewGrid_.size(); k++)
        {
            camera_->viewToReference(probeMat, viewGrid_[k], qCur);
            for (int i = 0; i < (int)probes.size(); i++)
            {
                const double stray = norm(qCur.at<Point2d>(i) - probes[size_t(i)]);
                strayPx_ = std::max(strayPx_, std::isfinite(stray) ? stray : 1.0);
                if (k > 0)
                {
                    const double d = norm(qCur.at<Point2d>(i) - qPrev.at<Point2d>(i));
                    peakStepPx_ = std::max(peakStepPx_, std::isfinite(d) ? 1.25 * d : 1.0);
                }
            }
            std::swap(qPrev, qCur);
        }
    }

    //! The image's corners, edge midpoints and centre, where a rotation moves pixels fastest.
    std::vector<Point2d> probePixels() const
    {
        const double xs[3] = {0, (W_ - 1) * 0.5, W_ - 1.0}, ys[3] = {0, (H_ - 1) * 0.5, H_ - 1.0};
        std::vector<Point2d> probes;
        for (double x : xs)
            for (double y : ys)
                probes.push_back(Point2d(x, y));
        return probes;
    }

    /** One axis: pixels per radian, the numeric derivative of the mapping at the probe pixels and at
    angles over [aMin, aMax], with a margin for pixels between the probes; sizes the fine time grid. */
    double pixelsPerRadian(double aMin, double aMax) const
    {
        const double eps = 1e-4;
        const double as[3] = {aMin, 0.5 * (aMin + aMax), aMax};
        const std::vector<Point2d> probes = probePixels();
        double pxPerRad = 0;
        for (double a : as)
            for (const Point2d& p : probes)
            {
                const Point2d p1 = camera_->viewToReference(p, axisRotation(motion_.axis, a + eps));
                const Point2d p0 = camera_->viewToReference(p, axisRotation(motion_.axis, a - eps));
                const double s = norm(p1 - p0) / (2 * eps);
                if (std::isfinite(s))
                    pxPerRad = std::max(pxPerRad, s);
            }
        return pxPerRad * 1.25;
    }

    //! Rows [r0, r1) += rowWeight · the view turned by R; rowSum gathers the weights.
    void accumulate(const Matx33d& R, int r0, int r1)
    {
        camera_->viewToReference(grid_.rowRange(r0, r1).reshape(2, 1), R, coarse_);
        coarse_ = coarse_.reshape(2, r1 - r0);
        if (sharp_.depth() == CV_32F)
            warpAccumulateCn<float>(sharp_, coarse_, cols_, r0, r1, rowWeight_, offset_, borderMode_, acc_);
        else
            warpAccumulateCn<double>(sharp_, coarse_, cols_, r0, r1, rowWeight_, offset_, borderMode_, acc_);
        for (int r = r0; r < r1; r++)
            rowSum_[r] += rowWeight_[r];
    }

    const Mat sharp_;
    const detail::ViewMotion& motion_;
    const Ptr<CameraModel> camera_;
    const RollingShutter& shutter_;
    const int borderMode_;
    const int W_, H_;
    const Point2d offset_;  // the camera's frame inside the sharp view, pixels
    double T0_, T1_;        // the readout, seconds
    std::vector<double> tGrid_;        // uniform survey of the readout, seconds
    std::vector<Matx33d> viewGrid_;    // the view's rotation at each survey time
    double strayPx_ = 0;     // the largest distance of a probe pixel from its reference position, pixels
    double peakStepPx_ = 0;  // the largest image motion between two survey samples, pixels
    std::vector<int> cols_;  // the columns where the map is evaluated
    Mat grid_;               // those pixels of every row, CV_64FC2
    Mat coarse_;             // their map at one view
    Mat acc_;
    std::vector<double> rowWeight_, rowSum_;
};

//! Throws when an argument of renderBlurred other than the motion is out of range.
void checkRenderFrame(const Mat& sharp, const Ptr<CameraModel>& camera, const RollingShutter& shutter,
                      double maxStepPx, int borderMode)
{
    CV_Assert(camera && "renderBlurred: camera must not be null");
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
    detail::checkShutter(shutter, "renderBlurred", "shutter.", H);
    if (!(maxStepPx > 0 && maxStepPx <= 1))
        CV_Error_(Error::StsBadArg, ("renderBlurred: maxStepPx=%g must be in (0, 1] (pixels)", maxStepPx));
    if (!(borderMode == BORDER_CONSTANT || borderMode == BORDER_REPLICATE || borderMode == BORDER_REFLECT ||
          borderMode == BORDER_WRAP || borderMode == BORDER_REFLECT_101))
        CV_Error_(Error::StsBadArg,
                  ("renderBlurred: borderMode=%d must be BORDER_CONSTANT, _REPLICATE, _REFLECT, _WRAP or _REFLECT_101",
                   borderMode));
}

//! The forward model of one frame (arguments checked).
void renderFrame(const Mat& sharp, const detail::ViewMotion& motion, const Ptr<CameraModel>& camera,
                 const RollingShutter& shutter, OutputArray _blurred, double maxStepPx, int borderMode)
{
    Mat linear;  // light adds up in linear intensity, not in sRGB codes
    if (sharp.depth() == CV_8U)
        srgbToLinear(sharp, linear);
    else
        linear = sharp;

    FrameRenderer frame(linear, motion, camera, shutter, borderMode);
    frame.surveyMotion();
    if (frame.stillAtReference())
    {
        sharp(frame.view()).copyTo(_blurred);
        return;
    }
    frame.prepare();
    if (shutter.exposure <= 0)
        frame.exposeInstantRows();
    else
    {
        std::vector<double> t;
        std::vector<Matx33d> R;
        frame.adaptiveSamples(maxStepPx, t, R);
        frame.exposeSamples(t, R);
    }
    const Mat average = frame.averageRows();
    if (sharp.depth() == CV_8U)
        linearToSrgb(average, _blurred, CV_8U);
    else
        average.copyTo(_blurred);
}

}  // namespace

void renderBlurred(InputArray _sharp, const Ptr<Plant>& plant, const SwitchSchedule& schedule,
                   const Ptr<CameraModel>& camera, const RollingShutter& shutter, OutputArray blurred,
                   double thetaRef, double maxStepPx, int borderMode)
{
    const Mat sharp = _sharp.getMat();
    CV_Assert(plant && "renderBlurred: plant must not be null");
    checkRenderFrame(sharp, camera, shutter, maxStepPx, borderMode);
    if (!(schedule.times.empty() && schedule.levels.empty()))
        schedule.validate();
    const detail::ViewMotion motion =
        detail::ViewMotion::ofPlant("renderBlurred", plant, schedule, camera->getMountAxis(), thetaRef);
    renderFrame(sharp, motion, camera, shutter, blurred, maxStepPx, borderMode);
}

void renderBlurred(InputArray _sharp, const Ptr<CameraMotion>& motion, const Ptr<CameraModel>& camera,
                   const RollingShutter& shutter, OutputArray blurred, double tRef, double maxStepPx, int borderMode)
{
    const Mat sharp = _sharp.getMat();
    checkRenderFrame(sharp, camera, shutter, maxStepPx, borderMode);
    detail::checkMotionCovers(motion, shutter.readoutInterval(), "renderBlurred", "motion");
    if (std::isinf(tRef))
        CV_Error(Error::StsBadArg, "renderBlurred: tRef must be finite (seconds) or NaN (the motion's default "
                                   "reference: a plant's final rest, a sampled motion's mid-exposure)");
    renderFrame(sharp, detail::ViewMotion::of(motion, tRef, shutter), camera, shutter, blurred, maxStepPx,
                borderMode);
}

}  // namespace dynblur
}  // namespace cv
