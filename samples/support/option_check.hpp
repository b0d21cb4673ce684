// cv::CommandLineParser silently ignores options it does not know: a typo would run with the
// default instead. This checks argv against the parser's own key string first.
#ifndef DYNBLUR_SAMPLES_OPTION_CHECK_HPP
#define DYNBLUR_SAMPLES_OPTION_CHECK_HPP

#include <string>

namespace dynblur_samples {

/** Returns "" when every argument is a known option of `keys` (CommandLineParser syntax:
    "{name alias | default | help}..."), written --name, --name=value or -n; otherwise a message
    naming the first offending argument. */
std::string unknownOption(int argc, const char* const* argv, const std::string& keys);

}  // namespace dynblur_samples

#endif
