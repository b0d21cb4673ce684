// SPDX-License-Identifier: Apache-2.0
// The programs' option table (samples/support/cli_args.hpp): parsing, defaults and the usage text,
// all from one declaration per option.
#include "cli_args.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

using namespace dynblur_samples;

namespace {

CliOptions exampleOptions()
{
    CliOptions options("dynblur_example");
    options.synopsis("--a N [options]")
        .description("Does an example thing.")
        .option("a", "N", "", "a number of things")
        .option("rate", "HZ", "30", "a rate")
        .option("name", "TEXT", "none", "a name")
        .flag("fast", "go fast")
        .heading("More:", "A section of its own.")
        .option("count", "N", "4", "a count, long enough a help text that the usage has to wrap it onto a second "
                                   "line and a third one, each indented under the first, so we can see the indent")
        .alias("speedy", "fast")
        .footer("Exit status: 0 done, 2 bad usage.");
    return options;
}

CliArgs parse(const CliOptions& options, std::vector<std::string> words)
{
    words.insert(words.begin(), "dynblur_example");
    std::vector<char*> argv;
    for (std::string& word : words)
        argv.push_back(&word[0]);
    return options.parse(int(argv.size()), argv.data());
}

CliArgs parse(std::vector<std::string> words)
{
    return parse(exampleOptions(), std::move(words));
}

// The message of the std::runtime_error `f` throws ("" when it throws none).
template <typename F>
std::string refusal(F f)
{
    try
    {
        f();
    }
    catch (const std::runtime_error& e)
    {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(CliArgs, ValueAfterTheNameOrAfterEquals)
{
    EXPECT_EQ(parse({"--a", "1"}).integer("a"), 1);
    EXPECT_EQ(parse({"--a=1"}).integer("a"), 1);
    EXPECT_DOUBLE_EQ(parse({"--rate=-2.5"}).num("rate"), -2.5);
    EXPECT_DOUBLE_EQ(parse({"--rate", "-2.5"}).num("rate"), -2.5);  // a negative value is a value, not an option
    EXPECT_EQ(parse({"--name="}).str("name"), "");                  // given empty: not the default
    EXPECT_EQ(parse({"-h"}).has("help"), true);
    EXPECT_EQ(parse({"--help"}).has("help"), true);
}

TEST(CliArgs, RepeatedOptionKeepsEveryValueInOrder)
{
    const CliArgs args = parse({"--name", "x", "--a=1", "--name=y"});
    EXPECT_EQ(args.all("name"), (std::vector<std::string>{"x", "y"}));
    EXPECT_EQ(args.str("name"), "y");
    EXPECT_TRUE(args.all("rate").empty());  // absent: none, whatever its default
}

TEST(CliArgs, Flags)
{
    EXPECT_TRUE(parse({"--fast"}).has("fast"));
    EXPECT_TRUE(parse({"--speedy"}).has("fast"));  // an alias reads as its option
    EXPECT_FALSE(parse({"--a", "1"}).has("fast"));
    const std::string message = refusal([] { parse({"--fast=yes"}); });
    EXPECT_NE(message.find("--fast takes no value"), std::string::npos) << message;
}

TEST(CliArgs, UnknownOptionNamed)
{
    const std::string message = refusal([] { parse({"--a", "1", "--bogus", "2"}); });
    EXPECT_NE(message.find("unknown option '--bogus'"), std::string::npos) << message;
    EXPECT_NE(refusal([] { parse({"--bogus=2"}); }).find("'--bogus=2'"), std::string::npos);
}

TEST(CliArgs, MissingValueNamed)
{
    const std::string message = refusal([] { parse({"--fast", "--a"}); });
    EXPECT_NE(message.find("--a needs a value"), std::string::npos) << message;
}

TEST(CliArgs, BadNumbersNamed)
{
    std::string message = refusal([] { parse({"--rate", "fast"}).num("rate"); });
    EXPECT_NE(message.find("--rate expects a number, got 'fast'"), std::string::npos) << message;
    message = refusal([] { parse({"--rate=inf"}).num("rate"); });
    EXPECT_NE(message.find("--rate"), std::string::npos) << message;
    message = refusal([] { parse({"--a", "1.5"}).integer("a"); });
    EXPECT_NE(message.find("--a expects an integer, got '1.5'"), std::string::npos) << message;
    message = refusal([] { parse({"--a", "1.5"}).integer("a", 3); });
    EXPECT_NE(message.find("--a expects an integer"), std::string::npos) << message;
}

TEST(CliArgs, DefaultsAsDeclared)
{
    const CliArgs args = parse({});
    EXPECT_DOUBLE_EQ(args.num("rate"), 30);
    EXPECT_EQ(args.integer("count"), 4);
    EXPECT_EQ(args.str("name"), "none");
    EXPECT_EQ(args.str("a"), "");
    EXPECT_FALSE(args.has("rate"));
    // A default that depends on other options is given at the read, and wins over the declared one.
    EXPECT_DOUBLE_EQ(args.num("rate", 25), 25);
    EXPECT_EQ(args.str("name", "other"), "other");
    EXPECT_DOUBLE_EQ(parse({"--rate", "10"}).num("rate", 25), 10);
    EXPECT_TRUE(args.declares("rate"));
    EXPECT_FALSE(args.declares("timing"));
}

TEST(CliArgs, ProgrammingErrors)
{
    const CliArgs args = parse({});
    EXPECT_THROW(args.has("undeclared"), std::logic_error);
    EXPECT_THROW(args.str("undeclared"), std::logic_error);
    EXPECT_THROW(args.num("a"), std::logic_error);  // absent, no default, no fallback
    EXPECT_THROW(CliOptions("x").option("a", "N", "", "").flag("a", ""), std::logic_error);
    EXPECT_THROW(CliOptions("x").flag("help", ""), std::logic_error);
    EXPECT_THROW(CliOptions("x").option("a", "", "", ""), std::logic_error);
    EXPECT_THROW(CliOptions("x").alias("b", "a"), std::logic_error);
}

TEST(CliArgs, PositionalOnlyWhereDeclared)
{
    const std::string message = refusal([] { parse({"file.csv"}); });
    EXPECT_NE(message.find("unexpected argument 'file.csv'"), std::string::npos) << message;
    CliOptions options = exampleOptions();
    options.positional();
    const CliArgs args = parse(options, {"one.csv", "--a", "1", "-5", "two.csv"});
    EXPECT_EQ(args.positional(), (std::vector<std::string>{"one.csv", "-5", "two.csv"}));
    EXPECT_EQ(args.integer("a"), 1);
}

TEST(CliArgs, GroupsDeclaredOnceReused)
{
    const CliOptionGroup shared{"Shared:", "",
                                {{"preset", "NAME", "frame-rate", "a preset"}, {"quiet", "", "", "hush"}}};
    const CliOptions options = CliOptions("x").option("a", "N", "1", "a").group(shared).option("b", "N", "2", "b");
    const CliArgs args = parse(options, {"--quiet"});
    EXPECT_EQ(args.str("preset"), "frame-rate");
    EXPECT_TRUE(args.has("quiet"));
    EXPECT_EQ(args.integer("b"), 2);
    const std::string usage = options.usage();
    EXPECT_LT(usage.find("--a N"), usage.find("Shared:"));
    EXPECT_LT(usage.find("Shared:"), usage.find("--preset NAME"));
}

TEST(CliArgs, UsageListsEveryOptionWithItsDefault)
{
    const std::string usage = exampleOptions().usage();
    EXPECT_EQ(usage.rfind("Usage: dynblur_example --a N [options]\nDoes an example thing.\n", 0), 0u) << usage;
    for (const char* line : {"  --a N                a number of things\n",
                             "  --rate HZ            a rate (default 30)\n",
                             "  --name TEXT          a name (default none)\n", "  --fast               go fast\n",
                             "  --help               this help\n\nMore:\nA section of its own.\n  --count N"})
        EXPECT_NE(usage.find(line), std::string::npos) << line << " in\n" << usage;
    EXPECT_NE(usage.find("(default 4)"), std::string::npos);
    EXPECT_LT(usage.find("--help"), usage.find("More:"));  // the program's own options end with --help
    const std::string footer = "\nExit status: 0 done, 2 bad usage.\n";
    EXPECT_EQ(usage.substr(usage.size() - footer.size()), footer);
    // Wrapped: no line beyond 100 columns, the continuation indented under the help column.
    std::istringstream lines(usage);
    int continued = 0;
    for (std::string line; std::getline(lines, line);)
    {
        EXPECT_LE(line.size(), 100u) << line;
        continued += line.rfind(std::string(23, ' '), 0) == 0;
    }
    EXPECT_GE(continued, 1) << usage;
}

TEST(CliArgs, NumberTextReadsBack)
{
    for (double v : {0.0, 1.0, 0.05, 34.7e-6, 1e3 * 0.033, 0.1 + 0.2, -2.5})
    {
        const std::string text = numberText(v);
        EXPECT_EQ(std::stod(text), v) << text;
    }
    EXPECT_EQ(numberText(0.05), "0.05");
    EXPECT_EQ(numberText(1000), "1000");
}
