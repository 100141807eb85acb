// The theory pages' Markdown (host/view/server/theory_markdown.hpp): the algorithm block read into
// lines, its flowchart's nodes and edges, the HTML and SVG made of them, links resolved to /docs/,
// and odd or hostile text that never crashes and never comes out as markup.
#include "view/server/theory_markdown.hpp"

#include <catch2/catch.hpp>

#include <set>
#include <string>
#include <tuple>

using namespace hsr::host;

namespace {

// The README's example (docs/theory/README.md).
const char* const zbuffer_block =
    "for each triangle T                                   @triangle\n"
    "    for each pixel (x, y) whose centre T covers        @rasterize\n"
    "        z ← depth of T at (x, y)\n"
    "        if z < Z[x, y]                                 @depth-test\n"
    "            Z[x, y] ← z; F[x, y] ← T                   @write\n";

using EdgeKey = std::tuple<int, int, std::string, bool>;

std::set<EdgeKey> edges_of(const Flowchart& chart) {
    std::set<EdgeKey> out;
    for (const FlowEdge& e : chart.edges) out.emplace(e.from, e.to, e.label, e.back);
    return out;
}

std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

}  // namespace

TEST_CASE("theory: the algorithm block's lines", "[theory]") {
    const std::vector<AlgorithmLine> lines = parse_algorithm(zbuffer_block);
    REQUIRE(lines.size() == 5);
    CHECK(lines[0].depth == 0);
    CHECK(lines[1].depth == 1);
    CHECK(lines[2].depth == 2);
    CHECK(lines[4].depth == 3);
    CHECK(lines[0].phase == "triangle");
    CHECK(lines[1].phase == "rasterize");
    CHECK(lines[2].phase.empty());
    CHECK(lines[3].phase == "depth-test");
    CHECK(lines[4].phase == "write");
    CHECK(lines[0].text == "for each triangle T");
    CHECK(lines[4].text == "Z[x, y] ← z; F[x, y] ← T");
    CHECK(lines[0].kind == LineKind::loop);
    CHECK(lines[2].kind == LineKind::step);
    CHECK(lines[3].kind == LineKind::decision);
    // A tag needs two spaces before it and a plain name; an e-mail address is not a tag.
    const std::vector<AlgorithmLine> odd = parse_algorithm("x ← a@b\nsend to me @home\nstep  @bad!tag\n");
    REQUIRE(odd.size() == 3);
    CHECK(odd[0].phase.empty());
    CHECK(odd[1].phase.empty());
    CHECK(odd[2].phase.empty());
    CHECK(odd[2].text == "step  @bad!tag");
}

TEST_CASE("theory: keywords in Russian and in either case", "[theory]") {
    const std::vector<AlgorithmLine> lines = parse_algorithm(
        "Для каждой грани F  @face\n    пока есть пиксели\n        если z < Z  @test\n            записать\n"
        "        иначе\n            пропустить\nВернуть F\nREPEAT\n    While x\n");
    REQUIRE(lines.size() == 9);
    CHECK(lines[0].kind == LineKind::loop);
    CHECK(lines[1].kind == LineKind::loop);
    CHECK(lines[2].kind == LineKind::decision);
    CHECK(lines[3].kind == LineKind::step);
    CHECK(lines[4].kind == LineKind::otherwise);
    CHECK(lines[6].kind == LineKind::end);
    CHECK(lines[7].kind == LineKind::loop);
    CHECK(lines[8].kind == LineKind::loop);
    const std::string html = pseudocode_html(lines);
    CHECK_THAT(html, Catch::Contains("<strong>Для</strong> <strong>каждой</strong> грани F"));
    CHECK_THAT(html, Catch::Contains("<strong>иначе</strong>"));
}

