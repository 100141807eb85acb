// The floating-horizon hidden-line plugin: against the independent ray-casting reference
// (line_reference.hpp) on formula surfaces from many views, a case checked by hand, its trace and
// counters, and its refusals (meshes that are not grids, views with no nearest-first order).
#include "hsr/error.hpp"
#include "hsr/lines.hpp"
#include "hsr/surface.hpp"
#include "line_test_support.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using line_tests::orbit;

namespace {

const char* const kPlugin = "floating-horizon";

// The tolerance of the comparison, in pixels: reference samples within this distance of a change of
// visibility (the reference's or the plugin's) are not checked. The horizons are linear between
// columns (4 per pixel, and one at every vertex), so where two horizon segments cross between two
// columns the horizon is a little too high there, and a change may move by a fraction of a column.
// Measured on these surfaces and views: no disagreement at 0.25 px, 2 samples at 0.1 px.
constexpr double kTolerancePx = 0.5;

const hsr::SceneData& surface(const std::string& formula, const std::string& range) {
    static std::map<std::string, hsr::SceneData> cache;
    const std::string key = formula + "|" + range;
    auto it = cache.find(key);
    if (it == cache.end()) it = cache.emplace(key, hsr::make_formula_surface(formula, hsr::parse_surface_range(range))).first;
    return it->second;
}

uint32_t columns_of(const hsr::SceneData& s) {
    const std::optional<hsr::SurfaceGrid> grid = hsr::find_surface_grid(s.view());
    REQUIRE(grid.has_value());
    return grid->columns;
}

bool is_grid_line(uint32_t a, uint32_t b, uint32_t columns) {
    const int64_t ca = a % columns, ra = a / columns, cb = b % columns, rb = b / columns;
    return (ra == rb && std::abs(ca - cb) == 1) || (ca == cb && std::abs(ra - rb) == 1);
}

// The drawing restricted to some of its edges (the grid lines, or all), in the form compare() takes.
struct Subset {
    hsr::EdgeList edges;
    std::vector<line_reference::Segment> segments;
};

Subset grid_lines(const hsr::LineDrawing& d, uint32_t columns, bool with_diagonals = false) {
    Subset out;
    std::vector<uint32_t> renumber(d.edges.size(), HSR_NO_EDGE);
    for (uint32_t e = 0; e < d.edges.size(); ++e) {
        const uint32_t a = d.edges.vertices[2 * e], b = d.edges.vertices[2 * e + 1];
        if (!with_diagonals && !is_grid_line(a, b, columns)) continue;
        renumber[e] = uint32_t(out.edges.size());
        out.edges.vertices.insert(out.edges.vertices.end(), {a, b});
        out.edges.faces.insert(out.edges.faces.end(), {d.edges.faces[2 * e], d.edges.faces[2 * e + 1]});
        out.edges.flags.push_back(d.edges.flags[e]);
    }
    for (const line_reference::Segment& s : line_tests::reference_segments(d))
        if (s.edge < renumber.size() && renumber[s.edge] != HSR_NO_EDGE) {
            line_reference::Segment copy = s;
            copy.edge = renumber[s.edge];
            out.segments.push_back(copy);
        }
    return out;
}

hsr::LineDrawing draw(const hsr::SceneData& s, const hsr_camera& camera, bool want_hidden = false,
                      const std::vector<hsr::Setting>& params = {}, std::ostream* trace = nullptr) {
    hsr::LineSettings settings;
    settings.edges = hsr::EdgeSelection::kAll;
    settings.want_hidden = want_hidden;
    settings.trace = trace;
    return line_tests::draw(kPlugin, s.view(), camera, settings, params);
}

std::string error_of(auto&& f) {
    try {
        f();
    } catch (const hsr::Error& e) {
        return e.what();
    }
    return "(no error)";
}

struct View {
    float yaw, pitch;
    bool ortho;
};

}  // namespace

