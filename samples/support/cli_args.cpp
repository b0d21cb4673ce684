// SPDX-License-Identifier: Apache-2.0
#include "cli_args.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace dynblur_samples {

namespace {

const size_t kWidth = 100;       // columns of the usage text
const size_t kHelpColumn = 23;   // where an option's help starts

/* `text` wrapped into lines of at most kWidth columns: the first starts at `column` (after what the
   caller wrote there), the others at `indent`; a '\n' in the text breaks the line. */
std::string wrap(const std::string& text, size_t column, size_t indent)
{
    std::string out;
    std::istringstream lines(text);
    bool firstLine = true;
    for (std::string line; std::getline(lines, line);)
    {
        if (!firstLine)
            out += "\n" + std::string(indent, ' '), column = indent;
        firstLine = false;
        std::istringstream words(line);
        bool lineEmpty = true;
        for (std::string word; words >> word;)
        {
            if (!lineEmpty && column + 1 + word.size() > kWidth)
                out += "\n" + std::string(indent, ' '), column = indent, lineEmpty = true;
            if (!lineEmpty)
                out += ' ', column++;
            out += word;
            column += word.size();
            lineEmpty = false;
        }
    }
    return out + "\n";
}

std::string optionLine(const CliOption& option)
{
    std::string left = "  --" + option.name + (option.value.empty() ? "" : " " + option.value);
    left += left.size() + 2 <= kHelpColumn ? std::string(kHelpColumn - left.size(), ' ') : "  ";
    const std::string help =
        option.help + (option.defaultValue.empty() ? "" : " (default " + option.defaultValue + ")");
    return left + wrap(help, left.size(), kHelpColumn);
}

bool isOptionArgument(const std::string& arg)
{
    // "-5" and "-.5" are numbers (a positional argument or an option's value), not options.
    return arg.size() >= 2 && arg[0] == '-' && !std::isdigit(static_cast<unsigned char>(arg[1])) && arg[1] != '.';
}

}  // namespace

std::string numberText(double value)
{
    // %g's six digits where they read back (1000 stays 1000), more only where they do not.
    char text[32];
    for (int digits = 6; digits <= 17; digits++)
    {
        std::snprintf(text, sizeof(text), "%.*g", digits, value);
        if (std::strtod(text, nullptr) == value)
            break;
    }
    return text;
}

// ---------------------------------------------------------------------------------------------
// The declaration

CliOptions::CliOptions(const std::string& program) : program_(program), sections_(1) {}

CliOptions& CliOptions::synopsis(const std::string& line)
{
    synopsis_.push_back(line);
    return *this;
}

CliOptions& CliOptions::description(const std::string& paragraph)
{
    description_.push_back(paragraph);
    return *this;
}

void CliOptions::declare(const CliOption& option)
{
    if (find(option.name) || option.name == "help")
        throw std::logic_error("CliOptions: --" + option.name + " is declared twice");
    sections_.back().options.push_back(option);
}

CliOptions& CliOptions::option(const std::string& name, const std::string& value, const std::string& defaultValue,
                               const std::string& help)
{
    return option({name, value, defaultValue, help});
}

CliOptions& CliOptions::option(const CliOption& option)
{
    if (option.value.empty())
        throw std::logic_error("CliOptions: --" + option.name + " takes a value: give its placeholder");
    declare(option);
    return *this;
}

CliOptions& CliOptions::flag(const std::string& name, const std::string& help)
{
    declare({name, "", "", help});
    return *this;
}

CliOptions& CliOptions::group(const CliOptionGroup& options)
{
    heading(options.heading, options.text);
    for (const CliOption& option : options.options)
        declare(option);
    return heading("");
}

CliOptions& CliOptions::heading(const std::string& heading, const std::string& text)
{
    sections_.push_back({heading, text, {}});
    return *this;
}

CliOptions& CliOptions::alias(const std::string& alias, const std::string& name)
{
    if (name != "help" && !find(name))
        throw std::logic_error("CliOptions: alias --" + alias + " of the undeclared --" + name);
    aliases_[alias] = name;
    return *this;
}

CliOptions& CliOptions::positional()
{
    positional_ = true;
    return *this;
}

CliOptions& CliOptions::footer(const std::string& paragraph)
{
    footer_.push_back(paragraph);
    return *this;
}

const CliOption* CliOptions::find(const std::string& name) const
{
    for (const Section& section : sections_)
        for (const CliOption& option : section.options)
            if (option.name == name)
                return &option;
    return nullptr;
}

// ---------------------------------------------------------------------------------------------
// The usage text

