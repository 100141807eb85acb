// The theory pages as HTML, the pseudocode and its flowchart (theory_markdown.hpp).
#include "view/server/theory_markdown.hpp"

#include "view/server/view_assets.hpp"

#include <cmark-gfm-core-extensions.h>
#include <cmark-gfm.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <memory>
#include <mutex>

namespace {

using hsr::host::AlgorithmLine;
using hsr::host::Flowchart;
using hsr::host::FlowEdge;
using hsr::host::FlowNode;
using hsr::host::LineKind;
using hsr::host::NodeKind;

// ---- words ---------------------------------------------------------------------------------------

std::string lowercase_word(std::string_view word) {
    // ASCII, and the capital Cyrillic letters a line may start with (U+0410..U+042F -> U+0430..U+044F).
    std::string out;
    for (std::size_t i = 0; i < word.size(); ++i) {
        const auto c = static_cast<unsigned char>(word[i]);
        if (c < 0x80) {
            out += static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
        } else if (c == 0xD0 && i + 1 < word.size()) {
            const auto d = static_cast<unsigned char>(word[i + 1]);
            if (d >= 0x90 && d <= 0x9F) out += "\xD0", out += static_cast<char>(d + 0x20);
            else if (d >= 0xA0 && d <= 0xAF) out += "\xD1", out += static_cast<char>(d - 0x20);
            else out += "\xD0", out += static_cast<char>(d);
            ++i;
        } else {
            out += static_cast<char>(c);
        }
    }
    return out;
}

// The word without the punctuation after it ("if" of "if:", "иначе" of "иначе,").
std::string_view bare_word(std::string_view word) {
    while (!word.empty() && std::string_view(":,;.").find(word.back()) != std::string_view::npos) word.remove_suffix(1);
    return word;
}

LineKind kind_of(std::string_view text) {
    const std::string first = lowercase_word(bare_word(text.substr(0, text.find(' '))));
    for (const char* w : {"for", "while", "repeat", "для", "пока", "повторять"})
        if (first == w) return LineKind::loop;
    for (const char* w : {"if", "если"})
        if (first == w) return LineKind::decision;
    for (const char* w : {"else", "otherwise", "иначе"})
        if (first == w) return LineKind::otherwise;
    for (const char* w : {"return", "вернуть"})
        if (first == w) return LineKind::end;
    return LineKind::step;
}

bool is_keyword(std::string_view word) {
    static constexpr std::array<const char*, 28> keywords = {
        "for",  "each",   "while", "repeat",  "until",  "if",     "then",    "else",   "otherwise", "return",
        "do",   "to",     "in",    "для",     "каждого", "каждой", "каждый", "каждых", "всех",      "пока",
        "повторять", "до", "если", "то",      "иначе",  "вернуть", "выполнять", "break"};
    const std::string lower = lowercase_word(bare_word(word));
    return std::any_of(keywords.begin(), keywords.end(), [&](const char* k) { return lower == k; });
}

bool is_phase_char(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
}

std::size_t codepoints(std::string_view text) {
    return static_cast<std::size_t>(std::count_if(text.begin(), text.end(), [](char c) {
        return (static_cast<unsigned char>(c) & 0xC0) != 0x80;
    }));
}

// The text in lines of at most `width` code points, broken at spaces (and inside a longer word).
std::vector<std::string> wrapped(std::string_view text, std::size_t width) {
    width = std::max<std::size_t>(width, 4);
    std::vector<std::string> lines;
    std::string line;
    std::size_t at = 0;
    while (at < text.size()) {
        std::size_t end = text.find(' ', at);
        if (end == std::string_view::npos) end = text.size();
        std::string_view word = text.substr(at, end - at);
        at = end + 1;
        if (word.empty()) continue;
        while (codepoints(word) > width) {  // a word longer than a line: cut at a code point
            if (!line.empty()) lines.push_back(std::move(line)), line.clear();
            std::size_t cut = 0, count = 0;
            while (cut < word.size() && count < width) {
                ++cut;
                while (cut < word.size() && (static_cast<unsigned char>(word[cut]) & 0xC0) == 0x80) ++cut;
                ++count;
            }
            lines.emplace_back(word.substr(0, cut));
            word.remove_prefix(cut);
        }
        if (word.empty()) continue;
        if (!line.empty() && codepoints(line) + 1 + codepoints(word) > width) lines.push_back(std::move(line)), line.clear();
        if (!line.empty()) line += ' ';
        line += word;
    }
    if (!line.empty() || lines.empty()) lines.push_back(line);
    return lines;
}

// ---- the flowchart's structure -------------------------------------------------------------------

struct Wiring {
    const std::vector<AlgorithmLine>& lines;
    const std::vector<std::vector<int>>& children;  // direct children of each line
    const std::vector<int>& owned_else;             // the else line a decision owns, or -1
    const std::vector<bool>& is_owned;              // an else line owned by a decision
    const std::vector<int>& node_of;                // line -> node, -1 for an owned else
    Flowchart& chart;
    bool russian;

