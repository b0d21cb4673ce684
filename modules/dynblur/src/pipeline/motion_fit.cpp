// SPDX-License-Identifier: Apache-2.0
// Fitting a MotionCorrection: the reference carried through the predicted blur, compared with the frame.
#include "precomp.hpp"

#include "imaging/psf_generator.hpp"
#include "motion/corrected_motion.hpp"
#include "restore/deconv_operator.hpp"
#include "pipeline/motion_fit.hpp"

#include <opencv2/imgproc.hpp>


namespace cv {
namespace dynblur {
namespace detail {

namespace {

//! The level of `pyramid` whose width is the largest at or below `width` (the coarsest when none is).
int levelAtMostWide(const LuminancePyramid& pyramid, int width)
{
    for (int level = 0; level < pyramid.levels(); level++)
        if (pyramid.images[size_t(level)].cols <= width)
            return level;
    return pyramid.levels() - 1;
}

/* The parameters in the units the fit works in, chosen so that a unit step moves the image by
   comparable amounts: the offset in milliseconds, the line delay and ωn in percent, ζ in tens of
   percent (the blur is least sensitive to it), the gyro bias in mrad/s. */
const double kUnit[kFitParameters] = {1e-3, 1e-2, 1e-2, 1e-1, 1e-3, 1e-3, 1e-3};
const double kStep[kFitParameters] = {0.1, 1, 1, 1, 1, 1, 1};  // forward-difference steps, fit units
// A step below these in every parameter ends a level.
const double kTolerance[kFitParameters] = {0.01, 0.05, 0.05, 0.1, 0.1, 0.1, 0.1};
/* Scales are searched within these bounds, fit units (±15 % line delay, ±10 % ωn, ±50 % ζ), and the
   bias within ±40 mrad/s (2.3 °/s: a phone's gyro bias is a fraction of that). */
const double kScaleBound[kFitParameters] = {0, 15, 10, 5, 40, 40, 40};
/* A weak prior toward the start, fit units: it decides only parameters that the frames do not
   observe (a global shutter's line delay, ζ in a frame that sees no ringing, a bias over a short
   still-to-frame interval). */
const double kPriorDeviation[kFitParameters] = {2, 10, 5, 3, 20, 20, 20};
/* A parameter whose standard deviation after the coarse fit exceeds this (fit units: 0.3 ms, 3 %,
   2 %, 25 %, 5 mrad/s) is not observed by the frames (their moving rows see content the reference
   never saw, or the motion they see does not depend on it): it keeps its start value. */
const double kObservable[kFitParameters] = {0.3, 3, 2, 2.5, 5, 5, 5};
// ... unless resetting it raises the cost by more than this fraction.
const double kUnobservedCostRise = 0.02;
/* Residuals counted per independent one by the significance test of a change (significantDrop):
   with 70 000 residuals at 320 px and four parameters it asks for a drop of about 0.4 %. */
const double kCorrelatedPixels = 16;
/* The ridge: a combination of parameters whose information from the frames is below this many times
   the prior's (fit units scaled by kPriorDeviation) is held at the prior. */
const double kRidgeInformation = 100;
// A parameter whose share in a held combination exceeds this (of a unit eigenvector) is reported held.
const double kRidgeMixing = 0.3;
// A fitted parameter within this fraction of its search half-width from a bound is pinned there.
const double kBoundMargin = 0.02;
// Local minima of the offset's scan the coarse fit starts from.
const size_t kStartsTried = 2;
// The scan's step of ωn when the plant is refined, fit units (percent).
const double kScanFrequencyStep = 4;
/* Pixel noise is never taken below this (linear intensity): an 8-bit frame's quantisation alone is
   about this much, and a synthetic noise-free frame must not make every model inconsistent. */
const double kNoiseFloor = 1e-3;
/* Node columns of the fit's kernels. Tiles, not rows: a reference at another angle than the frame
   is displaced by the whole move, and the projective rotation spreads that displacement across
   the columns by several pixels, which one kernel per row smears (RefinementQuality: window I
   against the still frame before the move kept 18 % of the gain with 4 columns). */
const int kFitTileColumns = 8;
// Light counted in a frame pixel from the reference, below which the pixel is left out.
const float kMinCoverage = 0.98f;
// Pixels at or above this (linear) may be clipped by the sensor: the linear model fails there.
const float kSaturated = 0.99f;
// The brightness gain between a frame and its still is sought within [1/kMaxGain, kMaxGain].
const double kMaxGain = 2;

FitVector toFitUnits(const MotionCorrection& c)
{
    FitVector q;
    q[0] = c.timeOffset / kUnit[0];
    q[1] = (c.lineDelayScale - 1) / kUnit[1];
    q[2] = (c.naturalFreqScale - 1) / kUnit[2];
    q[3] = (c.dampingScale - 1) / kUnit[3];
    for (int i = 0; i < 3; i++)
        q[4 + i] = c.gyroBias[i] / kUnit[4 + i];
    return q;
}

MotionCorrection fromFitUnits(const FitVector& q, const MotionCorrection& like)
{
    MotionCorrection c = like;
    c.timeOffset = q[0] * kUnit[0];
    c.lineDelayScale = 1 + q[1] * kUnit[1];
    c.naturalFreqScale = 1 + q[2] * kUnit[2];
    c.dampingScale = 1 + q[3] * kUnit[3];
    for (int i = 0; i < 3; i++)
        c.gyroBias[i] = q[4 + i] * kUnit[4 + i];
    return c;
}

//! The frames' residuals at one pyramid level: (frame − predicted) / σ over each frame's fixed mask.
class LevelResiduals
{
public:
    LevelResiduals(const Ptr<Plant>& plant, const std::vector<FitFrame>& frames, int width)
        : plant_(plant), frames_(frames)
    {
        for (const FitFrame& f : frames)
        {
            const int level = levelAtMostWide(*f.reference, width);
            levels_.push_back(level);
            sigma_.push_back(std::max(kNoiseFloor, f.reference->noiseSigma[size_t(level)]));
        }
    }

