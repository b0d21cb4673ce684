// SPDX-License-Identifier: Apache-2.0
// Fitting a MotionCorrection: the reference carried through the predicted blur, compared with the
// frame; coarse to fine, then the decisions on what the frames did not determine.
#include "precomp.hpp"

#include "motion/axis_chain_motion.hpp"
#include "refine/level_fit.hpp"
#include "refine/motion_fit.hpp"

namespace cv {
namespace dynblur {
namespace detail {

namespace {

// A parameter the coarse fit deems unobserved keeps its start unless that raises the cost by more than this.
const double kUnobservedCostRise = 0.02;
/* Residuals counted per independent one by the significance test of a change (significantDrop):
   with 70 000 residuals at 320 px and four parameters it asks for a drop of about 0.4 %. */
const double kCorrelatedPixels = 16;
/* The ridge: a combination of parameters whose information from the frames is below this many times
   the prior's (fit units scaled by FitParameter::priorDeviation) is held at the prior. */
const double kRidgeInformation = 100;
// A parameter whose share in a held combination exceeds this (of a unit eigenvector) is reported held.
const double kRidgeMixing = 0.3;
// A fitted parameter within this fraction of its search half-width from a bound is pinned there.
const double kBoundMargin = 0.02;
// Local minima of the offset's scan the coarse fit starts from.
const size_t kStartsTried = 2;

//! Where the fit stands between its stages: the parameters and what is known of them.
struct FitState
{
    FitVector q;                                 //!< the parameters, fit units
    FitMatrix covariance = FitMatrix::zeros();   //!< of the last fit that computed it
    std::vector<int> active;                     //!< the parameters still fitted
    FitVector coarseDeviation;                   //!< each tried parameter's deviation after the coarse fit
    int evaluations = 0;                         //!< forward models of the coarse level
};

/* The scan's variants of the start: the start itself, and for every active parameter with a scan
   step, each variant moved by that step either way. */
std::vector<FitVector> scanVariants(const FitVector& prior, const std::vector<int>& active)
{
    std::vector<FitVector> variants{prior};
    for (int j : active)
    {
        if (kFitTable[j].scanStep <= 0)
            continue;
        std::vector<FitVector> moved;
        for (const FitVector& v : variants)
            for (double step : {-kFitTable[j].scanStep, 0.0, kFitTable[j].scanStep})
            {
                moved.push_back(v);
                moved.back()[j] = prior[j] + step;
            }
        variants.swap(moved);
    }
    return variants;
}

/* The deepest local minima of the coarse objective over the clock offset's scan (FitSettings), for
   each of scanVariants, deepest first, at most `count`. */
std::vector<FitVector> scanStarts(LevelResiduals& coarse, const FitBox& box, const std::vector<int>& active,
                                  const FitSettings& settings, size_t count)
{
    const double unit = kFitTable[0].unit;  // the clock offset's
    const int steps = int(std::ceil(settings.maxTimeOffset / settings.scanStep));
    std::vector<FitVector> minima;
    std::vector<double> minimumCosts;
    std::vector<float> data;
    for (const FitVector& variant : scanVariants(box.prior, active))
    {
        std::vector<FitVector> candidates;
        std::vector<double> costs;
        for (int k = -steps; k <= steps; k++)
        {
            FitVector candidate = variant;
            candidate[0] = box.prior[0] + k * settings.scanStep / unit;
            data.clear();
            coarse.residuals(fromFitUnits(candidate, box.start), data);
            candidates.push_back(candidate);
            costs.push_back(squaredNorm(data, data.size()));
        }
        for (size_t k = 0; k < costs.size(); k++)
            if ((k == 0 || costs[k] < costs[k - 1]) && (k + 1 == costs.size() || costs[k] <= costs[k + 1]))
                minima.push_back(candidates[k]), minimumCosts.push_back(costs[k]);
    }
    std::vector<size_t> order(minima.size());
    for (size_t k = 0; k < order.size(); k++)
        order[k] = k;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return minimumCosts[a] < minimumCosts[b]; });
    std::vector<FitVector> starts;
    for (size_t k = 0; k < order.size() && k < count; k++)
        starts.push_back(minima[order[k]]);
    return starts;
}

/* The parameters `flags` turns on for `frames` (their motion's kind, their shutters, a mount's axes),
   less those of a mount's axes that no frame's move turns: no frame observes them, so they keep their
   start and their bits go to `unobserved`. */
std::vector<int> activeParameters(const std::vector<FitFrame>& frames, int flags, int& unobserved)
{
    bool rolling = false;
    for (const FitFrame& f : frames)
        rolling = rolling || f.shutter.lineDelay > 0;
    const AxisChainMotion* mount = frames[0].motion ? asAxisChainMotion(*frames[0].motion) : nullptr;
    const int motion = frames[0].motion.empty() ? FIT_PLANT_MOTION : mount ? FIT_MOUNT_MOTION : FIT_MEASURED_MOTION;
    std::vector<int> active;
    for (int j : flaggedParameters(flags, motion, rolling, mount ? mount->axisCount() : 1))
    {
        bool moves = !mount || kFitTable[j].axis < 0;
        for (size_t k = 0; k < frames.size() && !moves; k++)
            moves = asAxisChainMotion(*frames[k].motion)->axisMoves(kFitTable[j].axis);
        if (moves)
            active.push_back(j);
        else
            unobserved |= 1 << j;
    }
    return active;
}

/* The coarse stage: the offset's scan, a fit from its deepest minima, and the parameters it leaves
   uncertain, whose start explains the frames about as well: not observed by them (their moving rows
   see content the reference never saw), they keep their start rather than the noise's choice and
   leave `state.active`; their bits (bit j: kFitTable[j]) go to `unobserved`. */
void fitCoarse(const Ptr<Plant>& plant, const std::vector<FitFrame>& frames, const FitBox& box,
               const FitSettings& settings, FitState& state, int& unobserved)
{
    LevelResiduals coarse(plant, frames, settings.coarseWidth);
    coarse.fixMasks(box.start);
    // The offset's scan has one basin per few pixels of motion, and with the plant off as well the
    // deepest basin at the nominal plant may not be the true one: the fit starts from the deepest few.
    std::vector<FitVector> starts{box.prior};
    if (settings.flags & REFINE_TIME_OFFSET)
        starts = scanStarts(coarse, box, state.active, settings, kStartsTried);
    LevelFit coarseFit(coarse, state.active, box);
    double bestCost = std::numeric_limits<double>::infinity();
    FitMatrix startCovariance;
    for (const FitVector& candidate : starts)
    {
        double cost = 0;
        const FitVector fitted = coarse.pixels() > 0 ? coarseFit.run(candidate, 8, startCovariance, &cost) : candidate;
        if (cost < bestCost || starts.size() == 1)
            bestCost = cost, state.q = fitted, state.covariance = startCovariance;
    }
    std::vector<int> observed;
    std::vector<float> data;
    for (int j : state.active)
    {
        state.coarseDeviation[j] = coarse.pixels() > 0 ? std::sqrt(std::max(0.0, state.covariance(j, j)))
                                                       : std::numeric_limits<double>::infinity();
        bool keep = state.coarseDeviation[j] <= kFitTable[j].observable;
        if (!keep && coarse.pixels() > 0)
        {
            FitVector reset = state.q;
            reset[j] = box.prior[j];
            keep = coarseFit.cost(reset, data) > bestCost * (1 + kUnobservedCostRise);
        }
        if (keep)
            observed.push_back(j);
        else
            state.q[j] = box.prior[j], unobserved |= 1 << j;
    }
    state.active.swap(observed);
    state.evaluations += coarse.evaluations();
}

/* Into `held`, the bits (bit j: kFitTable[j]) of the `observed` parameters that a ridge mixes: a
   combination whose information from the frames at q is below kRidgeInformation times the prior's
   (eigenvectors of the information in prior units). `information` receives the eigenvalues, descending. Returns the
   parameter to hold first (the last in the table that a ridge mixes: a bias component or ζ, then ωn,
   the line delay and the clock, which varies most from frame to frame), or -1 when there is no ridge. */
int ridgeParameter(LevelFit& fit, const std::vector<int>& observed, const FitVector& q, int& held, FitVector& information)
{
    const int n = int(observed.size());
    const Mat info = fit.information(q);
    Mat scaled(n, n, CV_64F);
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++)
            scaled.at<double>(a, b) = info.at<double>(a, b) * kFitTable[observed[size_t(a)]].priorDeviation *
                                      kFitTable[observed[size_t(b)]].priorDeviation;
    Mat values, vectors;
    eigen(scaled, values, vectors);  // descending; rows are the eigenvectors
    information = FitVector();
    int hold = -1;
    for (int i = 0; i < n; i++)
    {
        information[i] = values.at<double>(i);
        if (values.at<double>(i) >= kRidgeInformation)
            continue;
        for (int a = 0; a < n; a++)
            if (std::abs(vectors.at<double>(i, a)) > kRidgeMixing)
                held |= 1 << observed[size_t(a)], hold = std::max(hold, observed[size_t(a)]);
    }
    return hold;
}

/* Parameters the frames observe one by one may still trade against each other along a ridge (a
   later clock against a stiffer plant, in a global-shutter frame at the end of a move): there the
   frames determine only a combination. The parameters the ridge mixes are held at the prior one by
   one, last in the table first (the clock, which varies most from frame to frame, is never held for
   a ridge), and the others are fitted again: only the combination the frames observe moves. */
void holdRidge(LevelResiduals& fine, const FitBox& box, const FitSettings& settings, FitState& state,
               FitResult& result, int& ridge)
{
    bool refit = false;
    while (state.active.size() > 1)
    {
        LevelFit activeFit(fine, state.active, box);
        const int hold = ridgeParameter(activeFit, state.active, state.q, ridge, result.information);
        if (hold <= 0)
            break;
        state.active.erase(std::find(state.active.begin(), state.active.end(), hold));
        state.q[hold] = box.prior[hold];
        refit = true;
    }
    if (refit)
    {
        LevelFit heldFit(fine, state.active, box);
        state.q = heldFit.run(state.q, 5, state.covariance, nullptr, settings.deviation);
    }
}

/* Whether the fit's drop of the squared residual from `startCost` to `cost` over `pixels` residuals
   with `parameters` fitted is more than noise would give: an F-test at the 0.1 % level on the
   residuals counted as kCorrelatedPixels per independent one (blur, the pyramid's averaging and the
   forward model's own error correlate neighbours), approximated with χ² quantiles. */
bool significantDrop(double startCost, double cost, size_t pixels, int parameters)
{
    if (parameters <= 0 || pixels == 0)
        return false;
    static const double kChiSquare999[6] = {0, 10.83, 13.82, 16.27, 18.47, 20.52};  // χ²_p at 0.999, p = 1..5
    const double independent = std::max(double(parameters) + 1, double(pixels) / kCorrelatedPixels);
    const double variance = cost / (independent - parameters);
    return (startCost - cost) / std::max(variance, 1e-300) > kChiSquare999[std::min(parameters, 5)];
}

//! The fine level's residuals at a fit's result: all of them, their squared sum, and each frame's mean square.
struct LevelCost
{
    std::vector<float> data;
    double cost = 0;
    std::vector<double> perFrame;
};

LevelCost levelCost(LevelResiduals& fine, const MotionCorrection& correction)
{
    LevelCost c;
    fine.residuals(correction, c.data, &c.perFrame);
    c.cost = squaredNorm(c.data, c.data.size());
    return c;
}

/* A parameter the fit left at a search bound was stopped there, not explained by the frames, unless
   the frames barely observe it (ζ where the frame sees no ringing): put back to its start without
   raising the residual by more than kUnobservedCostRise, it is held there (its bit goes to
   `unobserved`). Returns the parameters that stay at a bound. */
std::vector<int> releasePinned(LevelResiduals& fine, const FitBox& box, FitState& state, LevelCost& atResult,
                               int& unobserved)
{
    std::vector<int> pinned;
    for (bool again = true; again;)
    {
        again = false;
        pinned.clear();
        for (int j : state.active)
        {
            const double margin = kBoundMargin * (box.upper[j] - box.lower[j]) / 2;
            if (state.q[j] <= box.lower[j] + margin || state.q[j] >= box.upper[j] - margin)
                pinned.push_back(j);
        }
        for (size_t k = 0; k < pinned.size() && !again; k++)
        {
            const int j = pinned[k];
            std::vector<int> others = state.active;
            others.erase(std::find(others.begin(), others.end(), j));
            FitVector reset = state.q;
            reset[j] = box.prior[j];
            LevelFit heldFit(fine, others, box);
            FitMatrix unused;
            reset = heldFit.run(reset, 4, unused, nullptr, false);
            LevelCost held = levelCost(fine, fromFitUnits(reset, box.start));
            if (held.cost <= atResult.cost * (1 + kUnobservedCostRise))
            {
                state.q = reset, unobserved |= 1 << j, state.active.swap(others);
                std::swap(atResult, held);
                again = true;  // the others moved: look at the bounds afresh
            }
        }
    }
    return pinned;
}

}  // namespace

