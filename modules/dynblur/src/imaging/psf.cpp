// PsfBank and PsfGenerator: blur kernels predicted from the plant's trajectory and the shutter
// timing (seed equations 4–7, generalised to rolling shutters and to column variation).
#include "precomp.hpp"

#include <cstring>

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
    // A displacement many frames long is no blur any frame records, and its latent domain would not fit in memory.
    const int64 maxShift = 16 * int64(std::max(std::max(imageSize.width, imageSize.height), 64));
    for (size_t i = 0; i < n; i++)
        if (std::abs(int64(shifts[i].x)) > maxShift || std::abs(int64(shifts[i].y)) > maxShift)
            CV_Error_(Error::StsOutOfRange,
                      ("PsfBank: shifts[%d] = (%d, %d) px must be within ±%lld px (16 times the image's larger "
                       "side, at least 64)",
                       (int)i, shifts[i].x, shifts[i].y, (long long)maxShift));
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

//! Knots per natural period of the plant: the trajectory is sampled exactly at these instants (and
//! at every switch) and interpolated in between by cubic Hermite polynomials, whose error is
//! ≈ (ωn·h)⁴/384 of the move: < 1e-7 of it (< 1e-5 px for a 10° move at fx = 1230 px). Kernels
//! stay within L1 1e-4 of a dense computation (test PsfGenerator.KernelsMatchADenseReference);
//! half as many knots let a path that comes to rest at a switch reach 4e-4.
const double kKnotsPerPeriod = 100;
//! Largest angle step between two knots, radians (a plant moving faster than its nominal
//! frequency suggests gets denser knots).
const double kMaxKnotAngleStep = 0.02;

//! c0 + c1·s + c2·s² + c3·s³ for s in seconds from the start of a knot interval.
struct Cubic
{
    double c0, c1, c2, c3;

    //! The Hermite cubic with values p0, p1 and slopes v0, v1 at s = 0 and s = h.
    static Cubic hermite(double p0, double v0, double p1, double v1, double h) { return hermiteInv(p0, v0, p1, v1, 1 / h); }
    //! The same, given ih = 1/h.
    static Cubic hermiteInv(double p0, double v0, double p1, double v1, double ih)
    {
        const double slope = (p1 - p0) * ih;
        return Cubic{p0, v0, (3 * slope - 2 * v0 - v1) * ih, (v0 + v1 - 2 * slope) * ih * ih};
    }
    double operator()(double s) const { return c0 + s * (c1 + s * (c2 + s * c3)); }
    double slope(double s) const { return c1 + s * (2 * c2 + s * (3 * c3)); }
    //! Zeros of the slope strictly inside (lo, hi), increasing; returns their count.
    int turns(double lo, double hi, double z[2]) const
    {
        const double A = 3 * c3, B = 2 * c2, C = c1;
        // the slope A s² + B s + C keeps its sign on [lo, hi] when it does at both ends and its
        // own extremum (2 A s + B = 0) is outside: the common case, without a square root
        if (slope(lo) * slope(hi) > 0 && (2 * A * lo + B) * (2 * A * hi + B) >= 0)
            return 0;
        double r[2];
        int n = 0;
        if (A == 0)
        {
            if (B != 0)
                r[n++] = -C / B;
        }
        else
        {
            const double disc = B * B - 4 * A * C;
            if (disc >= 0)
            {
                const double q = -0.5 * (B + (B >= 0 ? 1 : -1) * std::sqrt(disc));
                r[n++] = q / A;
                if (q != 0)
                    r[n++] = C / q;
            }
        }
        int m = 0;
        for (int i = 0; i < n; i++)
            if (r[i] > lo && r[i] < hi)
                z[m++] = r[i];
        if (m == 2 && z[0] > z[1])
            std::swap(z[0], z[1]);
        return m;
    }
    /** The s in [lo, hi] where the cubic equals `target` to within 1e-9 (pixels), given that it is
    monotonic there and `target` lies between its values at lo and hi (safeguarded Newton). */
    double solve(double target, double lo, double hi) const
    {
        const double sign = (*this)(lo) < target ? 1.0 : -1.0;  // the cubic increases (+1) or decreases (−1)
        double s = lo;
        for (int it = 0; it < 60; it++)
        {
            const double f = (*this)(s) - target;
            if (std::abs(f) <= 1e-9)
                return s;
            if (f * sign < 0)
                lo = s;
            else
                hi = s;
            const double g = slope(s);
            double next = g != 0 ? s - f / g : 0.5 * (lo + hi);
            if (!(next > lo && next < hi))
                next = 0.5 * (lo + hi);
            if (next == s)
                return s;
            s = next;
        }
        return s;
    }
};