    /* Fixes each frame's mask: pixels the reference fully covers under `c` (eroded by two pixels,
       so the fit's steps do not move them across the edge), away from the border, not saturated. */
    void fixMasks(const MotionCorrection& c)
    {
        masks_.assign(frames_.size(), Mat());
        gains_.assign(frames_.size(), 1.0);
        weights_.assign(frames_.size(), Mat());
        pixels_ = 0;
        for (size_t i = 0; i < frames_.size(); i++)
        {
            Mat predicted, coverage;
            predict(i, c, predicted, coverage);
            const Mat& frame = frames_[i].frame.images[size_t(levels_[i])];
            const Mat& reference = frames_[i].reference->images[size_t(levels_[i])];
            Mat mask = (coverage >= kMinCoverage) & (frame < kSaturated) & (predicted < kSaturated);
            mask.setTo(0, reference >= kSaturated);  // the reference's clipped pixels spread through the blur
            erode(mask, mask, getStructuringElement(MORPH_RECT, Size(5, 5)), Point(-1, -1), 1, BORDER_CONSTANT,
                  Scalar(0));
            masks_[i] = mask;
            mask.convertTo(weights_[i], CV_32F, 1.0 / 255);
            pixels_ += size_t(countNonZero(mask));
        }
    }

    size_t pixels() const { return pixels_; }
    //! Each frame's brightness gain over its still at the last residuals() (frame ≈ gain × still blurred).
    const std::vector<double>& gains() const { return gains_; }
    size_t frames() const { return frames_.size(); }
    //! Whether the frames carry a measured motion (FitFrame::motion) rather than a plant's.
    bool measured() const { return !frames_[0].motion.empty(); }
    int evaluations() const { return evaluations_; }

