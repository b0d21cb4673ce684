// SPDX-License-Identifier: Apache-2.0
// PsfGenerator: blur kernels predicted from the plant's trajectory and the shutter timing (seed
// equations 4–7, generalised to rolling shutters and to column variation): where the nodes go, and
// one kernel per node.
#include "precomp.hpp"

#include "imaging/pinhole.hpp"
#include "imaging/psf_generator.hpp"
#include "imaging/psf_kernel.hpp"
#include "imaging/psf_plan.hpp"
#include "imaging/trajectory.hpp"
#include "motion/camera_motion.hpp"
#include "motion/shutter_check.hpp"

namespace cv {
namespace dynblur {

namespace {

using detail::KernelNode;
using detail::KernelScratch;
using detail::Pinhole;
using detail::Trajectory;
using detail::ViewMotion;

class PsfGeneratorImpl CV_FINAL : public PsfGenerator
{
public:
    PsfGeneratorImpl(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera)
        : plant_(plant), camera_(camera), maxKernel_(401), bandRows_(0), grid_(0, 0), autoTolerance_(0.25)
    {
    }

    PsfBank generate(int model, const SwitchSchedule& schedule, const RollingShutter& shutter,
                     double thetaRef) const CV_OVERRIDE;
    PsfBank generate(int model, const Ptr<CameraMotion>& motion, const RollingShutter& shutter,
                     double tRef) const CV_OVERRIDE;

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
    PsfPlan plan(const Ptr<CameraMotion>& motion, const RollingShutter& shutter, double tRef) const CV_OVERRIDE;
    double getAutoTolerance() const CV_OVERRIDE { return autoTolerance_; }
    void setAutoTolerance(double pixels) CV_OVERRIDE
    {
        if (!(pixels > 0) || !std::isfinite(pixels))
            CV_Error_(Error::StsOutOfRange,
                      ("PsfGenerator::setAutoTolerance: pixels=%g must be > 0 and finite (PSF_AUTO's largest "
                       "displacement error)",
                       pixels));
        autoTolerance_ = pixels;
    }
    String getDefaultName() const CV_OVERRIDE { return "dynblur.PsfGenerator"; }

    /* The bank of `model` for the views of `motion` (arguments checked); with PSF_AUTO its plan
       goes to `plan` when given (and only the plan is made when `planOnly`), and the bank's model is
       the one chosen. */
    PsfBank bankOf(int model, const ViewMotion& motion, const RollingShutter& shutter, PsfPlan* plan = nullptr,
                   bool planOnly = false) const;
    //! Throws unless `model` is a PsfModel and `shutter` reads the camera's rows.
    void checkModelAndShutter(int model, const RollingShutter& shutter) const;

private:
    int autoColumns(const Trajectory& tr, const Pinhole& pr, const RollingShutter& shutter) const;
    //! PSF_TILES's node columns and rows (the grid set, or the automatic one) into `bank`.
    void tileNodes(const Trajectory& tr, const Pinhole& pr, const RollingShutter& shutter, PsfBank& bank) const;
    std::vector<double> autoBands(const Trajectory& tr, const Pinhole& pr, const RollingShutter& shutter,
                                  const std::vector<double>& columns) const;

