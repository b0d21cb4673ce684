// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_PSF_HPP
#define OPENCV_DYNBLUR_PSF_HPP

#include <opencv2/dynblur/camera.hpp>
#include <opencv2/dynblur/camera_motion.hpp>
#include <opencv2/dynblur/plant.hpp>
#include <opencv2/dynblur/shutter.hpp>

#include <limits>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_imaging
//! @{

//! How the blur is allowed to vary over the frame.
enum PsfModel
{
    PSF_UNIFORM = 0,  //!< one kernel for the frame: the seed's method (image centre, centre row)
    PSF_ROWS = 1,     //!< one kernel per row band, each from its rows' own exposure interval
    PSF_TILES = 2,    //!< a grid of kernels: also varies across columns (projective rotation, distortion, axis)
    /** per frame, and per band of rows, the cheapest of the three whose displacement field is within
        PsfGenerator::getAutoTolerance of the exact one (PsfPlan says what was chosen where) */
    PSF_AUTO = 3
};

/** @brief What PSF_AUTO chose for one frame: the operator, and per band of rows whether one kernel
per row suffices.

The choice is made from the predicted motion before any kernel is drawn. The exact displacement
d(p, t) of a pixel p at time t (PsfGenerator's path) is evaluated on a grid of sample rows (at most
8 rows apart, every band's node row included), 17 columns from edge to edge and 5 instants of each
row's exposure. A row may share one kernel (PSF_ROWS) when every sampled pixel of it stays within
the tolerance of its centre column's displacement at every instant; the frame may take one kernel
(PSF_UNIFORM) when every sampled pixel stays within it of the frame centre's (same fraction of each
row's exposure). The bands are PSF_TILES's node rows; a band is given rows when every sampled row
its kernels reach (from the node row above to the one below) may share one kernel. So a model is
never chosen where the motion makes it wrong by more than the tolerance at a sampled point: a roll
about the optical axis moves the two ends of a row apart by about width × the roll's angle, and
beyond tolerance / width radians every band takes tiles.
*/
struct CV_EXPORTS_W_SIMPLE PsfPlan
{
    CV_WRAP PsfPlan();
    /** the operator the frame gets: PSF_UNIFORM, PSF_ROWS, or PSF_TILES (tile nodes in the bands
        listed as PSF_TILES, one kernel per row, the centre column's, in the others) */
    CV_PROP_RW int model;
    CV_PROP_RW double tolerance;           //!< the tolerance it was chosen with, pixels
    /** the largest distance of a sampled pixel's displacement from the frame centre's, pixels
        (PSF_UNIFORM's error) */
    CV_PROP_RW double uniformError;
    CV_PROP_RW std::vector<int> bandStart;    //!< first frame row of each band, increasing from 0
    CV_PROP_RW std::vector<int> bandModel;    //!< per band: PSF_UNIFORM, PSF_ROWS or PSF_TILES
    /** per band: the largest distance of a sampled pixel's displacement from its row's centre
        column's over the rows the band's kernels reach, pixels (PSF_ROWS's error there) */
    CV_PROP_RW std::vector<double> rowsError;
    CV_PROP_RW int rows;                      //!< frame rows

    /** @brief Share of the frame's rows given `model` (PSF_UNIFORM, PSF_ROWS or PSF_TILES), in [0, 1]. */
    CV_WRAP double rowShare(int model) const;
};

/** @brief Spatially variant blur: kernels on a grid of nodes, blended with partition-of-unity
weights.

Kernel n sits at node (nodeCols[n % nx], nodeRows[n / nx]) with nx = nodeCols.size(). Each kernel
is a PSF in convolution form plus an integer displacement: a latent (θ_ref view) point q spreads
to the blurred pixels q + shifts[n] + (u − c) with weight kernels[n](u), c the kernel's centre
element ((cols−1)/2, (rows−1)/2). Kernels are CV_32F, odd-sized, non-negative and sum to 1; a
pixel that does not move has a one-tap kernel at c with shift (0,0). The blurred frame is
\f[B(p) = \sum_n w_n(p) \sum_u k_n(u)\, L(p - s_n - (u - c))\f]
with \f$w_n(p) = w^y_j(p_y)\, w^x_i(p_x)\f$ for node n = (row j, column i), so \f$\sum_n w_n = 1\f$
and the weights are continuous: no seams @cite Hirsch2010Efficient. Along y, \f$w^y\f$ is the
linear (tent) interpolation between the two node rows around p. Along x, \f$w^x\f$ is 1 for the
nearer node column except over the middle half of the interval between two node columns, where it
moves linearly from one to the other: a pixel then takes a single column's kernels over half of
each interval, which halves the work of those pixels in the tile-wise operators. Both are constant
beyond the outermost nodes.
*/
struct CV_EXPORTS_W_SIMPLE PsfBank
{
    CV_WRAP PsfBank();
    CV_PROP_RW int model;                    //!< PsfModel that produced the bank
    CV_PROP_RW Size imageSize;               //!< frame size, pixels
    CV_PROP_RW std::vector<double> nodeRows; //!< node y coordinates, pixels, increasing
    CV_PROP_RW std::vector<double> nodeCols; //!< node x coordinates, pixels, increasing
    CV_PROP_RW std::vector<Mat> kernels;     //!< nodeRows.size()·nodeCols.size() kernels, row-major
    CV_PROP_RW std::vector<Point> shifts;    //!< integer displacement of each kernel's centre, pixels

