// Command-line parsing shared by the calibration tools: options as `--name value` or
// `--name=value`, flags as `--name`, everything else positional. Unknown options are errors
// (a typo must not calibrate with a default).
#ifndef DYNBLUR_CALIB_CLI_ARGS_HPP
#define DYNBLUR_CALIB_CLI_ARGS_HPP

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynblur_calib {

class Args
{
public:
    /** @param valued options that take a value; @param flags options that do not. Names without "--". */
    Args(int argc, char** argv, const std::set<std::string>& valued, const std::set<std::string>& flags)
    {
        for (int i = 1; i < argc; ++i)
        {
            std::string arg = argv[i];
            if (arg.size() < 2 || arg[0] != '-' || (arg.size() > 1 && (std::isdigit((unsigned char)arg[1]) || arg[1] == '.')))
            {
                positional_.push_back(arg);
                continue;
            }
            if (arg == "-h")
                arg = "--help";
            if (arg.compare(0, 2, "--") != 0)
                throw std::runtime_error("unknown option '" + arg + "' (see --help)");
            std::string name = arg.substr(2), value;
            const size_t eq = name.find('=');
            const bool inlineValue = eq != std::string::npos;
            if (inlineValue)
            {
                value = name.substr(eq + 1);
                name = name.substr(0, eq);
            }
            if (flags.count(name))
            {
                if (inlineValue)
                    throw std::runtime_error("option '--" + name + "' takes no value");
                flags_.insert(name);
            }
            else if (valued.count(name))
            {
                if (!inlineValue)
                {
                    if (i + 1 >= argc)
                        throw std::runtime_error("option '--" + name + "' needs a value");
                    value = argv[++i];
                }
                values_[name] = value;
            }
            else
                throw std::runtime_error("unknown option '" + arg + "' (see --help)");
        }
    }

    bool has(const std::string& name) const { return flags_.count(name) > 0 || values_.count(name) > 0; }
    const std::vector<std::string>& positional() const { return positional_; }

    std::string get(const std::string& name, const std::string& fallback) const
    {
        auto it = values_.find(name);
        return it == values_.end() ? fallback : it->second;
    }

    double number(const std::string& name, double fallback) const
    {
        auto it = values_.find(name);
        if (it == values_.end())
            return fallback;
        errno = 0;
        char* end = nullptr;
        const double v = std::strtod(it->second.c_str(), &end);
        if (it->second.empty() || *end != '\0' || errno != 0 || !std::isfinite(v))
            throw std::runtime_error("--" + name + " '" + it->second + "' is not a number");
        return v;
    }

    int integer(const std::string& name, int fallback) const
    {
        const double v = number(name, fallback);
        if (v != std::floor(v) || std::abs(v) > 1e9)
            throw std::runtime_error("--" + name + " '" + get(name, "") + "' is not an integer");
        return static_cast<int>(v);
    }

private:
    std::map<std::string, std::string> values_;
    std::set<std::string> flags_;
    std::vector<std::string> positional_;
};

}  // namespace dynblur_calib

#endif
