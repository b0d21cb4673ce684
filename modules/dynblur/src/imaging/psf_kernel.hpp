// SPDX-License-Identifier: Apache-2.0
// Private: one blur kernel, the path of a pixel over its row's exposure rasterised by dwell time.
#ifndef OPENCV_DYNBLUR_IMAGING_PSF_KERNEL_HPP
#define OPENCV_DYNBLUR_IMAGING_PSF_KERNEL_HPP

#include "imaging/cubic.hpp"
#include "imaging/pinhole.hpp"
#include "imaging/trajectory.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

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

//! Where a kernel is evaluated and when its row integrates light.
struct KernelNode
{
    Point2d pixel;   // where the kernel is evaluated, pixels
    double tStart;   // its row's exposure interval, seconds
    double tEnd;
};

/** @brief The kernel of `node` for the trajectory `tr` seen through `pinhole`: its path over the
node's exposure, splatted bilinearly with dwell-time weights and normalised to sum 1, appended to
scratch.kernels (kernelSize: its odd size), and the integer displacement `shift` of its centre,
pixels. Throws when the path needs a kernel side above maxKernel pixels or a ray turns behind the
reference camera. */
void rasterizeKernel(const Trajectory& tr, const Pinhole& pinhole, const KernelNode& node, int maxKernel,
                     KernelScratch& scratch, Size& kernelSize, Point& shift);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