//! The trajectory θ(t) − θ_ref over the frame readout, shared by all nodes of a bank: exact plant
//! samples (angle and rate) at knots, a cubic Hermite curve between them. The knots include every
//! switch inside the readout, where θ'' jumps, so each piece interpolates an analytic function.
struct Trajectory
{
    std::vector<double> t;      // knot times, seconds, strictly increasing
    std::vector<double> angle;  // θ − θ_ref at each knot, radians
    std::vector<double> rate;   // dθ/dt at each knot, rad/s
    std::vector<Matx33d> rot;   // R_axis(angle) at each knot
    std::vector<double> invStep;  // 1 / (t[k+1] − t[k]), 1/seconds
    Vec3d axis;

    Matx33d rotation(double a) const { return axisRotation(axis, a); }
    //! Index k of the knot interval [t[k], t[k+1]] holding `time` (clamped to the first/last one).
    int segment(double time) const
    {
        const int n = (int)t.size();
        if (n < 2)
            return 0;
        const int k = (int)(std::upper_bound(t.begin(), t.end(), time) - t.begin()) - 1;
        return std::min(n - 2, std::max(0, k));
    }
    //! θ − θ_ref at any time of the readout (Hermite interpolation between knots).
    double angleAt(double time) const
    {
        if (t.size() < 2)
            return angle[0];
        const int k = segment(time);
        const double h = t[k + 1] - t[k];
        return Cubic::hermite(angle[k], rate[k], angle[k + 1], rate[k + 1], h)(std::min(h, std::max(0.0, time - t[k])));
    }
};

//! The camera's mapping, unrolled: normalised ray of a node once, then a rotation per sample.
struct Projector
{
    double fx, fy, cx, cy, kud, kdu;
    Vec3d axis;

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
        if (!(Z > 1e-12))
            return Point2d(std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN());
        const Point2d q = distort(X / Z, Y / Z);
        return dm - q;
    }
    /** d as above and its time derivative for an angle changing at `rate` rad/s: the ray turns as
    dP/dθ = axis × P. Returns false when the ray turns behind the reference camera. */
    bool displacementAndRate(const Point2d& m, const Point2d& dm, const Matx33d& R, double rate, Point2d& d,
                             Point2d& dd) const
    {
        const double X = R(0, 0) * m.x + R(0, 1) * m.y + R(0, 2);
        const double Y = R(1, 0) * m.x + R(1, 1) * m.y + R(1, 2);
        const double Z = R(2, 0) * m.x + R(2, 1) * m.y + R(2, 2);
        if (!(Z > 1e-12))
            return false;
        const double dX = rate * (axis[1] * Z - axis[2] * Y);
        const double dY = rate * (axis[2] * X - axis[0] * Z);
        const double dZ = rate * (axis[0] * Y - axis[1] * X);
        const double iz = 1.0 / Z, x = X * iz, y = Y * iz;
        const double dx = (dX - x * dZ) * iz, dy = (dY - y * dZ) * iz;
        const double f = 1.0 + kud * (x * x + y * y), df = 2 * kud * (x * dx + y * dy);
        d = Point2d(dm.x - (cx + fx * x * f), dm.y - (cy + fy * y * f));
        dd = Point2d(-fx * (dx * f + x * df), -fy * (dy * f + y * df));
        return true;
    }
};

//! One knot interval of a node's path, clipped to the node's exposure: d(s) = (x(s), y(s)),
//! s ∈ [s0, s1] seconds from the interval's start.
struct PathPiece
{
    Cubic x, y;
    int n;           // cut[0] = s0 < … < cut[n−1] = s1: the ends and where x or y turns round
    double cut[6];   // between two cuts both coordinates are monotonic
    double xc[6], yc[6];  // the path at the cuts

