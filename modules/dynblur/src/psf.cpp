// PsfBank and PsfGenerator: blur kernels predicted from the plant's trajectory and the shutter
// timing (seed equations 4–7, generalised to rolling shutters and to column variation).
#include "precomp.hpp"

namespace cv {
namespace dynblur {

// ---------------------------------------------------------------------------------------------
// PsfBank

PsfBank::PsfBank() : model(PSF_UNIFORM), imageSize(0, 0) {}

void PsfBank::validate() const
{
    if (model != PSF_UNIFORM && model != PSF_ROWS && model != PSF_TILES)
        CV_Error_(Error::StsBadArg, ("PsfBank: model=%d must be PSF_UNIFORM, PSF_ROWS or PSF_TILES", model));
    if (imageSize.width <= 0 || imageSize.height <= 0)
        CV_Error_(Error::StsBadArg, ("PsfBank: imageSize %dx%d must be positive", imageSize.width, imageSize.height));
    if (nodeRows.empty() || nodeCols.empty())
        CV_Error(Error::StsBadArg, "PsfBank: nodeRows and nodeCols must not be empty");
    for (size_t i = 0; i < nodeRows.size(); i++)
        if (!std::isfinite(nodeRows[i]) || (i > 0 && !(nodeRows[i] > nodeRows[i - 1])))
            CV_Error(Error::StsBadArg, "PsfBank: nodeRows must be finite and strictly increasing (pixels)");
    for (size_t i = 0; i < nodeCols.size(); i++)
        if (!std::isfinite(nodeCols[i]) || (i > 0 && !(nodeCols[i] > nodeCols[i - 1])))
            CV_Error(Error::StsBadArg, "PsfBank: nodeCols must be finite and strictly increasing (pixels)");
    const size_t n = nodeRows.size() * nodeCols.size();
    if (kernels.size() != n)
        CV_Error_(Error::StsBadArg, ("PsfBank: kernels has %d entries, nodeRows.size()*nodeCols.size() = %d",
                                     (int)kernels.size(), (int)n));
    if (shifts.size() != n)
        CV_Error_(Error::StsBadArg,
                  ("PsfBank: shifts has %d entries, expected %d (one per kernel)", (int)shifts.size(), (int)n));
    for (size_t i = 0; i < n; i++)
    {
        const Mat& k = kernels[i];
        if (k.empty() || k.type() != CV_32FC1)
            CV_Error_(Error::StsBadArg, ("PsfBank: kernel %d must be a non-empty CV_32FC1 matrix", (int)i));
        if (k.rows % 2 == 0 || k.cols % 2 == 0)
            CV_Error_(Error::StsBadArg, ("PsfBank: kernel %d is %dx%d; its sides must be odd", (int)i, k.cols, k.rows));
        double sum = 0, minv = 0;
        for (int y = 0; y < k.rows; y++)
            for (int x = 0; x < k.cols; x++)
            {
                const float v = k.at<float>(y, x);
                if (!std::isfinite(v))
                    CV_Error_(Error::StsBadArg, ("PsfBank: kernel %d has a non-finite element", (int)i));
                sum += v;
                minv = std::min(minv, (double)v);
            }
        if (minv < 0)
            CV_Error_(Error::StsBadArg, ("PsfBank: kernel %d has a negative element (%g)", (int)i, minv));
        if (std::abs(sum - 1.0) > 1e-3)
            CV_Error_(Error::StsBadArg, ("PsfBank: kernel %d sums to %g, must sum to 1 (±1e-3)", (int)i, sum));
    }
}

Size PsfBank::maxKernelSize() const
{
    Size s(0, 0);
    for (const Mat& k : kernels)
    {
        s.width = std::max(s.width, k.cols);
        s.height = std::max(s.height, k.rows);
    }
    return s;
}

bool PsfBank::isIdentity() const
{
    for (size_t i = 0; i < kernels.size(); i++)
    {
        if (kernels[i].total() != 1)
            return false;
        if (i < shifts.size() && shifts[i] != Point(0, 0))
            return false;
    }
    return true;
}

// ---------------------------------------------------------------------------------------------
// PsfGenerator

namespace {

//! The trajectory θ(t) − θ_ref on a uniform time grid covering the frame readout, with the rotation
//! matrix of every grid sample; shared by all nodes of a bank.
struct Trajectory
{
    double t0 = 0, dt = 0;         // grid start and step, seconds (dt = 0: a single sample)
    std::vector<double> angle;     // θ − θ_ref at each sample, radians
    std::vector<Matx33d> rot;      // R_axis(angle) at each sample
    Vec3d axis;