FitResult fitMotionCorrection(const Ptr<Plant>& plant, const std::vector<FitFrame>& frames,
                              const MotionCorrection& start, const FitSettings& settings)
{
    CV_Assert(!frames.empty());
    const FitBox box(start, settings.maxTimeOffset);
    FitResult result;
    FitState state;
    state.q = box.prior;
    int unobserved = 0, ridge = 0;  // bit j: kFitTable[j]
    state.active = activeParameters(frames, settings.flags, unobserved);
    const std::vector<int> tried = state.active;

    // Coarse: the offset's scan and a first fit; what the frames do not observe keeps its start.
    if (settings.coarse)
        fitCoarse(plant, frames, box, settings, state, unobserved);

    // Fine: the fit again at the fine level, then what only a ridge determines held at the start.
    LevelResiduals fine(plant, frames, settings.fineWidth);
    fine.fixMasks(fromFitUnits(state.q, start));
    LevelFit fineFit(fine, state.active, box);
    if (fine.pixels() > 0)
        state.q = fineFit.run(state.q, settings.coarse ? 5 : 4, state.covariance, nullptr, settings.deviation);
    if (settings.coarse && fine.pixels() > 0)
        holdRidge(fine, box, settings, state, result, ridge);

    /* The decision: the start stays unless the fit explains the frames significantly better
       (significantDrop): a change within what the frames cannot tell apart would only move the
       restoration by the noise's whim. The fine fit began at the start when there was no coarse
       stage, and one frame's mean is the whole's: then its own residuals serve. */
    LevelCost atStart, atResult;
    if (!settings.coarse && frames.size() == 1 && fine.pixels() > 0)
    {
        atResult.data = fineFit.finalData();
        atResult.cost = squaredNorm(atResult.data, atResult.data.size());
        atResult.perFrame.push_back(atResult.cost / double(atResult.data.size()));
        atStart.cost = squaredNorm(fineFit.startData(), fineFit.startData().size());
        atStart.perFrame.push_back(atStart.cost / double(atResult.data.size()));
    }
    else
    {
        atStart = levelCost(fine, start);
        atResult = levelCost(fine, fromFitUnits(state.q, start));
    }
    const double startCost = atStart.cost;
    result.improvement = startCost > 0 ? 1 - atResult.cost / startCost : 0;
    result.unchanged = !significantDrop(startCost, atResult.cost, atResult.data.size(), int(state.active.size()));
    if (result.unchanged)
    {
        state.q = box.prior;
        atResult.perFrame = atStart.perFrame;
    }
    else
    {
        // A parameter stopped at a search bound: held at its start if the frames barely observe it, else reported.
        const std::vector<int> pinned = releasePinned(fine, box, state, atResult, unobserved);
        const MotionCorrection c = fromFitUnits(state.q, start);
        for (int j : pinned)
        {
            result.pinned |= kFitTable[j].flag;
            result.pinnedNote += result.pinnedNote.empty() ? "" : "; ";
            result.pinnedNote += pinnedNote(j, kFitTable[j].get(c), kFitTable[j].get(start), settings.maxTimeOffset);
        }
    }
    result.unobserved = flagsOfParameters(unobserved);
    result.ridge = flagsOfParameters(ridge);
    result.held = result.unobserved | result.ridge;
    result.unobservedParameters = unobserved;
    result.ridgeParameters = ridge;
    result.heldParameters = unobserved | ridge;

    // The result: the correction, its consistency over every frame and each frame's, the deviations.
    result.correction = fromFitUnits(state.q, start);
    if (!atResult.data.empty())
    {
        std::vector<float> data;
        fine.residuals(result.correction, data);  // the gains at the result
        result.gain = fine.gains()[0];
    }
    for (double meanSquare : atResult.perFrame)
        result.frameConsistency.push_back(std::sqrt(meanSquare));
    result.correction.consistency = atResult.data.empty()
                                        ? std::numeric_limits<double>::quiet_NaN()
                                        : std::sqrt(std::min(atResult.cost, startCost) / double(atResult.data.size()));
    for (int j = 0; j < kFitParameters; j++)
        result.deviation[j] = std::sqrt(std::max(0.0, state.covariance(j, j))) * kFitTable[j].unit;
    for (int j : tried)
        if (std::find(state.active.begin(), state.active.end(), j) == state.active.end())
            result.deviation[j] = state.coarseDeviation[j] * kFitTable[j].unit;  // how little the frames say about it
    result.evaluations = state.evaluations + fine.evaluations();
    return result;
}

std::vector<double> frameConsistency(const Ptr<Plant>& plant, const std::vector<FitFrame>& frames,
                                     const MotionCorrection& correction, int width)
{
    LevelResiduals level(plant, frames, width);
    level.fixMasks(correction);
    std::vector<float> data;
    std::vector<double> perFrame;
    level.residuals(correction, data, &perFrame);
    for (double& c : perFrame)
        c = std::sqrt(c);
    return perFrame;
}

std::vector<double> meanSquaredResiduals(const Ptr<Plant>& plant, const std::vector<FitFrame>& frames,
                                         const MotionCorrection& maskAt,
                                         const std::vector<MotionCorrection>& candidates, int width)
{
    LevelResiduals level(plant, frames, width);
    level.fixMasks(maskAt);
    std::vector<double> objective;
    std::vector<float> data;
    for (const MotionCorrection& c : candidates)
    {
        data.clear();
        level.residuals(c, data);
        objective.push_back(data.empty() ? std::numeric_limits<double>::quiet_NaN()
                                         : squaredNorm(data, data.size()) / double(data.size()));
    }
    return objective;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
