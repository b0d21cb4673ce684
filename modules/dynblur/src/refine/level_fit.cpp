// SPDX-License-Identifier: Apache-2.0
// Levenberg–Marquardt over a MotionCorrection's fitted parameters at one resolution.
#include "precomp.hpp"

#include "refine/level_fit.hpp"

namespace cv {
namespace dynblur {
namespace detail {

FitBox::FitBox(const MotionCorrection& told, double maxTimeOffset) : prior(toFitUnits(told)), start(told)
{
    for (int j = 0; j < kFitParameters; j++)
    {
        const FitParameter& p = kFitTable[j];
        if (p.quantity == FIT_CLOCK_OFFSET)
            lower[j] = prior[j] - maxTimeOffset / p.unit, upper[j] = prior[j] + maxTimeOffset / p.unit;
        else
            lower[j] = -p.searchHalfWidth, upper[j] = p.searchHalfWidth;
    }
}

LevelFit::LevelFit(FitResiduals& residuals, const std::vector<int>& active, const FitBox& box)
    : r_(residuals), active_(active), box_(box)
{
}

double LevelFit::cost(const FitVector& q, std::vector<float>& data)
{
    data.clear();
    r_.residuals(fromFitUnits(q, box_.start), data);
    double total = squaredNorm(data, data.size());
    for (int j : active_)
    {
        const double p = (q[j] - box_.prior[j]) / kFitTable[j].priorDeviation;
        total += p * p;
    }
    return total;
}

FitVector LevelFit::run(FitVector q, int maxIterations, FitMatrix& covariance, double* finalCost,
                       bool wantCovariance)
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
                candidate[j] = std::min(box_.upper[j], std::max(box_.lower[j], q[j] + delta.at<double>(a)));
                converged = converged && std::abs(candidate[j] - q[j]) < kFitTable[j].tolerance;
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

Mat LevelFit::information(const FitVector& q)
{
    std::vector<float> at;
    cost(q, at);
    const int n = int(active_.size());
    Mat jtj(n, n, CV_64F), jtr(n, 1, CV_64F);
    jacobianProducts(q, at, jtj, jtr, false);
    const double variance = squaredNorm(at, at.size()) / std::max(1.0, double(at.size()) - n);
    return jtj / std::max(variance, 1e-12);
}

void LevelFit::jacobianProducts(const FitVector& q, const std::vector<float>& at, Mat& jtj, Mat& jtr,
                                bool withPrior)
{
    const int n = int(active_.size());
    std::vector<std::vector<float>> columns(static_cast<size_t>(n));
    std::vector<float> shifted;
    for (int a = 0; a < n; a++)
    {
        const int j = active_[size_t(a)];
        FitVector moved = q;
        // Step inward at an upper bound, so the difference is taken inside the box.
        const double h = q[j] + kFitTable[j].step <= box_.upper[j] ? kFitTable[j].step : -kFitTable[j].step;
        moved[j] += h;
        shifted.clear();
        r_.residuals(fromFitUnits(moved, box_.start), shifted);
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
        jtr.at<double>(a) = g + (withPrior ? (q[j] - box_.prior[j]) / (kFitTable[j].priorDeviation * kFitTable[j].priorDeviation) : 0);
        for (int b = a; b < n; b++)
        {
            double s = 0;
            for (size_t k = 0; k < at.size(); k++)
                s += double(columns[size_t(a)][k]) * columns[size_t(b)][k];
            if (a == b && withPrior)
                s += 1.0 / (kFitTable[j].priorDeviation * kFitTable[j].priorDeviation);
            jtj.at<double>(a, b) = jtj.at<double>(b, a) = s;
        }
    }
}

double squaredNorm(const std::vector<float>& r, size_t count)
{
    double sum = 0;
    for (size_t k = 0; k < count; k++)
        sum += double(r[k]) * r[k];
    return sum;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
