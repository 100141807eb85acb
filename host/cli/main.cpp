// hsr: the command-line host. main() hands the arguments to a command (commands.hpp) and turns its
// errors into a one-line message and an exit status; the work lives in framework/ and plugins/.
#include "bench/bench_worker.hpp"
#include "common/commands.hpp"
#include "common/options.hpp"

#include "hsr/abi.h"
#include "hsr/error.hpp"
#include "hsr/plugin_faults.hpp"
#include "hsr/spelling.hpp"

#include <boost/program_options.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <exception>
#include <iostream>
#include <new>
#include <string>
#include <vector>

namespace {

const char* usage_text =
    "usage: hsr <command> [options]\n"
    "\n"
    "commands:\n"
    "  render MODEL   render a mesh (OBJ, OFF, PLY, STL) or a .scene file to PNG, or draw its\n"
    "                 visible edges to SVG/PNG with a hidden-line plugin (--algorithm appel)\n"
    "  plugins        list the plugins found, with their parameters\n"
    "  bench          time algorithms on models and deep scenes: table, CSV, SVG plot\n"
    "  view [MODEL]   look at models in a web browser: every plugin, its parameters and its steps\n"
    "\n"
    "  hsr --version  versions of hsr and of its plugin ABI\n"
    "  hsr <command> --help\n";

// The commands people run, for a mistyped one's suggestion.
const std::vector<std::string> command_names{"render", "plugins", "bench", "view"};

// Where a mistake in `command`'s words is explained: the command's own --help, which lists its
// options, or hsr's for a command that is not one.
std::string help_hint(const std::string& command) {
    const bool known = std::find(command_names.begin(), command_names.end(), command) != command_names.end();
    return known ? " (see hsr " + command + " --help)" : " (see hsr --help)";
}

}  // namespace

int main(int argc, char** argv) {
    using hsr::host::UsageError;
    hsr::report_plugin_faults();
    std::vector<std::string> args(argv + 1, argv + argc);
    std::string command;
    try {
        if (args.empty()) {
            std::cerr << usage_text;
            return 2;
        }
        command = args.front();
        args.erase(args.begin());
        hsr::host::check_argument_count(args.size());
        if (command == "--help" || command == "-h" || command == "help") {
            std::cout << usage_text;
            return 0;
        }
        if (command == "--version") {
            std::cout << fmt::format("hsr {} (plugin ABI {}.{})\n", HSR_VERSION, HSR_ABI_MAJOR, HSR_ABI_MINOR);
            return 0;
        }
        if (command == "render") return hsr::host::run_render(args);
        if (command == "plugins") return hsr::host::run_plugins(args);
        if (command == "bench") return hsr::host::run_bench(args);
        if (command == "view") return hsr::host::run_view(args);
        if (command == "view-worker") return hsr::host::run_view_worker(args);
        if (command == hsr::host::kBenchWorkerCommand) return hsr::host::run_bench_worker(args);  // hsr bench's own
        std::vector<std::string> known = command_names;
        known.insert(known.end(), {"--help", "--version"});
        const std::string suggestion = hsr::did_you_mean(command, known);
        throw UsageError("unknown command '{}'{}", hsr::printable(command),
                         suggestion.empty() ? " (commands: render, plugins, bench, view)" : suggestion);
    } catch (const UsageError& e) {
        std::cerr << "hsr: error: " << hsr::host::message_line(e.what()) << help_hint(command) << "\n";
        return 2;
    } catch (const boost::program_options::error& e) {
        std::cerr << "hsr: error: " << hsr::host::message_line(e.what()) << help_hint(command) << "\n";
        return 2;
    } catch (const hsr::Error& e) {
        std::cerr << "hsr: error: " << hsr::host::message_line(e.what()) << "\n";
        return 1;
    } catch (const std::bad_alloc&) {
        std::cerr << "hsr: error: out of memory\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "hsr: error: " << hsr::host::message_line(e.what()) << "\n";
        return 1;
    }
}
