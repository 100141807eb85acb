// Parsing a command's words (command_line.hpp).
#include "common/command_line.hpp"

#include "hsr/error.hpp"
#include "hsr/spelling.hpp"

#include <algorithm>
#include <optional>
#include <string_view>

namespace po = boost::program_options;

po::parsed_options hsr::host::parse_command_line(po::command_line_parser& parser, const po::options_description& shown) {
    try {
        return parser.run();
    } catch (const po::unknown_option& e) {
        const std::string typed = e.get_option_name();
        // "--widht=64" is named with its value in some versions of Boost.
        const std::string name = typed.substr(0, typed.find('='));
        // Compared without their dashes, which every option shares and which would make a long name
        // of a short slip.
        std::vector<std::string> known;
        for (const auto& option : shown.options())
            if (!option->long_name().empty()) known.push_back(option->long_name());
        const std::size_t dashes = std::min(name.find_first_not_of('-'), name.size());
        const std::optional<std::string> closest = hsr::closest_spelling(std::string_view(name).substr(dashes), known);
        throw hsr::UsageError("unknown option {}{}", hsr::printable(name),
                              closest ? " (did you mean --" + *closest + "?)" : "");
    }
}