    void edge(int from, int to, std::string label) { chart.edges.push_back({from, to, std::move(label), false}); }

    int first(const std::vector<int>& block, int next) const {
        for (int line : block)
            if (!is_owned[static_cast<std::size_t>(line)]) return node_of[static_cast<std::size_t>(line)];
        return next;
    }

    void wire(const std::vector<int>& block, int next) {
        std::vector<int> statements;
        for (int line : block)
            if (!is_owned[static_cast<std::size_t>(line)]) statements.push_back(line);
        for (std::size_t k = 0; k < statements.size(); ++k) {
            const auto line = static_cast<std::size_t>(statements[k]);
            const int node = node_of[line];
            const int follow = k + 1 < statements.size() ? node_of[static_cast<std::size_t>(statements[k + 1])] : next;
            const std::vector<int>& body = children[line];
            switch (lines[line].kind) {
                case LineKind::end:
                    edge(node, 1, "");
                    break;
                case LineKind::loop:
                    edge(node, first(body, node), "");
                    wire(body, node);
                    edge(node, follow, russian ? "выход" : "done");
                    break;
                case LineKind::decision: {
                    edge(node, first(body, follow), russian ? "да" : "yes");
                    wire(body, follow);
                    if (const int other = owned_else[line]; other >= 0) {
                        const std::vector<int>& no = children[static_cast<std::size_t>(other)];
                        edge(node, first(no, follow), russian ? "нет" : "no");
                        wire(no, follow);
                    } else {
                        edge(node, follow, russian ? "нет" : "no");
                    }
                    break;
                }
                default:
                    // Lines indented under a step (a procedure's body) run next, then what follows it.
                    edge(node, first(body, follow), "");
                    wire(body, follow);
                    break;
            }
        }
    }
};

// ---- drawing -------------------------------------------------------------------------------------

// The chart is 400 units wide and scales to the pane; boxes leave lanes for the edges on both sides
// (18 on the left, 34 on the right, where the "done" and "no" labels go).
constexpr double chart_width = 400, indent_left = 18, indent_right = 14, margin = 18, right_margin = 34, text_line = 14;
constexpr double gap = 22, char_width = 6.6;

struct Box {
    double left = 0, right = 0, top = 0, bottom = 0;
    double centre() const { return (left + right) / 2; }
    double middle() const { return (top + bottom) / 2; }
};

std::string number(double v) { return fmt::format("{:.1f}", v); }

}  // namespace

std::string hsr::host::html_escaped(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&#39;"; break;
            default: out += c;
        }
    }
    return out;
}