    //! The piece over [s0, s1] of the Hermite path with ends d0, d1 and rates v0, v1 over h = 1/ih
    //! seconds.
    PathPiece(const Point2d& d0, const Point2d& v0, const Point2d& d1, const Point2d& v1, double h, double ih,
              double s0, double s1)
        : x(Cubic::hermiteInv(d0.x, v0.x, d1.x, v1.x, ih)), y(Cubic::hermiteInv(d0.y, v0.y, d1.y, v1.y, ih)), n(0)
    {
        cut[n++] = s0;
        if (s1 > s0)
        {
            n += x.turns(s0, s1, cut + n);
            n += y.turns(s0, s1, cut + n);
            for (int i = 2; i < n; i++)  // insertion sort of the (at most four) turning points
                for (int j = i; j > 1 && cut[j] < cut[j - 1]; j--)
                    std::swap(cut[j], cut[j - 1]);
            cut[n++] = s1;
        }
        for (int i = 0; i < n; i++)
        {
            xc[i] = cut[i] == 0 ? d0.x : cut[i] == h ? d1.x : x(cut[i]);
            yc[i] = cut[i] == 0 ? d0.y : cut[i] == h ? d1.y : y(cut[i]);
        }
    }
    double s0() const { return cut[0]; }
    double s1() const { return cut[n - 1]; }
    void translate(double dx, double dy)
    {
        x.c0 += dx;
        y.c0 += dy;
        for (int i = 0; i < n; i++)
        {
            xc[i] += dx;
            yc[i] += dy;
        }
    }
};

//! Per-thread scratch space of kernel generation.
struct KernelScratch
{
    std::vector<Point2d> d, dd;  // a node's path and its rate at the knots
    std::vector<PathPiece> pieces;
    std::vector<double> acc;     // the kernel being accumulated
    std::vector<float> kernels;  // a stripe's finished kernels, one after the other
};

/** The integers a cubic crosses on [lo, hi], where it is monotonic, one after the other: `time` is
when it crosses `target` (+∞ when no integer is left before hi). First guess from the inverse
function's Hermite cubic when the slope at both ends is comparable (the common case), else from the
chord; Newton steps only when the guess is more than 1e-3 px off (a crossing placed δ px off
misplaces a kink of the bilinear weights, which costs O(δ²) of the piece), the safeguarded solver
when those do not get there (next to a turning point). */
struct Crossings
{
    const Cubic& c;
    double lo, hi, clo, chi, dir, target, last, time, value;  // value: c(time), within 1e-3 of target
    bool inverseGuess;
    Cubic inverse;  // s(value − clo) when inverseGuess
    double scale;   // else (hi − lo) / (chi − clo)

    Crossings(const Cubic& c_, double lo_, double hi_, double clo_, double chi_)
        : c(c_), lo(lo_), hi(hi_), clo(clo_), chi(chi_), dir(chi_ >= clo_ ? 1.0 : -1.0),
          target(dir > 0 ? cvFloor(clo_) + 1 : cvCeil(clo_) - 1), last(dir > 0 ? cvCeil(chi_) - 1 : cvFloor(chi_) + 1),
          time(0), value(0), inverseGuess(false), inverse(), scale(0)
    {
        if (dir * (last - target) < 0)
        {
            time = std::numeric_limits<double>::infinity();
            return;
        }
        const double g0 = dir * c.slope(lo), g1 = dir * c.slope(hi), span = chi - clo;
        inverseGuess = g0 > 0 && g1 > 0 && g0 < 4 * g1 && g1 < 4 * g0;
        if (inverseGuess)
        {
            const double r = 1 / (g0 * g1 * span);  // one division for 1/g0, 1/g1 and 1/span
            inverse = Cubic::hermiteInv(lo, dir * g1 * span * r, hi, dir * g0 * span * r, g0 * g1 * r);
        }
        else
            scale = (hi - lo) / span;
        time = solve(value);
    }
    //! On to the next integer.
    void advance()
    {
        target += dir;
        time = dir * (last - target) < 0 ? std::numeric_limits<double>::infinity() : solve(value);
    }
    double solve(double& at) const
    {
        const double tol = 1e-3;
        double s = inverseGuess ? inverse(target - clo) : lo + (target - clo) * scale;
        s = std::min(hi, std::max(lo, s));
        for (int it = 0; it < 4; it++)
        {
            at = c(s);
            const double f = at - target;
            if (std::abs(f) <= tol)
                return s;
            const double g = dir * std::max(dir * c.slope(s), 1e-300);
            s = std::min(hi, std::max(lo, s - f / g));
        }
        at = c(s);
        if (!(std::abs(at - target) <= tol))
        {
            s = c.solve(target, lo, hi);
            at = c(s);
        }
        return s;
    }
};