TEST_CASE("floating-horizon: agrees with ray casting on formula surfaces from many views", "[floating-horizon][slow]") {
    struct Case {
        const char* formula;
        const char* range;
    };
    const Case cases[] = {
        {"sin(x)*cos(y)", "-3:3,-3:3,28x28"},
        {"0.15*(x^2+y^2)", "-2.5:2.5,-2:2,24x20"},
        // A ridge across the middle that hides the valley behind it.
        {"1.6*exp(-4*y^2) - 0.8*exp(-3*(y-1.4)^2)*(1+0.3*cos(2*x))", "-2:2,-1.5:2.5,26x30"},
        // Steep, folded, with peaks inside cells.
        {"0.6*sin(2*x+y)*cos(1.5*y) + 0.2*x", "-2:2,-2:2,22x22"},
    };
    const View views[] = {
        {0, 30, false},   {25, 35, false},  {70, 25, false}, {115, 40, false}, {200, 30, false},
        {290, 20, false}, {160, -25, false}, {0.5, 30, true},   {45, 45, true},   {100, 15, true},
        {235, 35, true},  {330, -20, true},  {10, 5, false},
    };
    uint64_t checked = 0, hidden = 0;
    for (const Case& c : cases) {
        const hsr::SceneData& s = surface(c.formula, c.range);
        const uint32_t columns = columns_of(s);
        const hsr_scene scene = s.view();
        for (const View& v : views) {
            INFO(c.formula << " yaw " << v.yaw << " pitch " << v.pitch << (v.ortho ? " orthographic" : " perspective"));
            const hsr_camera camera = orbit(s, v.yaw, v.pitch, 1, v.ortho, 320);
            const hsr::LineDrawing d = draw(s, camera);
            const Subset lines = grid_lines(d, columns);
            REQUIRE(lines.edges.size() > 0);
            const line_reference::Comparison cmp =
                line_reference::compare(scene, camera, lines.edges, lines.segments, 0.25, kTolerancePx);
            INFO(cmp.first);
            CHECK(cmp.disagreements == 0);
            checked += cmp.checked;
            hidden += cmp.samples - cmp.reference_visible;
        }
    }
    // The views hide a good part of the lines, so the agreement means something.
    CHECK(hidden * 5 > checked);
}

TEST_CASE("floating-horizon: the other settings: image columns, no vertex columns", "[floating-horizon]") {
    const hsr::SceneData& s = surface("sin(x)*cos(y)", "-3:3,-3:3,24x24");
    const hsr_scene scene = s.view();
    const uint32_t columns = columns_of(s);
    // space=screen: the image's columns are vertical planes in an orthographic view without roll, so
    // the textbook's columns are exact there too.
    for (const View& v : {View{30, 30, true}, View{200, 40, true}}) {
        const hsr_camera camera = orbit(s, v.yaw, v.pitch, 1, v.ortho, 256);
        const Subset lines = grid_lines(draw(s, camera, false, {{"space", "screen"}}), columns);
        const line_reference::Comparison cmp =
            line_reference::compare(scene, camera, lines.edges, lines.segments, 0.25, kTolerancePx);
        INFO(cmp.first);
        CHECK(cmp.disagreements == 0);
    }
    // vertex-columns=false moves every vertex to the nearest even column: mostly right, not exactly.
    for (const View& v : {View{25, 35, false}, View{100, 15, true}}) {
        const hsr_camera camera = orbit(s, v.yaw, v.pitch, 1, v.ortho, 256);
        const hsr::LineDrawing d = draw(s, camera, false, {{"vertex-columns", "false"}});
        const Subset lines = grid_lines(d, columns);
        const line_reference::Comparison cmp =
            line_reference::compare(scene, camera, lines.edges, lines.segments, 0.25, kTolerancePx);
        CHECK(cmp.disagreements * 50 < cmp.checked);
        CHECK(d.counter("horizon-columns") < draw(s, camera).counter("horizon-columns"));
    }
}

TEST_CASE("floating-horizon: the diagonals, when asked for, agree too", "[floating-horizon]") {
    const hsr::SceneData& s = surface("sin(x)*cos(y)", "-3:3,-3:3,20x20");
    const hsr_scene scene = s.view();
    for (const View& v : {View{30, 30, false}, View{250, 40, true}}) {
        const hsr_camera camera = orbit(s, v.yaw, v.pitch, 1, v.ortho, 256);
        const hsr::LineDrawing without = draw(s, camera);
        const hsr::LineDrawing with = draw(s, camera, false, {{"diagonals", "true"}});
        CHECK(without.counter("edges-skipped") > 0);
        CHECK(with.counter("edges-skipped") == 0);
        CHECK(with.counter("edges-drawn") == with.edges.size());
        const Subset all = grid_lines(with, columns_of(s), true);
        const line_reference::Comparison cmp =
            line_reference::compare(scene, camera, all.edges, all.segments, 0.25, kTolerancePx);
        INFO(cmp.first);
        CHECK(cmp.disagreements == 0);
    }
}

