// SPDX-License-Identifier: Apache-2.0
#include "restore/fft_kernel.hpp"

#include <opencv2/core/utility.hpp>

#include <fftw3.h>

#include <complex>
#include <cstring>
#include <map>
#include <mutex>
#include <tuple>

namespace cv {
namespace dynblur {
namespace detail {

namespace {

struct FftwFree
{
    void operator()(void* p) const { fftwf_free(p); }
};
template <typename T>
using FftwBuffer = std::unique_ptr<T[], FftwFree>;

template <typename T>
FftwBuffer<T> allocate(size_t count)
{
    T* p = static_cast<T*>(fftwf_malloc(sizeof(T) * std::max<size_t>(count, 1)));
    if (!p)
        CV_Error(Error::StsNoMem, "FftKernel: fftwf_malloc failed");
    return FftwBuffer<T>(p);
}

struct PlanPair
{
    fftwf_plan forward = nullptr;  // real → half spectrum
    fftwf_plan inverse = nullptr;  // half spectrum → real (unnormalised, destroys its input)
};

/* FFTW's parallel loops, run on OpenCV's thread pool: with FFTW's own threads beside OpenCV's,
   the two pools take turns on the cores, and a small transform's time goes to context switches
   (RestorationBounds.RichardsonLucyUniform, many small transforms, shows it). Nested in a
   parallel_for_, OpenCV runs the jobs in the calling thread. */
void parallelLoop(void* (*work)(char*), char* jobData, size_t jobSize, int jobs, void* /*unused*/)
{
    parallel_for_(Range(0, jobs), [&](const Range& range) {
        for (int j = range.start; j < range.end; j++)
            work(jobData + jobSize * size_t(j));
    });
}

/* Plans live until the process exits, keyed by grid size and thread count. FFTW's planner is not
   thread safe, so creation is serialised; executing a plan on other (equally aligned) arrays with
   the new-array API is thread safe, which is how every FftKernel shares them. */
class PlanCache
{
public:
    static PlanCache& instance()
    {
        static PlanCache cache;
        return cache;
    }

    PlanPair get(Size grid)
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const int threads = std::max(1, cv::getNumThreads());
        const auto key = std::make_tuple(grid.height, grid.width, threads);
        auto found = plans_.find(key);
        if (found != plans_.end())
            return found->second;
        const size_t realCount = size_t(grid.area());
        const size_t complexCount = size_t(grid.height) * size_t(grid.width / 2 + 1);
        FftwBuffer<float> real = allocate<float>(realCount);
        FftwBuffer<fftwf_complex> spectrum = allocate<fftwf_complex>(complexCount);
        fftwf_plan_with_nthreads(threads);
        // ESTIMATE: planning is instant and does not touch the arrays; sizes come from
        // getOptimalDFTSize (products of 2, 3, 5), where FFTW's estimate is already good.
        PlanPair pair;
        pair.forward = fftwf_plan_dft_r2c_2d(grid.height, grid.width, real.get(), spectrum.get(), FFTW_ESTIMATE);
        pair.inverse = fftwf_plan_dft_c2r_2d(grid.height, grid.width, spectrum.get(), real.get(), FFTW_ESTIMATE);
        if (!pair.forward || !pair.inverse)
            CV_Error(Error::StsError, format("FftKernel: FFTW could not plan a %dx%d transform", grid.width, grid.height));
        plans_[key] = pair;
        return pair;
    }

private:
    PlanCache()
    {
        fftwf_init_threads();
        fftwf_threads_set_callback(parallelLoop, nullptr);
    }
    /* At exit: every FftKernel holding these plans was constructed after the cache (its
       constructor is what creates it), so it is destroyed before. */
    ~PlanCache()
    {
        for (auto& entry : plans_)
        {
            fftwf_destroy_plan(entry.second.forward);
            fftwf_destroy_plan(entry.second.inverse);
        }
        fftwf_cleanup_threads();
    }
    std::mutex mutex_;
    std::map<std::tuple<int, int, int>, PlanPair> plans_;
};

}  // namespace

struct FftKernel::Impl
{
    Size grid;
    int halfCols = 0;  // grid.width / 2 + 1
    PlanPair plans;
    FftwBuffer<float> realIn, realOut;
    FftwBuffer<fftwf_complex> spectrum, kernelSpectrum;
    bool inputDirty = true;  // realIn holds data outside the last image's footprint

    size_t complexCount() const { return size_t(grid.height) * size_t(halfCols); }