/** Accumulates the dwell-time-weighted bilinear splat of a path into a (2hy+3)×(2hx+1) buffer whose
element (hy+1, hx) is the kernel's centre: kernel rows −hy−1…hy+1, one of margin each side for
round-off that the caller folds back into the border; a corner beyond the columns −hx…hx (round-off
too) goes to the border column, as a clamp of the path would. */
struct Splatter
{
    double* acc;
    int stride, hx, hy;  // stride = 2hx + 1

    //! Adds the corner weights of cell (iu, iv): (iu, iv), (iu+1, iv), (iu, iv+1), (iu+1, iv+1).
    void add(int iu, int iv, double a00, double a01, double a10, double a11)
    {
        const int y = std::min(hy, std::max(-hy - 1, iv));
        const int x0 = std::min(hx, std::max(-hx, iu)) + hx, x1 = std::min(hx, std::max(-hx, iu + 1)) + hx;
        double* r0 = acc + (size_t)(y + hy + 1) * stride;
        r0[x0] += a00;
        r0[x1] += a01;
        r0[stride + x0] += a10;
        r0[stride + x1] += a11;
    }

    /** Splat of the piece between cuts i and i+1, where both coordinates are monotonic: split where
    either crosses an integer (a kink of the bilinear weights); in each cell the weights are linear
    in position, so Simpson's rule integrates them exactly for a path cubic in time (up to the
    product of the two coordinates' curvatures). */
    void monotone(const PathPiece& p, int i)
    {
        const double lo = p.cut[i], hi = p.cut[i + 1];
        const Cubic X = p.x, Y = p.y;
        Crossings cu(X, lo, hi, p.xc[i], p.xc[i + 1]), cv(Y, lo, hi, p.yc[i], p.yc[i + 1]);
        // the cell each piece lies in, tracked from crossing to crossing
        const int du = (int)cu.dir, dv = (int)cv.dir;
        int iu = du > 0 ? cvFloor(cu.clo) : cvCeil(cu.clo) - 1, iv = dv > 0 ? cvFloor(cv.clo) : cvCeil(cv.clo) - 1;
        double sa = lo, ua = cu.clo, va = cv.clo;
        for (;;)
        {
            // the piece's end: the next crossing of x or y, or the stretch's end
            const bool crossU = cu.time <= cv.time && cu.time < hi, crossV = !crossU && cv.time < hi;
            const double sb = std::max(sa, crossU ? cu.time : crossV ? cv.time : hi);
            const double ub = crossU ? cu.value : crossV ? X(sb) : cu.chi;
            const double vb = crossV ? cv.value : crossU ? Y(sb) : cv.chi;
            // Simpson's rule for ∫fu, ∫fv and ∫fu·fv, with fu = u − iu and fv = v − iv the position
            // in the cell (within [0, 1] but for the crossings' tolerance, whose O(δ²) effect the
            // linear extension keeps); then the four corner weights
            const double sm = 0.5 * (sa + sb), um = X(sm), vm = Y(sm);
            const double fu0 = ua - iu, fum = um - iu, fu1 = ub - iu;
            const double fv0 = va - iv, fvm = vm - iv, fv1 = vb - iv;
            const double I = sb - sa, w = I * (1.0 / 6.0);
            const double Iu = w * (fu0 + 4 * fum + fu1), Iv = w * (fv0 + 4 * fvm + fv1);
            const double Iuv = w * (fu0 * fv0 + 4 * fum * fvm + fu1 * fv1);
            add(iu, iv, I - Iu - Iv + Iuv, Iu - Iuv, Iv - Iuv, Iuv);
            if (crossU)
            {
                iu += du;
                cu.advance();
            }
            else if (crossV)
            {
                iv += dv;
                cv.advance();
            }
            else
                break;
            sa = sb;
            ua = ub;
            va = vb;
        }
    }