TEST_CASE("theory: the flowchart of loops and a decision", "[theory]") {
    const Flowchart chart = make_flowchart(parse_algorithm(zbuffer_block), false);
    // 0 start, 1 end, then a node a line: 2 triangle loop, 3 pixel loop, 4 z, 5 if, 6 write
    REQUIRE(chart.nodes.size() == 7);
    CHECK(chart.nodes[0].kind == NodeKind::start);
    CHECK(chart.nodes[1].kind == NodeKind::finish);
    CHECK(chart.nodes[2].kind == NodeKind::loop);
    CHECK(chart.nodes[3].kind == NodeKind::loop);
    CHECK(chart.nodes[4].kind == NodeKind::step);
    CHECK(chart.nodes[5].kind == NodeKind::decision);
    CHECK(chart.nodes[6].kind == NodeKind::step);
    CHECK(chart.nodes[2].phase == "triangle");
    CHECK(chart.nodes[5].phase == "depth-test");
    CHECK(chart.nodes[4].phase.empty());
    const std::set<EdgeKey> expected = {
        {0, 2, "", false},      {2, 3, "", false},     {3, 4, "", false},   {4, 5, "", false},
        {5, 6, "yes", false},   {6, 3, "", true},      {5, 3, "no", true},  // both back to the pixel loop
        {3, 2, "done", true},   {2, 1, "done", false},
    };
    CHECK(edges_of(chart) == expected);
    CHECK(chart.edges.size() == expected.size());

    const std::string svg = flowchart_svg(chart, false);
    CHECK_THAT(svg, Catch::StartsWith("<svg class=\"flowchart\""));
    CHECK(count(svg, "<g class=\"flow-node") == 7);
    CHECK(count(svg, "<g class=\"flow-node decision\" data-phase=\"depth-test\"") == 1);
    CHECK(count(svg, "<g class=\"flow-node loop\" data-phase=\"triangle\"") == 1);
    CHECK(count(svg, "class=\"flow-edge back\"") == 3);
    CHECK(count(svg, "<polygon") == 3);  // two loops, one diamond
    CHECK(count(svg, ">yes</text>") == 1);
    CHECK(count(svg, ">no</text>") == 1);
}

TEST_CASE("theory: if and else, and return", "[theory]") {
    const Flowchart chart = make_flowchart(parse_algorithm("если a\n    x\nиначе\n    y\nz\nвернуть z\n"), true);
    // 2 if, 3 x, 4 y, 5 z, 6 return: the else line has no node
    REQUIRE(chart.nodes.size() == 7);
    CHECK(chart.nodes[0].text == "начало");
    const std::set<EdgeKey> expected = {
        {0, 2, "", false}, {2, 3, "да", false}, {3, 5, "", false}, {2, 4, "нет", false},
        {4, 5, "", false}, {5, 6, "", false},   {6, 1, "", false},
    };
    CHECK(edges_of(chart) == expected);
    CHECK_THAT(flowchart_svg(chart, true), Catch::Contains(">да</text>"));
}

TEST_CASE("theory: a step with lines indented under it runs them next", "[theory]") {
    const Flowchart chart = make_flowchart(parse_algorithm("procedure P(W)\n    x\n    y\nP(all)\n"), false);
    REQUIRE(chart.nodes.size() == 6);
    const std::set<EdgeKey> expected = {{0, 2, "", false}, {2, 3, "", false}, {3, 4, "", false}, {4, 5, "", false}, {5, 1, "", false}};
    CHECK(edges_of(chart) == expected);
}

TEST_CASE("theory: odd layouts never crash and stay consistent", "[theory]") {
    const char* const blocks[] = {
        "",
        "\n\n   \n",
        "else\n",
        "    deep first\nshallow\n            jump three levels\n  two spaces\n",
        "if a\nelse\nelse\nif b\n",
        "for\n",
        "while x\n\tif tab\n\t\tstep\n",
        "return\nreturn\n",
        "repeat  @\nx  @@\ny  @ok\n",
    };
    for (const char* block : blocks) {
        INFO(block);
        const std::vector<AlgorithmLine> lines = parse_algorithm(block);
        const Flowchart chart = make_flowchart(lines, false);
        for (const FlowEdge& e : chart.edges) {
            CHECK(e.from >= 0);
            CHECK(e.to >= 0);
            CHECK(static_cast<std::size_t>(e.from) < chart.nodes.size());
            CHECK(static_cast<std::size_t>(e.to) < chart.nodes.size());
        }
        CHECK_FALSE(flowchart_svg(chart, false).empty());
        CHECK_FALSE(pseudocode_html(lines).empty());
    }
    std::string deep;
    for (int i = 0; i < 300; ++i) deep += std::string(static_cast<std::size_t>(i) * 4, ' ') + "for x\n";
    const Flowchart chart = make_flowchart(parse_algorithm(deep), false);
    CHECK(chart.nodes.size() == 302);
    CHECK_THAT(flowchart_svg(chart, false), Catch::EndsWith("</svg>\n"));
}