    /** @brief Throws cv::Exception when the bank is inconsistent (sizes, types, sums). */
    CV_WRAP void validate() const;
    /** @brief Largest kernel width and height over the bank, pixels. */
    CV_WRAP Size maxKernelSize() const;
    /** @brief True when every kernel is a one-tap kernel with zero shift (nothing to restore). */
    CV_WRAP bool isIdentity() const;
};

/** @brief Predicts the blur of every pixel from the plant's trajectory and the shutter timing
(seed equations 4–7, @cite DynblurSeed, generalised to rolling shutters).

For a blurred pixel p exposed over [t0, t1] the kernel is the path of p − q(t), with
q(t) = camera.viewToReference(p, θ(t) − θ_ref) the reference point it sees, splatted
bilinearly with weights proportional to dwell time and normalised to sum 1.
*/
class CV_EXPORTS_W PsfGenerator : public Algorithm
{
public:
    /** @param plant the positioner. @param camera the camera (image size, intrinsics, mount). */
    CV_WRAP static Ptr<PsfGenerator> create(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera);

    /** @brief Kernels for one frame.
    @param model PSF_UNIFORM, PSF_ROWS, PSF_TILES or PSF_AUTO (the bank's model is then the one chosen).
    @param schedule the command.
    @param shutter frame timing; rows must equal the camera's image height.
    @param thetaRef reference angle, radians; NaN: the schedule's final resting angle. */
    CV_WRAP virtual PsfBank generate(int model, const SwitchSchedule& schedule, const RollingShutter& shutter,
                                     double thetaRef = std::numeric_limits<double>::quiet_NaN()) const = 0;

    /** @brief A generator for a camera alone: it takes the motion with each frame
    (generate(model, motion, shutter, tRef)).
    @param camera the camera (image size, intrinsics). */
    CV_WRAP static Ptr<PsfGenerator> create(const Ptr<CameraModel>& camera);

    /** @brief Kernels for one frame of any camera motion (DESIGN §2, Rotation): the path of pixel p is
    that of q(t) = K·R(t)·K⁻¹·p with R(t) = Q_refᵀ·Q(t). A rotation about the optical axis, or a
    pan with a tilt, blurs along curves that change across each row: PSF_TILES follows them,
    PSF_ROWS only where the blur is the same along a row. A motion made by CameraMotion::fromPlant
    gives the same bank, to the bit, as generate(model, schedule, shutter, thetaRef) with that
    plant and the motion's axis as the camera's mount axis.
    @param model PSF_UNIFORM, PSF_ROWS, PSF_TILES or PSF_AUTO.
    @param motion the camera's motion; its time span must cover the frame's readout.
    @param shutter frame timing (the motion's clock); rows must equal the camera's image height.
    @param tRef reference time, seconds: the view at the orientation Q(tRef) is the latent image;
           NaN: CameraMotion::referenceOrientation's default (a plant's final rest, a sampled motion's
           mid-exposure). */
    CV_WRAP virtual PsfBank generate(int model, const Ptr<CameraMotion>& motion, const RollingShutter& shutter,
                                     double tRef = std::numeric_limits<double>::quiet_NaN()) const = 0;

    /** @brief What PSF_AUTO chooses for one frame (PsfPlan), at a small fraction of the bank's cost.
    @param motion the camera's motion; its time span must cover the frame's readout.
    @param shutter frame timing; rows must equal the camera's image height.
    @param tRef reference time, seconds; NaN: the motion's default reference. */
    CV_WRAP virtual PsfPlan plan(const Ptr<CameraMotion>& motion, const RollingShutter& shutter,
                                 double tRef = std::numeric_limits<double>::quiet_NaN()) const = 0;
    /** @brief How far PSF_AUTO lets a cheaper model's displacement field stray from the exact one,
    pixels (default 0.25: at 0.5 px one kernel per row cost up to 0.72 dB against tiles on a 45 px
    blur, docs/quality.md). */
    CV_WRAP virtual double getAutoTolerance() const = 0;
    /** @param pixels > 0 and finite. */
    CV_WRAP virtual void setAutoTolerance(double pixels) = 0;

    /** @brief Largest kernel extent allowed, pixels (default 401). A longer path is refused with
    an error that says so; raise the limit for longer exposures or faster moves. */
    CV_WRAP virtual int getMaxKernelSize() const = 0;
    CV_WRAP virtual void setMaxKernelSize(int pixels) = 0;
    /** @brief Row-band height for PSF_ROWS, rows; 0 (default) chooses it from how fast the
    kernel changes (down to one row). */
    CV_WRAP virtual int getBandRows() const = 0;
    CV_WRAP virtual void setBandRows(int rows) = 0;
    /** @brief Tile grid for PSF_TILES (columns × rows of nodes); (0,0) (default) chooses it: 8 to 48
    columns from how fast the path changes across x, and the row bands of PSF_ROWS. */
    CV_WRAP virtual Size getTileGrid() const = 0;
    CV_WRAP virtual void setTileGrid(const Size& grid) = 0;
};

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
