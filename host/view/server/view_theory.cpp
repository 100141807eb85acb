// The theory pages and the built-in docs of hsr view (view_theory.hpp).
#include "view/server/view_theory.hpp"

#include "view/server/theory_markdown.hpp"
#include "view/server/view_assets.hpp"
#include "view/server/view_models.hpp"

#include "hsr/params.hpp"

#include <fmt/format.h>

#include <fstream>
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

std::string embedded_text(const std::string& name) {
    const hsr::host::EmbeddedFile* file = hsr::host::find_embedded_file(name);
    return file ? std::string(reinterpret_cast<const char*>(file->bytes), file->size) : std::string();
}

std::string generated_page(const hsr::Plugin& plugin, bool russian) {
    const hsr_plugin_descriptor& d = plugin.descriptor;
    std::string md = fmt::format("# {}\n\n{}\n\n", escaped(d.name), escaped(d.description));
    if (russian)
        md += fmt::format("Модуль вида «{}», версия {}, собран под ABI модулей {}.{}. Своей страницы у него нет: эта "
                          "составлена из его описания и параметров.\n\n",
                          hsr::kind_name(d.kind), escaped(d.version ? d.version : "?"), d.abi_major, d.abi_minor);
    else
        md += fmt::format("A {} plugin, version {}, built against plugin ABI {}.{}. It has no page of its own: this one "
                          "is made from its description and parameters.\n\n",
                          hsr::kind_name(d.kind), escaped(d.version ? d.version : "?"), d.abi_major, d.abi_minor);
    if (d.param_count > 0) {
        md += russian ? "## Параметры\n\n" : "## Parameters\n\n";
        for (uint32_t i = 0; i < d.param_count; ++i) md += "- " + escaped(hsr::describe_param(hsr::param_desc(d, i)).c_str()) + "\n";
    }
    return md;
}

std::string file_text(const fs::path& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec) || fs::file_size(path, ec) > max_page_bytes) return {};
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// A plugin name that can be part of a file name: letters, digits, '-', '_' and '.', not first.
bool plain_name(const std::string& name) {
    if (name.empty() || name.size() > 100 || name.front() == '.') return false;
    return std::all_of(name.begin(), name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.';
    });
}

const char* fallback_note = "<p class=\"theory-note\">Русской страницы об этом алгоритме пока нет — ниже английская.</p>\n";

}  // namespace

nlohmann::json hsr::host::theory_page(const hsr::PluginRegistry& registry, const std::string& name, const std::string& language) {
    const bool russian = language == "ru";
    const std::string wanted = russian ? "ru" : "en";
    std::string markdown, shown_language = wanted, source = "built-in", page_path;
    if (plain_name(name)) {
        for (const std::string& lang : russian ? std::vector<std::string>{"ru", "en"} : std::vector<std::string>{"en"}) {
            page_path = "docs/theory/" + lang + "/" + name + ".md";
            markdown = embedded_text(page_path);
            if (!markdown.empty()) {
                shown_language = lang;
                break;
            }
        }
    }
    const hsr::Plugin* first = nullptr;
    if (markdown.empty()) {
        page_path.clear();
        source = "plugin";
        // A page beside a library of a plugin of that name; else one made from the first such plugin.
        for (const hsr::Plugin& plugin : registry.plugins()) {
            if (plugin.descriptor.name != name) continue;
            if (first == nullptr) first = &plugin;
            if (!plain_name(name)) continue;
            const fs::path folder = plugin.path.parent_path();
            if (russian) markdown = file_text(folder / (name + ".ru.md"));
            shown_language = wanted;
            if (markdown.empty()) {
                markdown = file_text(folder / (name + ".md"));
                shown_language = "en";
            }
            if (!markdown.empty()) break;
        }
        if (first == nullptr) throw ViewError(404, "", fmt::format("no plugin '{}'", hsr::printable(name)));
    }
    std::string title;
    if (markdown.empty()) {
        source = "generated";
        markdown = generated_page(*first, russian);
        shown_language = wanted;
        title = name;
        if (plain_name(name) && find_embedded_file("docs/algorithms/" + name + ".md") != nullptr) {
            page_path = "docs/theory/generated.md";
            markdown += russian ? "\n[Как алгоритм устроен в hsr](../algorithms/" + name + ".md)\n"
                                : "\n[How hsr implements it](../algorithms/" + name + ".md)\n";
        }
    }
    std::string html = render_page(markdown, {page_path, shown_language == "ru"});
    if (shown_language != wanted) html = fallback_note + html;
    return {{"name", name},
            {"title", title.empty() ? first_heading(markdown, name) : title},
            {"html", html},
            {"language", shown_language},
            {"source", source}};
}

hsr::host::DocFile hsr::host::doc_file(const std::string& path) {
    const std::string name = resolve_doc_path("docs/", path);
    const EmbeddedFile* file = name.empty() || name != "docs/" + path ? nullptr : find_embedded_file(name);
    if (file == nullptr) throw ViewError(404, "", fmt::format("no doc '{}'", hsr::printable(path)));
    const std::string bytes(reinterpret_cast<const char*>(file->bytes), file->size);
    const std::string ext = fs::path(name).extension().string();
    if (ext != ".md") {
        const char* type = ext == ".svg" ? "image/svg+xml" : ext == ".png" ? "image/png" : "text/plain; charset=utf-8";
        return {bytes, type};
    }
    const bool russian = name.rfind("docs/theory/ru/", 0) == 0;
    return {fmt::format("<!DOCTYPE html>\n<html lang=\"{}\">\n<head>\n<meta charset=\"utf-8\">\n"
                        "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>{}</title>\n"
                        "<link rel=\"stylesheet\" href=\"/static/docs.css\">\n</head>\n<body>\n<main class=\"doc\">\n{}</main>\n</body>\n</html>\n",
                        russian ? "ru" : "en", html_escaped(first_heading(bytes, name.substr(5))),
                        render_page(bytes, {name, russian})),
            "text/html; charset=utf-8"};
}
