// SPDX-License-Identifier: Apache-2.0
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

//! True when DYNBLUR_REQUIRE_TEST_DATA=1: missing test data is then a failure (DYNBLUR_REQUIRE_DATA).
inline bool testDataRequired()
{
    const char* env = std::getenv("DYNBLUR_REQUIRE_TEST_DATA");
    return env && std::string(env) == "1";
}

//! Runs `f` and expects a cv::Exception whose message contains `word` (an argument's name).
template <typename F>
void expectErrorNaming(F f, const std::string& word)
{
    try
    {
        f();
        ADD_FAILURE() << "no exception; expected one naming '" << word << "'";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    }
}

}  // namespace dynblur_test

/* When a data file is missing: a failure when DYNBLUR_REQUIRE_TEST_DATA=1 (the test command sets it,
   so a CI run without the data cannot pass by skipping every figure), else a skip with a message
   (a developer running one test by hand without the data). */
#define DYNBLUR_REQUIRE_DATA(var, name)                                                                    \
    const std::string var = dynblur_test::dataFile(name);                                                   \
    if (var.empty())                                                                                        \
    {                                                                                                       \
        if (dynblur_test::testDataRequired())                                                               \
            FAIL() << "test data '" << (name) << "' not found in " << dynblur_test::dataDir()               \
                   << " (DYNBLUR_REQUIRE_TEST_DATA=1: missing data is a failure; set DYNBLUR_TEST_DATA)";   \
        GTEST_SKIP() << "test data '" << (name) << "' not found in " << dynblur_test::dataDir()             \
                     << " (set DYNBLUR_TEST_DATA)";                                                         \
    }                                                                                                       \
    static_assert(true, "")

#endif
