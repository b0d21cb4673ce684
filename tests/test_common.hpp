// Shared by the GoogleTest files: where the test data lives, and small image metrics.
#ifndef DYNBLUR_TEST_COMMON_HPP
#define DYNBLUR_TEST_COMMON_HPP

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <cstdlib>
#include <string>
#include <sys/stat.h>

namespace dynblur_test {

//! Folder of the shared test data: $DYNBLUR_TEST_DATA, else ../shared/data beside the checkout.
inline std::string dataDir()
{
    const char* env = std::getenv("DYNBLUR_TEST_DATA");
    return (env && *env) ? std::string(env) : std::string(DYNBLUR_DEFAULT_TEST_DATA);
}

//! Full path of a data file, or "" when it is absent.
inline std::string dataFile(const std::string& name)
{
    const std::string path = dataDir() + "/" + name;
    struct stat info;
    return stat(path.c_str(), &info) == 0 ? path : std::string();
}

}  // namespace dynblur_test

//! Skips the current test, with a message, when a data file is missing.
#define DYNBLUR_REQUIRE_DATA(var, name)                                                        \
    const std::string var = dynblur_test::dataFile(name);                                       \
    if (var.empty())                                                                            \
        GTEST_SKIP() << "test data '" << (name) << "' not found in " << dynblur_test::dataDir() \
                     << " (set DYNBLUR_TEST_DATA)"

#endif