std::vector<AlgorithmLine> hsr::host::parse_algorithm(std::string_view block) {
    std::vector<AlgorithmLine> lines;
    std::size_t at = 0;
    while (at < block.size()) {
        std::size_t end = block.find('\n', at);
        if (end == std::string_view::npos) end = block.size();
        std::string_view raw = block.substr(at, end - at);
        at = end + 1;
        if (!raw.empty() && raw.back() == '\r') raw.remove_suffix(1);
        std::size_t spaces = 0;
        for (char c : raw) {
            if (c == ' ') ++spaces;
            else if (c == '\t') spaces += 4;
            else break;
        }
        std::string_view text = raw.substr(std::min(raw.find_first_not_of(" \t"), raw.size()));
        while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
        if (text.empty()) continue;
        AlgorithmLine line;
        line.depth = static_cast<int>(std::min<std::size_t>(spaces / 4, 12));
        // "@phase" after at least two spaces at the end of the line
        if (const std::size_t tag = text.rfind('@'); tag != std::string_view::npos && tag >= 2 && tag + 1 < text.size() &&
                                                      text[tag - 1] == ' ' && text[tag - 2] == ' ' &&
                                                      std::all_of(text.begin() + static_cast<std::ptrdiff_t>(tag + 1), text.end(), is_phase_char)) {
            line.phase = std::string(text.substr(tag + 1));
            text = text.substr(0, tag);
            while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
        }
        line.text = std::string(text);
        line.kind = kind_of(line.text);
        lines.push_back(std::move(line));
    }
    return lines;
}

Flowchart hsr::host::make_flowchart(const std::vector<AlgorithmLine>& lines, bool russian) {
    Flowchart chart;
    chart.nodes.push_back({NodeKind::start, russian ? "начало" : "start", "", -1});
    chart.nodes.push_back({NodeKind::finish, russian ? "конец" : "end", "", -1});
    const std::size_t n = lines.size();
    std::vector<int> parent(n, -1);
    std::vector<std::vector<int>> children(n);
    std::vector<int> top;
    std::vector<int> stack;
    for (std::size_t i = 0; i < n; ++i) {
        while (!stack.empty() && lines[static_cast<std::size_t>(stack.back())].depth >= lines[i].depth) stack.pop_back();
        parent[i] = stack.empty() ? -1 : stack.back();
        (parent[i] < 0 ? top : children[static_cast<std::size_t>(parent[i])]).push_back(static_cast<int>(i));
        stack.push_back(static_cast<int>(i));
    }
    // An else belongs to the decision just before it among its siblings.
    std::vector<int> owned_else(n, -1);
    std::vector<bool> is_owned(n, false);
    auto own = [&](const std::vector<int>& block) {
        for (std::size_t k = 1; k < block.size(); ++k) {
            const auto line = static_cast<std::size_t>(block[k]), before = static_cast<std::size_t>(block[k - 1]);
            if (lines[line].kind == LineKind::otherwise && lines[before].kind == LineKind::decision && owned_else[before] < 0) {
                owned_else[before] = static_cast<int>(line);
                is_owned[line] = true;
            }
        }
    };
    own(top);
    for (const std::vector<int>& block : children) own(block);
    std::vector<int> node_of(n, -1);
    for (std::size_t i = 0; i < n; ++i) {
        if (is_owned[i]) continue;
        NodeKind kind = NodeKind::step;
        if (lines[i].kind == LineKind::loop) kind = NodeKind::loop;
        else if (lines[i].kind == LineKind::decision) kind = NodeKind::decision;
        node_of[i] = static_cast<int>(chart.nodes.size());
        chart.nodes.push_back({kind, lines[i].text, lines[i].phase, static_cast<int>(i), lines[i].depth});
    }
    Wiring wiring{lines, children, owned_else, is_owned, node_of, chart, russian};
    wiring.edge(0, wiring.first(top, 1), "");
    wiring.wire(top, 1);
    // Rows run in node order, the finish last: an edge to a row not below its source goes back.
    auto row = [&](int node) { return node == 1 ? static_cast<int>(chart.nodes.size()) : node; };
    for (FlowEdge& e : chart.edges) e.back = row(e.to) <= row(e.from);
    return chart;
}

