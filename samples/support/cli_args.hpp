// SPDX-License-Identifier: Apache-2.0
// The one command-line reader of every program (samples/, calib/): "--name value" or
// "--name=value", flags without a value, positional arguments where a program takes them, unknown
// names refused (a typo must not drive the actuators or calibrate with a default).
#ifndef DYNBLUR_SAMPLES_CLI_ARGS_HPP
#define DYNBLUR_SAMPLES_CLI_ARGS_HPP

#include <map>
#include <set>
#include <string>
#include <vector>

namespace dynblur_samples {

class CliArgs
{
public:
    /** @param valued option names that take a value; @param flags option names that do not.
    @param allowPositional accept arguments that are not options (file names, negative numbers).
    Throws std::runtime_error naming an unknown option, a missing value or an unexpected argument. */
    CliArgs(int argc, char** argv, const std::set<std::string>& valued, const std::set<std::string>& flags,
            bool allowPositional = false);

    bool has(const std::string& name) const { return values_.count(name) > 0; }
    std::string str(const std::string& name, const std::string& fallback) const;
    //! Throws std::runtime_error when the value is not a number.
    double num(const std::string& name, double fallback) const;
    int integer(const std::string& name, int fallback) const;
    //! Arguments that are not options, in order (only with allowPositional).
    const std::vector<std::string>& positional() const { return positional_; }

private:
    std::map<std::string, std::string> values_;
    std::vector<std::string> positional_;
};

}  // namespace dynblur_samples

#endif
