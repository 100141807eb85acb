// The algorithm pages of hsr view (view_theory.hpp).
#include "view_theory.hpp"

#include "view_assets.hpp"
#include "view_models.hpp"

#include "hsr/params.hpp"

#include <cmark.h>
#include <fmt/format.h>

#include <fstream>
#include <memory>
#include <sstream>

namespace fs = std::filesystem;

namespace {

constexpr std::uintmax_t max_page_bytes = 1u << 20;

// The text of the first line that starts with "# ", code marks (`) left out, or the fallback.
std::string first_heading(const std::string& markdown, const std::string& fallback) {
    std::istringstream in(markdown);
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("# ", 0) != 0) continue;
        std::string title = line.substr(2);
        std::erase(title, '`');
        return title;
    }
    return fallback;
}

// Backslash before every character Markdown could take as markup, so that a plugin's text stays text.
std::string escaped(const char* text) {
    std::string out;
    for (const char* c = text ? text : ""; *c; ++c) {
        if (std::string_view("\\`*_{}[]()#+-.!<>|&~").find(*c) != std::string_view::npos) out += '\\';
        out += *c == '\n' ? ' ' : *c;
    }
    return out;
}

std::string generated_page(const hsr::Plugin& plugin) {
    const hsr_plugin_descriptor& d = plugin.descriptor;
    std::string md = fmt::format("# {}\n\n{}\n\n", escaped(d.name), escaped(d.description));
    md += fmt::format("A {} plugin, version {}, built against plugin ABI {}.{}. It has no page of its own: this one "
                      "is made from its description and parameters.\n\n",
                      hsr::kind_name(d.kind), escaped(d.version ? d.version : "?"), d.abi_major, d.abi_minor);
    if (d.param_count > 0) {
        md += "## Parameters\n\n";
        for (uint32_t i = 0; i < d.param_count; ++i) md += "- " + escaped(hsr::describe_param(hsr::param_desc(d, i)).c_str()) + "\n";
    }
    return md;
}

}  // namespace

std::string hsr::host::markdown_to_html(const std::string& markdown) {
    std::unique_ptr<char, decltype(&std::free)> html(
        cmark_markdown_to_html(markdown.data(), markdown.size(), CMARK_OPT_SAFE), &std::free);
    return html ? std::string(html.get()) : std::string();
}

nlohmann::json hsr::host::theory_page(const hsr::PluginRegistry& registry, const std::string& name) {
    std::string markdown;
    if (const EmbeddedFile* page = find_embedded_file("algorithms/" + name + ".md"); page != nullptr && name.find('/') == std::string::npos) {
        markdown.assign(reinterpret_cast<const char*>(page->bytes), page->size);
    } else {
        const hsr::Plugin* plugin = nullptr;
        for (const hsr::Plugin& p : registry.plugins())
            if (p.descriptor.name == name) {
                plugin = &p;
                break;
            }
        if (plugin == nullptr) throw ViewError(404, "", fmt::format("no plugin '{}'", hsr::printable(name)));
        // A page beside the library: <folder>/<plugin name>.md.
        const fs::path beside = plugin->path.parent_path() / (name + ".md");
        std::error_code ec;
        if (fs::is_regular_file(beside, ec) && fs::file_size(beside, ec) <= max_page_bytes) {
            std::ifstream in(beside, std::ios::binary);
            std::ostringstream text;
            text << in.rdbuf();
            markdown = text.str();
        } else {
            markdown = generated_page(*plugin);
        }
    }
    return {{"name", name}, {"title", first_heading(markdown, name)}, {"html", markdown_to_html(markdown)}};
}
