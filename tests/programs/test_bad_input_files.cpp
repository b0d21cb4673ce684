// SPDX-License-Identifier: Apache-2.0
// Bad input to the programs' files and command lines (samples/support: plant file, response log,
// option reader), one table row per input as in tests/api/test_bad_input.cpp.
#include "bad_input_rows.hpp"

#include "cli_args.hpp"
#include "plant_file.hpp"
#include "response_log.hpp"

#include <opencv2/dynblur.hpp>

#include <string>
#include <vector>

using namespace cv;
using namespace cv::dynblur;
using namespace dynblur_test;

namespace {

const double kDeg = CV_PI / 180.0;

}  // namespace

TEST(BadInput, SampleFiles)
{
    using namespace dynblur_samples;
    const std::string goodPlant = tempPath("plant.yml");
    savePlantFile(goodPlant, *Plant::create(14.4, 0.12, kDeg), 16, "bad-input test");
    refuseAll(brokenFileRows("loadPlantFile", "plant.yml", readText(goodPlant), [](const std::string& path) { loadPlantFile(path); }));
    refuseAll({        {"loadPlantFile", "truncated (naturalFreqHz only)",
         [] { loadPlantFile(writeFile("trunc_plant.yml", "%YAML:1.0\n---\nnaturalFreqHz: 14.4\n")); },
         {"trunc_plant.yml", "needs a number"}},
        {"loadPlantFile", "dampingRatio = 1.5",
         [] {
             loadPlantFile(writeFile("zeta_plant.yml",
                                     "%YAML:1.0\n---\nnaturalFreqHz: 14.4\ndampingRatio: 1.5\ngain: 0.01745\nmaxLevel: 16\n"));
         },
         {"dampingRatio", "(0, 1)"}},
        {"loadPlantFile", "gain = .nan",
         [] {
             loadPlantFile(writeFile("nan_plant.yml",
                                     "%YAML:1.0\n---\nnaturalFreqHz: 14.4\ndampingRatio: 0.12\ngain: .nan\nmaxLevel: 16\n"));
         },
         {"gain"}},
        {"loadPlantFile", "naturalFreqHz a string",
         [] {
             loadPlantFile(writeFile("str_plant.yml",
                                     "%YAML:1.0\n---\nnaturalFreqHz: \"fast\"\ndampingRatio: 0.12\ngain: 0.01745\nmaxLevel: 16\n"));
         },
         {"naturalFreqHz"}},
        {"loadPlantFile", "maxLevel = 0",
         [] {
             loadPlantFile(writeFile("lvl_plant.yml",
                                     "%YAML:1.0\n---\nnaturalFreqHz: 14.4\ndampingRatio: 0.12\ngain: 0.01745\nmaxLevel: 0\n"));
         },
         {"maxLevel"}},
        {"readResponseLog", "missing file", [] { readResponseLog(tempPath("nope.csv")); }, {"nope.csv"}},
        {"parseResponseLog", "t = inf", [] { parseResponseLog("t,theta\n0,0\ninf,1\n", "a.csv"); }, {"a.csv:3"}},
        {"parseResponseLog", "binary garbage", [] { parseResponseLog(std::string("\x00\x01\x02,\xff\n\x03", 7), "a.csv"); }, {"a.csv"}},
    });
    // The programs' option reader throws std::runtime_error (its documented error).
    auto args = [](std::vector<std::string> v) {
        static std::vector<std::string> keep;
        keep = v;
        std::vector<char*> argv;
        for (std::string& s : keep)
            argv.push_back(&s[0]);
        return CliOptions("ctl").option("timeout", "S", "", "").flag("start", "").parse((int)argv.size(), argv.data());
    };
    refuseAll({{"CliArgs", "an unknown option", [&] { args({"ctl", "--bogus", "1"}); }, {"--bogus"}},
               {"CliArgs", "an option without its value", [&] { args({"ctl", "--timeout"}); }, {"timeout"}},
               {"CliArgs", "a number that is not one", [&] { args({"ctl", "--timeout", "soon"}).num("timeout", 0.5); }, {"timeout"}},
               {"CliArgs", "an integer that is not one",
                [&] { args({"ctl", "--timeout", "1.5"}).integer("timeout", 1); }, {"timeout"}}},
              true);
}