std::string hsr::host::pseudocode_html(const std::vector<AlgorithmLine>& lines) {
    std::string html = "<ol class=\"pseudocode\">\n";
    for (const AlgorithmLine& line : lines) {
        html += fmt::format("<li data-depth=\"{}\"", line.depth);
        if (!line.phase.empty()) html += fmt::format(" data-phase=\"{}\"", html_escaped(line.phase));
        html += "><code>";
        std::size_t at = 0;
        bool first = true;
        while (at <= line.text.size()) {
            std::size_t end = line.text.find(' ', at);
            if (end == std::string::npos) end = line.text.size();
            const std::string_view word = std::string_view(line.text).substr(at, end - at);
            if (!first) html += ' ';
            first = false;
            if (!word.empty() && is_keyword(word)) html += "<strong>" + html_escaped(word) + "</strong>";
            else html += html_escaped(word);
            at = end + 1;
        }
        html += "</code></li>\n";
    }
    return html + "</ol>\n";
}

std::string hsr::host::flowchart_svg(const Flowchart& chart, bool russian) {
    const std::size_t count = chart.nodes.size();
    std::vector<int> order;  // rows: start, the lines' nodes, finish
    order.push_back(0);
    for (std::size_t i = 2; i < count; ++i) order.push_back(static_cast<int>(i));
    if (count > 1) order.push_back(1);
    // Nesting deeper than the chart has room for is drawn at the deepest level it has.
    std::vector<Box> boxes(count);
    std::vector<std::vector<std::string>> texts(count);
    double y = 8;
    for (int node : order) {
        const auto i = static_cast<std::size_t>(node);
        const FlowNode& n = chart.nodes[i];
        const int d = std::clamp(n.depth, 0, 8);
        Box& b = boxes[i];
        if (n.kind == NodeKind::start || n.kind == NodeKind::finish) {
            const double centre = (margin + chart_width - right_margin) / 2;
            b.left = centre - 45;
            b.right = centre + 45;
            texts[i] = {n.text};
        } else {
            b.left = margin + d * indent_left;
            b.right = chart_width - right_margin - d * indent_right;
        }
        const double width = b.right - b.left;
        double height = 0;
        if (n.kind == NodeKind::decision) {
            texts[i] = wrapped(n.text, static_cast<std::size_t>(width * 0.62 / char_width));
            height = std::max(36.0, (text_line * static_cast<double>(texts[i].size()) + 4) / 0.4);
        } else if (n.kind == NodeKind::loop) {
            texts[i] = wrapped(n.text, static_cast<std::size_t>((width - 28) / char_width));
            height = text_line * static_cast<double>(texts[i].size()) + 12;
        } else if (n.kind == NodeKind::step) {
            texts[i] = wrapped(n.text, static_cast<std::size_t>((width - 12) / char_width));
            height = text_line * static_cast<double>(texts[i].size()) + 12;
        } else {
            height = 24;
        }
        b.top = y;
        b.bottom = y + height;
        y = b.bottom + gap;
    }
    const double total_height = y - gap + 8;

    std::string svg = fmt::format(
        "<svg class=\"flowchart\" viewBox=\"0 0 {} {}\" width=\"100%\" role=\"img\" aria-label=\"{}\" "
        "xmlns=\"http://www.w3.org/2000/svg\">\n"
        "<defs><marker id=\"flow-arrow\" viewBox=\"0 0 8 8\" refX=\"7\" refY=\"4\" markerWidth=\"7\" markerHeight=\"7\" "
        "orient=\"auto-start-reverse\"><path d=\"M0 0L8 4L0 8z\" class=\"flow-arrowhead\"/></marker></defs>\n",
        number(chart_width), number(total_height), russian ? "блок-схема алгоритма" : "flowchart of the algorithm");

    // Edges first, so that the nodes sit over their ends.
    for (const FlowEdge& e : chart.edges) {
        if (e.from < 0 || e.to < 0 || static_cast<std::size_t>(e.from) >= count || static_cast<std::size_t>(e.to) >= count) continue;
        const Box& a = boxes[static_cast<std::size_t>(e.from)];
        const Box& b = boxes[static_cast<std::size_t>(e.to)];
        std::string path;
        double label_x = 0, label_y = 0;
        const bool below = b.top >= a.bottom;
        const bool next_row = below && b.top - a.bottom <= gap + 0.5;
        if (e.back) {
            // out of the source's left side, up the lane left of the target, into its left side
            const double lane = b.left - 9;
            const double out_y = e.from == e.to ? a.bottom - 6 : a.middle() + 4;
            path = fmt::format("M{} {}H{}V{}H{}", number(a.left), number(out_y), number(lane), number(b.middle() - 4), number(b.left));
            label_x = a.left + 4;  // in the gap below the source, clear of the lanes
            label_y = a.bottom + 11;
        } else if (next_row && !(chart.nodes[static_cast<std::size_t>(e.from)].kind == NodeKind::decision && (e.label == "no" || e.label == "нет"))) {
            const double mid = a.bottom + gap / 2;
            path = fmt::format("M{} {}V{}H{}V{}", number(a.centre()), number(a.bottom), number(mid), number(b.centre()), number(b.top));
            label_x = a.centre() + 4;
            label_y = a.bottom + 10;
        } else {
            // out of the source's right side, down the lane right of it, into the target's top
            const double lane = a.right + 7;
            const double above = b.top - 6;
            path = fmt::format("M{} {}H{}V{}H{}V{}", number(a.right), number(a.middle()), number(lane), number(above),
                               number(b.centre()), number(b.top));
            label_x = a.right + 2;
            label_y = a.middle() - 3;
        }
        svg += fmt::format("<path class=\"flow-edge{}\" d=\"{}\" marker-end=\"url(#flow-arrow)\"/>\n", e.back ? " back" : "", path);
        if (!e.label.empty())
            svg += fmt::format("<text class=\"flow-label\" x=\"{}\" y=\"{}\">{}</text>\n", number(label_x), number(label_y),
                               html_escaped(e.label));
    }

    for (int node : order) {
        const auto i = static_cast<std::size_t>(node);
        const FlowNode& n = chart.nodes[i];
        const Box& b = boxes[i];
        static constexpr std::array<const char*, 5> kind_names = {"start", "finish", "step", "loop", "decision"};
        svg += fmt::format("<g class=\"flow-node {}\"", kind_names[static_cast<std::size_t>(n.kind)]);
        if (!n.phase.empty()) svg += fmt::format(" data-phase=\"{}\"", html_escaped(n.phase));
        if (n.line >= 0) svg += fmt::format(" data-line=\"{}\"", n.line);
        svg += ">";
        const double h = b.bottom - b.top;
        switch (n.kind) {
            case NodeKind::start:
            case NodeKind::finish:
                svg += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" rx=\"{}\"/>", number(b.left), number(b.top),
                                   number(b.right - b.left), number(h), number(h / 2));
                break;
            case NodeKind::decision:
                svg += fmt::format("<polygon points=\"{},{} {},{} {},{} {},{}\"/>", number(b.centre()), number(b.top), number(b.right),
                                   number(b.middle()), number(b.centre()), number(b.bottom), number(b.left), number(b.middle()));
                break;
            case NodeKind::loop:
                svg += fmt::format("<polygon points=\"{},{} {},{} {},{} {},{} {},{} {},{}\"/>", number(b.left + 10), number(b.top),
                                   number(b.right - 10), number(b.top), number(b.right), number(b.middle()), number(b.right - 10),
                                   number(b.bottom), number(b.left + 10), number(b.bottom), number(b.left), number(b.middle()));
                break;
            default:
                svg += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" rx=\"3\"/>", number(b.left), number(b.top),
                                   number(b.right - b.left), number(h));
        }
        const double first_y = b.middle() - text_line * (static_cast<double>(texts[i].size()) - 1) / 2 + 4;
        svg += fmt::format("<text x=\"{}\" text-anchor=\"middle\">", number(b.centre()));
        for (std::size_t k = 0; k < texts[i].size(); ++k)
            svg += fmt::format("<tspan x=\"{}\" y=\"{}\">{}</tspan>", number(b.centre()), number(first_y + text_line * static_cast<double>(k)),
                               html_escaped(texts[i][k]));
        svg += "</text></g>\n";
    }
    return svg + "</svg>\n";
}

