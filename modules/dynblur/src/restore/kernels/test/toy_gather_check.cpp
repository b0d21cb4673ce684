// The toy gathers (../toy_gather.hpp) against their references on rows whose width is not a multiple
// of any vector width, so that the tail runs too. Exits non-zero on a mismatch.
#include "../toy_gather.hpp"
#include "kernel_check.hpp"

#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

using namespace cv::dynblur::kernels;

int main()
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> value(0.05f, 0.95f);
    const int width = 1283, taps = 21, margin = 40;
    std::vector<int> offsets(taps);
    std::vector<float> weights(taps);
    for (int t = 0; t < taps; t++)
    {
        offsets[size_t(t)] = t * 2 - margin / 2 + int(rng() % 3);  // spread over ±margin/2, uneven steps
        weights[size_t(t)] = value(rng) / taps;
    }
    std::vector<float> src(size_t(width + 2 * margin));
    std::vector<uint16_t> packed(src.size());
    for (size_t i = 0; i < src.size(); i++)
    {
        src[i] = value(rng);
        uint32_t bits;
        std::memcpy(&bits, &src[i], sizeof bits);
        packed[i] = uint16_t(bits >> 16);  // truncated: the test compares the kernels, not the packing
    }
    std::vector<float> start(static_cast<size_t>(width));
    for (float& v : start)
        v = value(rng);

    bool ok = true;
    std::vector<float> want = start, got = start;
    toyGatherRef(src.data() + margin, offsets.data(), weights.data(), taps, want.data(), width);
    toyGather(src.data() + margin, offsets.data(), weights.data(), taps, got.data(), width);
    ok &= kernel_check::report("float gather vs reference", kernel_check::maxRelativeError(got.data(), want.data(), width));

    want = start;
    got = start;
    toyGatherRef(packed.data() + margin, offsets.data(), weights.data(), taps, want.data(), width);
    toyGather(packed.data() + margin, offsets.data(), weights.data(), taps, got.data(), width);
    ok &= kernel_check::report("bfloat16 gather vs reference", kernel_check::maxRelativeError(got.data(), want.data(), width));

    std::printf("toy_gather_check: %s\n", ok ? "PASS" : "FAIL");
    return ok ? 0 : 1;
}
