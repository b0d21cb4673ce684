// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_PARAMETER_FILE_HPP
#define OPENCV_DYNBLUR_PARAMETER_FILE_HPP

#include <opencv2/core.hpp>

#include <map>
#include <string>
#include <vector>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_motion
//! @{

/** @brief Reader of the module's parameter files: flat maps of names to numbers or sequences of
numbers, in the YAML, XML or JSON form cv::FileStorage writes (SwitchSchedule::save, the plant files
of the sample programs).

These files come from outside the program, so they are not handed to cv::FileStorage's readers,
which trust their input: in OpenCV 4.6 some malformed files hang the YAML reader, crash the XML
reader or exhaust the stack of all three (found by fuzz/fuzz_schedule_file and fuzz_plant_file).
This reader accepts the flat subset only, never recurses, and refuses anything else with a
cv::Exception (StsParseError) naming the file, the line and what is allowed. The format is told by
the first character: `<` XML, `{` JSON, anything else YAML.

- YAML: optional `%YAML:1.x` (or `%YAML 1.x`) and `---` lines, then one `name: value` line per entry
  at column 0: a scalar (number, word or quoted string), a flow sequence `[a, b, ...]` (it may go on
  over several lines), or nothing, then block items `- a` on the next lines; `#` comments; `...`
  ends the document.
- XML: optional `<?xml ...?>` and comments, then `<opencv_storage>` holding `<name>tokens</name>`
  elements (whitespace-separated tokens: one is a scalar, several a sequence).
- JSON: one object of `"name": value` members, a value being a number, a string, true, false, null
  or an array of those; `//` line comments.

Text is ASCII or UTF-8 with tab, CR and LF as the only control characters; at most 64 MiB.
*/
class CV_EXPORTS ParameterFile
{
public:
    /** @brief Reads and parses a file.
    @param filename path of the file.
    @param what what the file is, for the messages (e.g. "schedule file", or "Where: schedule file"
    for "Where: cannot open the schedule file 'name'"). */
    static ParameterFile load(const String& filename, const String& what);
    /** @brief Parses text. @param text the file's content. @param source names it in messages. */
    static ParameterFile parse(const std::string& text, const String& source);

    //! @brief Whether the file has an entry `name`.
    bool has(const String& name) const;
    //! @brief The names of the entries, sorted.
    std::vector<String> names() const;
    /** @brief The finite number `name`; throws naming it when it is absent, a sequence or not a number. */
    double real(const String& name) const;
    /** @brief The integer `name` (in int's range); throws naming it otherwise. */
    int integer(const String& name) const;
    /** @brief The sequence of finite numbers `name` (XML: one or more tokens); throws naming the
    entry, and the index of a bad element, otherwise. */
    std::vector<double> reals(const String& name) const;
    /** @brief The sequence of integers `name` (in int's range); throws naming the entry and index otherwise. */
    std::vector<int> integers(const String& name) const;

    //! @brief One entry as read: its tokens, whether it is a sequence, and its line (1-based).
    struct Entry
    {
        std::vector<std::string> tokens;
        bool sequence = false;
        int line = 0;
    };

private:
    const Entry& entry(const String& name) const;
    const Entry& scalar(const String& name, const char* kind) const;    //!< throws unless one token
    const Entry& sequence(const String& name, const char* kind) const;  //!< throws unless a sequence
    std::string where(const Entry& e) const;

    std::string source_;
    bool xml_ = false;  //!< XML does not tell a one-element sequence from a scalar
    std::map<std::string, Entry> entries_;
};

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
