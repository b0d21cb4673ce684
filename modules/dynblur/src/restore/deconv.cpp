#include "precomp.hpp"

#include "restore/deconv_operator.hpp"
#include "restore/deconv_rl.hpp"
#include "restore/fft_kernel.hpp"
#include "restore/simd_clones.hpp"

#include <opencv2/imgproc.hpp>

#include <climits>
#include <cstring>

namespace cv {
namespace dynblur {

RLParams::RLParams()
    : iterations(20), damping(0), tvWeight(0.002), boundary(RL_BOUNDARY_PAD), accelerate(true), tolerance(0),
      colorIterations(-1), blurPrecision(RL_BLUR_FLOAT32)
{
}

namespace {

using detail::BankBlurOperator;
using detail::BlurOperator;
using detail::UniformBlurOperator;
using detail::kUnobserved;

//! A pixel counts as observed (validMask 255) when at least this fraction of its light reached the frame.
constexpr float kObservedFraction = 0.1f;

//! Automatic damping, in noise standard deviations: updates within the noise are suppressed (3σ is
//! deconvlucy's documented choice).
constexpr double kAutoDampingSigmas = 3.0;

/* `nonNegative`: Richardson–Lucy's data are intensities; its multiplicative update divides by the
   blurred estimate and turns a negative pixel into a pull of either sign, so a dark frame with
   zero-mean noise comes back with spikes up to the projection bound. The linear operators take
   any finite values. */
void checkImage(InputArray image, const char* name, const char* function, bool nonNegative)
{
    if (image.empty())
        CV_Error(Error::StsBadArg, format("%s: '%s' is empty", function, name));
    if (image.depth() != CV_32F)
        CV_Error(Error::StsUnsupportedFormat,
                 format("%s: '%s' has depth %s; only CV_32F (linear intensity) is accepted", function, name,
                        depthToString(image.depth())));
    if (image.channels() < 1 || image.channels() > 4)
        CV_Error(Error::StsBadArg,
                 format("%s: '%s' has %d channels; 1 to 4 are accepted", function, name, image.channels()));
    if (image.dims() > 2)
        CV_Error(Error::StsBadArg, format("%s: '%s' must be a 2-D image", function, name));
    float low = 0, high = 0;
    if (!detail::finiteRange(image.getMat(), low, high))
        CV_Error(Error::StsBadArg, format("%s: '%s' contains NaN or Inf; it must be finite", function, name));
    if (nonNegative && low < 0)
        CV_Error(Error::StsOutOfRange,
                 format("%s: '%s' has a pixel of %g; intensities must be >= 0 (clip the data at 0 first, as a "
                        "sensor does)",
                        function, name, low));
}

//! The parameters with an automatic damping (NaN) replaced by the multiple of the frame's noise.
RLParams resolveDamping(const RLParams& params, const detail::ObservedFrame& observed)
{
    RLParams resolved = params;
    if (std::isnan(resolved.damping))
        resolved.damping = kAutoDampingSigmas * observed.noiseSigma;
    return resolved;
}

//! Validates a kernel and returns it as CV_32F normalised to sum 1.
Mat normalizedKernel(InputArray psf, const char* name, const char* function)
{
    if (psf.empty())
        CV_Error(Error::StsBadArg, format("%s: '%s' is empty", function, name));
    if (psf.channels() != 1 || (psf.depth() != CV_32F && psf.depth() != CV_64F))
        CV_Error(Error::StsUnsupportedFormat,
                 format("%s: '%s' must be one channel, CV_32F or CV_64F", function, name));
    const Size size = psf.size();
    if (size.width % 2 == 0 || size.height % 2 == 0)
        CV_Error(Error::StsBadArg,
                 format("%s: '%s' is %dx%d; both sides must be odd so the kernel has a centre element", function,
                        name, size.width, size.height));
    Mat kernel;
    psf.getMat().convertTo(kernel, CV_32F);
    if (!checkRange(kernel, true))
        CV_Error(Error::StsBadArg, format("%s: '%s' contains NaN or Inf", function, name));
    double minValue = 0;
    minMaxLoc(kernel, &minValue);
    if (minValue < 0)
        CV_Error(Error::StsBadArg,
                 format("%s: '%s' has a negative element (%g); a PSF must be >= 0", function, name, minValue));
    const double total = sum(kernel)[0];
    if (!(total > 0))
        CV_Error(Error::StsBadArg, format("%s: '%s' sums to %g; it must sum to a positive value", function, name,
                                          total));
    kernel *= 1.0 / total;
    return kernel;
}

void checkBank(const PsfBank& bank, Size imageSize, const char* function)
{
    const size_t nodes = bank.nodeRows.size() * bank.nodeCols.size();
    if (nodes == 0)
        CV_Error(Error::StsBadArg, format("%s: 'bank' has no nodes (nodeRows and nodeCols must be non-empty)",
                                          function));
    if (bank.kernels.size() != nodes || bank.shifts.size() != nodes)
        CV_Error(Error::StsBadArg,
                 format("%s: 'bank' has %zu kernels and %zu shifts for %zu nodes (nodeRows x nodeCols)", function,
                        bank.kernels.size(), bank.shifts.size(), nodes));
    if (bank.imageSize != imageSize)
        CV_Error(Error::StsBadSize,
                 format("%s: 'bank' is for %dx%d images but the image is %dx%d", function, bank.imageSize.width,
                        bank.imageSize.height, imageSize.width, imageSize.height));
    for (size_t n = 0; n < nodes; n++)
    {
        const Mat& k = bank.kernels[n];
        if (k.empty() || k.type() != CV_32FC1 || k.rows % 2 == 0 || k.cols % 2 == 0)
            CV_Error(Error::StsBadArg,
                     format("%s: 'bank.kernels[%zu]' must be a non-empty, odd-sized, one-channel CV_32F kernel",
                            function, n));
    }
    bank.validate();  // sums, signs, node order: the bank's own contract
}

//! The frame planes moved into a latent domain: the frame at `origin`, borders replicated.
std::vector<Mat> embedPlanes(const std::vector<Mat>& frame, const BlurOperator& op)
{
    const Point o = op.origin();
    const Size latent = op.latentSize(), size = op.frameSize();
    std::vector<Mat> planes(frame.size());
    for (size_t c = 0; c < frame.size(); c++)
        copyMakeBorder(frame[c], planes[c], o.y, latent.height - size.height - o.y, o.x,
                       latent.width - size.width - o.x, BORDER_REPLICATE);
    return planes;
}

/* out = the planes' `roi` (CV_32F, one size; an empty roi: all of them) interleaved, rows in
   parallel. With a luminance change, the planes take it as they are read; with `clampToUnit` the
   output is clamped to [0, 1]. */
void writeOutput(const std::vector<Mat>& planes, OutputArray out, bool clampToUnit = false,
                 const detail::LuminanceChange& change = detail::LuminanceChange(), Rect roi = Rect())
{
    if (roi.empty())
        roi = Rect(Point(), planes[0].size());
    const int channels = int(planes.size());
    out.create(roi.size(), CV_32FC(channels));
    Mat image = out.getMat();
    parallel_for_(Range(0, image.rows), [&](const Range& rows) {
        const int n = roi.width;
        std::vector<const float*> sources(planes.size());
        // With a change: the planes' mean, then each plane's changed row (the sources).
        std::vector<float> changed(change.restored.empty() ? 0 : size_t(n) * (planes.size() + 1));
        std::vector<float*> changedRows(planes.size());
        if (!changed.empty())
            for (size_t c = 0; c < planes.size(); c++)
                sources[c] = changedRows[c] = changed.data() + (c + 1) * size_t(n);
        for (int y = rows.start; y < rows.end; y++)
        {
            if (changed.empty())
                for (size_t c = 0; c < planes.size(); c++)
                    sources[c] = planes[c].ptr<float>(y + roi.y) + roi.x;
            else
                change.applyRow(planes, y + roi.y, roi.x, n, changed.data(), changedRows.data());
            detail::interleaveRow(sources.data(), channels, n, image.ptr<float>(y));
            if (clampToUnit)
                detail::clampRowToUnit(image.ptr<float>(y), n * channels);
        }
    });
}

/* out = max(moved / normaliser, 0) where the normaliser exceeds kUnobserved, `fill` elsewhere: the
   start's row. The quotient is taken everywhere (its divisor kept ≥ 1e-3) and then selected, so
   the loop vectorises. */
DYNBLUR_SIMD_CLONES
void normalizedRow(const float* __restrict moved, const float* __restrict normalizer, float fill, int n,
                   float* __restrict out)
{
    for (int x = 0; x < n; x++)
    {
        const float quotient = std::max(moved[x] / std::max(normalizer[x], kObservedFraction * 1e-2f), 0.f);
        out[x] = normalizer[x] > kUnobserved ? quotient : fill;
    }
}

}  // namespace

void checkRLParams(const RLParams& params, const char* function)
{
    if (params.iterations < 1 || params.iterations > 100000)
        CV_Error(Error::StsOutOfRange,
                 format("%s: params.iterations = %d must be in [1, 100000]", function, params.iterations));
    if (!std::isnan(params.damping) && !(params.damping >= 0 && std::isfinite(params.damping)))
        CV_Error(Error::StsOutOfRange,
                 format("%s: params.damping = %g must be finite and >= 0 (0: off), or NaN (automatic)", function,
                        params.damping));
    if (!(params.tvWeight >= 0) || !std::isfinite(params.tvWeight))
        CV_Error(Error::StsOutOfRange,
                 format("%s: params.tvWeight = %g must be finite and >= 0 (0: off)", function, params.tvWeight));
    if (!(params.tolerance >= 0) || !std::isfinite(params.tolerance))
        CV_Error(Error::StsOutOfRange,
                 format("%s: params.tolerance = %g must be finite and >= 0 (0: never stop early)", function,
                        params.tolerance));
    if (params.colorIterations < -1)
        CV_Error(Error::StsOutOfRange,
                 format("%s: params.colorIterations = %d must be >= 0, or -1 (every iteration in colour)", function,
                        params.colorIterations));
    if (params.boundary != RL_BOUNDARY_ZERO && params.boundary != RL_BOUNDARY_PAD)
        CV_Error(Error::StsOutOfRange,
                 format("%s: params.boundary = %d must be RL_BOUNDARY_ZERO (0) or RL_BOUNDARY_PAD (1)", function,
                        params.boundary));
    if (params.blurPrecision != RL_BLUR_FLOAT32 && params.blurPrecision != RL_BLUR_BFLOAT16)
        CV_Error(Error::StsOutOfRange,
                 format("%s: params.blurPrecision = %d must be RL_BLUR_FLOAT32 (0) or RL_BLUR_BFLOAT16 (1)", function,
                        params.blurPrecision));
}

void richardsonLucy(InputArray blurred, InputArray psf, OutputArray latent, const RLParams& params, InputArray initial)
{
    const char* fn = "richardsonLucy";
    checkImage(blurred, "blurred", fn, true);
    checkRLParams(params, fn);
    const Mat kernel = normalizedKernel(psf, "psf", fn);
    if (!initial.empty())
    {
        checkImage(initial, "initial", fn, true);
        if (initial.size() != blurred.size() || initial.type() != blurred.type())
            CV_Error(Error::StsBadSize, format("%s: 'initial' must have the size and type of 'blurred'", fn));
    }

    /* RL is homogeneous, but FFTW's float transforms of a frame near 1e-30 (or 1e30) push its small
       (large) coefficients out of the normal range. The frame is run at the power of two that brings
       its mean near 1, which changes no rounding, and the result is scaled back. */
    const Scalar channelMeans = mean(blurred);
    double level = 0;
    for (int c = 0; c < blurred.channels(); c++)
        level += channelMeans[c] / blurred.channels();
    // Within 2^±100, so that the factor and its inverse are normal floats too.
    const double unit = level > 0 ? std::ldexp(1.0, -std::min(std::max(std::ilogb(level), -100), 100)) : 1.0;
    const Mat observed = unit == 1.0 ? blurred.getMat() : Mat(blurred.getMat() * unit);
    detail::RLWorkspace workspace;
    const detail::ObservedFrame observedFrame =
        detail::observeFrame(observed, workspace.observed, std::isnan(params.damping));
    std::vector<Mat> start;
    if (initial.empty())
        start = observedFrame.planes;  // embedPlanes copies them
    else
        split(initial.getMat() * unit, start);
    RLParams scaled = params;
    if (!std::isnan(params.damping))
        scaled.damping *= unit;  // intensity units
    scaled = resolveDamping(scaled, observedFrame);  // an automatic damping is taken on the scaled frame

    const bool pad = params.boundary == RL_BOUNDARY_PAD;
    UniformBlurOperator op(blurred.size(), kernel, pad);
    std::vector<Mat> estimate = embedPlanes(start, op);
    for (Mat& e : estimate)
        e = max(e, 0.f);
    Mat normalizer;  // ZERO: scikit-image's unnormalised update (Aᵀ1 taken as 1)
    if (pad)
        op.adjoint(Mat::ones(blurred.size(), CV_32F), normalizer);
    detail::LuminanceChange change;
    detail::iterateRichardsonLucy(op, observed, observedFrame, normalizer, scaled, estimate, workspace, change);

    writeOutput(estimate, latent, false, change, Rect(op.origin(), op.frameSize()));
    if (unit != 1.0)
    {
        Mat out = latent.getMat();
        out *= 1.0 / unit;
    }
}

namespace detail {

/* Rows per strip in fillFromNearest: a band of invalid rows reaches its valid pixels through tens
   of rows, so narrower strips would each transform the band's reach again. */
constexpr int kFillStripRows = 128;

namespace {

/* fillFromNearest where every row is wholly valid or wholly invalid (`rowReach` -1 or INT_MAX), as
   a row-wise bank leaves a frame (the rows beyond the motion at one edge): an invalid row's nearest
   valid pixels are straight up or down in the nearest valid row, which the distance transform finds
   too (its 5×5 mask measures every other path as longer), so that row is copied, a copy instead of
   a transform over every such row of a row-wise frame. Returns false, doing nothing,
   for any other mask, or when a row lies as far from a valid row above as below (the transform's
   choice between them is its own) or has none. */
bool fillWholeRows(Mat& image, const std::vector<int>& rowReach)
{
    const int height = image.rows;
    std::vector<int> source(size_t(height), -1);
    for (int y = 0, above = -1; y < height; y++)
    {
        if (rowReach[size_t(y)] == -1)
            above = y;
        else if (rowReach[size_t(y)] != INT_MAX)
            return false;
        else
            source[size_t(y)] = above;
    }
    for (int y = height - 1, below = -1; y >= 0; y--)
    {
        if (rowReach[size_t(y)] == -1)
        {
            below = y;
            continue;
        }
        const int above = source[size_t(y)];
        if (above < 0 && below < 0)
            return false;
        if (above >= 0 && below >= 0 && y - above == below - y)
            return false;
        source[size_t(y)] = above < 0 || (below >= 0 && below - y < y - above) ? below : above;
    }
    for (int y = 0; y < height; y++)
        if (rowReach[size_t(y)] == INT_MAX)
            image.row(source[size_t(y)]).copyTo(image.row(y));
    return true;
}

}  // namespace

/* The distance transform runs on boxes around the invalid pixels, not on the box of their rows:
   every run of invalid pixels along a row has a valid pixel within a known reach (along its row
   or, when the row has none, straight up or down to the nearest row that has one and then along
   it), so the nearest valid pixel lies in the run's box grown by that reach. The invalid pixels
   are the frame's edges across the motion: a band of rows, and slivers down the sides whose common
   box was most of the frame. Runs are grouped by strips of rows; a strip's runs whose grown boxes
   share columns share one transform, and the groups run in parallel. */
void fillFromNearest(Mat& image, const Mat& valid)
{
    struct Run
    {
        int y, begin, end, reach;
    };
    const int height = valid.rows, width = valid.cols;
    std::vector<std::vector<Run>> rowRuns(static_cast<size_t>(height));
    std::vector<int> rowReach(size_t(height), -1);  // -1: every pixel valid; INT_MAX: none
    parallel_for_(Range(0, height), [&](const Range& rows) {
        for (int y = rows.start; y < rows.end; y++)
        {
            const uchar *v = valid.ptr<uchar>(y), *end = v + width;
            const uchar* x = static_cast<const uchar*>(std::memchr(v, 0, size_t(width)));
            if (!x)
                continue;
            std::vector<Run>& runs = rowRuns[size_t(y)];
            while (x)
            {
                const uchar* stop = std::find_if(x, end, [](uchar m) { return m != 0; });
                runs.push_back({y, int(x - v), int(stop - v), 0});
                x = stop < end ? static_cast<const uchar*>(std::memchr(stop, 0, size_t(end - stop))) : nullptr;
            }
            int& reach = rowReach[size_t(y)];
            if (runs.size() == 1 && runs[0].begin == 0 && runs[0].end == width)
            {
                reach = INT_MAX;
                continue;
            }
            for (Run& r : runs)
            {
                const int length = r.end - r.begin;
                r.reach = r.begin > 0 && r.end < width ? (length + 1) / 2 : length;  // one valid end or two
                reach = std::max(reach, r.reach);
            }
        }
    });
    if (fillWholeRows(image, rowReach))
        return;
    // Rows with no valid pixel reach down or up to the nearest row with one, then along it.
    std::vector<int> fromAbove(size_t(height), INT_MAX);
    for (int y = 0, last = -1; y < height; y++)
        if (rowReach[size_t(y)] != INT_MAX)
            last = y;
        else if (last >= 0)
            fromAbove[size_t(y)] = y - last + std::max(rowReach[size_t(last)], 0);
    bool anyValid = false;
    for (int y = height - 1, last = -1; y >= 0; y--)
    {
        if (rowReach[size_t(y)] != INT_MAX)
        {
            last = y;
            anyValid = true;
        }
        else
        {
            const int below = last >= 0 ? last - y + std::max(rowReach[size_t(last)], 0) : INT_MAX;
            rowReach[size_t(y)] = std::min(fromAbove[size_t(y)], below);
            rowRuns[size_t(y)][0].reach = rowReach[size_t(y)];
        }
    }
    if (!anyValid)
        return;

    struct Group
    {
        Rect box;
        std::vector<Run> runs;
    };
    std::vector<Group> groups;
    const Rect imageRect(Point(), valid.size());
    for (int strip = 0; strip < height; strip += kFillStripRows)
    {
        std::vector<Run> runs;
        for (int y = strip; y < std::min(height, strip + kFillStripRows); y++)
            runs.insert(runs.end(), rowRuns[size_t(y)].begin(), rowRuns[size_t(y)].end());
        const auto grown = [&](const Run& r) {
            return Rect(Point(r.begin - r.reach, r.y - r.reach), Point(r.end + r.reach, r.y + r.reach + 1)) & imageRect;
        };
        std::sort(runs.begin(), runs.end(), [&](const Run& a, const Run& b) { return grown(a).x < grown(b).x; });
        for (size_t i = 0; i < runs.size(); i++)
        {
            const Rect box = grown(runs[i]);
            if (i == 0 || box.x >= groups.back().box.br().x)
                groups.push_back({box, {}});
            groups.back().box |= box;
            groups.back().runs.push_back(runs[i]);
        }
    }
    const size_t channels = size_t(image.channels());
    parallel_for_(Range(0, int(groups.size())), [&](const Range& range) {
        for (int g = range.start; g < range.end; g++)
        {
            const Rect roi = groups[size_t(g)].box;
            const Mat validRoi = valid(roi);
            Mat distance, labels;
            distanceTransform(validRoi == 0, distance, labels, DIST_L2, DIST_MASK_5, DIST_LABEL_PIXEL);
            // Each valid pixel carries its own label: map labels back to their positions.
            std::vector<Point> where(size_t(roi.area()) + 1, Point(-1, -1));
            for (int y = 0; y < roi.height; y++)
            {
                const uchar* v = validRoi.ptr<uchar>(y);
                const int* label = labels.ptr<int>(y);
                for (int x = 0; x < roi.width; x++)
                    if (v[x])
                        where[size_t(label[x])] = Point(x + roi.x, y + roi.y);
            }
            for (const Run& run : groups[size_t(g)].runs)
            {
                const int* label = labels.ptr<int>(run.y - roi.y) - roi.x;
                float* out = image.ptr<float>(run.y);
                for (int x = run.begin; x < run.end; x++)
                {
                    const Point source = where[size_t(label[x])];
                    if (source.x < 0)
                        continue;  // cannot happen: each run's grown box holds a valid pixel
                    const float* from = image.ptr<float>(source.y) + size_t(source.x) * channels;
                    std::copy(from, from + channels, out + size_t(x) * channels);
                }
            }
        }
    });
}

void restoreVariant(const Mat& observed, const PsfBank& bank, const RLParams& params, RLWorkspace& ws,
                    OutputArray latent, OutputArray validMask, bool clampToUnit)
{
    const bool pad = params.boundary == RL_BOUNDARY_PAD;
    std::unique_ptr<BlurOperator> blur = createBankOperator(bank, pad, params.blurPrecision == RL_BLUR_BFLOAT16);
    BlurOperator& op = *blur;
    const Size frameSize = observed.size(), latentSize = op.latentSize();
    // The frame of ones lives in the (packed) ratio plane, which the iterations fill later: no memory of its own.
    op.adjointOfOnes(ws.normalizer, op.gathersPackedRows() ? ws.packedRatio : ws.ratio);

    /* Start: the frame moved back by each node's displacement (the normalised adjoint of the
       displacement-only blur), so content begins where the view at θ_ref has it and RL only has to
       sharpen; latent pixels that displacement does not reach start at the channel's mean. */
    const ObservedFrame observedFrame = observeFrame(observed, ws.observed, std::isnan(params.damping));
    const std::vector<Mat>& observedPlanes = observedFrame.planes;
    const Scalar& channelMean = observedFrame.channelMean;
    std::vector<Mat>& estimate = ws.estimate;
    estimate.resize(observedPlanes.size());
    for (Mat& e : estimate)
        e.create(latentSize, CV_32F);
    displacementAdjoint(bank, displacementShifts(bank), latentSize, op.origin(), observedPlanes,
                        [&](int y, const float* weight, const float* const* moved) {
                            for (size_t c = 0; c < estimate.size(); c++)
                                normalizedRow(moved[c], weight, float(std::max(channelMean[int(c)], 0.0)),
                                              latentSize.width, estimate[c].ptr<float>(y));
                        });

    LuminanceChange change;
    iterateRichardsonLucy(op, observed, observedFrame, ws.normalizer, resolveDamping(params, observedFrame), estimate,
                          ws, change);

    if (!ws.persistent)
    {
        ws.observed.clear();
        ws.other.clear();
        ws.step.release();
        ws.ratio.release();
    }
    const Rect frame(op.origin(), frameSize);
    compare(ws.normalizer(frame), kObservedFraction, ws.valid, CMP_GT);
    writeOutput(estimate, latent, clampToUnit, change, frame);
    // The fill's distance transform allocates: the planes it no longer needs go first.
    change.restored.release();
    if (!ws.persistent)
        ws.estimate.clear();
    Mat output = latent.getMat();
    fillFromNearest(output, ws.valid);
    if (validMask.needed())
        ws.valid.copyTo(validMask);
}

}  // namespace detail

void richardsonLucyVariant(InputArray blurred, const PsfBank& bank, OutputArray latent, const RLParams& params,
                           OutputArray validMask)
{
    const char* fn = "richardsonLucyVariant";
    checkImage(blurred, "blurred", fn, true);
    checkRLParams(params, fn);
    checkBank(bank, blurred.size(), fn);
    detail::RLWorkspace workspace;
    detail::restoreVariant(blurred.getMat(), bank, params, workspace, latent, validMask);
}

void applyPsfBank(InputArray latent, const PsfBank& bank, OutputArray blurred)
{
    const char* fn = "applyPsfBank";
    checkImage(latent, "latent", fn, false);
    checkBank(bank, latent.size(), fn);
    std::vector<Mat> planes;
    split(latent.getMat(), planes);
    std::unique_ptr<BlurOperator> op = detail::createBankOperator(bank, false);
    std::vector<Mat> out(planes.size());
    for (size_t c = 0; c < planes.size(); c++)
        op->forward(planes[c], out[c]);
    writeOutput(out, blurred);
}

void wienerDeconvolve(InputArray blurred, const PsfBank& bank, OutputArray latent, double noiseToSignal)
{
    const char* fn = "wienerDeconvolve";
    checkImage(blurred, "blurred", fn, false);
    checkBank(bank, blurred.size(), fn);
    if (!(noiseToSignal > 0) || !std::isfinite(noiseToSignal))
        CV_Error(Error::StsOutOfRange,
                 format("%s: noiseToSignal = %g must be finite and > 0", fn, noiseToSignal));

    const Size size = blurred.size();
    std::vector<Mat> planes;
    split(blurred.getMat(), planes);
    std::vector<Mat> numerator(planes.size());
    for (Mat& n : numerator)
        n = Mat::zeros(size, CV_32F);
    Mat denominator = Mat::zeros(size, CV_32F);

    // Node `node`'s share of each coordinate along one axis: the blending weights of the forward
    // operator (detail::nodeRowWeights, nodeColumnWeights).
    auto nodeWeights = [](const std::vector<detail::AxisWeight>& axis, int node) {
        std::vector<float> w(axis.size(), 0.f);
        for (size_t t = 0; t < axis.size(); t++)
            for (int k = 0; k < 2; k++)
                if (axis[t].node[k] == node)
                    w[t] += axis[t].weight[k];
        return w;
    };
    auto support = [](const std::vector<float>& w) {
        int begin = int(w.size()), end = 0;
        for (int t = 0; t < int(w.size()); t++)
            if (w[size_t(t)] > 0)
            {
                begin = std::min(begin, t);
                end = t + 1;
            }
        return Range(std::min(begin, end), end);
    };

    const int nx = int(bank.nodeCols.size()), ny = int(bank.nodeRows.size());
    const auto rowAxis = detail::nodeRowWeights(bank, size.height);
    const auto colAxis = detail::nodeColumnWeights(bank, size.width);
    for (int j = 0; j < ny; j++)
    {
        const std::vector<float> wy = nodeWeights(rowAxis, j);
        const Range rows = support(wy);
        for (int i = 0; i < nx; i++)
        {
            const std::vector<float> wx = nodeWeights(colAxis, i);
            const Range cols = support(wx);
            if (rows.empty() || cols.empty())
                continue;
            const size_t n = size_t(j * nx + i);
            Mat kernel;
            bank.kernels[n].convertTo(kernel, CV_32F);
            const Point shift = bank.shifts[n];

            /* The node's region plus a margin for the kernel's reach and the inverse filter's
               tails, mirrored where it leaves the frame, then faded to its mean over an outer
               band so the FFT's periodic wrap meets no step (no ringing from the wrap). */
            const int marginX = kernel.cols + 16, marginY = kernel.rows + 16;
            const Rect region(cols.start - marginX, rows.start - marginY, cols.size() + 2 * marginX,
                              rows.size() + 2 * marginY);
            const Size grid(getOptimalDFTSize(region.width + 2 * marginX), getOptimalDFTSize(region.height + 2 * marginY));
            const Rect inside = region & Rect(Point(), size);
            const Point gridOrigin = region.tl() - Point(marginX, marginY);  // frame coords of grid (0,0)
            detail::FftKernel fft(grid, kernel);
            Mat taper(grid, CV_32F);
            for (int y = 0; y < grid.height; y++)
                for (int x = 0; x < grid.width; x++)
                {
                    const int dx = std::min(x, grid.width - 1 - x), dy = std::min(y, grid.height - 1 - y);
                    const float fx = std::min(1.f, float(dx) / float(marginX));
                    const float fy = std::min(1.f, float(dy) / float(marginY));
                    taper.at<float>(y, x) = (0.5f - 0.5f * std::cos(float(CV_PI) * fx)) *
                                            (0.5f - 0.5f * std::cos(float(CV_PI) * fy));
                }

            for (size_t c = 0; c < planes.size(); c++)
            {
                Mat padded;
                const Point at = inside.tl() - gridOrigin;
                copyMakeBorder(planes[c](inside), padded, at.y, grid.height - at.y - inside.height, at.x,
                               grid.width - at.x - inside.width, BORDER_REFLECT_101);
                const float level = float(mean(planes[c](inside))[0]);
                padded = (padded - level).mul(taper) + level;
                Mat restored;
                fft.wiener(padded, restored, float(noiseToSignal));
                // restored(p) is the latent at p − shift (grid p ↔ frame p + gridOrigin).
                for (int y = rows.start; y < rows.end; y++)
                {
                    const int qy = y - shift.y;
                    if (qy < 0 || qy >= size.height)
                        continue;
                    const float* src = restored.ptr<float>(y - gridOrigin.y);
                    float* num = numerator[c].ptr<float>(qy);
                    float* den = denominator.ptr<float>(qy);
                    for (int x = cols.start; x < cols.end; x++)
                    {
                        const int qx = x - shift.x;
                        if (qx < 0 || qx >= size.width)
                            continue;
                        const float w = wy[size_t(y)] * wx[size_t(x)];
                        num[qx] += w * src[x - gridOrigin.x];
                        if (c == 0)
                            den[qx] += w;
                    }
                }
            }
        }
    }
    Mat valid = denominator > 1e-3f;
    std::vector<Mat> out(planes.size());
    for (size_t c = 0; c < planes.size(); c++)
        out[c] = numerator[c] / max(denominator, 1e-3f);
    writeOutput(out, latent);
    Mat output = latent.getMat();
    detail::fillFromNearest(output, valid);
}

}  // namespace dynblur
}  // namespace cv
