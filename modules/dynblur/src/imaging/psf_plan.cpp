// SPDX-License-Identifier: Apache-2.0
// PsfPlan: PSF_AUTO's choice of the cheapest operator whose displacement field stays within a
// tolerance of the exact one, per frame and per band of rows.
#include "precomp.hpp"

#include "imaging/psf_plan.hpp"

namespace cv {
namespace dynblur {

namespace {

// The sample grid of PsfPlan's rule: columns edge to edge, instants of each row's exposure, rows.
constexpr int kPlanColumns = 17;
constexpr int kPlanInstants = 5;
constexpr int kPlanRowStep = 8;

}  // namespace

PsfPlan::PsfPlan() : model(PSF_TILES), tolerance(0), uniformError(0), rows(0) {}

double PsfPlan::rowShare(int which) const
{
    if (which != PSF_UNIFORM && which != PSF_ROWS && which != PSF_TILES)
        CV_Error_(Error::StsBadArg,
                  ("PsfPlan::rowShare: model=%d must be PSF_UNIFORM (0), PSF_ROWS (1) or PSF_TILES (2)", which));
    if (rows <= 0 || bandStart.size() != bandModel.size())
        return 0;
    int count = 0;
    for (size_t b = 0; b < bandStart.size(); b++)
        if (bandModel[b] == which)
            count += (b + 1 < bandStart.size() ? bandStart[b + 1] : rows) - bandStart[b];
    return double(count) / rows;
}

PsfPlan detail::planPsf(const Trajectory& tr, const Pinhole& pinhole, const RollingShutter& shutter, Size size,
                        const std::vector<double>& nodeRows, double tolerance)
{
    const int W = size.width, H = size.height, bands = int(nodeRows.size());
    CV_Assert(bands > 0);
    // Sample rows: every kPlanRowStep-th, the last and every node row.
    std::vector<double> rows;
    for (int y = 0; y < H; y += kPlanRowStep)
        rows.push_back(y);
    rows.push_back(H - 1);
    rows.insert(rows.end(), nodeRows.begin(), nodeRows.end());
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());

    /* d(x, y, t) at each sample (row, instant, column); the centre column is xc, kept apart so
       the rows' error is measured against it. NaN (a ray behind the camera) counts as infinitely far. */
    const double xc = 0.5 * (W - 1), yc = 0.5 * (H - 1);
    const auto displacementsAt = [&](double y, std::vector<Point2d>& d, Point2d* centre) {
        const Vec2d interval = shutter.intervalAt(y);
        for (int s = 0; s < kPlanInstants; s++)
        {
            const Matx33d R = tr.rotationAt(interval[0] + (interval[1] - interval[0]) * s / (kPlanInstants - 1));
            for (int c = 0; c <= kPlanColumns; c++)  // the last one: the centre column
            {
                const Point2d p(c < kPlanColumns ? (W - 1) * double(c) / (kPlanColumns - 1) : xc, y);
                const Point2d m = pinhole.undistort(p);
                const Point2d dp = pinhole.displacement(m, pinhole.distort(m.x, m.y), R);
                if (c < kPlanColumns)
                    d[size_t(s * kPlanColumns + c)] = dp;
                else
                    centre[s] = dp;
            }
        }
    };
    const auto distance = [](const Point2d& a, const Point2d& b) {
        const double n = norm(a - b);
        return std::isnan(n) ? std::numeric_limits<double>::infinity() : n;
    };
    Point2d frameCentre[kPlanInstants];
    {
        std::vector<Point2d> unused(size_t(kPlanInstants * kPlanColumns));
        displacementsAt(yc, unused, frameCentre);
    }
    std::vector<double> rowsError(rows.size()), uniformError(rows.size());
    parallel_for_(Range(0, int(rows.size())), [&](const Range& range) {
        std::vector<Point2d> d(size_t(kPlanInstants * kPlanColumns));
        for (int i = range.start; i < range.end; i++)
        {
            Point2d centre[kPlanInstants];
            displacementsAt(rows[size_t(i)], d, centre);
            double er = 0, eu = 0;
            for (int s = 0; s < kPlanInstants; s++)
                for (int c = 0; c < kPlanColumns; c++)
                {
                    er = std::max(er, distance(d[size_t(s * kPlanColumns + c)], centre[s]));
                    eu = std::max(eu, distance(d[size_t(s * kPlanColumns + c)], frameCentre[s]));
                }
            rowsError[size_t(i)] = er;
            uniformError[size_t(i)] = eu;
        }
    });

    PsfPlan plan;
    plan.tolerance = tolerance;
    plan.rows = H;
    plan.uniformError = *std::max_element(uniformError.begin(), uniformError.end());
    bool anyTiles = false;
    for (int b = 0; b < bands; b++)
    {
        // The band's rows: halfway to its neighbours; its kernels reach from the node above to the one below.
        plan.bandStart.push_back(b == 0 ? 0 : int(std::ceil(0.5 * (nodeRows[size_t(b - 1)] + nodeRows[size_t(b)]))));
        const double reachFrom = b == 0 ? 0.0 : nodeRows[size_t(b - 1)];
        const double reachTo = b + 1 == bands ? H - 1.0 : nodeRows[size_t(b + 1)];
        double error = 0;
        for (size_t i = 0; i < rows.size(); i++)
            if (rows[i] >= reachFrom && rows[i] <= reachTo)
                error = std::max(error, rowsError[i]);
        plan.rowsError.push_back(error);
        const bool rowsSuffice = error <= tolerance;
        anyTiles = anyTiles || !rowsSuffice;
        plan.bandModel.push_back(rowsSuffice ? PSF_ROWS : PSF_TILES);
    }
    plan.model = plan.uniformError <= tolerance ? PSF_UNIFORM : anyTiles ? PSF_TILES : PSF_ROWS;
    if (plan.model == PSF_UNIFORM)
        std::fill(plan.bandModel.begin(), plan.bandModel.end(), int(PSF_UNIFORM));
    return plan;
}

}  // namespace dynblur
}  // namespace cv
