// The theory pages as HTML: Markdown with GitHub's tables (cmark-gfm, safe mode: raw HTML and
// javascript: links dropped), the ```algorithm block as numbered pseudocode and a flowchart drawn
// from it (docs/theory/README.md says how pages write it), the ```example block as an empty
// <div class="worked-example"> the page fills, and links and images resolved to the viewer's
// GET /docs/<path>.
//
// The flowchart is made here on the server rather than in the page so that one place escapes every
// text of a page, and so that Catch2 tests it beside the rest (tests/test_theory_markdown.cpp).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace hsr::host {

// ---- the algorithm block -------------------------------------------------------------------------

enum class LineKind { loop, decision, otherwise, end, step };

struct AlgorithmLine {
    int depth = 0;       // four spaces of indent a level
    std::string text;    // without the indent and the @phase tag
    std::string phase;   // the tag without '@', or empty
    LineKind kind = LineKind::step;
};

// The lines of a ```algorithm block; blank lines left out. Never throws.
std::vector<AlgorithmLine> parse_algorithm(std::string_view block);

enum class NodeKind { start, finish, step, loop, decision };

struct FlowNode {
    NodeKind kind = NodeKind::step;
    std::string text;
    std::string phase;
    int line = -1;  // index into the lines, -1 for start and finish
    int depth = 0;  // the line's nesting
};

struct FlowEdge {
    int from = 0, to = 0;  // node indices
    std::string label;     // "yes", "no", "done" (in the page's language) or empty
    bool back = false;     // a loop's back edge
};

struct Flowchart {
    std::vector<FlowNode> nodes;  // nodes[0] is start, nodes[1] is finish
    std::vector<FlowEdge> edges;
};

// The flowchart of the lines: a node per line but `else`, edges in execution order. russian: the
// labels ("да", "нет", "начало", ...) in Russian.
Flowchart make_flowchart(const std::vector<AlgorithmLine>& lines, bool russian);

// <ol class="pseudocode"> with a <li data-depth data-phase> per line, keywords in <strong>.
std::string pseudocode_html(const std::vector<AlgorithmLine>& lines);

// An inline <svg class="flowchart"> of the chart, every node a <g data-phase>.
std::string flowchart_svg(const Flowchart& chart, bool russian);

// ---- the page ------------------------------------------------------------------------------------

struct PageContext {
    // The page's path under docs/ ("docs/theory/en/zbuffer.md") for resolving relative links and
    // images; empty for a page from elsewhere, whose relative links are left as text.
    std::string path;
    bool russian = false;
};

// Markdown to HTML as above. A relative link or image that names a file built into hsr under docs/
// becomes "/docs/<path>"; one that names nothing there is left as its text. http(s), mailto and
// #fragment links stay as they are.
std::string render_page(const std::string& markdown, const PageContext& context);

// Escapes & < > " ' for HTML text and attributes.
std::string html_escaped(std::string_view text);

// "docs/theory/en/x.md" and "../images/a.svg" -> "docs/theory/images/a.svg"; empty when it leaves
// docs/ or is not a plain relative path.
std::string resolve_doc_path(std::string_view page, std::string_view target);

}  // namespace hsr::host
