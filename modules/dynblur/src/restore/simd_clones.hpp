// SPDX-License-Identifier: Apache-2.0
// The element-wise row loops are compiled for the build's baseline; where GCC targets x86-64 they
// are cloned for AVX2 and AVX-512 as well, and the CPU picks at load time.
#ifndef OPENCV_DYNBLUR_RESTORE_SIMD_CLONES_HPP
#define OPENCV_DYNBLUR_RESTORE_SIMD_CLONES_HPP

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define DYNBLUR_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define DYNBLUR_SIMD_CLONES
#endif

#endif
