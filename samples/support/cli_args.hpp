// SPDX-License-Identifier: Apache-2.0
// The one command-line reader of every program (samples/, calib/). A program declares each option
// once (CliOptions: name, value placeholder, default, help); the parsing, the defaults and the --help
// text all come from that declaration. "--name value" or "--name=value", flags without a value,
// positional arguments where a program takes them; unknown names are refused (a typo must not drive
// the actuators or calibrate with a default).
#ifndef DYNBLUR_SAMPLES_CLI_ARGS_HPP
#define DYNBLUR_SAMPLES_CLI_ARGS_HPP

#include <map>
#include <string>
#include <vector>

namespace dynblur_samples {

//! One option as a program declares it.
struct CliOption
{
    std::string name;          //!< without the dashes: "line-delay"
    std::string value;         //!< the value's placeholder in the usage ("S", "FILE.yml"); empty: a flag
    std::string defaultValue;  //!< returned by a read when the option is absent, shown as "(default X)"; "": none
    std::string help;          //!< one paragraph (a '\n' breaks the line); the usage wraps it
};

//! Options declared alike by several programs, under an optional heading and paragraph.
struct CliOptionGroup
{
    std::string heading;  //!< a line of its own above the options ("Simulation:"); empty: none
    std::string text;     //!< a paragraph under the heading
    std::vector<CliOption> options;
};

//! The shortest text that reads back as `value` (a default taken from a program's own constants).
std::string numberText(double value);

class CliArgs;

/** @brief A program's options, declared once: CliOptions("dynblur_x").synopsis(...).option(...)...,
then parse(argc, argv) and printHelp(args). Every program has --help (and -h). Declaring a name twice,
or an option without its value's placeholder, is a programming error (std::logic_error). */
class CliOptions
{
public:
    explicit CliOptions(const std::string& program);

    //! A synopsis line: "Usage: PROGRAM line" (the first), "       PROGRAM line" (the others).
    CliOptions& synopsis(const std::string& line);
    //! A paragraph of the description, under the synopsis.
    CliOptions& description(const std::string& paragraph);
    //! An option taking a value; `defaultValue` "" for none.
    CliOptions& option(const std::string& name, const std::string& value, const std::string& defaultValue,
                       const std::string& help);
    //! An option declared elsewhere (one that several programs share).
    CliOptions& option(const CliOption& option);
    CliOptions& flag(const std::string& name, const std::string& help);
    //! A group's options, under its heading; the options declared next follow it without one.
    CliOptions& group(const CliOptionGroup& options);
    //! Starts a section of the usage: the options declared next go under `heading` and `text`.
    CliOptions& heading(const std::string& heading, const std::string& text = "");
    //! Another name the option is also given by (read as `name`).
    CliOptions& alias(const std::string& alias, const std::string& name);
    //! Accepts arguments that are not options (file names, negative numbers), listed by positional().
    CliOptions& positional();
    //! A paragraph after the options (the exit status).
    CliOptions& footer(const std::string& paragraph);

    //! The --help text: synopsis, description, one wrapped block per option with its default, footer.
    std::string usage() const;
    //! Throws std::runtime_error naming an unknown option, a missing value, a flag's value or a stray argument.
    CliArgs parse(int argc, char** argv) const;
    //! Prints usage() when --help (or -h) was given; returns whether it did (the program then exits 0).
    bool printHelp(const CliArgs& args) const;

private:
    struct Section
    {
        std::string heading, text;
        std::vector<CliOption> options;
    };
    const CliOption* find(const std::string& name) const;
    void declare(const CliOption& option);

    std::string program_;
    std::vector<std::string> synopsis_, description_, footer_;
    std::vector<Section> sections_;
    std::map<std::string, std::string> aliases_;
    bool positional_ = false;
};

/** @brief A parsed command line. Reading a name the program did not declare is a programming error
(std::logic_error), as is a number read without a fallback from an option absent with no default. */
class CliArgs
{
public:
    //! Whether the option was given on the command line.
    bool has(const std::string& name) const;
    //! Whether the program declares the option (code shared by programs that do and do not).
    bool declares(const std::string& name) const { return declared_.count(name) > 0; }
    //! The value given, else the declared default ("" when none).
    std::string str(const std::string& name) const;
    //! The value given, else `fallback` (a default that depends on other options).
    std::string str(const std::string& name, const std::string& fallback) const;
    //! Throws std::runtime_error naming the option when the value is not a number.
    double num(const std::string& name) const;
    double num(const std::string& name, double fallback) const;
    //! Throws std::runtime_error naming the option when the value is not an integer.
    int integer(const std::string& name) const;
    int integer(const std::string& name, int fallback) const;
    //! A comma-separated list of numbers (the value given or the default); throws std::runtime_error naming the option.
    std::vector<double> numbers(const std::string& name) const;
    //! Every value given to a repeatable option, in command-line order (--plant A --plant B); none when absent.
    std::vector<std::string> all(const std::string& name) const;
    //! Arguments that are not options, in order (only with CliOptions::positional).
    const std::vector<std::string>& positional() const { return positional_; }

private:
    friend class CliOptions;
    const CliOption& declared(const std::string& name) const;
    //! The text a numeric read parses: the value given or the declared default.
    std::string numberSource(const std::string& name) const;

    std::map<std::string, CliOption> declared_;
    std::map<std::string, std::string> values_;          // the last value given
    std::map<std::string, std::vector<std::string>> given_;  // every value given
    std::vector<std::string> positional_;
};

}  // namespace dynblur_samples

#endif