    /* Appends every frame's residuals under `c` to `out` (in mask order); `perFrame`, when given,
       receives each frame's mean squared residual. */
    void residuals(const MotionCorrection& c, std::vector<float>& out, std::vector<double>* perFrame = nullptr)
    {
        if (perFrame)
            perFrame->assign(frames_.size(), 0.0);
        for (size_t i = 0; i < frames_.size(); i++)
        {
            Mat predicted, coverage;
            predict(i, c, predicted, coverage);
            const Mat& frame = frames_[i].frame.images[size_t(levels_[i])];
            // Light that fell outside the reference is made up from what fell inside.
            predicted = predicted / max(coverage, 0.5);
            /* The still may be brighter or darker than the frame (a webcam's automatic exposure, the
               lighting): the gain that fits best, in closed form (least squares over the mask). */
            const double cross = predicted.dot(frame.mul(weights_[i]));
            const double power = predicted.dot(predicted.mul(weights_[i]));
            gains_[i] = power > 0 ? std::min(kMaxGain, std::max(1 / kMaxGain, cross / power)) : 1.0;
            const float gain = float(gains_[i]);
            const float inverseSigma = float(1.0 / sigma_[i]);
            double sum = 0;
            size_t count = 0;
            for (int y = 0; y < frame.rows; y++)
            {
                const uchar* m = masks_[i].ptr<uchar>(y);
                const float *b = frame.ptr<float>(y), *p = predicted.ptr<float>(y);
                for (int x = 0; x < frame.cols; x++)
                {
                    if (!m[x])
                        continue;
                    const float r = (b[x] - gain * p[x]) * inverseSigma;
                    out.push_back(r);
                    sum += double(r) * r;
                    count++;
                }
            }
            if (perFrame)
                (*perFrame)[i] = count ? sum / double(count) : std::numeric_limits<double>::quiet_NaN();
        }
    }

private:
    void predict(size_t i, const MotionCorrection& c, Mat& predicted, Mat& coverage)
    {
        const FitFrame& f = frames_[i];
        const int level = levels_[i];
        const Ptr<CameraModel>& camera = f.reference->cameras[size_t(level)];
        const Mat& reference = f.reference->images[size_t(level)];
        const RollingShutter shutter = shutterAtLevel(c.correctShutter(f.shutter), level);
        PsfBank bank;
        if (f.motion)
        {
            // The still lies at its capture time on the same clock as the frame: the offset moves both.
            Ptr<PsfGenerator> generator = PsfGenerator::create(camera);
            generator->setTileGrid(Size(kFitTileColumns, 0));
            bank = generatePsfBank(*generator, PSF_TILES, correctedView(f.motion, c, f.referenceTime + c.timeOffset,
                                                                          shutter),
                                   shutter);
        }
        else
        {
            Ptr<PsfGenerator> generator = PsfGenerator::create(c.correctPlant(plant_), camera);
            generator->setTileGrid(Size(kFitTileColumns, 0));
            bank = generator->generate(PSF_TILES, f.schedule, shutter, f.referenceAngle);
        }
        std::unique_ptr<BlurOperator> op = createBankOperator(bank, false);
        op->forward(reference, predicted);
        if (ones_.size() != reference.size())
            ones_ = Mat::ones(reference.size(), CV_32F);
        op->forward(ones_, coverage);
        evaluations_++;
    }