    Matx33d rotation(double a) const { return axisRotation(axis, a); }
    //! Angle at any time inside the grid, linear between samples.
    double angleAt(double t) const
    {
        if (dt <= 0 || angle.size() < 2)
            return angle[0];
        const double u = (t - t0) / dt;
        const int n = (int)angle.size();
        int k = std::min(n - 2, std::max(0, (int)std::floor(u)));
        const double f = std::min(1.0, std::max(0.0, u - k));
        return angle[k] + f * (angle[k + 1] - angle[k]);
    }
};

//! The camera's mapping, unrolled: normalised ray of a node once, then a rotation per sample.
struct Projector
{
    double fx, fy, cx, cy, kud, kdu;

    Point2d undistort(const Point2d& p) const
    {
        const double xd = (p.x - cx) / fx, yd = (p.y - cy) / fy;
        const double f = 1.0 + kdu * (xd * xd + yd * yd);
        return Point2d(xd * f, yd * f);
    }
    Point2d distort(double x, double y) const
    {
        const double f = 1.0 + kud * (x * x + y * y);
        return Point2d(cx + fx * x * f, cy + fy * y * f);
    }
    //! d = p − q with q = p + distort(R·m) − distort(m) (CameraModel::viewToReference).
    Point2d displacement(const Point2d& m, const Point2d& dm, const Matx33d& R) const
    {
        const double X = R(0, 0) * m.x + R(0, 1) * m.y + R(0, 2);
        const double Y = R(1, 0) * m.x + R(1, 1) * m.y + R(1, 2);
        const double Z = R(2, 0) * m.x + R(2, 1) * m.y + R(2, 2);
        const Point2d q = distort(X / Z, Y / Z);
        return dm - q;
    }
};

struct Node
{
    Point2d pixel;   // where the kernel is evaluated, pixels
    double tStart;   // its row's exposure interval, seconds
    double tEnd;
};

class PsfGeneratorImpl CV_FINAL : public PsfGenerator
{
public:
    PsfGeneratorImpl(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera)
        : plant_(plant), camera_(camera), maxKernel_(401), bandRows_(0), grid_(0, 0)
    {
    }

    PsfBank generate(int model, const SwitchSchedule& schedule, const RollingShutter& shutter,
                     double thetaRef) const CV_OVERRIDE;

    int getMaxKernelSize() const CV_OVERRIDE { return maxKernel_; }
    void setMaxKernelSize(int pixels) CV_OVERRIDE
    {
        if (pixels < 1)
            CV_Error_(Error::StsBadArg, ("PsfGenerator::setMaxKernelSize: pixels=%d must be >= 1", pixels));
        maxKernel_ = pixels;
    }
    int getBandRows() const CV_OVERRIDE { return bandRows_; }
    void setBandRows(int rows) CV_OVERRIDE
    {
        if (rows < 0)
            CV_Error_(Error::StsBadArg, ("PsfGenerator::setBandRows: rows=%d must be >= 0 (0: automatic)", rows));
        bandRows_ = rows;
    }
    Size getTileGrid() const CV_OVERRIDE { return grid_; }
    void setTileGrid(const Size& grid) CV_OVERRIDE
    {
        if (grid.width < 0 || grid.height < 0)
            CV_Error_(Error::StsBadArg, ("PsfGenerator::setTileGrid: grid %dx%d must be >= 0 (0: automatic)",
                                         grid.width, grid.height));
        grid_ = grid;
    }
    String getDefaultName() const CV_OVERRIDE { return "dynblur.PsfGenerator"; }

private:
    Trajectory trajectory(const SwitchSchedule& schedule, const RollingShutter& shutter, double thetaRef,
                          const Projector& pr) const;
    void kernel(const Trajectory& tr, const Projector& pr, const Node& node, std::vector<Point2d>& path,
                std::vector<double>& weight, Mat& k, Point& shift) const;
    int autoColumns(const Trajectory& tr, const Projector& pr, const RollingShutter& shutter) const;
    std::vector<double> autoBands(const Trajectory& tr, const Projector& pr, const RollingShutter& shutter,
                                  const std::vector<double>& columns) const;

