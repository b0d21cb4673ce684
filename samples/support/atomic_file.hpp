// SPDX-License-Identifier: Apache-2.0
// Writing output files so that none is ever half-written: write to a temporary name beside the
// target, then rename it into place (a rename within one folder is atomic).
#ifndef DYNBLUR_SAMPLES_ATOMIC_FILE_HPP
#define DYNBLUR_SAMPLES_ATOMIC_FILE_HPP

#include <string>

namespace dynblur_samples {

//! "dir/name.ext" -> "dir/name"; a path without an extension is kept whole.
std::string pathStem(const std::string& path);

//! Temporary file name for `path`, in the same folder and with the same extension (so writers that
//! choose the format by extension still do).
std::string temporaryPathFor(const std::string& path);

//! Renames `temporary` to `path`; on failure removes `temporary` and throws cv::Exception.
void renameIntoPlace(const std::string& temporary, const std::string& path);

//! Writes `text` to `path` whole (a temporary file renamed into place); throws cv::Exception naming `path`.
void writeTextFile(const std::string& path, const std::string& text);

}  // namespace dynblur_samples

#endif