    void load(const Mat& src)
    {
        CV_DbgAssert(src.type() == CV_32FC1 && src.rows <= grid.height && src.cols <= grid.width);
        if (inputDirty || src.size() != loadedSize)
        {
            std::memset(realIn.get(), 0, sizeof(float) * size_t(grid.area()));
            inputDirty = false;
        }
        loadedSize = src.size();
        for (int y = 0; y < src.rows; y++)
            std::memcpy(realIn.get() + size_t(y) * grid.width, src.ptr<float>(y), sizeof(float) * size_t(src.cols));
    }

    void store(Mat& dst, Size size) const
    {
        dst.create(size, CV_32FC1);
        for (int y = 0; y < size.height; y++)
            std::memcpy(dst.ptr<float>(y), realOut.get() + size_t(y) * grid.width, sizeof(float) * size_t(size.width));
    }

    Size loadedSize;
};

FftKernel::FftKernel(Size transformSize, const Mat& kernel, Point shift) : impl_(new Impl)
{
    CV_Assert(kernel.type() == CV_32FC1 && kernel.rows % 2 == 1 && kernel.cols % 2 == 1);
    CV_Assert(transformSize.width >= kernel.cols && transformSize.height >= kernel.rows);
    Impl& m = *impl_;
    m.grid = transformSize;
    m.halfCols = transformSize.width / 2 + 1;
    m.plans = PlanCache::instance().get(transformSize);
    m.realIn = allocate<float>(size_t(transformSize.area()));
    m.realOut = allocate<float>(size_t(transformSize.area()));
    m.spectrum = allocate<fftwf_complex>(m.complexCount());
    m.kernelSpectrum = allocate<fftwf_complex>(m.complexCount());

    // Kernel centre (plus shift) at the origin, wrapped around the grid.
    std::memset(m.realIn.get(), 0, sizeof(float) * size_t(transformSize.area()));
    const int cx = (kernel.cols - 1) / 2, cy = (kernel.rows - 1) / 2;
    for (int v = 0; v < kernel.rows; v++)
    {
        const float* row = kernel.ptr<float>(v);
        const int y = ((v - cy + shift.y) % m.grid.height + m.grid.height) % m.grid.height;
        for (int u = 0; u < kernel.cols; u++)
        {
            const int x = ((u - cx + shift.x) % m.grid.width + m.grid.width) % m.grid.width;
            m.realIn[size_t(y) * m.grid.width + x] += row[u];
        }
    }
    fftwf_execute_dft_r2c(m.plans.forward, m.realIn.get(), m.kernelSpectrum.get());
    m.inputDirty = true;
}

FftKernel::~FftKernel() {}

Size FftKernel::linearSize(Size imageSize, Size kernelSize)
{
    return Size(getOptimalDFTSize(imageSize.width + kernelSize.width - 1),
                getOptimalDFTSize(imageSize.height + kernelSize.height - 1));
}

Size FftKernel::transformSize() const { return impl_->grid; }

/* src → spectrum → spectrum[i] = gain(kernel spectrum[i]) · spectrum[i] → dst. FFTW's inverse is
   unnormalised, so 1/N is folded into the gain. */
template <typename Gain>
void FftKernel::filter(const Mat& src, Mat& dst, Gain gain)
{
    Impl& m = *impl_;
    m.load(src);
    fftwf_execute_dft_r2c(m.plans.forward, m.realIn.get(), m.spectrum.get());
    const float scale = 1.f / float(m.grid.area());
    std::complex<float>* s = reinterpret_cast<std::complex<float>*>(m.spectrum.get());
    const std::complex<float>* k = reinterpret_cast<const std::complex<float>*>(m.kernelSpectrum.get());
    const size_t n = m.complexCount();
    for (size_t i = 0; i < n; i++)
        s[i] *= gain(k[i]) * scale;
    fftwf_execute_dft_c2r(m.plans.inverse, m.spectrum.get(), m.realOut.get());
    m.store(dst, src.size());
}

void FftKernel::convolve(const Mat& src, Mat& dst, bool adjoint)
{
    if (adjoint)
        filter(src, dst, [](std::complex<float> k) { return std::conj(k); });
    else
        filter(src, dst, [](std::complex<float> k) { return k; });
}

void FftKernel::wiener(const Mat& src, Mat& dst, float noiseToSignal)
{
    CV_Assert(src.size() == impl_->grid);
    filter(src, dst, [noiseToSignal](std::complex<float> k) { return std::conj(k) / (std::norm(k) + noiseToSignal); });
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
