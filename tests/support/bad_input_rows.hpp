// SPDX-License-Identifier: Apache-2.0
// Table-driven bad-input checks (docs/reliability.md): one row per refused input, printed as
// "[ refused ] entry point | input | message" lines, from which the reliability table is built.
// Shared by the module's tests (tests/api/test_bad_input.cpp) and the programs' (tests/programs/).
#ifndef DYNBLUR_TEST_BAD_INPUT_ROWS_HPP
#define DYNBLUR_TEST_BAD_INPUT_ROWS_HPP

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <cstdio>
#include <fstream>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <string>
#include <typeinfo>
#include <unistd.h>
#include <vector>

namespace dynblur_test {

//! One bad input: the call, and the words its error message must contain (the argument's name,
//! and the allowed range or kind where there is one).
struct Row
{
    std::string entry;
    std::string input;
    std::function<void()> call;
    std::vector<std::string> words;
};

inline std::string oneLine(std::string s)
{
    for (char& c : s)
        if (c == '\n' || c == '\r')
            c = ' ';
    return s.size() > 160 ? s.substr(0, 157) + "..." : s;
}

//! Runs one row; returns "" when it was refused as required, else what went wrong. `message`
//! receives the error message.
inline std::string tryRow(const Row& r, bool runtimeErrorIsDocumented, std::string& message)
{
    message.clear();
    try
    {
        r.call();
        return r.entry + " accepted " + r.input;
    }
    catch (const cv::Exception& e)
    {
        message = e.err;
    }
    catch (const std::runtime_error& e)
    {
        message = e.what();
        if (!runtimeErrorIsDocumented)
            return r.entry + " with " + r.input + " threw std::runtime_error, not cv::Exception: " + message;
    }
    catch (const std::exception& e)
    {
        message = e.what();
        return r.entry + " with " + r.input + " threw " + typeid(e).name() + ": " + message;
    }
    for (const std::string& w : r.words)
        if (message.find(w) == std::string::npos)
            return r.entry + " with " + r.input + ": the message does not name '" + w + "': " + oneLine(message);
    return "";
}

//! Runs the rows; every one must throw cv::Exception (or std::runtime_error where documented)
//! naming its words.
inline void refuseAll(const std::vector<Row>& rows, bool runtimeErrorIsDocumented = false)
{
    for (const Row& r : rows)
    {
        std::string message;
        const std::string problem = tryRow(r, runtimeErrorIsDocumented, message);
        if (!problem.empty())
            ADD_FAILURE() << problem;
        std::printf("[ refused ] %s | %s | %s\n", r.entry.c_str(), r.input.c_str(), oneLine(message).c_str());
        std::fflush(stdout);
    }
}

inline std::string tempPath(const std::string& name)
{
    return ::testing::TempDir() + cv::format("dynblur_bad_%d_", (int)::getpid()) + name;
}

inline std::string writeFile(const std::string& name, const std::string& text)
{
    const std::string path = tempPath(name);
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

//! Rows every file reader must refuse by naming the file: a missing file, an empty one, the first
//! half of a good one, and garbage bytes (binary, with a NUL).
inline std::vector<Row> brokenFileRows(const std::string& entry, const std::string& name, const std::string& goodText,
                                const std::function<void(const std::string&)>& read)
{
    const std::string half = goodText.substr(0, goodText.size() / 2);
    return {
        {entry, "missing file", [=] { read(tempPath("missing_" + name)); }, {"missing_" + name}},
        {entry, "empty file", [=] { read(writeFile("empty_" + name, "")); }, {"empty_" + name}},
        {entry, "truncated file (first half)", [=] { read(writeFile("half_" + name, half)); }, {"half_" + name}},
        {entry, "garbage bytes", [=] { read(writeFile("garbage_" + name, std::string("\x01\x7f\xfe{[<::>]}\x00zz", 14))); },
         {"garbage_" + name}},
    };
}

inline std::string readText(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace dynblur_test

#endif