TEST_CASE("floating-horizon: by hand, a ridge hides the flat curve behind it below a known height",
          "[floating-horizon]") {
    // Three curves 1 apart in depth (world z = 0, -1, -2): flat z = 0 in front and behind, and between
    // them a ridge rising to the right, 0.25 (x + 1). Orthographic, yaw 0, pitch p: window height
    // goes with h cos p - z sin p, so the back curve sits at 2 sin p and the ridge at
    // 0.25 (x + 1) cos p + sin p: the back curve is hidden exactly where the ridge is higher on the
    // screen, x > x* = 4 tan p - 1, to its right end. There the horizon is the ridge's own segment
    // (the diagonal of the cell, from the lower ridge corner to the back curve, stays below the back
    // curve), so the crossing is exact up to rounding. (A ridge falling to the right would not do:
    // its cells' diagonals run from the higher ridge corner to the back curve, and the triangles on
    // them, turned away from the eye, hide the back curve to the end of the cell.)
    const hsr::SceneData& s = surface("0.25*(x+1)*(1-abs(y-1))", "-1:1,0:2,41x3");
    const hsr_scene scene = s.view();
    const float pitch = 20;
    const hsr_camera camera = orbit(s, 0, pitch, 1, true, 400);
    std::ostringstream trace;
    const hsr::LineDrawing d = draw(s, camera, true, {}, &trace);
    const double x_star = 4 * std::tan(pitch * 3.14159265358979323846 / 180) - 1;
    const glm::dmat4 vp = line_reference::view_projection(camera);
    auto window = [&](double x, double h, double z) { return line_reference::to_window(camera, vp, {x, h, z}); };
    const glm::dvec2 crossing = window(x_star, 0, -2);
    const double back_y = window(0, 0, -2).y, back_x0 = window(-1, 0, -2).x, back_x1 = window(1, 0, -2).x;
    double visible_back = 0, hidden_back = 0, visible_ridge = 0;
    int crossings_seen = 0;
    for (const hsr::LineSegment& seg : d.segments) {
        const uint32_t a = d.edges.vertices[2 * seg.edge], b = d.edges.vertices[2 * seg.edge + 1];
        const double length = glm::length(glm::dvec2(seg.b - seg.a));
        if (a >= 82 && b >= 82) {  // the back curve, at the window height of 2 sin p throughout
            CHECK(seg.a.y == Approx(back_y).margin(1e-3));
            CHECK(seg.b.y == Approx(back_y).margin(1e-3));
            (seg.qi == 0 ? visible_back : hidden_back) += length;
            for (const glm::vec2 end : {seg.a, seg.b}) {
                bool at_a_vertex = false;
                for (int k = 0; k <= 40; ++k) at_a_vertex |= std::abs(end.x - window(-1 + k * 0.05, 0, -2).x) < 1e-3;
                if (!at_a_vertex) {  // an end inside an edge: the crossing, at x*
                    ++crossings_seen;
                    CHECK(end.x == Approx(crossing.x).margin(2e-3));
                }
            }
        } else if (a >= 41 && a < 82 && b >= 41 && b < 82 && seg.qi == 0) {
            visible_ridge += length;
        }
    }
    CHECK(crossings_seen == 2);  // the crossing ends one segment and starts the next
    CHECK(hidden_back == Approx(back_x1 - crossing.x).margin(1e-2));
    CHECK(visible_back + hidden_back == Approx(back_x1 - back_x0).margin(1e-2));
    // Nothing hides the ridge.
    double ridge_length = 0;
    for (int k = 0; k < 40; ++k) {
        const double x0 = -1 + k * 0.05, x1 = x0 + 0.05;
        ridge_length += glm::length(window(x1, 0.25 * (x1 + 1), -1) - window(x0, 0.25 * (x0 + 1), -1));
    }
    CHECK(visible_ridge == Approx(ridge_length).margin(1e-2));
    // And ray casting agrees on the curves. (Not on the cross edges: in this exactly aligned view the
    // reference's rays from a cross edge run along the cross edges in front of it, between triangles,
    // and miss the surface that hides them.)
    Subset curves = grid_lines(d, 41);
    for (size_t e = 0; e < curves.edges.size(); ++e)
        if (curves.edges.vertices[2 * e] / 41 != curves.edges.vertices[2 * e + 1] / 41) curves.edges.flags[e] = ~0u;
    hsr::EdgeList rows;
    std::vector<uint32_t> renumber(curves.edges.size(), HSR_NO_EDGE);
    for (size_t e = 0; e < curves.edges.size(); ++e)
        if (curves.edges.flags[e] != ~0u) {
            renumber[e] = uint32_t(rows.size());
            rows.vertices.insert(rows.vertices.end(), {curves.edges.vertices[2 * e], curves.edges.vertices[2 * e + 1]});
            rows.faces.insert(rows.faces.end(), {curves.edges.faces[2 * e], curves.edges.faces[2 * e + 1]});
            rows.flags.push_back(curves.edges.flags[e]);
        }
    std::vector<line_reference::Segment> row_segments;
    for (line_reference::Segment seg : curves.segments)
        if (renumber[seg.edge] != HSR_NO_EDGE) {
            seg.edge = renumber[seg.edge];
            row_segments.push_back(seg);
        }
    REQUIRE(rows.size() == 3 * 40);
    const line_reference::Comparison cmp = line_reference::compare(scene, camera, rows, row_segments, 0.25, kTolerancePx);
    INFO(cmp.first);
    CHECK(cmp.disagreements == 0);

    // Counters and the trace.
    CHECK(d.counter("curves") == 3);
    CHECK(d.counter("crossings") == 1);  // the back curve's, and no other
    CHECK(d.counter("columns-updated") > 0);
    CHECK(d.counter("horizon-columns") >= 4 * uint64_t(back_x1 - back_x0));
    const std::string t = trace.str();
    for (const char* type : {"curve-begin", "edge-begin", "horizon-update"})
        CHECK(t.find(std::string("\"type\":\"") + type + "\"") != std::string::npos);
    // The one crossing event: the back curve's edges run from right to left here, so the edge from
    // x = 0.5 to 0.45 turns visible at x*, at the parameter (0.5 - x*) / 0.05 along it.
    const size_t at = t.find("\"type\":\"visible-from\"");
    REQUIRE(at != std::string::npos);
    CHECK(t.find("-from\"", at + 22) == std::string::npos);
    const size_t t0 = t.find("\"t0\":", at);
    REQUIRE(t0 != std::string::npos);
    CHECK(std::stod(t.substr(t0 + 5)) == Approx((0.5 - x_star) / 0.05).margin(1e-5));
}