std::string hsr::host::resolve_doc_path(std::string_view page, std::string_view target) {
    if (page.empty() || target.empty() || target.front() == '/' || target.find(':') != std::string_view::npos ||
        target.find('\\') != std::string_view::npos)
        return {};
    std::vector<std::string> parts;
    auto push_all = [&](std::string_view path) {
        std::size_t at = 0;
        while (at <= path.size()) {
            std::size_t end = path.find('/', at);
            if (end == std::string_view::npos) end = path.size();
            const std::string_view part = path.substr(at, end - at);
            at = end + 1;
            if (part.empty() || part == ".") continue;
            if (part == "..") {
                if (parts.empty()) return false;
                parts.pop_back();
            } else {
                parts.emplace_back(part);
            }
        }
        return true;
    };
    const std::size_t slash = page.rfind('/');
    if (slash == std::string_view::npos || !push_all(page.substr(0, slash)) || !push_all(target)) return {};
    if (parts.size() < 2 || parts.front() != "docs") return {};
    std::string out;
    for (const std::string& part : parts) out += (out.empty() ? "" : "/") + part;
    return out;
}

namespace {

// The URL a link or image of the page takes in the viewer, or empty to leave it as text.
std::string viewer_url(const std::string& url, const std::string& page) {
    if (url.empty()) return {};
    if (url.front() == '#' || url.rfind("http://", 0) == 0 || url.rfind("https://", 0) == 0 || url.rfind("mailto:", 0) == 0)
        return url;
    const std::size_t cut = url.find_first_of("#?");
    const std::string path = url.substr(0, cut);
    const std::string fragment = cut == std::string::npos || url[cut] != '#' ? "" : url.substr(cut);
    std::string resolved = hsr::host::resolve_doc_path(page, path);
    // A Russian page's link to a theory page not yet written in Russian: the English one.
    if (const std::string russian = "docs/theory/ru/"; resolved.rfind(russian, 0) == 0 && hsr::host::find_embedded_file(resolved) == nullptr)
        resolved = "docs/theory/en/" + resolved.substr(russian.size());
    if (resolved.empty() || hsr::host::find_embedded_file(resolved) == nullptr) return {};
    return "/" + resolved + fragment;
}

void replace_with_children(cmark_node* node) {
    while (cmark_node* child = cmark_node_first_child(node)) {
        cmark_node_unlink(child);
        cmark_node_insert_before(node, child);
    }
    cmark_node_free(node);
}

// GitHub's anchor of a heading: its text in lower case, punctuation dropped, spaces as '-'.
std::string heading_anchor(cmark_node* heading) {
    std::string text;
    std::unique_ptr<cmark_iter, decltype(&cmark_iter_free)> iter(cmark_iter_new(heading), &cmark_iter_free);
    for (cmark_event_type ev; (ev = cmark_iter_next(iter.get())) != CMARK_EVENT_DONE;) {
        cmark_node* node = cmark_iter_get_node(iter.get());
        const cmark_node_type type = cmark_node_get_type(node);
        if (ev == CMARK_EVENT_ENTER && (type == CMARK_NODE_TEXT || type == CMARK_NODE_CODE))
            if (const char* literal = cmark_node_get_literal(node)) text += literal;
    }
    std::string anchor;
    for (const char c : lowercase_word(text)) {
        const auto u = static_cast<unsigned char>(c);
        if (u >= 0x80 || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_') anchor += c;
        else if (c == ' ') anchor += '-';
    }
    return anchor;
}

cmark_node* raw_block(const std::string& html) {
    cmark_node* block = cmark_node_new(CMARK_NODE_CUSTOM_BLOCK);
    cmark_node_set_on_enter(block, html.c_str());
    cmark_node_set_on_exit(block, "");
    return block;
}

}  // namespace

std::string hsr::host::render_page(const std::string& markdown, const PageContext& context) {
    static std::once_flag registered;
    std::call_once(registered, [] { cmark_gfm_core_extensions_ensure_registered(); });
    const int options = CMARK_OPT_DEFAULT;  // safe: raw HTML and javascript: links dropped
    std::unique_ptr<cmark_parser, decltype(&cmark_parser_free)> parser(cmark_parser_new(options), &cmark_parser_free);
    if (cmark_syntax_extension* table = cmark_find_syntax_extension("table")) cmark_parser_attach_syntax_extension(parser.get(), table);
    cmark_parser_feed(parser.get(), markdown.data(), markdown.size());
    std::unique_ptr<cmark_node, decltype(&cmark_node_free)> document(cmark_parser_finish(parser.get()), &cmark_node_free);

    std::vector<cmark_node*> blocks, links, headings;
    {
        std::unique_ptr<cmark_iter, decltype(&cmark_iter_free)> iter(cmark_iter_new(document.get()), &cmark_iter_free);
        for (cmark_event_type ev; (ev = cmark_iter_next(iter.get())) != CMARK_EVENT_DONE;) {
            if (ev != CMARK_EVENT_ENTER) continue;
            cmark_node* node = cmark_iter_get_node(iter.get());
            const cmark_node_type type = cmark_node_get_type(node);
            if (type == CMARK_NODE_CODE_BLOCK) blocks.push_back(node);
            else if (type == CMARK_NODE_HEADING && cmark_node_get_heading_level(node) > 1) headings.push_back(node);
            else if (type == CMARK_NODE_LINK || type == CMARK_NODE_IMAGE) links.push_back(node);
        }
    }
    // An anchor before each section's heading, as GitHub names it, for links to it (#idea).
    for (cmark_node* node : headings)
        if (const std::string anchor = heading_anchor(node); !anchor.empty())
            cmark_node_insert_before(node, raw_block("<a id=\"" + html_escaped(anchor) + "\"></a>\n"));
    for (cmark_node* node : links) {
        const char* url = cmark_node_get_url(node);
        const std::string target = viewer_url(url ? url : "", context.path);
        if (target.empty()) replace_with_children(node);
        else cmark_node_set_url(node, target.c_str());
    }
    for (cmark_node* node : blocks) {
        const char* info = cmark_node_get_fence_info(node);
        const std::string kind = info ? std::string(info).substr(0, std::string(info).find(' ')) : "";
        std::string html;
        if (kind == "algorithm") {
            const char* code = cmark_node_get_literal(node);
            const std::vector<AlgorithmLine> lines = parse_algorithm(code ? code : "");
            html = "<div class=\"algorithm\">\n" + pseudocode_html(lines) + flowchart_svg(make_flowchart(lines, context.russian), context.russian) +
                   "</div>\n";
        } else if (kind == "example") {
            html = "<div class=\"worked-example\"></div>\n";
        } else {
            continue;
        }
        cmark_node* block = raw_block(html);
        cmark_node_insert_before(node, block);
        cmark_node_free(node);
    }
    std::unique_ptr<char, decltype(&std::free)> html(
        cmark_render_html(document.get(), options, cmark_parser_get_syntax_extensions(parser.get())), &std::free);
    return html ? std::string(html.get()) : std::string();
}
