// Private: the linear blur operators that Richardson–Lucy inverts, and their exact adjoints.
// tests/test_deconv.cpp includes this header to check <A x, y> == <x, Aᵀ y>.
#ifndef OPENCV_DYNBLUR_DECONV_OPERATOR_HPP
#define OPENCV_DYNBLUR_DECONV_OPERATOR_HPP

#include "opencv2/dynblur/deconv.hpp"

#include <memory>
#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

class FftKernel;

/** @brief A linear blur A from a latent domain (the frame, possibly extended by margins) to the
frame. Latent pixel (x, y) of the array is frame coordinate (x − origin.x, y − origin.y).
Planes are CV_32FC1. */
class CV_EXPORTS BlurOperator
{
public:
    virtual ~BlurOperator() {}
    virtual Size frameSize() const = 0;
    virtual Size latentSize() const = 0;
    virtual Point origin() const = 0;
    //! frame = A · latent
    virtual void forward(const Mat& latent, Mat& frame) = 0;
    //! latent = Aᵀ · frame
    virtual void adjoint(const Mat& frame, Mat& latent) = 0;
};

/** @brief One kernel everywhere (convolution form), through FFTW. With `pad` the latent domain is
the frame grown by the kernel's half-size on each side; otherwise it is the frame, zero outside. */
class CV_EXPORTS UniformBlurOperator CV_FINAL : public BlurOperator
{
public:
    UniformBlurOperator(Size frameSize, const Mat& kernel32f, bool pad);
    ~UniformBlurOperator();
    Size frameSize() const CV_OVERRIDE { return frame_; }
    Size latentSize() const CV_OVERRIDE { return latent_; }
    Point origin() const CV_OVERRIDE { return origin_; }
    void forward(const Mat& latent, Mat& frame) CV_OVERRIDE;
    void adjoint(const Mat& frame, Mat& latent) CV_OVERRIDE;

private:
    Size frame_, latent_;
    Point origin_;
    std::unique_ptr<FftKernel> fft_;
    Mat scratch_;
};

/** @brief The PsfBank's blended blur B(p) = Σ_n w_n(p) Σ_u k_n(u) L(p − s_n − (u − c)), applied
in the spatial domain as sparse taps (zero taps skipped, shifts are index offsets), rows in
parallel. With `pad` the latent domain is the bounding box of every pixel any tap reads (the
kernels' reach, shifts included); otherwise it is the frame and reads outside it are zero.
The bank is trusted (validated by the caller). */
class CV_EXPORTS BankBlurOperator CV_FINAL : public BlurOperator
{
public:
    BankBlurOperator(const PsfBank& bank, bool pad);
    Size frameSize() const CV_OVERRIDE { return frame_; }
    Size latentSize() const CV_OVERRIDE { return latent_; }
    Point origin() const CV_OVERRIDE { return origin_; }
    void forward(const Mat& latent, Mat& frame) CV_OVERRIDE;
    void adjoint(const Mat& frame, Mat& latent) CV_OVERRIDE;

    struct TapRow
    {
        int dy = 0;               // latent row read = frame row + dy
        std::vector<int> dx;      // latent col read = frame col + dx
        std::vector<float> weight;
    };
    struct Node
    {
        std::vector<TapRow> rows;
        int dyMin = 0, dyMax = 0;
    };
    //! Tent weight along one axis: up to two (node index, weight) pairs per coordinate.
    struct AxisWeight
    {
        int node[2] = {0, 0};
        float weight[2] = {0.f, 0.f};
    };

private:
    void forwardRows(const Mat& latent, Mat& frame, const Range& rows) const;
    void adjointRows(const Mat& frame, Mat& latent, const Range& rows) const;
    float rowWeight(int nodeRow, int frameRow) const;

    Size frame_, latent_;
    Point origin_;
    int nodeCols_ = 1, nodeRows_ = 1;
    std::vector<Node> nodes_;                 // row-major, nodeRows_ × nodeCols_
    std::vector<AxisWeight> rowWeights_;      // per frame row
    std::vector<Range> nodeRowSupport_;       // frame rows where each node row's weight > 0
    std::vector<Range> nodeColSupport_;       // frame cols where each node col's weight > 0
    std::vector<std::vector<float>> colWeight_;  // per node col, weights over its support
};

/** @brief Bilinear tent weights of every integer coordinate in [0, length) between the nodes `z`
(increasing), constant beyond the outermost nodes: the PsfBank blending weights along one axis,
shared by the spatial operator and the Wiener path. */
std::vector<BankBlurOperator::AxisWeight> tentWeights(const std::vector<double>& z, int length);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