TEST_CASE("floating-horizon: visible and hidden pieces cover each drawn edge", "[floating-horizon]") {
    const hsr::SceneData& s = surface("sin(x)*cos(y)", "-3:3,-3:3,16x16");
    const hsr_camera camera = orbit(s, 40, 30, 1, false, 256);
    std::ostringstream trace;
    const hsr::LineDrawing d = draw(s, camera, true, {}, &trace);
    // One trace event per crossing, and a segment more than edges drawn per crossing.
    size_t from_events = 0, begin_events = 0;
    for (size_t at = 0; (at = trace.str().find("-from\"", at)) != std::string::npos; ++at) ++from_events;
    for (size_t at = 0; (at = trace.str().find("\"edge-begin\"", at)) != std::string::npos; ++at) ++begin_events;
    CHECK(from_events == d.counter("crossings"));
    CHECK(begin_events == d.counter("edges-drawn"));
    CHECK(d.segments.size() == d.counter("edges-drawn") + d.counter("crossings"));
    CHECK(trace.str().find("\"visible-from\"") != std::string::npos);
    std::vector<double> covered(d.edges.size(), 0.0);
    uint64_t hidden = 0;
    for (const hsr::LineSegment& seg : d.segments) {
        covered[seg.edge] += glm::length(seg.b - seg.a);
        CHECK((seg.qi == 0 || seg.qi == -1));
        hidden += seg.qi == -1;
    }
    CHECK(hidden > 0);
    const glm::dmat4 vp = line_reference::view_projection(camera);
    const hsr_scene scene = s.view();
    const uint32_t columns = columns_of(s);
    for (uint32_t e = 0; e < d.edges.size(); ++e) {
        const uint32_t a = d.edges.vertices[2 * e], b = d.edges.vertices[2 * e + 1];
        if (!is_grid_line(a, b, columns)) {
            CHECK(covered[e] == 0.0);  // diagonals are not drawn by default
            continue;
        }
        const double length = glm::length(line_reference::to_window(camera, vp, line_reference::position(scene, a)) -
                                          line_reference::to_window(camera, vp, line_reference::position(scene, b)));
        CHECK(covered[e] == Approx(length).margin(1e-3));
    }
}

double distance_to_segment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 d = b - a;
    const double len2 = glm::dot(d, d);
    const double u = len2 > 0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
    return glm::length(a + u * d - p);
}

