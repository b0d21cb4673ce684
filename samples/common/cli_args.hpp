// A small command-line reader for the actuator-bus programs: "--name value" or "--name=value",
// flags without a value, unknown names refused (a typo must not drive the actuators wrongly).
#ifndef DYNBLUR_SAMPLES_CLI_ARGS_HPP
#define DYNBLUR_SAMPLES_CLI_ARGS_HPP

#include <map>
#include <set>
#include <string>

namespace dynblur_samples {

class CliArgs
{
public:
    /** @param valued option names that take a value; @param flags option names that do not.
    Throws std::runtime_error naming an unknown option or a missing value. */
    CliArgs(int argc, char** argv, const std::set<std::string>& valued, const std::set<std::string>& flags);

    bool has(const std::string& name) const { return values_.count(name) > 0; }
    std::string str(const std::string& name, const std::string& fallback) const;
    //! Throws std::runtime_error when the value is not a number.
    double num(const std::string& name, double fallback) const;
    int integer(const std::string& name, int fallback) const;

private:
    std::map<std::string, std::string> values_;
};

}  // namespace dynblur_samples

#endif