    Ptr<Plant> plant_;
    Ptr<CameraModel> camera_;
    int maxKernel_;
    int bandRows_;
    Size grid_;
    double autoTolerance_;
};

//! The view's rotation at the start, middle and end of the exposure of row position `row`: the
//! points that sign a row's path when nodes are placed.
void exposureRotations(const Trajectory& tr, const RollingShutter& shutter, double row, Matx33d R[3])
{
    const Vec2d interval = shutter.intervalAt(row);
    const double a = interval[0], b = interval[1];
    R[0] = tr.rotationAt(a);
    R[1] = tr.rotationAt(0.5 * (a + b));
    R[2] = tr.rotationAt(b);
}

/* Largest change of a kernel's path (start, middle, end) across one automatic row band, pixels.
   0.4 px restores as well as one band per row (DeblurQuality; a point source's spot within 1 % of
   the per-row one, PointSourceMatchesRendererRollingShutter) with three quarters of the kernels
   of 0.25 px; at 0.5 px that spot's error grows by 16 %. */
const double kBandTolerancePx = 0.4;
/* Node columns of an automatic tile grid: kBandTolerancePx between neighbouring columns' paths, at
   least 8 and at most 16 columns. At most 8 loses 0.7-1.2 dB in a tilt's window I, and there 16
   restore as well as 64 (within 0.1 dB) with neighbours up to 2 px apart (DeblurQuality). A pan's
   shift changes along a row up to ~10x faster: 16 columns there lose 1-2 dB and double the spots
   (PanTiltQuality.DISABLED_WindowITileColumns), so beyond 16 columns are added until neighbours
   differ by kColumnStepPx, up to kMaxAutoTileCols, which bounds the bank (columns x row bands). */
const int kMinAutoTileCols = 8, kFineAutoTileCols = 16, kMaxAutoTileCols = 48;
const double kColumnStepPx = 2.5;

int PsfGeneratorImpl::autoColumns(const Trajectory& tr, const Pinhole& pr, const RollingShutter& shutter) const
{
    // Largest change of a path point (start, middle, end) per pixel along x, over probe rows;
    // the node spacing keeps adjacent kernels within kBandTolerancePx of each other.
    const Size size = camera_->getImageSize();
    const int W = size.width, H = size.height, nProbeCols = 33, nProbeRows = 33;
    double slope = 0;
    for (int j = 0; j < nProbeRows; j++)
    {
        const double y = (H - 1) * (double)j / (nProbeRows - 1);
        Matx33d R[3];
        exposureRotations(tr, shutter, y, R);
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
    const double fine = std::min((double)kFineAutoTileCols, std::max((double)kMinAutoTileCols,
                                                                      std::ceil(W * slope / kBandTolerancePx)));
    return (int)std::max(fine, std::min((double)kMaxAutoTileCols, std::ceil(W * slope / kColumnStepPx)));
}

std::vector<double> PsfGeneratorImpl::autoBands(const Trajectory& tr, const Pinhole& pr,
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
            Matx33d R[3];
            exposureRotations(tr, shutter, r, R);
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

void PsfGeneratorImpl::tileNodes(const Trajectory& tr, const Pinhole& pr, const RollingShutter& shutter,
                                 PsfBank& bank) const
{
    const Size size = camera_->getImageSize();
    const int W = size.width, H = size.height;
    const int nx = grid_.width > 0 ? grid_.width : autoColumns(tr, pr, shutter);
    for (int i = 0; i < nx; i++)
        bank.nodeCols.push_back((i + 0.5) * W / nx - 0.5);
    if (grid_.height > 0)
    {
        for (int j = 0; j < grid_.height; j++)
            bank.nodeRows.push_back((j + 0.5) * H / grid_.height - 0.5);
    }
    else
        bank.nodeRows = autoBands(tr, pr, shutter, std::vector<double>{0.0, 0.5 * (W - 1), W - 1.0});
}

void PsfGeneratorImpl::checkModelAndShutter(int model, const RollingShutter& shutter) const
{
    if (model != PSF_UNIFORM && model != PSF_ROWS && model != PSF_TILES && model != PSF_AUTO)
        CV_Error_(Error::StsBadArg, ("PsfGenerator::generate: model=%d must be PSF_UNIFORM (0), PSF_ROWS (1), "
                                     "PSF_TILES (2) or PSF_AUTO (3)",
                                     model));
    detail::checkShutter(shutter, "PsfGenerator::generate", "shutter.", camera_->getImageSize().height);
}

PsfBank PsfGeneratorImpl::generate(int model, const SwitchSchedule& schedule, const RollingShutter& shutter,
                                   double thetaRef) const
{
    if (plant_.empty())
        CV_Error(Error::StsBadArg, "PsfGenerator::generate: this generator was created without a plant; give it the "
                                   "motion: generate(model, motion, shutter, tRef)");
    checkModelAndShutter(model, shutter);
    if (std::isinf(thetaRef))
        CV_Error(Error::StsBadArg,
                 "PsfGenerator::generate: thetaRef must be finite (radians) or NaN (the final resting angle)");
    if (!(schedule.times.empty() && schedule.levels.empty()))
        schedule.validate();
    ViewMotion view;
    view.plant = plant_;
    view.schedule = schedule;
    view.axis = camera_->getMountAxis();
    view.thetaRef = std::isnan(thetaRef) ? plant_->restingAngle(schedule.finalLevel()) : thetaRef;
    return bankOf(model, view, shutter);
}

PsfBank PsfGeneratorImpl::generate(int model, const Ptr<CameraMotion>& motion, const RollingShutter& shutter,
                                   double tRef) const
{
    checkModelAndShutter(model, shutter);
    detail::checkMotionCovers(motion, shutter.readoutInterval(), "PsfGenerator::generate", "motion");
    if (std::isinf(tRef))
        CV_Error(Error::StsBadArg, "PsfGenerator::generate: tRef must be finite (seconds) or NaN (the motion's default "
                                   "reference: a plant's final rest, a sampled motion's mid-exposure)");
    return bankOf(model, ViewMotion::of(motion, tRef, shutter), shutter);
}

PsfPlan PsfGeneratorImpl::plan(const Ptr<CameraMotion>& motion, const RollingShutter& shutter, double tRef) const
{
    checkModelAndShutter(PSF_AUTO, shutter);
    detail::checkMotionCovers(motion, shutter.readoutInterval(), "PsfGenerator::plan", "motion");
    if (std::isinf(tRef))
        CV_Error(Error::StsBadArg, "PsfGenerator::plan: tRef must be finite (seconds) or NaN (the motion's default "
                                   "reference)");
    PsfPlan result;
    bankOf(PSF_AUTO, ViewMotion::of(motion, tRef, shutter), shutter, &result, true);
    return result;
}

PsfBank PsfGeneratorImpl::bankOf(int model, const ViewMotion& motion, const RollingShutter& shutter,
                                 PsfPlan* plan, bool planOnly) const
{
    const Size size = camera_->getImageSize();
    Pinhole pr = detail::pinholeOf(*camera_);
    if (motion.oneAxis())
        pr.axis = motion.axis;
    const Trajectory tr = detail::sampleTrajectory(motion, shutter.readoutInterval());
    const int W = size.width, H = size.height;

    PsfBank bank;
    bank.imageSize = size;
    const double xc = 0.5 * (W - 1), yc = 0.5 * (H - 1);
    /* PSF_AUTO: the tile nodes, then the plan on their node rows; a band of rows takes one kernel,
       the centre column's, in every node column. */
    std::vector<bool> rowsOnly;
    if (model == PSF_AUTO)
    {
        tileNodes(tr, pr, shutter, bank);
        const PsfPlan chosen = detail::planPsf(tr, pr, shutter, size, bank.nodeRows, autoTolerance_);
        if (plan)
            *plan = chosen;
        if (planOnly)
            return bank;
        model = chosen.model;
        if (model == PSF_TILES)
            for (int band : chosen.bandModel)
                rowsOnly.push_back(band != PSF_TILES);
        else
            bank = PsfBank();  // the cheaper model's own nodes, below
        bank.imageSize = size;
    }
    bank.model = model;
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
    else if (bank.nodeRows.empty())  // PSF_AUTO has placed them
        tileNodes(tr, pr, shutter, bank);

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
            const bool shared = !rowsOnly.empty() && rowsOnly[size_t(i / nx)];
            if (shared && i % nx != 0)
                continue;  // the band's kernel, copied below
            KernelNode node;
            node.pixel = Point2d(shared ? xc : bank.nodeCols[i % nx], bank.nodeRows[i / nx]);
            const Vec2d interval = shutter.intervalAt(node.pixel.y);
            node.tStart = interval[0];
            node.tEnd = interval[1];
            detail::rasterizeKernel(tr, pr, node, maxKernel_, scratch, sizes[size_t(i - range.start)], bank.shifts[i]);
        }
        Mat stripe(1, int(scratch.kernels.size()), CV_32F);
        std::copy(scratch.kernels.begin(), scratch.kernels.end(), stripe.ptr<float>());
        int start = 0;
        for (int i = range.start; i < range.end; i++)
        {
            const Size size = sizes[size_t(i - range.start)];
            if (size.area() == 0)
                continue;  // a shared band's other columns
            bank.kernels[i] = stripe.colRange(start, start + size.area()).reshape(1, size.height);
            start += size.area();
        }
    }, std::min(n, 64));
    for (int i = 0; i < n; i++)
        if (!rowsOnly.empty() && rowsOnly[size_t(i / nx)] && i % nx != 0)
        {
            bank.kernels[i] = bank.kernels[i - i % nx];
            bank.shifts[i] = bank.shifts[i - i % nx];
        }
    return bank;
}

}  // namespace

PsfBank detail::generatePsfBank(const PsfGenerator& generator, int model, const ViewMotion& motion,
                                const RollingShutter& shutter, PsfPlan* plan)
{
    const PsfGeneratorImpl& impl = dynamic_cast<const PsfGeneratorImpl&>(generator);
    impl.checkModelAndShutter(model, shutter);
    return impl.bankOf(model, motion, shutter, plan);
}

Ptr<PsfGenerator> PsfGenerator::create(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera)
{
    if (!plant)
        CV_Error(Error::StsNullPtr, "PsfGenerator::create: plant must not be null");
    if (!camera)
        CV_Error(Error::StsNullPtr, "PsfGenerator::create: camera must not be null");
    return makePtr<PsfGeneratorImpl>(plant, camera);
}

Ptr<PsfGenerator> PsfGenerator::create(const Ptr<CameraModel>& camera)
{
    if (!camera)
        CV_Error(Error::StsNullPtr, "PsfGenerator::create: camera must not be null");
    return makePtr<PsfGeneratorImpl>(Ptr<Plant>(), camera);
}

}  // namespace dynblur
}  // namespace cv