std::string CliOptions::usage() const
{
    std::string text;
    for (size_t i = 0; i < synopsis_.size(); i++)
        text += (i == 0 ? "Usage: " : "       ") + program_ + " " + synopsis_[i] + "\n";
    for (const std::string& paragraph : description_)
        text += wrap(paragraph, 0, 0);
    text += "\n";
    const std::string help = optionLine({"help", "", "", "this help"});
    bool helpListed = false;
    for (const Section& section : sections_)
    {
        if (!section.heading.empty())
        {
            // --help closes the program's own options; a section opens a paragraph of its own.
            if (!helpListed)
                text += help, helpListed = true;
            text += "\n" + wrap(section.heading, 0, 0);
        }
        if (!section.text.empty())
            text += wrap(section.text, 0, 0);
        for (const CliOption& option : section.options)
            text += optionLine(option);
    }
    if (!helpListed)
        text += help;
    if (!footer_.empty())
        text += "\n";
    for (const std::string& paragraph : footer_)
        text += wrap(paragraph, 0, 0);
    return text;
}

bool CliOptions::printHelp(const CliArgs& args) const
{
    if (!args.has("help"))
        return false;
    std::fputs(usage().c_str(), stdout);
    return true;
}

// ---------------------------------------------------------------------------------------------
// Parsing

CliArgs CliOptions::parse(int argc, char** argv) const
{
    CliArgs args;
    args.declared_["help"] = {"help", "", "", "this help"};
    for (const Section& section : sections_)
        for (const CliOption& option : section.options)
            args.declared_[option.name] = option;
    for (int i = 1; i < argc; ++i)
    {
        std::string arg = argv[i];
        if (!isOptionArgument(arg))
        {
            if (!positional_)
                throw std::runtime_error("unexpected argument '" + arg + "' (options start with --)");
            args.positional_.push_back(arg);
            continue;
        }
        if (arg == "-h")
            arg = "--help";
        arg = arg.substr(arg.find_first_not_of('-'));
        std::string name = arg, value;
        const size_t eq = arg.find('=');
        const bool hasValue = eq != std::string::npos;
        if (hasValue)
        {
            name = arg.substr(0, eq);
            value = arg.substr(eq + 1);
        }
        const auto alias = aliases_.find(name);
        if (alias != aliases_.end())
            name = alias->second;
        const auto declared = args.declared_.find(name);
        if (declared == args.declared_.end())
            throw std::runtime_error("unknown option '" + std::string(argv[i]) + "' (see --help)");
        if (declared->second.value.empty())
        {
            if (hasValue)
                throw std::runtime_error("option --" + name + " takes no value");
        }
        else if (!hasValue)
        {
            if (i + 1 >= argc)
                throw std::runtime_error("option --" + name + " needs a value");
            value = argv[++i];
        }
        args.values_[name] = value;
        args.given_[name].push_back(value);
    }
    return args;
}

// ---------------------------------------------------------------------------------------------
// Reading

const CliOption& CliArgs::declared(const std::string& name) const
{
    const auto it = declared_.find(name);
    if (it == declared_.end())
        throw std::logic_error("CliArgs: --" + name + " is read but not declared");
    return it->second;
}

bool CliArgs::has(const std::string& name) const
{
    declared(name);
    return values_.count(name) > 0;
}

std::vector<std::string> CliArgs::all(const std::string& name) const
{
    return has(name) ? given_.at(name) : std::vector<std::string>();
}

std::string CliArgs::str(const std::string& name) const
{
    return has(name) ? values_.at(name) : declared(name).defaultValue;
}

std::string CliArgs::str(const std::string& name, const std::string& fallback) const
{
    return has(name) ? values_.at(name) : fallback;
}

std::string CliArgs::numberSource(const std::string& name) const
{
    if (!has(name) && declared(name).defaultValue.empty())
        throw std::logic_error("CliArgs: --" + name + " has no default: read it with a fallback");
    return str(name);
}

static double parseNumber(const std::string& name, const std::string& text)
{
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v))
        throw std::runtime_error("--" + name + " expects a number, got '" + text + "'");
    return v;
}

static int parseInteger(const std::string& name, const std::string& text)
{
    const double v = parseNumber(name, text);
    if (v != std::floor(v) || std::abs(v) > 2147483647.0)
        throw std::runtime_error("--" + name + " expects an integer, got '" + text + "'");
    return static_cast<int>(v);
}

double CliArgs::num(const std::string& name) const
{
    return parseNumber(name, numberSource(name));
}

double CliArgs::num(const std::string& name, double fallback) const
{
    return has(name) ? parseNumber(name, values_.at(name)) : fallback;
}

std::vector<double> CliArgs::numbers(const std::string& name) const
{
    const std::string text = numberSource(name);
    std::vector<double> values;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');)
    {
        char* end = nullptr;
        const double v = std::strtod(item.c_str(), &end);
        if (item.empty() || *end != '\0' || !std::isfinite(v))
            throw std::runtime_error("--" + name + " expects numbers separated by commas, got '" + text + "'");
        values.push_back(v);
    }
    return values;
}

int CliArgs::integer(const std::string& name) const
{
    return parseInteger(name, numberSource(name));
}

int CliArgs::integer(const std::string& name, int fallback) const
{
    return has(name) ? parseInteger(name, values_.at(name)) : fallback;
}

}  // namespace dynblur_samples