    Ptr<Plant> plant_;
    Ptr<CameraModel> camera_;
    int maxKernel_;
    int bandRows_;
    Size grid_;
};

//! Largest motion between two grid samples, pixels.
const double kMaxGridStepPx = 0.1;
//! Largest change of a kernel's path (start, middle, end) across one automatic row band, pixels.
const double kBandTolerancePx = 0.25;
//! Range of node columns of an automatic tile grid.
const int kMinAutoTileCols = 8;
// 16 columns restore as well as 64 (within 0.1 dB in window I, where the keystone is largest) at a
// quarter of the cost; see the DeblurQuality tests.
const int kMaxAutoTileCols = 16;

Trajectory PsfGeneratorImpl::trajectory(const SwitchSchedule& schedule, const RollingShutter& shutter,
                                        double thetaRef, const Projector& pr) const
{
    const Size size = camera_->getImageSize();
    const double T0 = shutter.frameStart;
    const double T1 = T0 + (size.height - 1) * shutter.lineDelay + shutter.exposure;
    Trajectory tr;
    tr.axis = camera_->getMountAxis();
    tr.t0 = T0;
    if (!(T1 > T0))
    {
        Mat th;
        plant_->response(schedule, Mat(1, 1, CV_64F, Scalar(T0)), th);
        tr.angle.assign(1, th.at<double>(0) - thetaRef);
        tr.rot.assign(1, tr.rotation(tr.angle[0]));
        return tr;
    }
    // Coarse pass: angular range and fastest step, to size the fine grid.
    const int nc = 1025;
    Mat tc(1, nc, CV_64F), thc, wc;
    for (int i = 0; i < nc; i++)
        tc.at<double>(i) = T0 + (T1 - T0) * i / (nc - 1);
    plant_->response(schedule, tc, thc);
    plant_->velocity(schedule, tc, wc);
    double maxRate = 0, aMax = 0;
    for (int i = 0; i < nc; i++)
    {
        maxRate = std::max(maxRate, std::abs(wc.at<double>(i)));
        aMax = std::max(aMax, std::abs(thc.at<double>(i) - thetaRef));
        if (i > 0)  // a step the velocity samples could miss (peak between samples)
            maxRate = std::max(maxRate, std::abs(thc.at<double>(i) - thc.at<double>(i - 1)) / ((T1 - T0) / (nc - 1)));
    }
    maxRate *= 1.2;
    // Pixels per radian at the image corners (where a rotation moves pixels fastest), at the
    // largest angle reached; the rotation's own speed up grows with the angle.
    double pxPerRad = std::max(pr.fx, pr.fy);
    const Size s = size;
    const Point2d probes[5] = {Point2d(0, 0), Point2d(s.width - 1, 0), Point2d(0, s.height - 1),
                               Point2d(s.width - 1, s.height - 1), Point2d(0.5 * (s.width - 1), 0.5 * (s.height - 1))};
    for (const Point2d& p : probes)
        for (double a : {-aMax, 0.0, aMax})
        {
            const double e = 1e-4;
            const Point2d m = pr.undistort(p);
            const Point2d dm = pr.distort(m.x, m.y);
            const Point2d d1 = pr.displacement(m, dm, tr.rotation(a + e));
            const Point2d d0 = pr.displacement(m, dm, tr.rotation(a - e));
            const double v = norm(d1 - d0) / (2 * e);
            if (std::isfinite(v))
                pxPerRad = std::max(pxPerRad, v);
        }
    const double pxPerSec = maxRate * pxPerRad;
    double n = pxPerSec > 0 ? std::ceil((T1 - T0) * pxPerSec / kMaxGridStepPx) : 1.0;
    n = std::min(4.0e6, std::max(n, 64.0));
    const int ns = (int)n + 1;
    tr.dt = (T1 - T0) / (ns - 1);
    Mat t(1, ns, CV_64F), th;
    double* tp = t.ptr<double>();
    for (int i = 0; i < ns; i++)
        tp[i] = T0 + tr.dt * i;
    plant_->response(schedule, t, th);
    tr.angle.resize(ns);
    tr.rot.resize(ns);
    const double* thp = th.ptr<double>();
    for (int i = 0; i < ns; i++)
    {
        tr.angle[i] = thp[i] - thetaRef;
        tr.rot[i] = tr.rotation(tr.angle[i]);
    }
    return tr;
}

void PsfGeneratorImpl::kernel(const Trajectory& tr, const Projector& pr, const Node& node,
                              std::vector<Point2d>& path, std::vector<double>& weight, Mat& k, Point& shift) const
{
    const Point2d m = pr.undistort(node.pixel);
    const Point2d dm = node.pixel + (pr.distort(m.x, m.y) - node.pixel);  // p + distort(m) − p
    path.clear();
    weight.clear();
    const double a = node.tStart, b = node.tEnd;
    if (!(b > a) || tr.dt <= 0)
    {
        path.push_back(pr.displacement(m, dm, tr.rotation(tr.angleAt(a))));
        weight.push_back(1.0);
    }
    else
    {
        // Samples: the interval's ends plus every grid time strictly inside; trapezoid weights.
        const int n = (int)tr.angle.size();
        int k0 = std::max(0, (int)std::floor((a - tr.t0) / tr.dt) + 1);
        int k1 = std::min(n - 1, (int)std::ceil((b - tr.t0) / tr.dt) - 1);
        while (k0 <= k1 && tr.t0 + k0 * tr.dt <= a)
            k0++;
        while (k1 >= k0 && tr.t0 + k1 * tr.dt >= b)
            k1--;
        double tPrev = a;
        path.push_back(pr.displacement(m, dm, tr.rotation(tr.angleAt(a))));
        weight.push_back(0.0);
        for (int i = k0; i <= k1; i++)
        {
            const double ti = tr.t0 + i * tr.dt;
            const double h = ti - tPrev;
            weight.back() += 0.5 * h;
            path.push_back(pr.displacement(m, dm, tr.rot[i]));
            weight.push_back(0.5 * h);
            tPrev = ti;
        }
        const double h = b - tPrev;
        weight.back() += 0.5 * h;
        path.push_back(pr.displacement(m, dm, tr.rotation(tr.angleAt(b))));
        weight.push_back(0.5 * h);
    }

    // Bounding box of the path → integer shift (its centre) and odd kernel extents around it.
    double x0 = path[0].x, x1 = x0, y0 = path[0].y, y1 = y0;
    for (const Point2d& d : path)
    {
        if (!(std::isfinite(d.x) && std::isfinite(d.y)))
            CV_Error(Error::StsOutOfRange,
                     "PsfGenerator::generate: a pixel's ray turns behind the reference camera (angle too large)");
        x0 = std::min(x0, d.x);
        x1 = std::max(x1, d.x);
        y0 = std::min(y0, d.y);
        y1 = std::max(y1, d.y);
    }
    shift = Point(cvRound(0.5 * (x0 + x1)), cvRound(0.5 * (y0 + y1)));
    const double tol = 1e-6;  // sub-micro-pixel round-off must not grow a still pixel's kernel
    const int hx = std::max(0, (int)std::ceil(std::max(x1 - shift.x, shift.x - x0) - tol));
    const int hy = std::max(0, (int)std::ceil(std::max(y1 - shift.y, shift.y - y0) - tol));
    const int kw = 2 * hx + 1, kh = 2 * hy + 1;
    if (kw > maxKernel_ || kh > maxKernel_)
        CV_Error_(Error::StsOutOfRange,
                  ("PsfGenerator::generate: the blur path at pixel (%.1f, %.1f) needs a %dx%d kernel, above the "
                   "limit of %d pixels (getMaxKernelSize); raise it with PsfGenerator::setMaxKernelSize",
                   node.pixel.x, node.pixel.y, kw, kh, maxKernel_));

    // Bilinear splat with dwell-time weights, in double, then normalised to sum 1.
    Mat acc = Mat::zeros(kh, kw, CV_64F);
    double total = 0;
    for (size_t i = 0; i < path.size(); i++)
    {
        const double w = weight[i];
        if (w <= 0)
            continue;
        const double u = std::min((double)hx, std::max((double)-hx, path[i].x - shift.x));
        const double v = std::min((double)hy, std::max((double)-hy, path[i].y - shift.y));
        int iu = cvFloor(u), iv = cvFloor(v);
        double fu = u - iu, fv = v - iv;
        if (iu >= hx)
        {
            iu = hx;
            fu = 0;
        }
        if (iv >= hy)
        {
            iv = hy;
            fv = 0;
        }
        double* r0 = acc.ptr<double>(iv + hy) + iu + hx;
        r0[0] += w * (1 - fu) * (1 - fv);
        if (fu > 0)
            r0[1] += w * fu * (1 - fv);
        if (fv > 0)
        {
            double* r1 = acc.ptr<double>(iv + hy + 1) + iu + hx;
            r1[0] += w * (1 - fu) * fv;
            if (fu > 0)
                r1[1] += w * fu * fv;
        }
        total += w;
    }
    acc.convertTo(k, CV_32F, 1.0 / total);
}

int PsfGeneratorImpl::autoColumns(const Trajectory& tr, const Projector& pr, const RollingShutter& shutter) const
{
    // Largest change of a path point (start, middle, end) per pixel along x, over probe rows;
    // the node spacing keeps adjacent kernels within kBandTolerancePx of each other.
    const Size size = camera_->getImageSize();
    const int W = size.width, H = size.height, nProbeCols = 33, nProbeRows = 33;
    double slope = 0;
    for (int j = 0; j < nProbeRows; j++)
    {
        const double y = (H - 1) * (double)j / (nProbeRows - 1);
        const double a = shutter.frameStart + y * shutter.lineDelay, b = a + shutter.exposure;
        const Matx33d R[3] = {tr.rotation(tr.angleAt(a)), tr.rotation(tr.angleAt(0.5 * (a + b))),
                              tr.rotation(tr.angleAt(b))};
        Point2d prev[3];
        for (int i = 0; i < nProbeCols; i++)
        {
            const double x = (W - 1) * (double)i / (nProbeCols - 1);
            const Point2d m = pr.undistort(Point2d(x, y));
            const Point2d dm = pr.distort(m.x, m.y);
            for (int k = 0; k < 3; k++)
            {
                const Point2d d = pr.displacement(m, dm, R[k]);
                if (i > 0)
                    slope = std::max(slope, norm(d - prev[k]) / ((W - 1) / (nProbeCols - 1.0)));
                prev[k] = d;
            }
        }
    }
    const double needed = std::ceil(W * slope / kBandTolerancePx);
    return (int)std::min((double)kMaxAutoTileCols, std::max((double)kMinAutoTileCols, needed));
}

std::vector<double> PsfGeneratorImpl::autoBands(const Trajectory& tr, const Projector& pr,
                                                const RollingShutter& shutter,
                                                const std::vector<double>& columns) const
{
    // Signature of each row: its path's start, middle and end at each probe column. A band grows
    // while every signature point stays within kBandTolerancePx of the band's first row.
    const int H = camera_->getImageSize().height;
    const int nc = (int)columns.size();
    std::vector<Point2d> sig((size_t)H * nc * 3);
    for (int r = 0; r < H; r++)
    {
        const double a = shutter.frameStart + r * shutter.lineDelay, b = a + shutter.exposure;
        const Matx33d R[3] = {tr.rotation(tr.angleAt(a)), tr.rotation(tr.angleAt(0.5 * (a + b))),
                              tr.rotation(tr.angleAt(b))};
        for (int c = 0; c < nc; c++)
        {
            const Point2d p(columns[c], r);
            const Point2d m = pr.undistort(p);
            const Point2d dm = pr.distort(m.x, m.y);
            for (int j = 0; j < 3; j++)
                sig[((size_t)r * nc + c) * 3 + j] = pr.displacement(m, dm, R[j]);
        }
    }
    std::vector<double> centres;
    int start = 0;
    for (int r = 1; r <= H; r++)
    {
        bool close = r < H;
        for (int i = 0; close && i < nc * 3; i++)
            close = norm(sig[(size_t)r * nc * 3 + i] - sig[(size_t)start * nc * 3 + i]) <= kBandTolerancePx;
        if (!close)
        {
            centres.push_back(0.5 * (start + r - 1));
            start = r;
        }
    }
    return centres;
}

PsfBank PsfGeneratorImpl::generate(int model, const SwitchSchedule& schedule, const RollingShutter& shutter,
                                   double thetaRef) const
{
    if (model != PSF_UNIFORM && model != PSF_ROWS && model != PSF_TILES)
        CV_Error_(Error::StsBadArg,
                  ("PsfGenerator::generate: model=%d must be PSF_UNIFORM (0), PSF_ROWS (1) or PSF_TILES (2)", model));
    const Size size = camera_->getImageSize();
    if (!std::isfinite(shutter.frameStart))
        CV_Error(Error::StsBadArg, "PsfGenerator::generate: shutter.frameStart must be finite (seconds)");
    if (!(std::isfinite(shutter.exposure) && shutter.exposure >= 0))
        CV_Error_(Error::StsBadArg, ("PsfGenerator::generate: shutter.exposure=%g must be finite and >= 0 (seconds)",
                                     shutter.exposure));
    if (!(std::isfinite(shutter.lineDelay) && shutter.lineDelay >= 0))
        CV_Error_(Error::StsBadArg,
                  ("PsfGenerator::generate: shutter.lineDelay=%g must be finite and >= 0 (seconds)", shutter.lineDelay));
    if (shutter.rows != size.height)
        CV_Error_(Error::StsBadArg, ("PsfGenerator::generate: shutter.rows=%d must equal the camera's image height %d",
                                     shutter.rows, size.height));
    if (std::isinf(thetaRef))
        CV_Error(Error::StsBadArg,
                 "PsfGenerator::generate: thetaRef must be finite (radians) or NaN (the final resting angle)");
    if (!(schedule.times.empty() && schedule.levels.empty()))
        schedule.validate();
    if (std::isnan(thetaRef))
        thetaRef = plant_->restingAngle(schedule.finalLevel());

    const Projector pr{camera_->getFx(), camera_->getFy(), camera_->getCx(), camera_->getCy(), camera_->getKud(),
                       camera_->getKdu()};
    const Trajectory tr = trajectory(schedule, shutter, thetaRef, pr);
    const int W = size.width, H = size.height;

    PsfBank bank;
    bank.model = model;
    bank.imageSize = size;
    const double xc = 0.5 * (W - 1), yc = 0.5 * (H - 1);
    if (model == PSF_UNIFORM)
    {
        bank.nodeCols.assign(1, xc);
        bank.nodeRows.assign(1, yc);
    }
    else if (model == PSF_ROWS)
    {
        bank.nodeCols.assign(1, xc);
        if (bandRows_ > 0)
        {
            for (int a = 0; a < H; a += bandRows_)
                bank.nodeRows.push_back(0.5 * (a + std::min(H, a + bandRows_) - 1));
        }
        else
            bank.nodeRows = autoBands(tr, pr, shutter, std::vector<double>(1, xc));
    }
    else
    {
        const int nx = grid_.width > 0 ? grid_.width : autoColumns(tr, pr, shutter);
        for (int i = 0; i < nx; i++)
            bank.nodeCols.push_back((i + 0.5) * W / nx - 0.5);
        if (grid_.height > 0)
        {
            for (int j = 0; j < grid_.height; j++)
                bank.nodeRows.push_back((j + 0.5) * H / grid_.height - 0.5);
        }
        else
            bank.nodeRows = autoBands(tr, pr, shutter, std::vector<double>{0.0, xc, W - 1.0});
    }

    const int nx = (int)bank.nodeCols.size(), n = (int)(bank.nodeRows.size() * nx);
    bank.kernels.resize(n);
    bank.shifts.resize(n);
    parallel_for_(Range(0, n), [&](const Range& range) {
        std::vector<Point2d> path;
        std::vector<double> weight;
        for (int i = range.start; i < range.end; i++)
        {
            Node node;
            node.pixel = Point2d(bank.nodeCols[i % nx], bank.nodeRows[i / nx]);
            node.tStart = shutter.frameStart + node.pixel.y * shutter.lineDelay;
            node.tEnd = node.tStart + shutter.exposure;
            kernel(tr, pr, node, path, weight, bank.kernels[i], bank.shifts[i]);
        }
    });
    return bank;
}

}  // namespace

Ptr<PsfGenerator> PsfGenerator::create(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera)
{
    if (!plant)
        CV_Error(Error::StsNullPtr, "PsfGenerator::create: plant must not be null");
    if (!camera)
        CV_Error(Error::StsNullPtr, "PsfGenerator::create: camera must not be null");
    return makePtr<PsfGeneratorImpl>(plant, camera);
}

}  // namespace dynblur
}  // namespace cv