    Ptr<Plant> plant_;
    const std::vector<FitFrame>& frames_;
    std::vector<int> levels_;
    std::vector<double> sigma_;
    std::vector<Mat> masks_, weights_;  // weights_: the masks as 0 and 1 in CV_32F
    std::vector<double> gains_;
    Mat ones_;
    size_t pixels_ = 0;
    int evaluations_ = 0;
};

double squaredNorm(const std::vector<float>& r, size_t count)
{
    double sum = 0;
    for (size_t k = 0; k < count; k++)
        sum += double(r[k]) * r[k];
    return sum;
}

//! Levenberg–Marquardt over the active parameters of q at one level, with the prior toward `prior`.
class LevelFit
{
public:
    LevelFit(LevelResiduals& residuals, const std::vector<int>& active, const FitVector& prior, const FitVector& lower,
             const FitVector& upper, const MotionCorrection& like)
        : r_(residuals), active_(active), prior_(prior), lower_(lower), upper_(upper), like_(like)
    {
    }

    //! Data plus prior cost at q; `data` receives the residual vector.
    double cost(const FitVector& q, std::vector<float>& data)
    {
        data.clear();
        r_.residuals(fromFitUnits(q, like_), data);
        double total = squaredNorm(data, data.size());
        for (int j : active_)
        {
            const double p = (q[j] - prior_[j]) / kPriorDeviation[j];
            total += p * p;
        }
        return total;
    }

    /** Fits from q; `finalCost`, when given, receives the cost at the result; `covariance` is left
        zero unless `wantCovariance` (it costs a Jacobian at the result). */
    FitVector run(FitVector q, int maxIterations, FitMatrix& covariance, double* finalCost = nullptr,
              bool wantCovariance = true)
    {
        std::vector<float> current, shifted;
        double currentCost = cost(q, current);
        startData_ = current;
        double lambda = 1e-3;
        const int n = int(active_.size());
        Mat jtj(n, n, CV_64F), jtr(n, 1, CV_64F);
        for (int iteration = 0; iteration < maxIterations && n > 0; iteration++)
        {
            jacobianProducts(q, current, jtj, jtr, true);
            bool accepted = false, converged = false;
            for (int attempt = 0; attempt < 6 && !accepted; attempt++)
            {
                Mat damped = jtj.clone();
                for (int a = 0; a < n; a++)
                    damped.at<double>(a, a) += lambda * jtj.at<double>(a, a) + 1e-9;
                Mat delta;
                solve(damped, -jtr, delta, DECOMP_CHOLESKY);
                FitVector candidate = q;
                converged = true;
                for (int a = 0; a < n; a++)
                {
                    const int j = active_[size_t(a)];
                    candidate[j] = std::min(upper_[j], std::max(lower_[j], q[j] + delta.at<double>(a)));
                    converged = converged && std::abs(candidate[j] - q[j]) < kTolerance[j];
                }
                const double candidateCost = cost(candidate, shifted);
                if (candidateCost < currentCost)
                {
                    q = candidate, currentCost = candidateCost, current.swap(shifted);
                    lambda = std::max(1e-7, lambda / 4);
                    accepted = true;
                }
                else
                {
                    lambda *= 8;
                }
            }
            if (!accepted || converged)
                break;
        }
        // Curvature at the result: the parameters' covariance for independent pixel noise.
        covariance = FitMatrix::zeros();
        if (n > 0 && wantCovariance)
        {
            jacobianProducts(q, current, jtj, jtr, true);
            const double dof = std::max(1.0, double(current.size()) - n);
            const double variance = squaredNorm(current, current.size()) / dof;
            Mat inverse = jtj.inv(DECOMP_SVD) * variance;
            for (int a = 0; a < n; a++)
                for (int b = 0; b < n; b++)
                    covariance(active_[size_t(a)], active_[size_t(b)]) = inverse.at<double>(a, b);
        }
        if (finalCost)
            *finalCost = currentCost;
        finalData_.swap(current);
        return q;
    }

    /* The data's information about the active parameters at q (JᵀJ of the residuals in noise
       units, without the prior, over the residual's mean square): their inverse covariance. */
    Mat information(const FitVector& q)
    {
        std::vector<float> at;
        cost(q, at);
        const int n = int(active_.size());
        Mat jtj(n, n, CV_64F), jtr(n, 1, CV_64F);
        jacobianProducts(q, at, jtj, jtr, false);
        const double variance = squaredNorm(at, at.size()) / std::max(1.0, double(at.size()) - n);
        return jtj / std::max(variance, 1e-12);
    }