    void piece(const PathPiece& p)
    {
        for (int i = 0; i + 1 < p.n; i++)
            if (p.cut[i + 1] > p.cut[i])
                monotone(p, i);
    }

    //! A single sample (zero exposure): the bilinear splat of one point.
    void point(double u, double v)
    {
        const int iu = cvFloor(u), iv = cvFloor(v);
        const double fu = std::min(1.0, std::max(0.0, u - iu)), fv = std::min(1.0, std::max(0.0, v - iv));
        add(iu, iv, (1 - fu) * (1 - fv), fu * (1 - fv), (1 - fu) * fv, fu * fv);
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
        const Size image = camera_->getImageSize();
        if (grid.width < 0 || grid.height < 0 || grid.width > image.width || grid.height > image.height)
            CV_Error_(Error::StsBadArg,
                      ("PsfGenerator::setTileGrid: grid %dx%d must be within [0, %d] x [0, %d] nodes (the image "
                       "size; 0: automatic)",
                       grid.width, grid.height, image.width, image.height));
        grid_ = grid;
    }
    String getDefaultName() const CV_OVERRIDE { return "dynblur.PsfGenerator"; }

private:
    Trajectory trajectory(const SwitchSchedule& schedule, const RollingShutter& shutter, double thetaRef) const;
    /* A node's kernel, appended to scratch.kernels (kernelSize its size), and its shift. */
    void kernel(const Trajectory& tr, const Projector& pr, const Node& node, KernelScratch& scratch, Size& kernelSize,
                Point& shift) const;
    int autoColumns(const Trajectory& tr, const Projector& pr, const RollingShutter& shutter) const;
    std::vector<double> autoBands(const Trajectory& tr, const Projector& pr, const RollingShutter& shutter,
                                  const std::vector<double>& columns) const;

    Ptr<Plant> plant_;
    Ptr<CameraModel> camera_;
    int maxKernel_;
    int bandRows_;
    Size grid_;
};

/* Largest change of a kernel's path (start, middle, end) across one automatic row band, pixels.
   0.4 px restores as well as one band per row (DeblurQuality; a point source's spot within 1 % of
   the per-row one, PointSourceMatchesRendererRollingShutter) with three quarters of the kernels
   of 0.25 px; at 0.5 px that spot's error grows by 16 %. */
const double kBandTolerancePx = 0.4;
//! Range of node columns of an automatic tile grid.
const int kMinAutoTileCols = 8;
// 16 columns restore as well as 64 (within 0.1 dB in window I, where the keystone is largest) at a
// quarter of the cost; see the DeblurQuality tests.
const int kMaxAutoTileCols = 16;

