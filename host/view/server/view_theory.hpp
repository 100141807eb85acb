// GET /api/theory/<name>?lang=en|ru: an algorithm's theory page as HTML, and GET /docs/<path>: the
// docs built into hsr, which the pages link to (theory_markdown.hpp renders both).
#pragma once

#include "hsr/plugin_registry.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace hsr::host {

// {"name", "title", "html", "language", "source"}: docs/theory/<language>/<name>.md as built in;
// else <name>.md / <name>.ru.md beside the library of a plugin of that name; else a page made from
// the plugin's description and parameters. A Russian page missing, the English one is shown with
// a note in Russian saying so ("language" is then "en"). source: "built-in", "plugin" or
// "generated". ViewError 404 when there is neither a page nor a plugin of that name.
nlohmann::json theory_page(const hsr::PluginRegistry& registry, const std::string& name, const std::string& language);

struct DocFile {
    std::string body;
    std::string content_type;
};

// docs/<path> as built into hsr: a Markdown file as a whole HTML page (its links resolved to
// /docs/ too), any other file as it is. ViewError 404 for a path that is not a built-in doc (one
// with "..", "." or empty parts never is).
DocFile doc_file(const std::string& path);

}  // namespace hsr::host
