// SPDX-License-Identifier: Apache-2.0
// Linked into every kernel test that scripts/arm_check.sh builds, compiled with that build's flags:
// fails the build if the universal intrinsics did not get the vector width the build was made for
// (DYNBLUR_EXPECT_SIMD_WIDTH, bytes), and before main() runs one v_fma on v_float32 and prints which
// vectors that was, so each test's log shows it ran on NEON, SSE, AVX2 or AVX-512 and not on OpenCV's
// C++ emulation (CV_SIMD128_CPP) or plain scalar code.
#include <opencv2/core/hal/intrin.hpp>

#include <cstdio>
#include <cstdlib>
#if defined(__aarch64__) && defined(__linux__)
#include <asm/hwcap.h>
#include <sys/auxv.h>
#endif

#ifndef DYNBLUR_EXPECT_SIMD_WIDTH
#error "scripts/arm_check.sh passes -DDYNBLUR_EXPECT_SIMD_WIDTH=<bytes>"
#endif
#if !CV_SIMD || CV_SIMD128_CPP || CV_SIMD_WIDTH != DYNBLUR_EXPECT_SIMD_WIDTH
#error "the universal intrinsics do not have the vector width this build was asked for"
#endif
#if defined(__aarch64__) && !(CV_NEON && CV_SIMD128)
#error "an aarch64 build without NEON universal intrinsics"
#endif

namespace {

const char* simdName()
{
#if CV_AVX512_SKX
    return CV_FMA3 ? "AVX-512 (SKX)+FMA" : "AVX-512 (SKX)";
#elif CV_AVX2
    return CV_FMA3 ? "AVX2+FMA" : "AVX2";
#elif CV_NEON
    return "NEON";
#elif CV_SSE2
    return CV_SSE4_1 ? "SSE4.1" : "SSE2";
#else
    return "unknown";
#endif
}

__attribute__((constructor)) void probe()
{
    float a[cv::v_float32::nlanes], out[cv::v_float32::nlanes];
    for (int i = 0; i < cv::v_float32::nlanes; i++)
        a[i] = float(i);
    cv::v_store(out, cv::v_fma(cv::vx_load(a), cv::vx_setall_f32(2.f), cv::vx_setall_f32(1.f)));
    for (int i = 0; i < cv::v_float32::nlanes; i++)
        if (out[i] != 2.f * float(i) + 1.f)
        {
            std::fprintf(stderr, "[simd] v_fma on %s gave a wrong lane %d\n", simdName(), i);
            std::exit(3);
        }
    const char* cpu = "";
#if defined(__aarch64__) && defined(__linux__)
    cpu = (getauxval(AT_HWCAP) & HWCAP_ASIMD) ? ", CPU reports ASIMD" : ", CPU does not report ASIMD";
#endif
    std::printf("[simd] %s: CV_SIMD_WIDTH %d, v_float32 of %d lanes, one v_fma checked%s\n", simdName(),
                int(CV_SIMD_WIDTH), int(cv::v_float32::nlanes), cpu);
    std::fflush(stdout);
}

}  // namespace
