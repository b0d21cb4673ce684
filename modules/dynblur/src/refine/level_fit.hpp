// SPDX-License-Identifier: Apache-2.0
// Private: Levenberg–Marquardt over a MotionCorrection's fitted parameters at one resolution.
#ifndef OPENCV_DYNBLUR_REFINE_LEVEL_FIT_HPP
#define OPENCV_DYNBLUR_REFINE_LEVEL_FIT_HPP

#include "refine/fit_parameters.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

//! What a fit minimises: the residuals of a correction (the fit sums their squares).
class FitResiduals
{
public:
    virtual ~FitResiduals() {}
    //! Appends the residuals of `c` to `out`, always as many and in the same order.
    virtual void residuals(const MotionCorrection& c, std::vector<float>& out) = 0;
};

//! Where a fit starts and may go, in fit units: the start (the prior's centre) and the search box.
struct FitBox
{
    /** @param told the correction the fit starts from (a calibration, or none).
    @param maxTimeOffset the clock offset's search half-width around it, seconds. */
    FitBox(const MotionCorrection& told, double maxTimeOffset);

    FitVector prior;          //!< `told` in fit units: the prior's centre
    FitVector lower, upper;   //!< the search bounds of every parameter
    MotionCorrection start;   //!< `told`, whose unfitted fields every candidate keeps
};

/** @brief Levenberg–Marquardt @cite Marquardt1963Algorithm over the `active` parameters of a
correction (the residuals of one level of frames, or of feature tracks), with a weak prior toward the box's start (FitParameter::priorDeviation), steps clamped to
its bounds. */
class LevelFit
{
public:
    //! `residuals` and `box` must outlive the fit.
    LevelFit(FitResiduals& residuals, const std::vector<int>& active, const FitBox& box);

    //! Data plus prior cost at q; `data` receives the residual vector.
    double cost(const FitVector& q, std::vector<float>& data);

    /** Fits from q, at most `maxIterations` steps; `finalCost`, when given, receives the cost at the
        result; `covariance` is left zero unless `wantCovariance` (it costs a Jacobian at the result). */
    FitVector run(FitVector q, int maxIterations, FitMatrix& covariance, double* finalCost = nullptr,
                  bool wantCovariance = true);

    /** The data's information about the active parameters at q (JᵀJ of the residuals in noise
        units, without the prior, over the residual's mean square): their inverse covariance. */
    Mat information(const FitVector& q);

    //! The data residuals at the last run's start and result.
    const std::vector<float>& startData() const { return startData_; }
    const std::vector<float>& finalData() const { return finalData_; }

private:
    /* JᵀJ and Jᵀr of the data at q (forward differences; `at` holds the data at q), and of the prior
       when `withPrior`. */
    void jacobianProducts(const FitVector& q, const std::vector<float>& at, Mat& jtj, Mat& jtr, bool withPrior);

    FitResiduals& r_;
    std::vector<float> startData_, finalData_;
    std::vector<int> active_;
    const FitBox& box_;
};

//! The sum of squares of the first `count` values of `r`.
double squaredNorm(const std::vector<float>& r, size_t count);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
