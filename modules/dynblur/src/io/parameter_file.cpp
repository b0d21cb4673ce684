// SPDX-License-Identifier: Apache-2.0
// ParameterFile: a non-recursive reader of flat YAML / XML / JSON parameter files (see the header
// for why cv::FileStorage's readers are not used on them).
#include "precomp.hpp"

#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace cv {
namespace dynblur {

namespace {

const size_t kMaxBytes = size_t(64) << 20;

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }
bool isNameStart(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool isNameChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'; }

std::string trim(const std::string& s)
{
    size_t a = 0, b = s.size();
    while (a < b && isBlank(s[a]))
        ++a;
    while (b > a && isBlank(s[b - 1]))
        --b;
    return s.substr(a, b - a);
}

//! Shortened, printable copy of a token for messages.
std::string shown(const std::string& token)
{
    std::string s = token.size() > 40 ? token.substr(0, 40) + "..." : token;
    return "'" + s + "'";
}

//! Collects the entries and reports errors with the source and the line.
class Builder
{
public:
    Builder(const std::string& text, const std::string& source) : text_(text), source_(source) {}

    [[noreturn]] void fail(int line, const std::string& what) const
    {
        CV_Error(Error::StsParseError, source_ + ", line " + std::to_string(line) + ": " + what);
    }

    int lineAt(size_t pos) const
    {
        return 1 + static_cast<int>(std::count(text_.begin(), text_.begin() + std::min(pos, text_.size()), '\n'));
    }

    ParameterFile::Entry& add(const std::string& name, bool sequence, int line)
    {
        if (name.empty() || !isNameStart(name[0]) ||
            !std::all_of(name.begin(), name.end(), [](char c) { return isNameChar(c); }))
            fail(line, "the name " + shown(name) + " is not a plain name (a letter or '_', then letters, digits, "
                       "'_', '-' or '.')");
        const auto found = entries.find(name);
        if (found != entries.end())
            fail(line, "'" + name + "' appears twice (first on line " + std::to_string(found->second.line) + ")");
        ParameterFile::Entry& e = entries[name];
        e.sequence = sequence;
        e.line = line;
        return e;
    }

    std::map<std::string, ParameterFile::Entry> entries;

private:
    const std::string& text_;
    const std::string& source_;
};

//! A quoted string starting at s[i] (' or "), on one line; returns its content, i past the closing quote.
std::string readQuoted(const std::string& s, size_t& i, const Builder& b, int line)
{
    const char q = s[i++];
    std::string out;
    while (i < s.size() && s[i] != '\n')
    {
        const char c = s[i++];
        if (c == q)
        {
            if (q == '\'' && i < s.size() && s[i] == '\'')  // YAML's '' inside '...'
            {
                out += '\'';
                ++i;
                continue;
            }
            return out;
        }
        if (c == '\\' && q == '"' && i < s.size() && s[i] != '\n')
            out += s[i++];
        else
            out += c;
    }
    b.fail(line, "a string opened with " + std::string(1, q) + " is not closed on its line");
}

// ---- YAML -------------------------------------------------------------------------------------

//! Removes a # comment (at the start or after a blank, outside quotes).
std::string stripYamlComment(const std::string& line)
{
    char quote = 0;
    for (size_t i = 0; i < line.size(); ++i)
    {
        const char c = line[i];
        if (quote)
        {
            if (c == quote)
                quote = 0;
            else if (c == '\\' && quote == '"')
                ++i;
        }
        else if (c == '\'' || c == '"')
            quote = c;
        else if (c == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t'))
            return line.substr(0, i);
    }
    return line;
}

//! One YAML scalar (plain or quoted) that must fill `v` (already trimmed).
std::string yamlScalar(const std::string& v, const Builder& b, int line)
{
    if (v[0] == '\'' || v[0] == '"')
    {
        size_t i = 0;
        std::string s = readQuoted(v, i, b, line);
        if (!trim(v.substr(i)).empty())
            b.fail(line, "text after the quoted string: " + shown(trim(v.substr(i))));
        return s;
    }
    if (v.find_first_of("[]{}") != std::string::npos || (v[0] == '-' && v.size() > 1 && v[1] == ' ') ||
        v.find(": ") != std::string::npos || v[0] == '&' || v[0] == '*' || v[0] == '!' || v[0] == '|' || v[0] == '>')
        b.fail(line, "the value " + shown(v) + " is not a number, a word or a quoted string (nested collections, "
                     "anchors, tags and multi-line text are not supported)");
    return v;
}

//! Feeds the items of an open flow sequence from t[i...] (one line): "a, b, ]". Closes `flow` at ']'.
void feedFlow(const std::string& t, size_t i, ParameterFile::Entry*& flow, bool& expectsItem, const Builder& b,
              int line)
{
    while (flow && i < t.size())
    {
        const char c = t[i];
        if (c == ' ' || c == '\t')
        {
            ++i;
            continue;
        }
        if (c == ']')
        {
            if (expectsItem && !flow->tokens.empty())
                b.fail(line, "a sequence item is missing before ']'");
            flow = nullptr;
            if (!trim(t.substr(i + 1)).empty())
                b.fail(line, "text after the sequence: " + shown(trim(t.substr(i + 1))));
            return;
        }
        if (c == ',')
        {
            if (expectsItem)
                b.fail(line, "a sequence item is missing before ','");
            expectsItem = true;
            ++i;
            continue;
        }
        if (!expectsItem)
            b.fail(line, "',' or ']' expected between sequence items, found " + shown(t.substr(i)));
        std::string item;
        if (c == '\'' || c == '"')
            item = readQuoted(t, i, b, line);
        else
        {
            const size_t end = std::min(t.find_first_of(",]", i), t.size());
            item = trim(t.substr(i, end - i));
            i = end;
            if (item.find_first_of("[{}") != std::string::npos)
                b.fail(line, "nested collections are not supported: " + shown(item));
        }
        flow->tokens.push_back(item);
        expectsItem = false;
    }
}

void parseYaml(const std::string& text, Builder& b)
{
    std::istringstream in(text);
    std::string raw;
    int lineNo = 0;
    bool started = false, ended = false;
    ParameterFile::Entry* block = nullptr;  // entry "name:" taking "- item" lines
    ParameterFile::Entry* flow = nullptr;   // "[" sequence going on over lines
    bool expectsItem = true;
    while (std::getline(in, raw))
    {
        ++lineNo;
        const std::string line = stripYamlComment(raw);
        const std::string t = trim(line);
        if (t.empty())
            continue;
        if (ended)
            b.fail(lineNo, "text after the end of the document ('...'): " + shown(t));
        if (flow)
        {
            feedFlow(t, 0, flow, expectsItem, b, lineNo);
            continue;
        }
        if (t.compare(0, 5, "%YAML") == 0)
        {
            if (started)
                b.fail(lineNo, "'%YAML' must come first");
            if (t.compare(0, 8, "%YAML:1.") != 0 && t.compare(0, 8, "%YAML 1.") != 0)
                b.fail(lineNo, "only YAML 1.x is supported, found " + shown(t));
            continue;
        }
        if (t == "---")
        {
            if (started)
                b.fail(lineNo, "only one YAML document is read ('---' after the entries)");
            started = true;
            continue;
        }
        started = true;
        if (t == "...")
        {
            ended = true;
            continue;
        }
        if (t[0] == '-' && (t.size() == 1 || t[1] == ' ' || t[1] == '\t'))
        {
            if (!block)
                b.fail(lineNo, "a '- item' line belongs under a 'name:' line that has no value");
            const std::string v = trim(t.substr(1));
            if (v.empty())
                b.fail(lineNo, "an empty '- ' item");
            block->tokens.push_back(yamlScalar(v, b, lineNo));
            continue;
        }
        if (line[0] == ' ' || line[0] == '\t')
            b.fail(lineNo, "an entry 'name: value' starts at column 1 (nested maps are not supported): " + shown(t));
        size_t colon = 0;
        std::string name;
        if (t[0] == '"' || t[0] == '\'')
        {
            name = readQuoted(t, colon, b, lineNo);
            while (colon < t.size() && t[colon] == ' ')
                ++colon;
        }
        else
        {
            colon = std::min(t.find(':'), t.size());
            name = trim(t.substr(0, colon));
        }
        if (colon >= t.size() || t[colon] != ':' || (colon + 1 < t.size() && t[colon + 1] != ' ' && t[colon + 1] != '\t'))
            b.fail(lineNo, "expected 'name: value', found " + shown(t));
        const std::string v = trim(t.substr(colon + 1));
        block = nullptr;
        if (v.empty())
            block = &b.add(name, true, lineNo);
        else if (v[0] == '[')
        {
            flow = &b.add(name, true, lineNo);
            expectsItem = true;
            feedFlow(v, 1, flow, expectsItem, b, lineNo);
        }
        else
            b.add(name, false, lineNo).tokens.push_back(yamlScalar(v, b, lineNo));
    }
    if (flow)
        b.fail(flow->line, "the sequence opened with '[' is not closed");
}

// ---- XML --------------------------------------------------------------------------------------

//! Skips blanks and <!-- comments -->.
void skipXmlSpace(const std::string& s, size_t& i, const Builder& b)
{
    for (;;)
    {
        while (i < s.size() && isBlank(s[i]))
            ++i;
        if (s.compare(i, 4, "<!--") != 0)
            return;
        const size_t end = s.find("-->", i + 4);
        if (end == std::string::npos)
            b.fail(b.lineAt(i), "the comment '<!--' is not closed");
        i = end + 3;
    }
}

//! Decodes the five predefined entities; refuses others.
std::string xmlText(const std::string& s, const Builder& b, size_t at)
{
    std::string out;
    for (size_t i = 0; i < s.size(); ++i)
    {
        if (s[i] != '&')
        {
            out += s[i];
            continue;
        }
        static const char* const names[5][2] = {{"&lt;", "<"}, {"&gt;", ">"}, {"&amp;", "&"}, {"&quot;", "\""},
                                                {"&apos;", "'"}};
        bool known = false;
        for (const auto& n : names)
            if (s.compare(i, std::strlen(n[0]), n[0]) == 0)
            {
                out += n[1];
                i += std::strlen(n[0]) - 1;
                known = true;
                break;
            }
        if (!known)
            b.fail(b.lineAt(at + i), "only the entities &lt; &gt; &amp; &quot; &apos; are supported");
    }
    return out;
}

void parseXml(const std::string& text, Builder& b)
{
    size_t i = 0;
    skipXmlSpace(text, i, b);
    if (text.compare(i, 5, "<?xml") == 0)
    {
        const size_t end = text.find("?>", i);
        if (end == std::string::npos)
            b.fail(b.lineAt(i), "the declaration '<?xml' is not closed with '?>'");
        i = end + 2;
    }
    skipXmlSpace(text, i, b);
    const std::string root = "<opencv_storage>";
    if (text.compare(i, root.size(), root) != 0)
        b.fail(b.lineAt(i), "expected " + root + " (the root element cv::FileStorage writes)");
    i += root.size();
    for (;;)
    {
        skipXmlSpace(text, i, b);
        const int line = b.lineAt(i);
        if (i >= text.size())
            b.fail(line, "</opencv_storage> is missing");
        if (text.compare(i, 2, "</") == 0)
        {
            if (text.compare(i, root.size() + 1, "</opencv_storage>") != 0)
                b.fail(line, "expected </opencv_storage> or an element, found " + shown(text.substr(i, 30)));
            i += root.size() + 1;
            skipXmlSpace(text, i, b);
            if (i < text.size())
                b.fail(b.lineAt(i), "text after </opencv_storage>: " + shown(text.substr(i, 30)));
            return;
        }
        if (text[i] != '<')
            b.fail(line, "expected an element <name>, found " + shown(text.substr(i, 30)));
        const size_t close = text.find('>', i);
        if (close == std::string::npos)
            b.fail(line, "the tag " + shown(text.substr(i, 30)) + " is not closed with '>'");
        std::string name = text.substr(i + 1, close - i - 1);
        const bool empty = !name.empty() && name.back() == '/';
        if (empty)
            name.pop_back();
        if (name.find_first_of(" \t\r\n=\"'") != std::string::npos)
            b.fail(line, "attributes are not supported: " + shown(text.substr(i, close - i + 1)));
        ParameterFile::Entry& e = b.add(name, false, line);
        i = close + 1;
        if (empty)
        {
            e.sequence = true;
            continue;
        }
        const size_t end = text.find('<', i);
        const std::string closing = "</" + name + ">";
        if (end == std::string::npos || text.compare(end, closing.size(), closing) != 0)
            b.fail(b.lineAt(std::min(end, text.size())), "expected " + closing + " (nested elements are not supported)");
        const std::string content = xmlText(text.substr(i, end - i), b, i);
        // Whitespace-separated tokens; a "quoted string" is one token.
        for (size_t k = 0; k < content.size();)
        {
            if (isBlank(content[k]))
            {
                ++k;
                continue;
            }
            if (content[k] == '"')
            {
                const size_t q = content.find('"', k + 1);
                if (q == std::string::npos)
                    b.fail(line, "a string opened with \" is not closed in <" + name + ">");
                e.tokens.push_back(content.substr(k + 1, q - k - 1));
                k = q + 1;
                continue;
            }
            size_t q = k;
            while (q < content.size() && !isBlank(content[q]))
                ++q;
            e.tokens.push_back(content.substr(k, q - k));
            k = q;
        }
        e.sequence = e.tokens.size() != 1;
        i = end + closing.size();
    }
}

// ---- JSON -------------------------------------------------------------------------------------

//! Skips blanks and // line comments.
void skipJsonSpace(const std::string& s, size_t& i)
{
    for (;;)
    {
        while (i < s.size() && isBlank(s[i]))
            ++i;
        if (s.compare(i, 2, "//") != 0)
            return;
        i = std::min(s.find('\n', i), s.size());
    }
}

//! A JSON scalar at s[i]: a string, or a run of number / literal characters.
std::string jsonScalar(const std::string& s, size_t& i, const Builder& b)
{
    const int line = b.lineAt(i);
    if (i >= s.size())
        b.fail(line, "a value is missing at the end of the file");
    if (s[i] == '"')
        return readQuoted(s, i, b, line);
    if (s[i] == '{' || s[i] == '[')
        b.fail(line, "nested objects and arrays are not supported");
    const size_t start = i;
    while (i < s.size() && (std::isalnum(static_cast<unsigned char>(s[i])) || s[i] == '.' || s[i] == '+' || s[i] == '-'))
        ++i;
    if (i == start)
        b.fail(line, "expected a value, found " + shown(s.substr(start, 30)));
    return s.substr(start, i - start);
}

void parseJson(const std::string& text, Builder& b)
{
    size_t i = 0;
    skipJsonSpace(text, i);
    ++i;  // '{', checked by the caller
    bool first = true;
    for (;;)
    {
        skipJsonSpace(text, i);
        if (i < text.size() && text[i] == '}' && first)
            break;
        if (i >= text.size() || text[i] != '"')
            b.fail(b.lineAt(i), "expected a member \"name\": value");
        const int line = b.lineAt(i);
        const std::string name = readQuoted(text, i, b, line);
        skipJsonSpace(text, i);
        if (i >= text.size() || text[i] != ':')
            b.fail(b.lineAt(i), "expected ':' after \"" + name + "\"");
        ++i;
        skipJsonSpace(text, i);
        if (i < text.size() && text[i] == '[')
        {
            ParameterFile::Entry& e = b.add(name, true, line);
            ++i;
            skipJsonSpace(text, i);
            if (i < text.size() && text[i] == ']')
                ++i;
            else
                for (;;)
                {
                    skipJsonSpace(text, i);
                    e.tokens.push_back(jsonScalar(text, i, b));
                    skipJsonSpace(text, i);
                    if (i < text.size() && text[i] == ',')
                    {
                        ++i;
                        continue;
                    }
                    if (i < text.size() && text[i] == ']')
                    {
                        ++i;
                        break;
                    }
                    b.fail(b.lineAt(i), "expected ',' or ']' in the array \"" + name + "\"");
                }
        }
        else
            b.add(name, false, line).tokens.push_back(jsonScalar(text, i, b));
        skipJsonSpace(text, i);
        first = false;
        if (i < text.size() && text[i] == ',')
        {
            ++i;
            continue;
        }
        if (i < text.size() && text[i] == '}')
            break;
        b.fail(b.lineAt(i), "expected ',' or '}' after the member \"" + name + "\"");
    }
    ++i;
    skipJsonSpace(text, i);
    if (i < text.size())
        b.fail(b.lineAt(i), "text after the closing '}': " + shown(text.substr(i, 30)));
}

bool toReal(const std::string& token, double& value)
{
    if (token.empty() || isBlank(token[0]))
        return false;
    errno = 0;
    char* end = nullptr;
    value = std::strtod(token.c_str(), &end);
    return end == token.c_str() + token.size() && errno != ERANGE && std::isfinite(value);
}

bool toInt(const std::string& token, int& value)
{
    if (token.empty() || !(std::isdigit(static_cast<unsigned char>(token[0])) || token[0] == '-' || token[0] == '+'))
        return false;
    errno = 0;
    char* end = nullptr;
    const long long v = std::strtoll(token.c_str(), &end, 10);
    if (end != token.c_str() + token.size() || errno == ERANGE || v < INT_MIN || v > INT_MAX)
        return false;
    value = static_cast<int>(v);
    return true;
}

}  // namespace

ParameterFile ParameterFile::load(const String& filename, const String& what)
{
    std::ifstream in(filename.c_str(), std::ios::binary);
    if (!in)
    {
        // "Where: the timing file" reads "Where: cannot open the timing file 'name'".
        const size_t colon = what.rfind(": ");
        const String where = colon == String::npos ? String() : what.substr(0, colon + 2);
        const String noun = colon == String::npos ? what : what.substr(colon + 2);
        CV_Error(Error::StsError, where + "cannot open the " + noun + " '" + filename + "'");
    }
    std::string text;
    char chunk[65536];
    while (in.read(chunk, sizeof(chunk)) || in.gcount() > 0)
    {
        text.append(chunk, static_cast<size_t>(in.gcount()));
        if (text.size() > kMaxBytes)
            CV_Error(Error::StsParseError, what + " '" + filename + "' is larger than 64 MiB");
    }
    if (in.bad())
        CV_Error(Error::StsError, "cannot read " + what + " '" + filename + "'");
    return parse(text, what + " '" + filename + "'");
}

ParameterFile ParameterFile::parse(const std::string& text, const String& source)
{
    if (text.size() > kMaxBytes)
        CV_Error(Error::StsParseError, source + " is larger than 64 MiB");
    Builder b(text, source);
    int line = 1;
    for (size_t i = 0; i < text.size(); ++i)
    {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        if (c == '\n')
            ++line;
        else if (c < 0x20 && c != '\t' && c != '\r')
            b.fail(line, format("control character 0x%02X; the text may hold tab, CR and LF and characters from 0x20 "
                                "up only", c));
    }
    ParameterFile file;
    file.source_ = source;
    size_t first = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;  // UTF-8 byte order mark
    const std::string body = text.substr(first);
    first = 0;
    while (first < body.size() && isBlank(body[first]))
        ++first;
    if (first == body.size())
        CV_Error(Error::StsParseError, source + " is empty");
    Builder parser(body, source);
    if (body[first] == '<')
    {
        file.xml_ = true;
        parseXml(body, parser);
    }
    else if (body[first] == '{')
        parseJson(body, parser);
    else
        parseYaml(body, parser);
    file.entries_.swap(parser.entries);
    return file;
}

bool ParameterFile::has(const String& name) const { return entries_.count(name) > 0; }

std::vector<String> ParameterFile::names() const
{
    std::vector<String> out;
    for (const auto& e : entries_)
        out.push_back(e.first);
    return out;
}

const ParameterFile::Entry& ParameterFile::entry(const String& name) const
{
    const auto found = entries_.find(name);
    if (found == entries_.end())
        CV_Error(Error::StsParseError, source_ + " has no entry '" + name + "'");
    return found->second;
}

std::string ParameterFile::where(const Entry& e) const { return source_ + ", line " + std::to_string(e.line); }

namespace {

const char* const kIntRange = " is not an integer in [-2147483648, 2147483647]";

//! The tokens of `e` converted by `convert`; `what` describes a bad one in the message.
template <typename T, typename Convert>
std::vector<T> convertTokens(const ParameterFile::Entry& e, const std::string& where, const String& name,
                             Convert convert, const char* what)
{
    std::vector<T> out(e.tokens.size());
    for (size_t k = 0; k < out.size(); ++k)
        if (!convert(e.tokens[k], out[k]))
            CV_Error(Error::StsParseError, where + format(": '%s'[%zu] = ", name.c_str(), k) + shown(e.tokens[k]) + what);
    return out;
}

}  // namespace

double ParameterFile::real(const String& name) const
{
    const Entry& e = scalar(name, "number");
    double v = 0;
    if (!toReal(e.tokens[0], v))
        CV_Error(Error::StsParseError, where(e) + ": '" + name + "' = " + shown(e.tokens[0]) + " is not a finite number");
    return v;
}

int ParameterFile::integer(const String& name) const
{
    const Entry& e = scalar(name, "integer");
    int v = 0;
    if (!toInt(e.tokens[0], v))
        CV_Error(Error::StsParseError, where(e) + ": '" + name + "' = " + shown(e.tokens[0]) + kIntRange);
    return v;
}

std::vector<double> ParameterFile::reals(const String& name) const
{
    return convertTokens<double>(sequence(name, "numbers, e.g. [0.0, 0.002]"), where(entry(name)), name, toReal,
                                 " is not a finite number");
}

std::vector<int> ParameterFile::integers(const String& name) const
{
    return convertTokens<int>(sequence(name, "integers, e.g. [4, 8]"), where(entry(name)), name, toInt, kIntRange);
}

const ParameterFile::Entry& ParameterFile::scalar(const String& name, const char* kind) const
{
    const Entry& e = entry(name);
    if (e.tokens.size() != 1 || (e.sequence && !xml_))
        CV_Error(Error::StsParseError, where(e) + ": '" + name + "' must be one " + kind +
                                           (e.tokens.empty() ? ", it has no value" : ", not a sequence"));
    return e;
}

const ParameterFile::Entry& ParameterFile::sequence(const String& name, const char* kind) const
{
    const Entry& e = entry(name);
    if (!e.sequence && !xml_)
        CV_Error(Error::StsParseError, where(e) + ": '" + name + "' must be a sequence of " + kind);
    return e;
}

}  // namespace dynblur
}  // namespace cv
