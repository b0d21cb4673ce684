// SPDX-License-Identifier: Apache-2.0
/* Blind refinement: the time offset that makes the frame's own second-order statistics consistent
   with its predicted blur.

   A blurred row is a weighted sum of scene rows (its kernel, collapsed across the columns). For a
   scene whose vertical semivariogram is γ, the mean squared difference of rows r and r + t is

       V(r, t) = −Σᵢⱼ aᵢ aⱼ γ(|pᵢ − pⱼ|) + 2σ²

   with a the kernel of row r + t minus the kernel of row r (weights aᵢ at scene rows pᵢ, Σ a = 0)
   and σ² the pixel noise. The rows a candidate keeps still measure γ directly; the moving rows'
   measured V is then compared with the prediction of each candidate's kernels. Unlike the residual
   of a restoration re-blurred against the frame, this does not favour less blur: a kernel that is
   too short predicts rows more different than they are, one too long predicts them more alike. */
#include "precomp.hpp"

#include "refine/blind_fit.hpp"
#include "restore/deconv_rl.hpp"
#include "refine/fit_pyramid.hpp"

namespace cv {
namespace dynblur {
namespace detail {

namespace {

// The variogram's largest lag, rows at the criterion's resolution: beyond a kernel's span plus kLags.
const int kMaxLag = 48;
// Lags between moving rows that are compared, rows.
const int kLags = 8;
// Columns at each side left out of the variograms (the projective blur's edge, the frame's border).
const int kMarginColumns = 4;
// A kernel spanning at most this many rows moves less than a pixel: the row counts as still.
const int kStillSpan = 2;
// The time offset's scan step, seconds.
const double kScanStep = 0.25e-3;

//! One row's kernel collapsed across the columns: the scene rows it sums, and their weights.
struct RowProfile
{
    std::vector<double> position, weight;
};

/* Each row's profile under one candidate (PSF_ROWS, one band per row); `still` receives 1 for a row
   that moves less than a pixel, whose profile is then one tap at its centroid (the splat of a
   fractional displacement is not a blur the scene saw). */
std::vector<RowProfile> rowProfiles(const PsfBank& bank, int rows, std::vector<char>& still)
{
    std::vector<RowProfile> profiles(static_cast<size_t>(rows));
    still.assign(static_cast<size_t>(rows), 0);
    const size_t columns = bank.nodeCols.size();
    size_t node = 0;
    for (int r = 0; r < rows; r++)
    {
        while (node + 1 < bank.nodeRows.size() &&
               std::abs(bank.nodeRows[node + 1] - r) <= std::abs(bank.nodeRows[node] - r))
            node++;
        const size_t index = node * columns + columns / 2;
        const Mat& kernel = bank.kernels[index];
        const int shift = bank.shifts[index].y, centre = (kernel.rows - 1) / 2;
        RowProfile& p = profiles[size_t(r)];
        double centroid = 0, total = 0;
        int first = kernel.rows, last = -1;
        for (int u = 0; u < kernel.rows; u++)
        {
            const double w = sum(kernel.row(u))[0];
            if (w <= 1e-4)
                continue;
            const double position = r - shift - (u - centre);
            p.position.push_back(position);
            p.weight.push_back(w);
            centroid += w * position, total += w;
            first = std::min(first, u), last = std::max(last, u);
        }
        if (last - first + 1 <= kStillSpan)
        {
            still[size_t(r)] = 1;
            p.position.assign(1, centroid / total);
            p.weight.assign(1, 1.0);
        }
    }
    return profiles;
}

//! The semivariogram γ at a real lag (linear between the measured lags, constant beyond the last).
inline double semivariogram(const std::vector<double>& gamma, double lag)
{
    lag = std::abs(lag);
    const int k = int(lag);
    if (k + 1 >= int(gamma.size()))
        return gamma.back();
    const double f = lag - k;
    return gamma[size_t(k)] * (1 - f) + gamma[size_t(k + 1)] * f;
}

//! −Σ aᵢ aⱼ γ(pᵢ − pⱼ) for a = `upper` − `lower`: the predicted mean squared difference of the two rows, noise-free.
double predictedDifference(const RowProfile& lower, const RowProfile& upper, const std::vector<double>& gamma)
{
    double cross = 0, own = 0;
    for (size_t i = 0; i < upper.position.size(); i++)
        for (size_t j = 0; j < lower.position.size(); j++)
            cross += upper.weight[i] * lower.weight[j] * semivariogram(gamma, upper.position[i] - lower.position[j]);
    for (const RowProfile* p : {&lower, &upper})
        for (size_t i = 0; i < p->position.size(); i++)
            for (size_t j = i + 1; j < p->position.size(); j++)
                own += 2 * p->weight[i] * p->weight[j] * semivariogram(gamma, p->position[i] - p->position[j]);
    return 2 * cross - own;
}

/* The mean squared log ratio of measured to predicted, at the scene contrast (a scale of γ: the
   still rows need not have the moving rows' contrast) that fits best. */
double logMisfit(const std::vector<double>& measured, const std::vector<double>& predicted, double noise)
{
    double best = std::numeric_limits<double>::infinity();
    for (double scale = 0.125; scale <= 8.0; scale *= 1.04)
    {
        double sum = 0;
        for (size_t k = 0; k < measured.size(); k++)
        {
            const double q = std::log(std::max(measured[k], 1e-12)) -
                             std::log(std::max(scale * predicted[k] + 2 * noise, 1e-12));
            sum += q * q;
        }
        best = std::min(best, sum);
    }
    return best / double(measured.size());
}

}  // namespace

BlindFrame prepareBlindFrame(const Mat& frame, const Ptr<CameraModel>& camera, int maxWidth)
{
    const LuminancePyramid pyramid = buildPyramid(linearLuminance(frame), camera, maxWidth, true);
    BlindFrame b;
    b.luminance = pyramid.images.back();
    b.camera = pyramid.cameras.back();
    b.halvings = pyramid.levels() - 1;
    b.noiseVariance = pyramid.noiseSigma.back() * pyramid.noiseSigma.back();
    const Mat& y = b.luminance;
    b.maxLag = std::min(kMaxLag, y.rows - 1);
    b.variogram.create(y.rows, b.maxLag + 1, CV_64F);
    b.variogram.setTo(-1);
    const int x0 = std::min(kMarginColumns, y.cols / 4), x1 = y.cols - x0;
    parallel_for_(Range(0, y.rows), [&](const Range& range) {
        for (int r = range.start; r < range.end; r++)
        {
            const float* a = y.ptr<float>(r);
            double* v = b.variogram.ptr<double>(r);
            v[0] = 0;
            for (int t = 1; t <= b.maxLag && r + t < y.rows; t++)
            {
                const float* c = y.ptr<float>(r + t);
                double sum = 0;
                for (int x = x0; x < x1; x++)
                    sum += double(c[x] - a[x]) * (c[x] - a[x]);
                v[t] = sum / (x1 - x0);
            }
        }
    });
    return b;
}

std::vector<double> blindObjective(const Ptr<Plant>& plant, const BlindFrame& frame, const SwitchSchedule& schedule,
                                   const RollingShutter& shutter, const std::vector<MotionCorrection>& candidates)
{
    const int rows = frame.luminance.rows;
    std::vector<std::vector<RowProfile>> profiles(candidates.size());
    std::vector<char> stillEverywhere(static_cast<size_t>(rows), 1), still;
    for (size_t c = 0; c < candidates.size(); c++)
    {
        Ptr<PsfGenerator> generator = PsfGenerator::create(candidates[c].correctPlant(plant), frame.camera);
        generator->setBandRows(1);
        const PsfBank bank = generator->generate(
            PSF_ROWS, schedule, shutterAtLevel(candidates[c].correctShutter(shutter), frame.halvings));
        profiles[c] = rowProfiles(bank, rows, still);
        for (int r = 0; r < rows; r++)
            stillEverywhere[size_t(r)] = stillEverywhere[size_t(r)] && still[size_t(r)];
    }
    std::vector<double> objective(candidates.size(), std::numeric_limits<double>::quiet_NaN());

    // The scene's semivariogram from pairs of rows still under every candidate (as the same light).
    std::vector<double> gamma(size_t(frame.maxLag + 1), 0.0), count(size_t(frame.maxLag + 1), 0.0);
    int stillRows = 0;
    for (int r = 0; r < rows; r++)
    {
        if (!stillEverywhere[size_t(r)])
            continue;
        stillRows++;
        for (int t = 1; t <= frame.maxLag && r + t < rows; t++)
            if (stillEverywhere[size_t(r + t)])
                gamma[size_t(t)] += frame.variogram.at<double>(r, t) / 2 - frame.noiseVariance, count[size_t(t)]++;
    }
    if (stillRows < kBlindMinStillRows || stillRows == rows)
        return objective;
    for (size_t t = 1; t < gamma.size(); t++)
        gamma[t] = count[t] > 0 ? std::max(0.0, gamma[t] / count[t]) : gamma[t - 1];

    // The moving rows' measured differences, one set for every candidate (so the values form a curve).
    std::vector<Vec2i> pairs;
    std::vector<double> measured;
    for (int r = 0; r < rows; r++)
        for (int t = 1; t <= kLags && r + t < rows; t++)
            if (!stillEverywhere[size_t(r)] || !stillEverywhere[size_t(r + t)])
                pairs.emplace_back(r, r + t), measured.push_back(frame.variogram.at<double>(r, t));
    parallel_for_(Range(0, int(candidates.size())), [&](const Range& range) {
        std::vector<double> predicted(pairs.size());
        for (int c = range.start; c < range.end; c++)
        {
            for (size_t k = 0; k < pairs.size(); k++)
                predicted[k] = predictedDifference(profiles[size_t(c)][size_t(pairs[k][0])],
                                                   profiles[size_t(c)][size_t(pairs[k][1])], gamma);
            objective[size_t(c)] = logMisfit(measured, predicted, frame.noiseVariance);
        }
    });
    return objective;
}

BlindResult fitBlindTimeOffset(const Ptr<Plant>& plant, const BlindFrame& frame, const SwitchSchedule& schedule,
                               const RollingShutter& shutter, const MotionCorrection& start, double maxTimeOffset,
                               double decisive)
{
    const int steps = std::max(1, int(std::round(maxTimeOffset / kScanStep)));
    std::vector<MotionCorrection> scan;
    for (int k = -steps; k <= steps; k++)
    {
        scan.push_back(start);
        scan.back().timeOffset = start.timeOffset + k * kScanStep;
    }
    const std::vector<double> objective = blindObjective(plant, frame, schedule, shutter, scan);
    BlindResult result;
    result.correction = start;
    result.candidates = int(scan.size());
    const size_t at = size_t(steps);
    if (!std::isfinite(objective[at]))
        return result;
    result.observed = true;
    size_t best = at;
    for (size_t k = 0; k < objective.size(); k++)
        if (objective[k] < objective[best])
            best = k;
    result.score = objective[at];
    result.decisiveness = (objective[at] - objective[best]) / objective[best];
    if (best == at || !(result.decisiveness > decisive))
        return result;
    // The parabola through the minimum and its neighbours places it between the scan's steps.
    double offset = 0;
    if (best > 0 && best + 1 < objective.size())
    {
        const double l = objective[best - 1], m = objective[best], r = objective[best + 1];
        const double curvature = l - 2 * m + r;
        if (curvature > 0)
            offset = std::max(-0.5, std::min(0.5, 0.5 * (l - r) / curvature));
    }
    result.correction.timeOffset = scan[best].timeOffset + offset * kScanStep;
    result.score = objective[best];
    result.applied = true;
    return result;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
