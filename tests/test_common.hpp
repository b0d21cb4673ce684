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

//! Skips the current test, with a message, when a data file is missing.
#define DYNBLUR_REQUIRE_DATA(var, name)                                                        \
    const std::string var = dynblur_test::dataFile(name);                                       \
    if (var.empty())                                                                            \
        GTEST_SKIP() << "test data '" << (name) << "' not found in " << dynblur_test::dataDir() \
                     << " (set DYNBLUR_TEST_DATA)"

#endif
