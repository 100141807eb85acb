// The theory pages (docs/theory/README.md): every built-in hidden-surface and hidden-line plugin has
// docs/theory/en/<name>.md and docs/theory/ru/<name>.md, built into hsr; each holds the README's
// headings in its language and one ```algorithm block whose @phase tags are exactly the plugin's
// phases, each tagged at least once. Everything missing is listed in one message.
#include "hsr/plugin_registry.hpp"
#include "view/server/theory_markdown.hpp"
#include "view/server/view_assets.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::string read(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

struct Headings {
    std::string title;                 // "# " (the title line's start)
    std::vector<std::string> others;   // "## Idea", ...
};

// The README's table of headings: its first column English, its second Russian.
Headings readme_headings(const std::string& readme, int column) {
    Headings h;
    for (const std::string& line : lines_of(readme)) {
        if (line.rfind("| `#", 0) != 0) continue;
        std::vector<std::string> cells;  // the cells' text without the code marks
        std::istringstream row(line.substr(1));
        for (std::string cell; std::getline(row, cell, '|');) {
            std::erase(cell, '`');
            const std::size_t first = cell.find_first_not_of(' '), last = cell.find_last_not_of(' ');
            cells.push_back(first == std::string::npos ? "" : cell.substr(first, last - first + 1));
        }
        if (cells.size() < 2) continue;
        const std::string& heading = cells[static_cast<std::size_t>(column)];
        if (heading.rfind("## ", 0) == 0) h.others.push_back(heading);
        else h.title = "# ";
    }
    return h;
}

// The problems of one page, each a line.
void check_page(const hsr::Plugin& plugin, const std::string& language, const Headings& headings,
                std::vector<std::string>& problems) {
    const std::string name = plugin.descriptor.name;
    const std::string where = "docs/theory/" + language + "/" + name + ".md";
    const fs::path path = fs::path(HSR_SOURCE_DIR) / where;
    if (!fs::exists(path)) {
        problems.push_back(where + ": missing");
        return;
    }
    if (hsr::host::find_embedded_file(where) == nullptr) problems.push_back(where + ": not built into hsr");
    const std::vector<std::string> lines = lines_of(read(path));
    if (lines.empty() || lines[0].rfind(headings.title, 0) != 0 || lines[0].find(": ") == std::string::npos)
        problems.push_back(where + ": does not start with a title \"# <the algorithm's name>: <what it is>\"");
    const std::set<std::string> present(lines.begin(), lines.end());
    for (const std::string& heading : headings.others)
        if (present.count(heading) == 0) problems.push_back(where + ": no heading \"" + heading + "\"");
    // The algorithm blocks and their tags.
    int blocks = 0;
    std::string block;
    bool inside = false;
    for (const std::string& line : lines) {
        if (!inside && line == "```algorithm") {
            inside = true;
            ++blocks;
        } else if (inside && line.rfind("```", 0) == 0) {
            inside = false;
        } else if (inside && blocks == 1) {
            block += line + "\n";
        }
    }
    if (blocks != 1) {
        problems.push_back(where + ": " + std::to_string(blocks) + " algorithm blocks, not one");
        if (blocks == 0) return;
    }
    std::set<std::string> listed, tagged;
    for (const hsr::PluginPhase& phase : plugin.phases) listed.insert(phase.name);
    if (listed.empty()) problems.push_back(name + ": the plugin lists no phases (test_phases)");
    for (const hsr::host::AlgorithmLine& line : hsr::host::parse_algorithm(block)) {
        if (line.phase.empty()) continue;
        tagged.insert(line.phase);
        if (!listed.empty() && listed.count(line.phase) == 0)
            problems.push_back(where + ": @" + line.phase + " is not a phase of " + name);
    }
    for (const std::string& phase : listed)
        if (tagged.count(phase) == 0) problems.push_back(where + ": phase " + phase + " is tagged on no line");
}

}  // namespace

TEST_CASE("theory pages: every algorithm plugin has a page in each language, its phases tagged", "[theory]") {
    const std::string readme = read(fs::path(HSR_SOURCE_DIR) / "docs/theory/README.md");
    const Headings english = readme_headings(readme, 0), russian = readme_headings(readme, 1);
    // The README's table is what the pages are checked against: it must be there to read.
    REQUIRE(english.others.size() == 6);
    REQUIRE(russian.others.size() == 6);
    CHECK(english.others[0] == "## Idea");
    CHECK(russian.others[0] == "## Идея");

    hsr::PluginRegistry registry;
    registry.scan_directory(HSR_PLUGIN_DIR);
    std::vector<std::string> problems;
    int algorithms = 0;
    for (const hsr::Plugin& plugin : registry.plugins()) {
        if (plugin.descriptor.kind != HSR_KIND_HIDDEN_SURFACE_REMOVER && plugin.descriptor.kind != HSR_KIND_HIDDEN_LINE_REMOVER) continue;
        ++algorithms;
        check_page(plugin, "en", english, problems);
        check_page(plugin, "ru", russian, problems);
    }
    CHECK(algorithms >= 14);
    std::string message;
    for (const std::string& problem : problems) message += "\n  " + problem;
    INFO(problems.size() << " problems with the theory pages:" << message);
    CHECK(problems.empty());
}