    //! The data residuals at the last run's start and result.
    const std::vector<float>& startData() const { return startData_; }
    const std::vector<float>& finalData() const { return finalData_; }

private:
    /* JᵀJ and Jᵀr of the data at q (forward differences; `at` holds the data at q), and of the prior
       when `withPrior`. */
    void jacobianProducts(const FitVector& q, const std::vector<float>& at, Mat& jtj, Mat& jtr, bool withPrior)
    {
        const int n = int(active_.size());
        std::vector<std::vector<float>> columns(static_cast<size_t>(n));
        std::vector<float> shifted;
        for (int a = 0; a < n; a++)
        {
            const int j = active_[size_t(a)];
            FitVector moved = q;
            // Step inward at an upper bound, so the difference is taken inside the box.
            const double h = q[j] + kStep[j] <= upper_[j] ? kStep[j] : -kStep[j];
            moved[j] += h;
            shifted.clear();
            r_.residuals(fromFitUnits(moved, like_), shifted);
            std::vector<float>& column = columns[size_t(a)];
            column.resize(at.size());
            for (size_t k = 0; k < at.size(); k++)
                column[k] = float((shifted[k] - at[k]) / h);
        }
        for (int a = 0; a < n; a++)
        {
            const int j = active_[size_t(a)];
            double g = 0;
            for (size_t k = 0; k < at.size(); k++)
                g += double(columns[size_t(a)][k]) * at[k];
            jtr.at<double>(a) = g + (withPrior ? (q[j] - prior_[j]) / (kPriorDeviation[j] * kPriorDeviation[j]) : 0);
            for (int b = a; b < n; b++)
            {
                double s = 0;
                for (size_t k = 0; k < at.size(); k++)
                    s += double(columns[size_t(a)][k]) * columns[size_t(b)][k];
                if (a == b && withPrior)
                    s += 1.0 / (kPriorDeviation[j] * kPriorDeviation[j]);
                jtj.at<double>(a, b) = jtj.at<double>(b, a) = s;
            }
        }
    }

