// SPDX-License-Identifier: Apache-2.0
// scripts/compare_revisions.sh's timing program: the frame-rate setting's restoration by two
// revisions of the library, alternating in one process.
//
//   compare_revisions_driver OLD_SHIM.so NEW_SHIM.so ROUNDS
//
// Each shim (shim.cpp) is one revision's public API behind extern "C" functions, linked to that
// revision's library. Both are dlopened RTLD_LOCAL, so neither's symbols join the global scope where
// the other would find them, and RTLD_DEEPBIND, so each binds first to its own dependencies even if
// something loaded globally exports the same names. Neither flag would give two libraries by itself:
// the dynamic linker satisfies a DT_NEEDED from any object already loaded with that soname, and both
// revisions build libopencv_dynblur.so. So the script links each shim to a copy whose soname is its
// own (libopencv_dynblur_old.so, libopencv_dynblur_new.so); this program checks, with dladdr on the
// DynamicDeblurrer::create each shim calls, that two files at two addresses were loaded. OpenCV and
// the other dependencies are loaded once and shared: the thread pool both sides use is the same.
//
// Both sides restore the same frame (rendered by the old side). Each round times one restoration per
// side, the order alternating round to round; the machine's speed drifts over minutes, so the figure
// is the median over rounds of the within-round ratio new/old, with its min and max.
#include "../paired_rounds.hpp"  // median (the header brings Google Benchmark: the driver links it)

#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

struct Shim
{
    const char* label = "";
    const char* (*revision)() = nullptr;
    const char* (*library)(const void** base) = nullptr;
    int (*renderFrame)(float* out, int rows, int cols) = nullptr;
    void* (*setup)(const float* frame, int rows, int cols, int frameRate) = nullptr;
    void (*run)(void* handle) = nullptr;
    const void* (*result)(void* handle, size_t* bytes, int* type) = nullptr;
    void (*teardown)(void* handle) = nullptr;
    void* handle = nullptr;
};

template <class F>
void bind(void* so, const char* path, const char* name, F& f)
{
    f = reinterpret_cast<F>(dlsym(so, name));
    if (!f)
    {
        std::fprintf(stderr, "compare_revisions: %s has no %s\n", path, name);
        std::exit(2);
    }
}

Shim load(const char* path, const char* label)
{
    void* so = dlopen(path, RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND);
    if (!so)
    {
        std::fprintf(stderr, "compare_revisions: %s\n", dlerror());
        std::exit(2);
    }
    Shim s;
    s.label = label;
    bind(so, path, "compare_revision", s.revision);
    bind(so, path, "compare_library", s.library);
    bind(so, path, "compare_render_frame", s.renderFrame);
    bind(so, path, "compare_setup", s.setup);
    bind(so, path, "compare_run", s.run);
    bind(so, path, "compare_result", s.result);
    bind(so, path, "compare_teardown", s.teardown);
    return s;
}

double timeRun(const Shim& s)
{
    const auto start = std::chrono::steady_clock::now();
    s.run(s.handle);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv)
{
    if (argc != 5 || (std::strcmp(argv[4], "frame-rate") != 0 && std::strcmp(argv[4], "default") != 0))
    {
        std::fprintf(stderr, "usage: %s OLD_SHIM.so NEW_SHIM.so ROUNDS frame-rate|default\n", argv[0]);
        return 2;
    }
    const bool frameRate = std::strcmp(argv[4], "frame-rate") == 0;
    const int rounds = std::atoi(argv[3]);
    if (rounds < 1)
    {
        std::fprintf(stderr, "compare_revisions: ROUNDS must be at least 1\n");
        return 2;
    }
    Shim sides[2] = {load(argv[1], "old"), load(argv[2], "new")};

    const void* base[2] = {nullptr, nullptr};
    std::string library[2];
    for (int k = 0; k < 2; k++)
    {
        library[k] = sides[k].library(&base[k]);
        std::printf("%s: revision %s, library %s loaded at %p\n", sides[k].label, sides[k].revision(),
                    library[k].c_str(), base[k]);
    }
    if (library[0] == library[1] || base[0] == base[1])
    {
        std::printf("compare_revisions: both sides run the same library; nothing to compare\n");
        return 1;
    }
    std::printf("two libraries loaded: yes\n");

    const int rows = 960, cols = 1280;
    std::vector<float> frame(size_t(rows) * cols * 3);
    if (sides[0].renderFrame(frame.data(), rows, cols) != 0)
    {
        std::fprintf(stderr, "compare_revisions: the frame is not %dx%d RGB float\n", cols, rows);
        return 2;
    }
    for (Shim& s : sides)
        s.handle = s.setup(frame.data(), rows, cols, frameRate ? 1 : 0);  // each restores once to warm up

    std::vector<double> ms[2];
    for (int r = 0; r < rounds; r++)
        for (int k = 0; k < 2; k++)
        {
            const int which = (r + k) % 2;  // old first in even rounds, new first in odd ones
            ms[which].push_back(timeRun(sides[which]));
        }
    std::vector<double> ratio;
    for (int r = 0; r < rounds; r++)
        ratio.push_back(ms[1][size_t(r)] / ms[0][size_t(r)]);
    std::printf("%d paired rounds (order alternating), %s setting, %dx%d RGB float frame:\n", rounds, argv[4], cols,
                rows);
    std::printf("  old median %.1f ms, new median %.1f ms\n", dynblur_perf::median(ms[0]), dynblur_perf::median(ms[1]));
    std::printf("  new/old per round: median %.3f, min %.3f, max %.3f\n", dynblur_perf::median(ratio),
                *std::min_element(ratio.begin(), ratio.end()), *std::max_element(ratio.begin(), ratio.end()));

    size_t bytes[2];
    int type[2];
    const void* pixels[2];
    for (int k = 0; k < 2; k++)
        pixels[k] = sides[k].result(sides[k].handle, &bytes[k], &type[k]);
    if (bytes[0] != bytes[1] || type[0] != type[1])
        std::printf("restored images: different sizes or types (%zu bytes, type %d vs %zu bytes, type %d)\n", bytes[0],
                    type[0], bytes[1], type[1]);
    else
    {
        const bool equal = std::memcmp(pixels[0], pixels[1], bytes[0]) == 0;
        double maxAbs = 0;
        if ((type[0] & 7) == 5)  // CV_32F depth
        {
            const float* a = static_cast<const float*>(pixels[0]);
            const float* b = static_cast<const float*>(pixels[1]);
            for (size_t i = 0; i < bytes[0] / sizeof(float); i++)
                maxAbs = std::max(maxAbs, std::fabs(double(a[i]) - double(b[i])));
            std::printf("restored images: %s (max abs difference %.3g)\n", equal ? "bitwise equal" : "NOT bitwise equal",
                        maxAbs);
        }
        else
            std::printf("restored images: %s\n", equal ? "bitwise equal" : "NOT bitwise equal");
    }
    for (Shim& s : sides)
        s.teardown(s.handle);
    return 0;
}
