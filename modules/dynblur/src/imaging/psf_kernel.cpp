// SPDX-License-Identifier: Apache-2.0
// One blur kernel: a node's path over its exposure, integrated exactly into bilinear weights.
#include "precomp.hpp"

#include "imaging/psf_kernel.hpp"

#include <cstring>

namespace cv {
namespace dynblur {
namespace detail {

namespace {

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

}  // namespace

void rasterizeKernel(const Trajectory& tr, const Pinhole& pr, const KernelNode& node, int maxKernel,
                     KernelScratch& sc, Size& kernelSize, Point& shift)
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
    {
        const bool inFront = tr.spin.empty()
                                 ? pr.displacementAndRate(m, dm, tr.rot[i], tr.rate[i], sc.d[i - ka], sc.dd[i - ka])
                                 : pr.displacementAndRate(m, dm, tr.rot[i], tr.spin[i], sc.d[i - ka], sc.dd[i - ka]);
        if (!inFront)
            CV_Error_(Error::StsOutOfRange,
                      ("PsfGenerator::generate: the ray of pixel (%.1f, %.1f) turns behind the reference camera at "
                       "t = %.6f s: the view turns by more than the field of view from the reference (thetaRef or "
                       "tRef too far from the frame's motion?)",
                       node.pixel.x, node.pixel.y, tr.t[i]));
    }

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
    if (kw > maxKernel || kh > maxKernel)
        CV_Error_(Error::StsOutOfRange,
                  ("PsfGenerator::generate: the blur path at pixel (%.1f, %.1f) needs a %dx%d kernel, above the "
                   "limit of %d pixels (getMaxKernelSize); raise it with PsfGenerator::setMaxKernelSize",
                   node.pixel.x, node.pixel.y, kw, kh, maxKernel));

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

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