// The index (1-based) of the last trace line containing `needle`, or 0.
uint64_t last_event_with(const std::string& trace, const std::string& needle) {
    std::istringstream lines(trace);
    std::string line;
    uint64_t found = 0;
    for (uint64_t k = 1; std::getline(lines, line); ++k)
        if (line.find(needle) != std::string::npos) found = k;
    return found;
}

TEST_CASE("floating-horizon: a curve's step draws the curve and the horizons", "[floating-horizon][trace]") {
    const hsr::SceneData& s = surface("sin(x)*cos(y)", "-3:3,-3:3,16x16");
    for (const bool screen : {true, false}) {
        INFO("space=" << (screen ? "screen" : "vertical"));
        const hsr_camera camera = orbit(s, 40, 30, 1, true, 256);
        const std::vector<hsr::Setting> params = {{"space", screen ? "screen" : "vertical"}, {"diagonals", "true"}};
        std::ostringstream trace;
        const hsr::LineDrawing whole = draw(s, camera, false, params, &trace);
        // The last curve's step: after it, every edge of the grid is in the horizons.
        const uint64_t last = last_event_with(trace.str(), "\"text\":\"curve 16 of 16: ");
        REQUIRE(last > 0);
        CHECK(last_event_with(trace.str(), "visible pieces") == last);
        hsr::LineSettings settings;
        settings.edges = hsr::EdgeSelection::kAll;
        settings.stop_after_event = last;
        const hsr::LineDrawing step = line_tests::draw(kPlugin, s.view(), camera, settings, params);
        REQUIRE(step.stopped_at);
        const hsr::TraceEventRecord& e = *step.stopped_at;
        CHECK(e.type == "horizon-update");
        CHECK(e.text.rfind("curve 16 of 16: ", 0) == 0);
        REQUIRE(e.roles.size() * 4 == e.lines.size());
        size_t subject = 0;
        std::vector<glm::dvec2> upper, lower;  // the horizons' line starts, in the order drawn
        for (size_t k = 0; k < e.roles.size(); ++k) {
            const float* l = &e.lines[4 * k];
            for (int c = 0; c < 4; ++c) REQUIRE(std::isfinite(l[c]));
            for (int c = 0; c < 4; c += 2) {
                CHECK(l[c] > -2.0f);
                CHECK(l[c] < float(camera.width) + 2.0f);
                CHECK(l[c + 1] > -2.0f);
                CHECK(l[c + 1] < float(camera.height) + 2.0f);
            }
            REQUIRE(e.roles[k] <= HSR_STEP_CONTEXT);
            if (e.roles[k] == HSR_STEP_SUBJECT) ++subject;
            if (e.roles[k] == HSR_STEP_CONTEXT) ((upper.size() == lower.size() ? upper : lower)).push_back({l[0], l[1]});
        }
        CHECK(subject == 15);  // the curve's 15 segments
        REQUIRE(upper.size() == lower.size());
        REQUIRE(upper.size() > 100);
        // The horizons are the top and the bottom of everything drawn: at each column, the least and
        // the greatest y of the visible segments there. (In an orthographic view without roll the
        // vertical planes along the view are the image's columns too.)
        size_t compared = 0;
        for (size_t k = 0; k < upper.size(); ++k) {
            const double x = upper[k].x;
            double top = INFINITY, bottom = -INFINITY;
            for (const hsr::LineSegment& seg : whole.segments) {
                if (seg.qi != 0) continue;
                const double x0 = std::min(seg.a.x, seg.b.x), x1 = std::max(seg.a.x, seg.b.x);
                if (x < x0 - 1e-4 || x > x1 + 1e-4) continue;
                if (x1 - x0 < 1e-6) {
                    top = std::min({top, double(seg.a.y), double(seg.b.y)});
                    bottom = std::max({bottom, double(seg.a.y), double(seg.b.y)});
                    continue;
                }
                const double f = std::clamp((x - seg.a.x) / (double(seg.b.x) - seg.a.x), 0.0, 1.0);
                const double y = seg.a.y + f * (double(seg.b.y) - seg.a.y);
                top = std::min(top, y);
                bottom = std::max(bottom, y);
            }
            if (!std::isfinite(top)) continue;
            INFO("column x = " << x);
            CHECK(upper[k].x == Approx(lower[k].x).margin(1e-3));
            CHECK(upper[k].y == Approx(top).margin(0.02));
            CHECK(lower[k].y == Approx(bottom).margin(0.02));
            ++compared;
        }
        CHECK(compared + 2 >= upper.size());
    }
    // In perspective the horizons' columns are planes through the eye, which the image shows leaning:
    // there each point of a horizon still lies on a visible segment, the one that made it.
    const hsr_camera camera = orbit(s, 40, 30, 1, false, 256);
    std::ostringstream trace;
    const hsr::LineDrawing whole = draw(s, camera, false, {{"diagonals", "true"}}, &trace);
    hsr::LineSettings settings;
    settings.edges = hsr::EdgeSelection::kAll;
    settings.stop_after_event = last_event_with(trace.str(), "\"text\":\"curve 16 of 16: ");
    const hsr::LineDrawing step = line_tests::draw(kPlugin, s.view(), camera, settings, {{"diagonals", "true"}});
    REQUIRE(step.stopped_at);
    size_t points = 0;
    for (size_t k = 0; k < step.stopped_at->roles.size(); ++k) {
        if (step.stopped_at->roles[k] != HSR_STEP_CONTEXT) continue;
        const glm::dvec2 p(step.stopped_at->lines[4 * k], step.stopped_at->lines[4 * k + 1]);
        double nearest = INFINITY;
        for (const hsr::LineSegment& seg : whole.segments)
            if (seg.qi == 0) nearest = std::min(nearest, distance_to_segment(p, seg.a, seg.b));
        INFO("horizon point " << p.x << ", " << p.y);
        CHECK(nearest < 0.02);
        ++points;
    }
    CHECK(points > 100);
}