Trajectory PsfGeneratorImpl::trajectory(const SwitchSchedule& schedule, const RollingShutter& shutter,
                                        double thetaRef) const
{
    const Size size = camera_->getImageSize();
    const double T0 = shutter.frameStart;
    const double T1 = T0 + (size.height - 1) * shutter.lineDelay + shutter.exposure;
    Trajectory tr;
    tr.axis = camera_->getMountAxis();
    if (!(T1 > T0))
        tr.t.assign(1, T0);
    const double fn = plant_->getNaturalFreqHz();
    double step = std::isfinite(fn) && fn > 0 ? 1.0 / (kKnotsPerPeriod * fn) : (T1 - T0) / 64;
    for (int refinement = 0;; refinement++)
    {
        if (T1 > T0)
        {
            // Uniform knots, then every switch strictly inside the readout; a uniform knot closer
            // than a tenth of a step to a switch gives way to it.
            const int n = (int)std::min(1.0e6, std::max(4.0, std::ceil((T1 - T0) / step)));
            const double h = (T1 - T0) / n;
            std::vector<std::pair<double, bool>> knots;  // time, is a switch
            for (int i = 0; i <= n; i++)
                knots.emplace_back(i == n ? T1 : T0 + h * i, false);
            for (double s : schedule.times)
                if (s > T0 && s < T1)
                    knots.emplace_back(s, true);
            std::sort(knots.begin(), knots.end());
            tr.t.clear();
            for (size_t i = 0; i < knots.size(); i++)
            {
                const double ti = knots[i].first;
                const bool end = ti == T0 || ti == T1;
                const bool yields = !knots[i].second && !end &&
                                    ((i > 0 && knots[i - 1].second && ti - knots[i - 1].first < 0.1 * h) ||
                                     (i + 1 < knots.size() && knots[i + 1].second && knots[i + 1].first - ti < 0.1 * h));
                if (!yields && (tr.t.empty() || ti > tr.t.back()))
                    tr.t.push_back(ti);
            }
        }
        const int nk = (int)tr.t.size();
        Mat tk(1, nk, CV_64F, tr.t.data()), th, om;
        plant_->response(schedule, tk, th);
        plant_->velocity(schedule, tk, om);
        tr.angle.resize(nk);
        tr.rate.resize(nk);
        double largestStep = 0;
        for (int i = 0; i < nk; i++)
        {
            tr.angle[i] = th.at<double>(i) - thetaRef;
            tr.rate[i] = om.at<double>(i);
            if (i > 0)
                largestStep = std::max(largestStep, std::abs(tr.angle[i] - tr.angle[i - 1]));
        }
        if (nk < 2 || largestStep <= kMaxKnotAngleStep || refinement >= 8 || nk > 500000)
            break;
        step *= 0.5 * kMaxKnotAngleStep / largestStep;
    }
    tr.rot.resize(tr.t.size());
    tr.invStep.resize(tr.t.size());
    for (size_t i = 0; i < tr.t.size(); i++)
    {
        tr.rot[i] = tr.rotation(tr.angle[i]);
        tr.invStep[i] = i + 1 < tr.t.size() ? 1 / (tr.t[i + 1] - tr.t[i]) : 0.0;
    }
    return tr;
}

