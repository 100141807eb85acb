// The algorithm pages of hsr view (view_theory.hpp).
#include "view/server/view_theory.hpp"

#include "view/server/view_assets.hpp"
#include "view/server/view_models.hpp"

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
    std::string markdown, title;
    if (const EmbeddedFile* page = find_embedded_file("algorithms/" + name + ".md"); page != nullptr && name.find('/') == std::string::npos) {
        markdown.assign(reinterpret_cast<const char*>(page->bytes), page->size);
    } else {
        // A page beside a library of a plugin of that name, <folder>/<plugin name>.md; else one made
        // from the first such plugin.
        const hsr::Plugin* first = nullptr;
        for (const hsr::Plugin& plugin : registry.plugins()) {
            if (plugin.descriptor.name != name) continue;
            if (first == nullptr) first = &plugin;
            const fs::path beside = plugin.path.parent_path() / (name + ".md");
            std::error_code ec;
            if (fs::is_regular_file(beside, ec) && fs::file_size(beside, ec) <= max_page_bytes) {
                std::ifstream in(beside, std::ios::binary);
                std::ostringstream text;
                text << in.rdbuf();
                markdown = text.str();
                break;
            }
        }
        if (first == nullptr) throw ViewError(404, "", fmt::format("no plugin '{}'", hsr::printable(name)));
        if (markdown.empty()) {
            markdown = generated_page(*first);
            title = name;
        }
    }
    return {{"name", name}, {"title", title.empty() ? first_heading(markdown, name) : title},
            {"html", markdown_to_html(markdown)}};
}
