// SPDX-License-Identifier: Apache-2.0
#include "cli_args.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace dynblur_samples {

CliArgs::CliArgs(int argc, char** argv, const std::set<std::string>& valued, const std::set<std::string>& flags,
                 bool allowPositional)
{
    for (int i = 1; i < argc; ++i)
    {
        std::string arg = argv[i];
        const bool isOption = arg.size() >= 2 && arg[0] == '-' && !std::isdigit(static_cast<unsigned char>(arg[1]))
                              && arg[1] != '.';
        if (!isOption)
        {
            if (!allowPositional)
                throw std::runtime_error("unexpected argument '" + arg + "' (options start with --)");
            positional_.push_back(arg);
            continue;
        }
        if (arg == "-h")
            arg = "--help";
        arg = arg.substr(arg.find_first_not_of('-'));
        std::string name = arg, value;
        const size_t eq = arg.find('=');
        bool hasValue = eq != std::string::npos;
        if (hasValue)
        {
            name = arg.substr(0, eq);
            value = arg.substr(eq + 1);
        }
        if (valued.count(name))
        {
            if (!hasValue)
            {
                if (i + 1 >= argc)
                    throw std::runtime_error("option --" + name + " needs a value");
                value = argv[++i];
            }
        }
        else if (flags.count(name))
        {
            if (hasValue)
                throw std::runtime_error("option --" + name + " takes no value");
        }
        else
            throw std::runtime_error("unknown option '" + std::string(argv[i]) + "' (see --help)");
        values_[name] = value;
    }
}

std::string CliArgs::str(const std::string& name, const std::string& fallback) const
{
    const auto it = values_.find(name);
    return it == values_.end() ? fallback : it->second;
}

double CliArgs::num(const std::string& name, double fallback) const
{
    const auto it = values_.find(name);
    if (it == values_.end())
        return fallback;
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (it->second.empty() || *end != '\0' || !std::isfinite(v))
        throw std::runtime_error("--" + name + " expects a number, got '" + it->second + "'");
    return v;
}

int CliArgs::integer(const std::string& name, int fallback) const
{
    const double v = num(name, fallback);
    if (v != std::floor(v) || std::abs(v) > 2147483647.0)
        throw std::runtime_error("--" + name + " expects an integer, got '" + str(name, "") + "'");
    return static_cast<int>(v);
}

}  // namespace dynblur_samples
