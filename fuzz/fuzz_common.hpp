// SPDX-License-Identifier: Apache-2.0
// Shared by the libFuzzer targets of fuzz/: the file-based parsers read a path, so each input is
// written to a scratch file first; a cv::Exception is the documented way to refuse bad input, and
// anything else escaping (another exception type, a crash, a sanitizer report, a hang) is a bug.
#ifndef DYNBLUR_FUZZ_COMMON_HPP
#define DYNBLUR_FUZZ_COMMON_HPP

#include <opencv2/core.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

namespace dynblur_fuzz {

//! A scratch file of this process (in $TMPDIR, else /tmp), named with `suffix`, overwritten by
//! every call and removed at exit.
inline const std::string& writeScratchFile(const uint8_t* data, size_t size, const char* suffix)
{
    static std::string path;
    if (path.empty())
    {
        const char* dir = std::getenv("TMPDIR");
        path = std::string(dir && *dir ? dir : "/tmp") + "/dynblur_fuzz_" + std::to_string(::getpid()) + suffix;
        std::atexit([] { std::remove(path.c_str()); });
    }
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f)
        std::abort();  // the harness itself cannot work: not a finding about the parser
    if (size > 0 && std::fwrite(data, 1, size, f) != size)
        std::abort();
    std::fclose(f);
    return path;
}

//! A refusal must say what is wrong: a cv::Exception with an empty message is a bug too.
inline void checkRefusal(const cv::Exception& e)
{
    if (e.err.empty())
        std::abort();
}

}  // namespace dynblur_fuzz

#endif
