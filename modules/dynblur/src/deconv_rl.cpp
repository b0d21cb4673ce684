#include "deconv_rl.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cmath>

namespace cv {
namespace dynblur {
namespace detail {

namespace {

// scikit-image adds this to the reblurred image before dividing; kept so ZERO-boundary results match.
constexpr float kRatioEpsilon = 1e-12f;

/* ratio = b / (A x), damped as MATLAB's deconvlucy does (White 1994): where the Poisson deviance
   between b and A x is within the damping threshold, the ratio is pulled to 1 (no update). */
void relativeBlur(const Mat& blurred, const Mat& reblurred, double damping, Mat& ratio)
{
    ratio.create(blurred.size(), CV_32FC1);
    const float invThreshold = damping > 0 ? float(2.0 / (damping * damping)) : 0.f;
    parallel_for_(Range(0, blurred.rows), [&](const Range& rows) {
        for (int y = rows.start; y < rows.end; y++)
        {
            const float* b = blurred.ptr<float>(y);
            const float* ab = reblurred.ptr<float>(y);
            float* r = ratio.ptr<float>(y);
            for (int x = 0; x < blurred.cols; x++)
                r[x] = ab[x] > 0.f ? b[x] / (ab[x] + kRatioEpsilon) : 0.f;
            if (invThreshold == 0.f)
                continue;
            for (int x = 0; x < blurred.cols; x++)
            {
                if (!(b[x] > 0.f && ab[x] > 0.f))
                    continue;
                float g = (b[x] * std::log(r[x]) + ab[x] - b[x]) * invThreshold;
                g = std::min(std::max(g, 0.f), 1.f);
                const float g2 = g * g, g4 = g2 * g2, g8 = g4 * g4;
                const float G = g8 * g * (10.f - 9.f * g);  // g^9 (10 − 9 g): 0 within the noise, 1 beyond
                r[x] = 1.f + G * (r[x] - 1.f);
            }
        }
    });
}

/* div(∇u/|∇u|) with forward differences for the gradient and backward ones for the divergence
   (the pair that makes −div the adjoint of ∇), zero flux across the array's edges. */
void tvCurvature(const Mat& u, float epsilon, Mat& nx, Mat& ny, Mat& curvature)
{
    nx.create(u.size(), CV_32FC1);
    ny.create(u.size(), CV_32FC1);
    curvature.create(u.size(), CV_32FC1);
    const int rows = u.rows, cols = u.cols;
    const float eps2 = epsilon * epsilon;
    parallel_for_(Range(0, rows), [&](const Range& range) {
        for (int y = range.start; y < range.end; y++)
        {
            const float* p = u.ptr<float>(y);
            const float* below = u.ptr<float>(std::min(y + 1, rows - 1));
            float* ox = nx.ptr<float>(y);
            float* oy = ny.ptr<float>(y);
            for (int x = 0; x < cols; x++)
            {
                const float gx = x + 1 < cols ? p[x + 1] - p[x] : 0.f;
                const float gy = y + 1 < rows ? below[x] - p[x] : 0.f;
                const float inv = 1.f / std::sqrt(gx * gx + gy * gy + eps2);
                ox[x] = gx * inv;
                oy[x] = gy * inv;
            }
        }
    });
    parallel_for_(Range(0, rows), [&](const Range& range) {
        for (int y = range.start; y < range.end; y++)
        {
            const float* ox = nx.ptr<float>(y);
            const float* oy = ny.ptr<float>(y);
            const float* oyAbove = y > 0 ? ny.ptr<float>(y - 1) : nullptr;
            float* c = curvature.ptr<float>(y);
            for (int x = 0; x < cols; x++)
                c[x] = ox[x] - (x > 0 ? ox[x - 1] : 0.f) + oy[x] - (oyAbove ? oyAbove[x] : 0.f);
        }
    });
}

}  // namespace

int iterateRichardsonLucy(BlurOperator& op, const std::vector<Mat>& blurred, const Mat& normalizer,
                          const RLParams& params, std::vector<Mat>& estimate)
{
    const size_t channels = blurred.size();
    CV_Assert(estimate.size() == channels);
    const Size latentSize = op.latentSize();
    const float tvWeight = float(params.tvWeight);

    // TV's |∇u| is regularised at a small fraction of the image level, so it stays scale free.
    double level = 0;
    for (const Mat& b : blurred)
        level += mean(b)[0];
    const float tvEpsilon = float(std::max(1e-3 * level / double(std::max<size_t>(channels, 1)), 1e-12));

    std::vector<Mat> previous(channels), predicted(channels), step(channels), stepBefore(channels);
    Mat reblurred, ratio, correction, nx, ny, curvature, next;
    double alpha = 0;
    int iteration = 0;
    for (; iteration < params.iterations; iteration++)
    {
        // Biggs–Andrews: extrapolate along the last step, by how well the last two steps agree.
        if (params.accelerate && iteration >= 2)
        {
            double num = 0, den = 0;
            for (size_t c = 0; c < channels; c++)
            {
                num += step[c].dot(stepBefore[c]);
                den += stepBefore[c].dot(stepBefore[c]);
            }
            alpha = den > 0 ? std::min(std::max(num / den, 0.0), 1.0) : 0.0;
        }
        double changeSq = 0, sizeSq = 0;
        for (size_t c = 0; c < channels; c++)
        {
            const Mat& x = estimate[c];
            Mat& y = predicted[c];
            if (alpha > 0)
            {
                addWeighted(x, 1 + alpha, previous[c], -alpha, 0, y);
                y = max(y, 0.f);  // RL needs a non-negative estimate
            }
            else
            {
                x.copyTo(y);
            }

            op.forward(y, reblurred);
            relativeBlur(blurred[c], reblurred, params.damping, ratio);
            op.adjoint(ratio, correction);
            if (tvWeight > 0)
                tvCurvature(y, tvEpsilon, nx, ny, curvature);

            next.create(latentSize, CV_32FC1);
            if (params.accelerate)
            {
                std::swap(stepBefore[c], step[c]);
                step[c].create(latentSize, CV_32FC1);
            }
            Mat& rlStep = step[c];
            parallel_for_(Range(0, latentSize.height), [&](const Range& rows) {
                for (int r = rows.start; r < rows.end; r++)
                {
                    const float* yp = y.ptr<float>(r);
                    const float* cp = correction.ptr<float>(r);
                    const float* np = normalizer.empty() ? nullptr : normalizer.ptr<float>(r);
                    const float* kp = tvWeight > 0 ? curvature.ptr<float>(r) : nullptr;
                    float* out = next.ptr<float>(r);
                    float* sp = params.accelerate ? rlStep.ptr<float>(r) : nullptr;
                    for (int col = 0; col < latentSize.width; col++)
                    {
                        const float norm = np ? np[col] : 1.f;
                        if (norm <= kUnobserved)
                        {
                            out[col] = yp[col];
                            if (sp)
                                sp[col] = 0.f;
                            continue;
                        }
                        float den = kp ? norm - tvWeight * kp[col] : norm;
                        den = std::max(den, 0.1f * norm);  // keeps a large λ from flipping the sign
                        out[col] = std::max(yp[col] * cp[col] / den, 0.f);
                        /* The extrapolation follows the data term's step only: TV's curvature
                           term flips sign from one iteration to the next on noise, which would
                           make successive steps look uncorrelated and switch acceleration off. */
                        if (sp)
                            sp[col] = yp[col] * (cp[col] / norm - 1.f);
                    }
                }
            });

            if (params.tolerance > 0)
            {
                const double change = norm(next, x, NORM_L2);
                changeSq += change * change;
                const double size = norm(x, NORM_L2);
                sizeSq += size * size;
            }
            std::swap(previous[c], estimate[c]);
            std::swap(estimate[c], next);
        }
        if (params.tolerance > 0 && sizeSq > 0 && std::sqrt(changeSq / sizeSq) < params.tolerance)
        {
            iteration++;
            break;
        }
    }
    return iteration;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
