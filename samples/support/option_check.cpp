#include "option_check.hpp"

#include <set>
#include <sstream>

namespace dynblur_samples {

std::string unknownOption(int argc, const char* const* argv, const std::string& keys)
{
    // Names are the words before the first '|' of each "{...}" entry.
    std::set<std::string> known;
    for (size_t open = keys.find('{'); open != std::string::npos; open = keys.find('{', open + 1))
    {
        const size_t bar = keys.find('|', open);
        std::istringstream names(keys.substr(open + 1, bar - open - 1));
        for (std::string name; names >> name;)
            known.insert(name);
    }
    for (int i = 1; i < argc; ++i)
    {
        const std::string argument = argv[i];
        if (argument.size() < 2 || argument[0] != '-')
            return "unexpected argument '" + argument + "' (options are written --name=value)";
        const std::string name = argument.substr(argument.find_first_not_of('-'));
        if (!known.count(name.substr(0, name.find('='))))
            return "unknown option '" + argument + "' (see --help)";
    }
    return "";
}

}  // namespace dynblur_samples