    LevelResiduals& r_;
    std::vector<float> startData_, finalData_;
    std::vector<int> active_;
    FitVector prior_, lower_, upper_;
    MotionCorrection like_;
};

/* The deepest local minima of the coarse objective over the offset's scan, deepest first, at most
   `count`. With the plant refined the scan is repeated at ωn scaled by ±kScanFrequencyStep: an error
   in ωn delays the end of a move by a growing amount, which the offset alone cannot match. */
std::vector<FitVector> scanStarts(LevelResiduals& coarse, const FitVector& prior, const MotionCorrection& start,
                              const FitSettings& settings, size_t count)
{
    const int steps = int(std::ceil(settings.maxTimeOffset / settings.scanStep));
    std::vector<double> frequencies{prior[2]};
    if ((settings.flags & REFINE_PLANT) && !coarse.measured())
        frequencies = {prior[2] - kScanFrequencyStep, prior[2], prior[2] + kScanFrequencyStep};
    std::vector<FitVector> minima;
    std::vector<double> minimumCosts;
    std::vector<float> data;
    for (double frequency : frequencies)
    {
        std::vector<FitVector> candidates;
        std::vector<double> costs;
        for (int k = -steps; k <= steps; k++)
        {
            FitVector candidate = prior;
            candidate[0] = prior[0] + k * settings.scanStep / kUnit[0];
            candidate[2] = frequency;
            data.clear();
            coarse.residuals(fromFitUnits(candidate, start), data);
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

}  // namespace

namespace {

int flagOf(int parameter)
{
    return parameter == 0 ? REFINE_TIME_OFFSET
           : parameter == 1 ? REFINE_LINE_DELAY
           : parameter < 4  ? REFINE_PLANT
                            : REFINE_GYRO_BIAS;
}

/* Into `held`, the flags of the `observed` parameters that a ridge mixes: a combination whose
   information from the frames at q is below kRidgeInformation times the prior's (eigenvectors of the
   information in prior units). `information` receives the eigenvalues, descending. Returns the
   parameter to hold first (the last in `observed` that a ridge mixes: a bias component or ζ, then ωn,
   the line delay and the clock, which varies most from frame to frame), or -1 when there is no ridge. */
int ridgeParameter(LevelFit& fit, const std::vector<int>& observed, const FitVector& q, int& held, FitVector& information)
{
    const int n = int(observed.size());
    const Mat info = fit.information(q);
    Mat scaled(n, n, CV_64F);
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++)
            scaled.at<double>(a, b) = info.at<double>(a, b) * kPriorDeviation[observed[size_t(a)]] *
                                      kPriorDeviation[observed[size_t(b)]];
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
                held |= flagOf(observed[size_t(a)]), hold = std::max(hold, observed[size_t(a)]);
    }
    return hold;
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

const char* const kParameterName[kFitParameters] = {"time offset", "line delay", "natural frequency", "damping ratio",
                                                    "gyro bias x",  "gyro bias y", "gyro bias z"};

}  // namespace

FitResult fitMotionCorrection(const Ptr<Plant>& plant, const std::vector<FitFrame>& frames,
                              const MotionCorrection& start, const FitSettings& settings)
{
    CV_Assert(!frames.empty());
    bool rolling = false;
    for (const FitFrame& f : frames)
        rolling = rolling || f.shutter.lineDelay > 0;
    std::vector<int> active;
    if (settings.flags & REFINE_TIME_OFFSET)
        active.push_back(0);
    if ((settings.flags & REFINE_LINE_DELAY) && rolling)
        active.push_back(1);
    const bool measured = !frames[0].motion.empty();
    if ((settings.flags & REFINE_PLANT) && !measured)
        active.push_back(2), active.push_back(3);
    if ((settings.flags & REFINE_GYRO_BIAS) && measured)
        active.push_back(4), active.push_back(5), active.push_back(6);

    const FitVector prior = toFitUnits(start);
    FitVector lower, upper;
    lower[0] = prior[0] - settings.maxTimeOffset / kUnit[0];
    upper[0] = prior[0] + settings.maxTimeOffset / kUnit[0];
    for (int j = 1; j < kFitParameters; j++)
        lower[j] = -kScaleBound[j], upper[j] = kScaleBound[j];

    FitResult result;
    FitVector q = prior;
    int evaluations = 0;
    FitMatrix covariance = FitMatrix::zeros();

    std::vector<int> observed = active;
    FitVector coarseDeviation;
    std::vector<float> data;
    if (settings.coarse)
    {
        LevelResiduals coarse(plant, frames, settings.coarseWidth);
        coarse.fixMasks(start);
        // Starts for the coarse fit: the offset's scan has one basin per few pixels of motion, and
        // with the plant off as well the deepest basin at the nominal plant may not be the true one.
        std::vector<FitVector> starts{prior};
        if (settings.flags & REFINE_TIME_OFFSET)
            starts = scanStarts(coarse, prior, start, settings, kStartsTried);
        LevelFit coarseFit(coarse, active, prior, lower, upper, start);
        double bestCost = std::numeric_limits<double>::infinity();
        FitMatrix startCovariance;
        for (const FitVector& candidate : starts)
        {
            double cost = 0;
            const FitVector fitted =
                coarse.pixels() > 0 ? coarseFit.run(candidate, 8, startCovariance, &cost) : candidate;
            if (cost < bestCost || starts.size() == 1)
                bestCost = cost, q = fitted, covariance = startCovariance;
        }
        /* A parameter the coarse fit leaves uncertain, and whose start value explains the frames
           about as well, is not observed by them (their moving rows see content the reference never
           saw): it keeps its start value rather than the noise's choice. */
        observed.clear();
        for (int j : active)
        {
            coarseDeviation[j] = coarse.pixels() > 0 ? std::sqrt(std::max(0.0, covariance(j, j)))
                                                     : std::numeric_limits<double>::infinity();
            bool keep = coarseDeviation[j] <= kObservable[j];
            if (!keep && coarse.pixels() > 0)
            {
                FitVector reset = q;
                reset[j] = prior[j];
                keep = coarseFit.cost(reset, data) > bestCost * (1 + kUnobservedCostRise);
            }
            if (keep)
                observed.push_back(j);
            else
                q[j] = prior[j], result.unobserved |= flagOf(j);
        }
        evaluations += coarse.evaluations();
    }
    const std::vector<int> tried = active;
    active.swap(observed);

    LevelResiduals fine(plant, frames, settings.fineWidth);
    fine.fixMasks(fromFitUnits(q, start));
    LevelFit fineFit(fine, active, prior, lower, upper, start);
    if (fine.pixels() > 0)
        q = fineFit.run(q, settings.coarse ? 5 : 4, covariance, nullptr, settings.deviation);
    /* Parameters the frames observe one by one may still trade against each other along a ridge (a
       later clock against a stiffer plant, in a global-shutter frame at the end of a move): there
       the frames determine only a combination. The parameters the ridge mixes are held at the prior
       one by one, ζ first, then ωn and the line delay (the clock, which varies most from frame to
       frame, is never held for a ridge), and the others are fitted again: only the combination the
       frames observe moves. */
    bool refit = false;
    while (settings.coarse && active.size() > 1 && fine.pixels() > 0)
    {
        LevelFit activeFit(fine, active, prior, lower, upper, start);
        const int hold = ridgeParameter(activeFit, active, q, result.ridge, result.information);
        if (hold <= 0)
            break;
        active.erase(std::find(active.begin(), active.end(), hold));
        q[hold] = prior[hold];
        refit = true;
    }
    if (refit)
    {
        LevelFit heldFit(fine, active, prior, lower, upper, start);
        q = heldFit.run(q, 5, covariance, nullptr, settings.deviation);
    }

    /* The start stays unless the fit explains the frames significantly better (significantDrop):
       a change within what the frames cannot tell apart would only move the restoration by the
       noise's whim. The fine fit began at the start when there was no coarse stage, and one frame's
       mean is the whole's: then its own residuals serve. */
    std::vector<double> perFrame, startPerFrame;
    double startCost = 0;
    if (!settings.coarse && frames.size() == 1 && fine.pixels() > 0)
    {
        data = fineFit.finalData();
        startCost = squaredNorm(fineFit.startData(), fineFit.startData().size());
        startPerFrame.push_back(startCost / double(data.size()));
        perFrame.push_back(squaredNorm(data, data.size()) / double(data.size()));
    }
    else
    {
        data.clear();
        fine.residuals(start, data, &startPerFrame);
        startCost = squaredNorm(data, data.size());
        data.clear();
        fine.residuals(fromFitUnits(q, start), data, &perFrame);
    }
    double cost = squaredNorm(data, data.size());
    const int fitted = int(active.size());
    result.improvement = startCost > 0 ? 1 - cost / startCost : 0;
    result.unchanged = !significantDrop(startCost, cost, data.size(), fitted);
    if (result.unchanged)
        q = prior, perFrame = startPerFrame;
    else
    {
        /* A parameter the fit left at a search bound was stopped there, not explained by the frames,
           unless the frames barely observe it (ζ where the frame sees no ringing): put back to its
           start without raising the residual by more than kUnobservedCostRise, it is held there. */
        std::vector<float> held;
        std::vector<double> heldPerFrame;
        std::vector<int> pinned;
        for (bool again = true; again;)
        {
            again = false;
            pinned.clear();
            for (int j : active)
            {
                const double margin = kBoundMargin * (upper[j] - lower[j]) / 2;
                if (q[j] <= lower[j] + margin || q[j] >= upper[j] - margin)
                    pinned.push_back(j);
            }
            for (size_t k = 0; k < pinned.size() && !again; k++)
            {
                const int j = pinned[k];
                std::vector<int> others = active;
                others.erase(std::find(others.begin(), others.end(), j));
                FitVector reset = q;
                reset[j] = prior[j];
                LevelFit heldFit(fine, others, prior, lower, upper, start);
                FitMatrix unused;
                reset = heldFit.run(reset, 4, unused, nullptr, false);
                held.clear();
                fine.residuals(fromFitUnits(reset, start), held, &heldPerFrame);
                const double heldCost = squaredNorm(held, held.size());
                if (heldCost <= cost * (1 + kUnobservedCostRise))
                {
                    q = reset, cost = heldCost, result.unobserved |= flagOf(j), active.swap(others);
                    data.swap(held), perFrame.swap(heldPerFrame);
                    again = true;  // the others moved: look at the bounds afresh
                }
            }
        }
        const MotionCorrection c = fromFitUnits(q, start);
        const double scale[4] = {0, c.lineDelayScale, c.naturalFreqScale, c.dampingScale};
        for (int j : pinned)
        {
            result.pinned |= flagOf(j);
            result.pinnedNote += result.pinnedNote.empty() ? "" : "; ";
            result.pinnedNote +=
                j == 0  ? format("time offset %+.2f ms at its search bound (%.2f ms either side of %+.2f ms)",
                                 c.timeOffset * 1e3, settings.maxTimeOffset * 1e3, start.timeOffset * 1e3)
                : j < 4 ? format("%s x%.3f at its search bound (x%.2f to x%.2f)", kParameterName[j], scale[j],
                                 1 - kScaleBound[j] * kUnit[j], 1 + kScaleBound[j] * kUnit[j])
                        : format("%s %+.2f deg/s at its search bound (%.2f deg/s either side of 0)",
                                 kParameterName[j], c.gyroBias[j - 4] * 180 / CV_PI,
                                 kScaleBound[j] * kUnit[j] * 180 / CV_PI);
        }
    }
    result.held = result.unobserved | result.ridge;
    if (!data.empty())
    {
        data.clear();
        fine.residuals(fromFitUnits(q, start), data);
        result.gain = fine.gains()[0];
    }
    result.correction = fromFitUnits(q, start);
    for (double& meanSquare : perFrame)
        result.frameConsistency.push_back(std::sqrt(meanSquare));
    result.correction.consistency = data.empty() ? std::numeric_limits<double>::quiet_NaN()
                                                 : std::sqrt(std::min(cost, startCost) / double(data.size()));
    for (int j = 0; j < kFitParameters; j++)
        result.deviation[j] = std::sqrt(std::max(0.0, covariance(j, j))) * kUnit[j];
    for (int j : tried)
        if (std::find(active.begin(), active.end(), j) == active.end())
            result.deviation[j] = coarseDeviation[j] * kUnit[j];  // how little the frames say about it
    result.evaluations = evaluations + fine.evaluations();
    return result;
}

String refinementFlagNames(int flags)
{
    std::vector<String> names;
    if (flags & REFINE_TIME_OFFSET)
        names.push_back("time offset");
    if (flags & REFINE_LINE_DELAY)
        names.push_back("line delay");
    if (flags & REFINE_PLANT)
        names.push_back("plant");
    if (flags & REFINE_GYRO_BIAS)
        names.push_back("gyro bias");
    String text;
    for (size_t k = 0; k < names.size(); k++)
        text += (k == 0 ? "" : k + 1 == names.size() ? " and " : ", ") + names[k];
    return text;
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
