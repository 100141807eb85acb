// GET /api/theory/<name>: an algorithm's page as HTML (cmark, safe mode: raw HTML dropped).
#pragma once

#include "hsr/plugin_registry.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace hsr::host {

// {"name", "title", "html"}: docs/algorithms/<name>.md as built in; else <name>.md beside the
// plugin's library (any library with a plugin of that name); else a page made from the plugin's
// description and parameters. ViewError 404 when there is neither a page nor a plugin of that name.
nlohmann::json theory_page(const hsr::PluginRegistry& registry, const std::string& name);

// CommonMark to HTML, raw HTML and unsafe links left out.
std::string markdown_to_html(const std::string& markdown);

}  // namespace hsr::host
