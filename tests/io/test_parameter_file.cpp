// SPDX-License-Identifier: Apache-2.0
// ParameterFile: the flat YAML / XML / JSON reader of schedule and plant files.
#include "test_common.hpp"

#include <opencv2/dynblur.hpp>

using namespace cv;
using namespace cv::dynblur;

namespace {

// What cv::FileStorage writes (OpenCV 4.6 and 5.x headers, comments, wrapped sequences).
const char* const kYaml = "%YAML:1.0\n---\n# identified by dynblur_identify_plant: residual 1e-3 rad\n"
                          "naturalFreqHz: 14.4\nmaxLevel: 16 # cells\ntimes: [ 0., 1.2699999999999999e-02,\n"
                          "    2.96e-02 ]\nlevels:\n  - 16\n  - -4\nname: \"C270 # not a comment\"\n";
const char* const kXml = "<?xml version=\"1.0\"?>\n<opencv_storage>\n<!-- a comment -->\n"
                         "<naturalFreqHz>14.4</naturalFreqHz>\n<maxLevel>16</maxLevel>\n"
                         "<times>\n  0. 1.2699999999999999e-02 2.96e-02</times>\n<levels>16 -4</levels>\n"
                         "<name>\"C270 &amp; co\"</name>\n</opencv_storage>\n";
const char* const kJson = "{\n    // a comment\n    \"naturalFreqHz\": 14.4,\n    \"maxLevel\": 16,\n"
                          "    \"times\": [ 0., 1.2699999999999999e-02, 2.96e-02 ],\n    \"levels\": [ 16, -4 ],\n"
                          "    \"name\": \"C270\"\n}\n";

std::string errorOf(const std::string& text)
{
    try
    {
        ParameterFile::parse(text, "f.yml");
    }
    catch (const cv::Exception& e)
    {
        return e.err;
    }
    return "(no error)";
}

}  // namespace

TEST(ParameterFile, ReadsWhatFileStorageWritesInEachFormat)
{
    for (const char* text : {kYaml, kXml, kJson})
    {
        const ParameterFile f = ParameterFile::parse(text, "f");
        EXPECT_DOUBLE_EQ(f.real("naturalFreqHz"), 14.4) << text;
        EXPECT_EQ(f.integer("maxLevel"), 16);
        EXPECT_EQ(f.reals("times"), (std::vector<double>{0.0, 1.2699999999999999e-02, 2.96e-02}));
        EXPECT_EQ(f.integers("levels"), (std::vector<int>{16, -4}));
        EXPECT_TRUE(f.has("name"));
        EXPECT_FALSE(f.has("gain"));
    }
    EXPECT_EQ(ParameterFile::parse("%YAML 1.2\n---\na: [ ]\n", "f").reals("a").size(), 0u);
    EXPECT_EQ(ParameterFile::parse("\xEF\xBB\xBF{ }", "f").names().size(), 0u);  // byte order mark, empty object
}

TEST(ParameterFile, ErrorsNameTheSourceTheLineAndWhatIsAllowed)
{
    EXPECT_EQ(errorOf(""), "f.yml is empty");
    EXPECT_EQ(errorOf("a: 1\nb: \x01\n"), "f.yml, line 2: control character 0x01; the text may hold tab, CR and LF "
                                          "and characters from 0x20 up only");
    EXPECT_EQ(errorOf("a: 1\na: 2\n"), "f.yml, line 2: 'a' appears twice (first on line 1)");
    EXPECT_EQ(errorOf("a: [1, 2\nb: 3\n"), "f.yml, line 2: ',' or ']' expected between sequence items, found 'b: 3'");
    EXPECT_EQ(errorOf("a: [1, 2,\n"), "f.yml, line 1: the sequence opened with '[' is not closed");
    EXPECT_EQ(errorOf("a: [1, [2]]\n"), "f.yml, line 1: nested collections are not supported: '[2'");
    EXPECT_EQ(errorOf("a:\n  b: 1\n"), "f.yml, line 2: an entry 'name: value' starts at column 1 (nested maps are not "
                                       "supported): 'b: 1'");
    EXPECT_EQ(errorOf("- 1\n"), "f.yml, line 1: a '- item' line belongs under a 'name:' line that has no value");
    EXPECT_EQ(errorOf("a: 1\n...\nb: 2\n"), "f.yml, line 3: text after the end of the document ('...'): 'b: 2'");
    EXPECT_EQ(errorOf("a: 1\n---\n"), "f.yml, line 2: only one YAML document is read ('---' after the entries)");
    EXPECT_EQ(errorOf("a: 'open\n"), "f.yml, line 1: a string opened with ' is not closed on its line");
    EXPECT_EQ(errorOf("<opencv_storage><a x=\"1\">2</a></opencv_storage>"),
              "f.yml, line 1: attributes are not supported: '<a x=\"1\">'");
    EXPECT_EQ(errorOf("<opencv_storage>\n<a><b>1</b></a></opencv_storage>"),
              "f.yml, line 2: expected </a> (nested elements are not supported)");
    EXPECT_EQ(errorOf("{\"a\": {\"b\": 1}}"), "f.yml, line 1: nested objects and arrays are not supported");
    EXPECT_EQ(errorOf("{\"a\": 1\n\"b\": 2}"), "f.yml, line 2: expected ',' or '}' after the member \"a\"");
    EXPECT_EQ(errorOf("{\"a\": 1} x"), "f.yml, line 1: text after the closing '}': 'x'");

    const ParameterFile f = ParameterFile::parse("a: [1, x]\nb: 1e400\nc: [1]\nd: 3000000000\n", "f.yml");
    dynblur_test::expectErrorNaming([&] { f.reals("a"); }, "f.yml, line 1: 'a'[1] = 'x' is not a finite number");
    dynblur_test::expectErrorNaming([&] { f.real("b"); }, "'b' = '1e400' is not a finite number");
    dynblur_test::expectErrorNaming([&] { f.real("c"); }, "'c' must be one number, not a sequence");
    dynblur_test::expectErrorNaming([&] { f.integers("b"); }, "'b' must be a sequence of integers");
    dynblur_test::expectErrorNaming([&] { f.integer("d"); }, "is not an integer in [-2147483648, 2147483647]");
    dynblur_test::expectErrorNaming([&] { f.real("e"); }, "f.yml has no entry 'e'");
    dynblur_test::expectErrorNaming([] { ParameterFile::load("/nonexistent/p.yml", "plant file"); },
                                    "cannot open the plant file '/nonexistent/p.yml'");
    dynblur_test::expectErrorNaming([] { TimingCalibration::load("nope.yml"); },
                                    "TimingCalibration::load: cannot open the timing file 'nope.yml'");
}
