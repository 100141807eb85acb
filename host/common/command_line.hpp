// A command's words parsed against its options, as every command parses them: an unknown option is a
// UsageError that suggests the nearest known one.
#pragma once

#include <boost/program_options.hpp>

#include <string>
#include <vector>

namespace hsr::host {

// Runs the parser. An unknown option is a UsageError, "unknown option --widht (did you mean
// --width?)", the suggestion taken from the options of `shown` (those --help lists).
boost::program_options::parsed_options parse_command_line(boost::program_options::command_line_parser& parser,
                                                          const boost::program_options::options_description& shown);

}  // namespace hsr::host