TEST_CASE("theory: text of the block is never markup", "[theory]") {
    const std::string block = "if <script>alert(1)</script> & \"q\" 'a'  @ok\n    <img src=x onerror=alert(1)>\n"
                              "x  @\"><script>\n";
    const std::vector<AlgorithmLine> lines = parse_algorithm(block);
    const std::string html = pseudocode_html(lines) + flowchart_svg(make_flowchart(lines, false), false);
    CHECK(html.find("<script") == std::string::npos);
    CHECK(html.find("<img") == std::string::npos);
    CHECK(html.find("\"q\"") == std::string::npos);
    CHECK_THAT(html, Catch::Contains("&lt;script&gt;"));
    CHECK_THAT(html, Catch::Contains("&lt;img src=x onerror=alert(1)&gt;"));
    const std::string page = render_page(std::string("```algorithm\n") + block + "```\n", {"docs/theory/en/t.md", false});
    CHECK(page.find("<script") == std::string::npos);
    CHECK(page.find("<img") == std::string::npos);
}

TEST_CASE("theory: links and figures resolve inside docs/", "[theory]") {
    CHECK(resolve_doc_path("docs/theory/en/x.md", "../images/a.svg") == "docs/theory/images/a.svg");
    CHECK(resolve_doc_path("docs/theory/en/x.md", "../../algorithms/zbuffer.md") == "docs/algorithms/zbuffer.md");
    CHECK(resolve_doc_path("docs/theory/en/x.md", "zbuffer.md") == "docs/theory/en/zbuffer.md");
    CHECK(resolve_doc_path("docs/theory/en/x.md", "./../en/./y.md") == "docs/theory/en/y.md");
    CHECK(resolve_doc_path("docs/theory/en/x.md", "../../../README.md").empty());
    CHECK(resolve_doc_path("docs/theory/en/x.md", "../../../../../etc/passwd").empty());
    CHECK(resolve_doc_path("docs/theory/en/x.md", "/etc/passwd").empty());
    CHECK(resolve_doc_path("docs/theory/en/x.md", "file:x.md").empty());
    CHECK(resolve_doc_path("", "abi.md").empty());

    const std::string html = render_page(
        "# T\n\n| a | b |\n| --- | --- |\n| 1 | 2 |\n\n"
        "[abi](../../abi.md#12b) [notes](../../algorithms/zbuffer.md) [gone](../../no-such.md) [out](../../../README.md) "
        "[web](https://example.org/x) [js](javascript:alert(1)) [here](#idea)\n\n"
        "![bench](../../images/bench.svg) ![none](../images/none.svg)\n\n<b>raw</b>\n\n```example\n```\n\n```cpp\nint x;\n```\n",
        {"docs/theory/en/t.md", false});
    CHECK_THAT(html, Catch::Contains("<table>"));
    CHECK_THAT(html, Catch::Contains("<th>a</th>"));
    CHECK(html.find("| ---") == std::string::npos);
    CHECK_THAT(html, Catch::Contains("<a href=\"/docs/abi.md#12b\">abi</a>"));
    CHECK_THAT(html, Catch::Contains("<a href=\"/docs/algorithms/zbuffer.md\">notes</a>"));
    CHECK_THAT(html, Catch::Contains(" gone "));
    CHECK(html.find("no-such") == std::string::npos);
    CHECK(html.find("README") == std::string::npos);
    CHECK_THAT(html, Catch::Contains("<a href=\"https://example.org/x\">web</a>"));
    CHECK(html.find("javascript:") == std::string::npos);
    CHECK_THAT(html, Catch::Contains("<a href=\"#idea\">here</a>"));
    CHECK_THAT(render_page("## The `Z` buffer, again!\n## Где метод ошибается\n", {}),
               Catch::Contains("<a id=\"the-z-buffer-again\"></a>\n<h2>") && Catch::Contains("<a id=\"где-метод-ошибается\"></a>"));
    CHECK_THAT(html, Catch::Contains("<img src=\"/docs/images/bench.svg\" alt=\"bench\""));
    CHECK(html.find("none.svg") == std::string::npos);
    CHECK(html.find("<b>") == std::string::npos);
    CHECK_THAT(html, Catch::Contains("<div class=\"worked-example\"></div>"));
    CHECK_THAT(html, Catch::Contains("<code class=\"language-cpp\">int x;"));
    // A page from elsewhere (beside a plugin's library): its relative links stay text.
    const std::string beside = render_page("[abi](../abi.md) ![f](f.png) [web](http://example.org)\n", {"", false});
    CHECK(beside.find("abi.md") == std::string::npos);
    CHECK(beside.find("<img") == std::string::npos);
    CHECK_THAT(beside, Catch::Contains("<a href=\"http://example.org\">web</a>"));
}
