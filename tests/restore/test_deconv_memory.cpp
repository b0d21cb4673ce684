// SPDX-License-Identifier: Apache-2.0
// Memory of the restorations: the frame-rate restoration's working set, and the 3-axis default's.
#include "rotation_motion.hpp"
#include "test_common.hpp"
#include "deconv_fixtures.hpp"

#include "restore/deconv_operator.hpp"
#include "restore/deconv_rl.hpp"
#include "restore/kernels/kernel_table.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <malloc.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <iostream>
#include <random>

namespace {

using namespace deconv_test;

// ---------------------------------------------------------------------------------------------
// (8) Memory: the frame-rate restoration's working set.

/* Counts the bytes of every Mat allocated while it is the default allocator (OpenCV's own
   allocator does the work), and the peak. */
class CountingAllocator CV_FINAL : public MatAllocator
{
public:
    UMatData* allocate(int dims, const int* sizes, int type, void* data, size_t* step, AccessFlag flags,
                       UMatUsageFlags usage) const CV_OVERRIDE
    {
        UMatData* u = std_->allocate(dims, sizes, type, data, step, flags, usage);
        if (u && !data)
        {
            u->currAllocator = this;
            const size_t now = current_ += u->size;
            size_t peak = peak_.load();
            while (now > peak && !peak_.compare_exchange_weak(peak, now))
            {
            }
        }
        return u;
    }
    bool allocate(UMatData* u, AccessFlag flags, UMatUsageFlags usage) const CV_OVERRIDE
    {
        return std_->allocate(u, flags, usage);
    }
    void deallocate(UMatData* u) const CV_OVERRIDE
    {
        if (u && !(u->flags & UMatData::USER_ALLOCATED))
            current_ -= u->size;
        std_->deallocate(u);
    }
    size_t peak() const { return peak_; }
    void resetPeak() { peak_ = current_.load(); }
    size_t current() const { return current_; }

private:
    MatAllocator* std_ = Mat::getStdAllocator();
    mutable std::atomic<size_t> current_{0}, peak_{0};
};

//! Bytes the heap holds right now (glibc; 0 where mallinfo2 is not what the allocator reports).
double heapInUse()
{
    const struct mallinfo2 m = mallinfo2();
    return double(m.uordblks + m.hblkhd);
}

/* Peak extra memory of richardsonLucyVariant on `frame` with `bank`, in frame planes per channel:
   its Mats, counted at their peak (the output excluded), plus the blur operator's tap lists, which
   live through the whole restoration. `operatorPlanes` receives the second part. */
double extraPlanesPerChannel(const Mat& frame, const PsfBank& bank, const RLParams& params, double& operatorPlanes)
{
    const double plane = double(frame.total()) * sizeof(float) * frame.channels();
    const double before = heapInUse();
    {
        const auto op = cv::dynblur::detail::createBankOperator(bank, true, params.blurPrecision == RL_BLUR_BFLOAT16);
        operatorPlanes = (heapInUse() - before) / plane;
    }
    Mat latent;
    CountingAllocator counter;
    MatAllocator* previous = Mat::getDefaultAllocator();
    Mat::setDefaultAllocator(&counter);
    richardsonLucyVariant(frame, bank, latent, params);
    Mat::setDefaultAllocator(previous);
    const double mats = (double(counter.peak()) - double(latent.total() * latent.elemSize())) / plane;
    latent.release();  // freed through the counter, which must outlive it
    return mats + operatorPlanes;
}

// The row-wise restoration of a 1280×960 RGB window III frame (the speed benchmark's) holds at
// most 4 frame-sized float planes per channel besides its input and output (the memory target of
// docs/performance.md). The tile-wise one is measured beside it and held to what it needs: its tap
// lists alone take ~3.9.
TEST(DeconvMemory, RowWiseRestorationStaysWithinFourFramePlanesPerChannel)
{
    Ptr<Plant> plant = Plant::create(14.4, 0.12, CV_PI / 180);
    Ptr<CameraModel> camera = CameraModel::create(1230, 1230, 639.5, 479.5, 1280, 960);
    const SwitchSchedule schedule = SwitchPlanner::create(plant, 16, PLAN_ROBUST)->plan(0.0, 10 * CV_PI / 180, 0.0);
    const RollingShutter shutter{0.012, 0.008, 1.0 / 30 / 960, 960};
    Ptr<PsfGenerator> generator = PsfGenerator::create(plant, camera);
    Mat frame(960, 1280, CV_32FC3);
    randu(frame, 0.05f, 0.95f);
    RLParams params = DynamicDeblurrer::create(plant, camera)->getRLParams();
    params.iterations = 10;
    for (int model : {PSF_ROWS, PSF_TILES})
    {
        const PsfBank bank = generator->generate(model, schedule, shutter);
        // Full color, then the frame-rate setting in float and in bfloat16.
        for (const std::pair<int, int>& setting :
             {std::make_pair(-1, int(RL_BLUR_FLOAT32)), std::make_pair(3, int(RL_BLUR_FLOAT32)),
              std::make_pair(3, int(RL_BLUR_BFLOAT16))})
        {
            params.colorIterations = setting.first;
            params.blurPrecision = setting.second;
            double taps = 0;
            const double extra = extraPlanesPerChannel(frame, bank, params, taps);
            std::cout << "[ measured ] " << (model == PSF_ROWS ? "row" : "tile")
                      << "-wise RL, 1280x960 RGB, 10 iterations, colorIterations " << setting.first
                      << (setting.second == RL_BLUR_BFLOAT16 ? ", bfloat16" : ", float32") << ": peak extra memory "
                      << extra << " frame planes per channel (Mats " << extra - taps << ", operator's taps " << taps
                      << ")" << std::endl;
            // the figures each setting measures are in docs/performance.md
            EXPECT_LE(extra, model == PSF_ROWS ? 4.0 : 8.0);
        }
    }

    /* The frame-rate setting as DynamicDeblurrer runs it, the color at half resolution: every Mat
       it keeps for the next frame (both workspaces, the half-size color, the luminance)
       and its temporaries, at their peak, plus the full-size operator's taps (the half-size one's
       are gone before it is built). Its figure is in docs/performance.md. */
    const double plane = double(frame.total()) * sizeof(float) * frame.channels();
    double taps = 0;
    {
        const double before = heapInUse();
        const auto op = cv::dynblur::detail::createBankOperator(generator->generate(PSF_ROWS, schedule, shutter), true,
                                                                true);
        taps = (heapInUse() - before) / plane;
    }
    CountingAllocator counter;
    MatAllocator* previous = Mat::getDefaultAllocator();
    Mat::setDefaultAllocator(&counter);
    Mat restored;
    {
        Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(plant, camera);
        deblurrer->setPsfModel(PSF_ROWS);
        params.colorIterations = 3;
        params.blurPrecision = RL_BLUR_BFLOAT16;
        deblurrer->setRLParams(params);
        deblurrer->setColorResolution(DEBLUR_COLOR_HALF_RESOLUTION);
        deblurrer->deblur(frame, schedule, shutter, restored);
    }
    Mat::setDefaultAllocator(previous);
    const double mats = (double(counter.peak()) - double(restored.total() * restored.elemSize())) / plane;
    restored.release();
    std::cout << "[ measured ] DynamicDeblurrer, row-wise, 1280x960 RGB, 10 iterations, 3 in color at half "
                 "resolution, bfloat16: peak extra memory "
              << mats + taps << " frame planes per channel (Mats " << mats << ", operator's taps " << taps << ")"
              << std::endl;
    EXPECT_LE(mats + taps, 4.0);
}

/* The default (tiles, 20 iterations, full color) on the same camera and shutter, its frame blurred by
   3-axis shakes of up to 30, 60 and 90 deg/s over a 20 ms exposure (blur paths up to ~40 px), holds at
   most twice the one-axis default's peak extra memory (the saccade frame above). */
TEST(DeconvMemory, ThreeAxisDefaultWithinTwiceTheOneAxis)
{
    Ptr<Plant> plant = Plant::create(14.4, 0.12, CV_PI / 180);
    Ptr<CameraModel> camera = CameraModel::create(1230, 1230, 639.5, 479.5, 1280, 960);
    const SwitchSchedule schedule = SwitchPlanner::create(plant, 16, PLAN_ROBUST)->plan(0.0, 10 * CV_PI / 180, 0.0);
    Mat frame(960, 1280, CV_32FC3);
    randu(frame, 0.05f, 0.95f);
    const RLParams params = DynamicDeblurrer::create(plant, camera)->getRLParams();
    double taps = 0;
    const double oneAxis = extraPlanesPerChannel(
        frame, PsfGenerator::create(plant, camera)->generate(PSF_TILES, schedule, RollingShutter(0.012, 0.008, 1.0 / 30 / 960, 960)),
        params, taps);
    std::cout << "[ measured ] one-axis default (tiles), 1280x960 RGB, window III: peak extra memory " << oneAxis
              << " frame planes per channel" << std::endl;
    for (double peakRate : {30.0, 60.0, 90.0})
    {
        const PsfBank bank = PsfGenerator::create(camera)->generate(PSF_TILES, dynblur_test::handShake(peakRate),
                                                                    RollingShutter(0.1, 0.020, 1.0 / 30 / 960, 960));
        const double threeAxis = extraPlanesPerChannel(frame, bank, params, taps);
        std::cout << "[ measured ] 3-axis shake " << peakRate << " deg/s, default (tiles), longest kernel "
                  << std::max(bank.maxKernelSize().width, bank.maxKernelSize().height) << " px: peak extra memory "
                  << threeAxis << " frame planes per channel (operator's taps " << taps << "), "
                  << threeAxis / oneAxis << "x the one-axis default's" << std::endl;
        EXPECT_LE(threeAxis, 2 * oneAxis) << peakRate << " deg/s";
    }
}

}  // namespace