TEST_CASE("floating-horizon: refuses meshes that are not grids, and views without an order", "[floating-horizon]") {
    for (const char* file : {"cube.obj", "bunny.obj"}) {
        const hsr::SceneData& m = line_tests::model(file);
        const hsr_camera camera = orbit(m, 30, 20, 1, false, 128);
        const std::string message = error_of([&] { draw(m, camera); });
        INFO(message);
        CHECK(message.find("floating-horizon: the scene is not a regular grid surface (") != std::string::npos);
        CHECK(message.find("--surface") != std::string::npos);
    }
    const hsr::SceneData& s = surface("sin(x)*cos(y)", "-3:3,-3:3,12x12");
    // Straight down, orthographic.
    std::string message = error_of([&] { draw(s, orbit(s, 0, 90, 1, true, 128)); });
    CHECK(message.find("looks straight down (or up) on the grid") != std::string::npos);
    // Perspective with the eye over the grid (and from below it).
    for (float pitch : {80.0f, -80.0f}) {
        message = error_of([&] { draw(s, orbit(s, 20, pitch, 1, false, 128)); });
        INFO(message);
        CHECK(message.find("the eye is above or below the grid's area") != std::string::npos);
    }
    // A steep view with the eye just outside the grid is still drawn.
    CHECK_NOTHROW(draw(s, orbit(s, 0, 70, 1, false, 128)));
}

TEST_CASE("floating-horizon: time on large grids", "[.timing][slow]") {
    // Not run by default: hsr's test runner skips tags starting with '.'. Run it with
    // test_floating_horizon "[.timing]" to measure (the numbers in docs/algorithms/floating-horizon.md).
    for (const char* range : {"-3:3,-3:3,64x64", "-3:3,-3:3,128x128", "-3:3,-3:3,256x256", "-3:3,-3:3,512x512"}) {
        const hsr::SceneData& s = surface("sin(x)*cos(y)", range);
        const hsr_camera camera = orbit(s, 30, 30, 1, false, 1024);
        for (const char* vertex_columns : {"true", "false"})
            for (int sub : {1, 4, 16}) {
                if (std::string(range).find("512") != std::string::npos && vertex_columns == std::string("true") && sub != 4)
                    continue;
                std::vector<double> ms;
                hsr::LineDrawing d;
                for (int k = 0; k < 5; ++k) {
                    d = draw(s, camera, false,
                             {{"subcolumns", std::to_string(sub)}, {"vertex-columns", vertex_columns}});
                    ms.push_back(d.lines_ms);
                }
                std::sort(ms.begin(), ms.end());
                std::printf("%s vertex-columns=%s subcolumns=%d: %.1f ms (median of 5), %llu horizon columns, %zu "
                            "segments, %llu edges drawn\n",
                            range, vertex_columns, sub, ms[2], (unsigned long long)d.counter("horizon-columns"),
                            d.segments.size(), (unsigned long long)d.counter("edges-drawn"));
            }
    }
}
