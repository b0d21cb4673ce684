// SPDX-License-Identifier: Apache-2.0
// Reading the CSV logs the programs take (response logs, recordings' frame and command logs): a
// header line naming the columns, then one record per line; fields separated by ',', ';', tab or
// runs of spaces.
#ifndef DYNBLUR_SAMPLES_CSV_FIELDS_HPP
#define DYNBLUR_SAMPLES_CSV_FIELDS_HPP

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace dynblur_samples {
namespace csv {

//! `s` without leading and trailing blanks (the "C" locale's).
std::string trim(const std::string& s);
//! Fields separated by ',', ';', tab or runs of spaces.
std::vector<std::string> splitFields(const std::string& line);
//! `s` in lower case (ASCII).
std::string lower(std::string s);
//! Throws cv::Exception (StsParseError) "source:line: what".
[[noreturn]] void parseError(const std::string& source, size_t line, const std::string& what);
//! Whether the whole field is one finite number; `value` receives it.
bool toDouble(const std::string& field, double& value);
/** The whole content of a text file; throws cv::Exception "cannot open <what> 'path'" (or "cannot
read") when it cannot. */
std::string readTextFile(const std::string& path, const std::string& what);

}  // namespace csv
}  // namespace dynblur_samples

#endif