void PsfGeneratorImpl::kernel(const Trajectory& tr, const Projector& pr, const Node& node, KernelScratch& sc,
                              Size& kernelSize, Point& shift) const
{
    const Point2d m = pr.undistort(node.pixel);
    const Point2d dm = node.pixel + (pr.distort(m.x, m.y) - node.pixel);  // p + distort(m) − p
    const double a = node.tStart, b = std::max(node.tStart, node.tEnd);
    const int nk = (int)tr.t.size();
    const int ka = tr.segment(a), kb = std::max(ka, tr.segment(b));
    const int kEnd = std::min(nk - 1, kb + 1);
    sc.d.resize(kEnd - ka + 1);
    sc.dd.resize(kEnd - ka + 1);
    for (int i = ka; i <= kEnd; i++)
        if (!pr.displacementAndRate(m, dm, tr.rot[i], tr.rate[i], sc.d[i - ka], sc.dd[i - ka]))
            CV_Error(Error::StsOutOfRange,
                     "PsfGenerator::generate: a pixel's ray turns behind the reference camera (angle too large)");

    // The path: one Hermite cubic per knot interval, clipped to [a, b].
    sc.pieces.clear();
    for (int i = ka; i < kEnd; i++)
    {
        const double h = tr.t[i + 1] - tr.t[i];
        const double s0 = std::max(0.0, a - tr.t[i]), s1 = std::min(h, b - tr.t[i]);
        if (sc.pieces.empty() || s1 > s0)
            sc.pieces.emplace_back(sc.d[i - ka], sc.dd[i - ka], sc.d[i + 1 - ka], sc.dd[i + 1 - ka], h, tr.invStep[i],
                                   s0, std::max(s0, s1));
    }
    // The path's start (the whole path when the exposure is zero).
    const Point2d p0 = sc.pieces.empty() ? sc.d[0] : Point2d(sc.pieces[0].xc[0], sc.pieces[0].yc[0]);
    if (!sc.pieces.empty() && !(sc.pieces[0].s1() > sc.pieces[0].s0()))
        sc.pieces.erase(sc.pieces.begin());

    // Bounding box of the path (ends and turning points of every piece) → integer shift (its
    // centre) and odd kernel extents around it.
    double x0, x1, y0, y1;
    if (sc.pieces.empty())
    {
        x0 = x1 = p0.x;
        y0 = y1 = p0.y;
    }
    else
    {
        x0 = y0 = std::numeric_limits<double>::infinity();
        x1 = y1 = -x0;
        for (const PathPiece& p : sc.pieces)
            for (int i = 0; i < p.n; i++)
            {
                x0 = std::min(x0, p.xc[i]);
                x1 = std::max(x1, p.xc[i]);
                y0 = std::min(y0, p.yc[i]);
                y1 = std::max(y1, p.yc[i]);
            }
    }
    if (!(std::isfinite(x0) && std::isfinite(x1) && std::isfinite(y0) && std::isfinite(y1)))
        CV_Error(Error::StsOutOfRange,
                 "PsfGenerator::generate: a pixel's ray turns behind the reference camera (angle too large)");
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

    // Bilinear splat with dwell-time weights, integrated exactly along the path, in double; then
    // the margin is folded into the border (the clamp of a path touching it) and the kernel
    // normalised to sum 1.
    const size_t n = (size_t)kh * kw;
    if (sc.acc.size() < n + 2 * kw)
        sc.acc.resize(n + 2 * kw);
    double* A = sc.acc.data();
    std::memset(A, 0, (n + 2 * kw) * sizeof(double));
    Splatter sp{A, kw, hx, hy};
    if (sc.pieces.empty())
        sp.point(p0.x - shift.x, p0.y - shift.y);
    else
        for (PathPiece& p : sc.pieces)
        {
            p.translate(-shift.x, -shift.y);
            sp.piece(p);
        }
    double* K = A + kw;  // the kernel's rows, contiguous; the margin rows fold into the border ones
    for (int x = 0; x < kw; x++)
    {
        K[x] += A[x];
        K[n - kw + x] += K[n + x];
    }
    // A weight that is zero but for round-off, or for the crossings' tolerance (see monotone()),
    // can come out slightly negative (≥ −1e-5 of the kernel): it is zero.
    double total = 0;
    for (size_t i = 0; i < n; i++)
    {
        K[i] = K[i] > 0 ? K[i] : 0.0;
        total += K[i];
    }
    kernelSize = Size(kw, kh);
    const double scale = 1.0 / total;
    const size_t start = sc.kernels.size();
    sc.kernels.resize(start + n);
    float* dst = sc.kernels.data() + start;
    for (size_t i = 0; i < n; i++)
        dst[i] = (float)(K[i] * scale);
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
    parallel_for_(Range(0, H), [&](const Range& rows) {
        for (int r = rows.start; r < rows.end; r++)
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
    }, 8);
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
                       camera_->getKdu(), camera_->getMountAxis()};
    const Trajectory tr = trajectory(schedule, shutter, thetaRef);
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
    /* Stripes of many kernels (one scratch space each), enough of them to balance the threads. A
       stripe's kernels share one allocation: a tile bank has ~10⁴ kernels, and allocating and
       freeing them one by one is a measurable part of a tile-wise frame (BM_PsfTilesAutoWindowIII
       in perf/perf_psf.cpp times the bank). */
    parallel_for_(Range(0, n), [&](const Range& range) {
        /* Kept per thread: a stripe's kernels grew their buffer by doubling, copying it about twice
           over, for every stripe of every frame. */
        thread_local KernelScratch scratch;
        scratch.kernels.clear();
        std::vector<Size> sizes(size_t(range.size()));
        for (int i = range.start; i < range.end; i++)
        {
            Node node;
            node.pixel = Point2d(bank.nodeCols[i % nx], bank.nodeRows[i / nx]);
            node.tStart = shutter.frameStart + node.pixel.y * shutter.lineDelay;
            node.tEnd = node.tStart + shutter.exposure;
            kernel(tr, pr, node, scratch, sizes[size_t(i - range.start)], bank.shifts[i]);
        }
        Mat stripe(1, int(scratch.kernels.size()), CV_32F);
        std::copy(scratch.kernels.begin(), scratch.kernels.end(), stripe.ptr<float>());
        int start = 0;
        for (int i = range.start; i < range.end; i++)
        {
            const Size size = sizes[size_t(i - range.start)];
            bank.kernels[i] = stripe.colRange(start, start + size.area()).reshape(1, size.height);
            start += size.area();
        }
    }, std::min(n, 64));
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
