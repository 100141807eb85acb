// floating-horizon: hidden-line removal for surfaces z = f(x, y) sampled on a regular grid, by the
// floating-horizon method: T. J. Wright, "A Two-Space Solution to the Hidden Line Problem for
// Plotting Functions of Two Variables", IEEE Transactions on Computers C-22(1), 1973, pp. 28-33; in
// the form David F. Rogers gives it in "Procedural Elements for Computer Graphics", 2nd ed.,
// McGraw-Hill 1998, section 4.2 ("Floating Horizon Algorithm"), including the cross-hatched variant
// (lines of constant x and of constant y) and the false side edges.
//
// The curves of the grid that run across the view (rows of constant y, or columns of constant x,
// whichever the camera looks along more) are processed from the nearest to the farthest. Two arrays
// over the columns of the picture, sampled `subcolumns` times per pixel and interpolated linearly
// between samples, hold the upper and the lower horizon: the highest and the lowest height reached
// so far. A piece of a curve is visible where it lies on or above the upper or on or below the lower
// horizon; where it crosses either one, the crossing point is computed by intersecting the curve's
// segment with the horizon's segment between two samples. After a curve is tested it raises the
// upper and lowers the lower horizon. Between two curves, the strip of the grid between them (its
// edges of the other direction and its cell diagonals) is processed the same way, in an order that
// is again nearest-first; the strip's two outer edges are Rogers' "false side edges", which keep the
// ends of farther curves from peeking out at the sides. Every edge of the grid enters the horizons;
// the requested ones are also cut into visible (and, on request, hidden) segments.
//
// The columns. With space=vertical (the default) the horizons are kept over a second picture taken
// from the same eye onto a vertical plane (the plane of constant depth of the curves): its columns
// are vertical planes through the eye (for an orthographic view, vertical planes along the view), in
// which the surface is a graph over the ray's horizontal line, so "above the highest or below the
// lowest of what is nearer" is exact. With space=screen they are the output image's columns, as in
// the textbook; in a perspective view those are planes through the eye that lean, and the method
// then misjudges lines near the column under the eye (docs/algorithms/floating-horizon.md measures
// it). Segments are always returned in the output image's window coordinates.
//
// The plugin refuses a scene that is not a grid laid out as hsr/surface.hpp fixes (the layout
// make_formula_surface and make_heightmap_surface build), and a camera for which the curves have no
// nearest-first order (the eye over the grid's area, or an orthographic view straight down or up).
//
// This file: the plugin and its loop over the curves and strips (render_lines). Beside it: grid.hpp
// (the grid's layout and the order of its curves), horizon.hpp (the two horizons).
#include "grid.hpp"
#include "horizon.hpp"

#include "hsr/sdk.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

using hsr::sdk::russian_plural;

namespace {

using floating_horizon::CurveOrder;
using floating_horizon::Element;
using floating_horizon::GridShape;
using floating_horizon::Horizon;
using floating_horizon::kInf;
using floating_horizon::Kind;
using floating_horizon::Piece;
using floating_horizon::SpacePoint;
using hsr::sdk::ParamSpec;

// Visible or hidden pieces shorter than this in the image, in pixels, join their neighbours.
constexpr double kSliverPx = 1e-3;
constexpr double kMaxHorizonColumns = double(uint64_t(1) << 24);

class FloatingHorizon final : public hsr::sdk::HiddenLineRemover {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "floating-horizon", "1.0.0",
        "floating horizon (Wright 1973; Rogers 4.2) for surfaces z = f(x, y) on a regular grid: upper and "
        "lower horizons per column, curves nearest first"};
    static inline const ParamSpec params[] = {
        ParamSpec::integer("subcolumns", "4", 1, 64, "horizon samples per pixel column"),
        ParamSpec::boolean("diagonals", false,
                           "also draw the requested cell diagonals (they always hide); off draws the grid lines only"),
        ParamSpec::boolean("vertex-columns", true,
                           "add a horizon column at every grid vertex (exact at the vertices); off moves the vertices "
                           "to the nearest even column (faster on grids much denser than the pixels)"),
        ParamSpec::choice("space", "vertical", "vertical|screen",
                          "keep the horizons over columns that are vertical planes through the eye (exact), or over "
                          "the image's columns (the textbook's; approximate in perspective)"),
        ParamSpec::integer("max-column-updates", "500000000", 1, 1e15,
                           "the most horizon columns the grid's edges may visit in one drawing, counted before any "
                           "is drawn (a few seconds' work at the default)"),
    };
    // ABI 1.5: the phases of the floating horizon, as Rogers writes it. The edges of a strip between
    // two curves are compared, cut and added as the curves' are, in a phase of their own.
    static inline const hsr::sdk::PhaseSpec phases[] = {
        {"sort", "order the curves from the nearest to the farthest"},
        {"curve", "take the next curve"},
        {"compare", "compare a segment of the curve with the upper and lower horizons"},
        {"intersect", "find where the segment crosses a horizon"},
        {"update", "raise the upper and lower the lower horizon along the curve"},
        {"strip", "test and add the edges between this curve and the next"},
    };

    static inline const hsr::sdk::TranslationSpec translations[] = {
        {"ru", "description",
         "алгоритм плавающего горизонта (Райт, 1973; Роджерс, 4.2) для поверхностей z = f(x, y) на регулярной "
         "сетке: верхний и нижний горизонты по столбцам, кривые от ближней к дальней"},
        {"ru", "param:subcolumns", "отсчётов на столбец пикселей"},
        {"ru", "help:subcolumns", "сколько отсчётов горизонта приходится на один столбец пикселей"},
        {"ru", "param:diagonals", "диагонали ячеек"},
        {"ru", "help:diagonals",
         "рисовать и запрошенные диагонали ячеек (в горизонты они входят всегда); если выключено, рисуются только "
         "линии сетки"},
        {"ru", "param:vertex-columns", "столбцы в вершинах"},
        {"ru", "help:vertex-columns",
         "добавить столбец горизонта в каждой вершине сетки (точно в вершинах); если выключено, вершины сдвигаются "
         "к ближайшему чётному столбцу (быстрее на сетках намного гуще пикселей)"},
        {"ru", "param:space", "столбцы горизонтов"},
        {"ru", "help:space",
         "хранить горизонты по столбцам — вертикальным плоскостям, проходящим через глаз (точно), или по столбцам "
         "изображения (как в учебнике; в перспективной проекции приближённо)"},
        {"ru", "choice:space:vertical", "вертикальные плоскости"},
        {"ru", "choice:space:screen", "столбцы изображения"},
        {"ru", "param:max-column-updates", "предельное число обновлений столбцов"},
        {"ru", "help:max-column-updates",
         "сколько столбцов горизонта могут затронуть рёбра сетки за один рисунок; подсчитывается до начала "
         "рисования (по умолчанию — несколько секунд работы)"},
        {"ru", "phase:sort", "упорядочить кривые от ближней к дальней"},
        {"ru", "phase:curve", "взять очередную кривую"},
        {"ru", "phase:compare", "сравнить отрезок кривой с верхним и нижним горизонтами"},
        {"ru", "phase:intersect", "найти точку, где отрезок пересекает горизонт"},
        {"ru", "phase:update", "поднять верхний и опустить нижний горизонт вдоль кривой"},
        {"ru", "phase:strip", "проверить и добавить рёбра между этой кривой и следующей"},
        {"ru", "counter:curves", "кривых"},
        {"ru", "counter:edges-processed", "рёбер внесено в горизонты"},
        {"ru", "counter:edges-drawn", "рёбер нарисовано"},
        {"ru", "counter:edges-skipped", "рёбер пропущено"},
        {"ru", "counter:crossings", "смен видимости"},
        {"ru", "counter:horizon-columns", "столбцов горизонтов"},
        {"ru", "counter:column-tests", "сравнений с горизонтами по столбцам"},
        {"ru", "counter:columns-updated", "значений горизонтов изменено"},
        {"ru", "step:sort", "сортировка кривых"},
        {"ru", "step:curve-begin", "очередная кривая"},
        {"ru", "step:edge-begin", "очередной отрезок"},
        {"ru", "step:visible-from", "начало видимого участка"},
        {"ru", "step:hidden-from", "начало невидимого участка"},
        {"ru", "step:horizon-update", "обновление горизонтов"},
    };

    explicit FloatingHorizon(const hsr::sdk::Params& p)
        : subcolumns_(int(p.integer("subcolumns"))),
          diagonals_(p.boolean("diagonals")),
          vertex_columns_(p.boolean("vertex-columns")),
          screen_space_(p.choice("space") == 1),
          max_column_updates_(uint64_t(p.integer("max-column-updates"))) {}

    void render_lines(const hsr::sdk::Scene& scene, const hsr_camera& camera, const hsr::sdk::LineRequest& request,
                      hsr::sdk::SegmentWriter& segments, const hsr::sdk::Trace& trace,
                      hsr::sdk::Counters& counters) override;

private:
    void map_request(const hsr::sdk::LineRequest& request, const GridShape& grid);
    void project(const hsr::sdk::Scene& scene, const hsr_camera& camera);
    // Tests a requested edge against the horizons and returns its pieces; adds an edge to them.
    void classify_edge(uint32_t a, uint32_t b, uint32_t edge);
    // Adds an edge to the horizons; returns the number of column values changed and, in event, the
    // "horizon-update" step to report (type nullptr when there is none).
    uint64_t update_edge(uint32_t a, uint32_t b, uint32_t edge, hsr::sdk::Trace::Event& event);
    // For a step: curve j (SUBJECT) and both horizons (CONTEXT) as lines in the output image.
    void draw_curve_and_horizons(uint32_t j) const;
    // The first step: the curves in their order, the nearest one as the subject.
    void sort_step() const;
    uint32_t& request_of(Kind kind, uint32_t i, uint32_t j);
    // Refuses the drawing when its edges would visit more than max-column-updates horizon columns.
    void check_column_updates() const;

    int subcolumns_;
    bool diagonals_;
    bool vertex_columns_;
    bool screen_space_;
    uint64_t max_column_updates_;

    // Per call.
    CurveOrder order_;
    std::vector<SpacePoint> window_;  // the output image: x, y (down), clip w
    std::vector<SpacePoint> space_;   // the horizons' space: column x, height, weight
    glm::dmat4 view_projection_{1.0};
    double image_width_ = 0, image_height_ = 0;
    uint64_t visible_pieces_ = 0;  // of the requested edges classified so far
    std::vector<uint32_t> curve_edge_, cross_edge_, diagonal_edge_;  // request index or HSR_NO_EDGE
    Horizon horizon_;
    std::vector<Piece> pieces_, merged_;
    const hsr::sdk::LineRequest* request_ = nullptr;
    hsr::sdk::SegmentWriter* segments_ = nullptr;
    const hsr::sdk::Trace* trace_ = nullptr;
    bool in_strip_ = false;  // the edges under way are a strip's, not a curve's (the phase of their steps)
    uint64_t crossings_ = 0, columns_updated_ = 0, column_tests_ = 0, drawn_ = 0;
};

uint32_t& FloatingHorizon::request_of(Kind kind, uint32_t i, uint32_t j) {
    switch (kind) {
    case Kind::curve: return curve_edge_[size_t(j) * (order_.layout.along - 1) + i];
    case Kind::cross: return cross_edge_[size_t(j) * order_.layout.along + i];
    default: return diagonal_edge_[size_t(j) * (order_.layout.along - 1) + i];
    }
}

void FloatingHorizon::render_lines(const hsr::sdk::Scene& scene, const hsr_camera& camera,
                                   const hsr::sdk::LineRequest& request, hsr::sdk::SegmentWriter& segments,
                                   const hsr::sdk::Trace& trace, hsr::sdk::Counters& counters) {
    hsr::sdk::refuse_clip_planes("floating-horizon", camera);
    GridShape grid;
    const std::string problem = grid_problem(scene, grid);
    if (!problem.empty())
        throw hsr::sdk::InvalidArgument(
            "floating-horizon: the scene is not a regular grid surface (" + problem +
            "); this plugin draws only surfaces z = f(x, y) laid out as hsr/surface.hpp makes them (--surface, "
            "--heightmap)");
    if (camera.width == 0 || camera.height == 0) throw hsr::sdk::InvalidArgument("floating-horizon: empty image");
    floating_horizon::choose_order(scene, camera, grid, order_);
    map_request(request, grid);
    project(scene, camera);
    check_column_updates();

    request_ = &request;
    segments_ = &segments;
    trace_ = &trace;
    crossings_ = columns_updated_ = column_tests_ = drawn_ = visible_pieces_ = 0;
    const uint32_t nI = order_.layout.along, nJ = order_.layout.curves;
    if (trace.enabled()) sort_step();
    // A grid edge from (i0, j0) to (i1, j1), in the request's direction when requested.
    auto ends = [&](uint32_t edge, uint32_t i0, uint32_t j0, uint32_t i1, uint32_t j1) {
        if (edge != HSR_NO_EDGE) return std::pair{request.vertex(edge, 0), request.vertex(edge, 1)};
        return std::pair{order_.layout.vertex(i0, j0), order_.layout.vertex(i1, j1)};
    };

    for (uint32_t n = 0; n < nJ; ++n) {
        const uint32_t j = order_.curves[n];
        in_strip_ = false;
        if (trace.enabled()) {
            uint32_t first = HSR_NO_EDGE;
            for (uint32_t i = 0; i + 1 < nI && first == HSR_NO_EDGE; ++i) first = request_of(Kind::curve, i, j);
            draw_curve_and_horizons(j);
            hsr::sdk::Trace::Event event{"curve-begin", first};
            event.phase = "curve";
            if (trace.russian())
                trace.emit(event, "кривая %u из %u: сравнивается с горизонтами более близких кривых", n + 1, nJ);
            else
                trace.emit(event, "curve %u of %u: tested against the horizons of the nearer ones", n + 1, nJ);
        }
        const uint64_t visible_before = visible_pieces_;
        // The curve is tested against the horizons of what is nearer as a whole (no part of a curve
        // can hide another part of it: the rays toward the eye leave it at once), then added.
        for (uint32_t i = 0; i + 1 < nI; ++i) {
            const uint32_t edge = request_of(Kind::curve, i, j);
            if (edge == HSR_NO_EDGE) continue;
            const auto [a, b] = ends(edge, i, j, i + 1, j);
            classify_edge(a, b, edge);
        }
        // The curve's last "horizon-update" step is held back to show the curve done.
        hsr::sdk::Trace::Event last{nullptr};
        uint64_t columns_changed = 0;
        for (uint32_t i = 0; i + 1 < nI; ++i) {
            const uint32_t edge = request_of(Kind::curve, i, j);
            const auto [a, b] = ends(edge, i, j, i + 1, j);
            hsr::sdk::Trace::Event event{nullptr};
            columns_changed += update_edge(a, b, edge, event);
            if (event.type == nullptr) continue;
            if (last.type != nullptr) trace.emit(last);
            last = event;
        }
        if (last.type != nullptr) {
            draw_curve_and_horizons(j);
            const auto visible = static_cast<unsigned long long>(visible_pieces_ - visible_before);
            const auto changed = static_cast<unsigned long long>(columns_changed);
            if (trace.russian())
                trace.emit(last, "кривая %u из %u: видимых участков — %llu; горизонты обновлены в %llu %s", n + 1, nJ,
                           visible, changed, russian_plural(changed, "столбце", "столбцах", "столбцах"));
            else
                trace.emit(last, "curve %u of %u: %llu visible pieces; the horizons moved at %llu column values", n + 1,
                           nJ, visible, changed);
        }
        if (n + 1 == nJ) break;
        // The strip between this curve and the next one: cross edges and diagonals, nearest first;
        // each is tested, then added, before the next.
        const uint32_t strip = std::min(j, order_.curves[n + 1]);
        in_strip_ = true;
        for (const Element& element : order_.strip) {
            const uint32_t i = element.i;
            const bool cross = element.kind == Kind::cross;
            uint32_t edge = request_of(element.kind, i, strip);
            const auto [a, b] = cross ? ends(edge, i, strip, i, strip + 1) : ends(edge, i, strip, i + 1, strip + 1);
            if (edge != HSR_NO_EDGE && (cross || diagonals_)) classify_edge(a, b, edge);
            if (!cross && !diagonals_) edge = HSR_NO_EDGE;
            hsr::sdk::Trace::Event event{nullptr};
            update_edge(a, b, edge, event);
            if (event.type != nullptr) trace.emit(event);
        }
    }

    // Requested edges not drawn: diagonals (without diagonals=true) and anything not of the grid.
    const uint64_t skipped = request.edge_count() > drawn_ ? request.edge_count() - drawn_ : 0;
    counters.set("curves", nJ);
    counters.set("edges-processed", uint64_t(nJ) * (nI - 1) + uint64_t(nJ - 1) * nI + uint64_t(nJ - 1) * (nI - 1));
    counters.set("edges-drawn", drawn_);
    counters.set("edges-skipped", skipped);
    counters.set("crossings", crossings_);
    counters.set("horizon-columns", horizon_.size());
    counters.set("column-tests", column_tests_);
    counters.set("columns-updated", columns_updated_);
}


// Every edge of the grid updates the horizons at the columns from one end's to the other's, so the
// work is known once the columns are: with a column at every vertex, a dense grid seen across the
// image makes each curve span about as many columns as the grid has vertices.
void FloatingHorizon::check_column_updates() const {
    const uint32_t nI = order_.layout.along, nJ = order_.layout.curves;
    const auto span = [&](uint32_t i0, uint32_t j0, uint32_t i1, uint32_t j1) {
        const int64_t a = horizon_.column(order_.layout.vertex(i0, j0)), b = horizon_.column(order_.layout.vertex(i1, j1));
        return uint64_t(std::abs(a - b) + 1);
    };
    uint64_t updates = 0;
    for (uint32_t j = 0; j < nJ; ++j)
        for (uint32_t i = 0; i < nI; ++i) {
            if (i + 1 < nI) updates += span(i, j, i + 1, j);
            if (j + 1 < nJ) updates += span(i, j, i, j + 1);
            if (i + 1 < nI && j + 1 < nJ) updates += span(i, j, i + 1, j + 1);
        }
    if (updates > max_column_updates_)
        throw hsr::sdk::InvalidArgument(
            "floating-horizon: the grid's edges would visit " + std::to_string(updates) +
            " horizon columns, over the limit of " + std::to_string(max_column_updates_) +
            " (raise it with max-column-updates=N, or set vertex-columns=false for a grid denser than the pixels)");
}

// Each requested edge becomes a curve segment, a cross edge or a diagonal of the grid.
void FloatingHorizon::map_request(const hsr::sdk::LineRequest& request, const GridShape& grid) {
    const uint32_t nI = order_.layout.along, nJ = order_.layout.curves;
    curve_edge_.assign(size_t(nJ) * (nI - 1), HSR_NO_EDGE);
    cross_edge_.assign(size_t(nJ - 1) * nI, HSR_NO_EDGE);
    diagonal_edge_.assign(size_t(nJ - 1) * (nI - 1), HSR_NO_EDGE);
    const uint32_t V = grid.columns * grid.rows;
    for (uint32_t e = 0; e < request.edge_count(); ++e) {
        const uint32_t a = request.vertex(e, 0), b = request.vertex(e, 1);
        if (a >= V || b >= V) continue;
        const uint32_t ca = a % grid.columns, ra = a / grid.columns, cb = b % grid.columns, rb = b / grid.columns;
        const int64_t ia = order_.layout.curves_are_rows ? ca : ra, ja = order_.layout.curves_are_rows ? ra : ca;
        const int64_t ib = order_.layout.curves_are_rows ? cb : rb, jb = order_.layout.curves_are_rows ? rb : cb;
        const uint32_t i = uint32_t(std::min(ia, ib)), j = uint32_t(std::min(ja, jb));
        if (ja == jb && std::abs(ia - ib) == 1)
            request_of(Kind::curve, i, j) = e;
        else if (ia == ib && std::abs(ja - jb) == 1)
            request_of(Kind::cross, i, j) = e;
        else if (std::abs(ia - ib) == 1 && ia - ib == ja - jb)
            request_of(Kind::diagonal, i, j) = e;
    }
}

// Every vertex in the output image (window_) and in the horizons' space (space_), and the horizons'
// columns. The vertical space is a central projection from the eye (parallel along the view, for an
// orthographic camera) onto a plane of constant depth: column x = lateral offset / depth distance,
// height = height offset / depth distance. Both are projective maps, so edges stay straight.
void FloatingHorizon::project(const hsr::sdk::Scene& scene, const hsr_camera& camera) {
    const glm::dmat4 vp(hsr::sdk::load_matrix(camera.view_projection));
    view_projection_ = vp;
    image_width_ = camera.width;
    image_height_ = camera.height;
    const uint32_t V = scene.vertex_count();
    window_.resize(V);
    space_.resize(V);
    double window_min = kInf, window_max = -kInf, space_min = kInf, space_max = -kInf;
    for (uint32_t v = 0; v < V; ++v) {
        const glm::dvec3 p(scene.position(v));
        const glm::dvec4 clip = vp * glm::dvec4(p, 1.0);
        if (!(clip.w > 0) || !std::isfinite(clip.x / clip.w) || !std::isfinite(clip.y / clip.w))
            throw hsr::sdk::InvalidArgument("floating-horizon: grid vertex " + std::to_string(v) +
                                            " is not in front of the eye; the camera must see the whole grid");
        SpacePoint& w = window_[v];
        w.x = (clip.x / clip.w + 1.0) * 0.5 * camera.width;
        w.h = (1.0 - clip.y / clip.w) * 0.5 * camera.height;  // window y, down
        w.w = clip.w;
        window_min = std::min(window_min, w.x);
        window_max = std::max(window_max, w.x);

        SpacePoint& s = space_[v];
        if (screen_space_) {
            s = {w.x, -w.h, w.w};
        } else {
            const double depth = order_.layout.curves_are_rows ? -p.z : p.x, lateral = order_.layout.curves_are_rows ? p.x : -p.z;
            if (order_.view.perspective) {
                const double distance = order_.view.depth_sign * (depth - order_.view.eye_depth);  // > 0 (choose_order)
                s = {(lateral - order_.view.eye_lateral) / distance, (p.y - order_.view.eye_height) / distance, distance};
            } else {
                const double along = depth / order_.view.ray_depth;  // the ray through p meets depth 0 here
                s = {lateral - along * order_.view.ray_lateral, p.y - along * order_.view.ray_height, 1.0};
            }
        }
        space_min = std::min(space_min, s.x);
        space_max = std::max(space_max, s.x);
    }
    // Columns: `subcolumns` per pixel of the output image; in the vertical space as many over the
    // grid's extent as the grid spans pixels across the image.
    const double pixels = std::max(window_max - window_min, 1.0);
    const double count = pixels * subcolumns_ + 3 + V;
    if (count > kMaxHorizonColumns)
        throw hsr::sdk::InvalidArgument("floating-horizon: the grid spans " + std::to_string(pixels) +
                                        " pixels across the image; at subcolumns=" + std::to_string(subcolumns_) +
                                        " the horizons would need more than " +
                                        std::to_string(uint64_t(kMaxHorizonColumns)) +
                                        " columns (zoom out or lower subcolumns)");
    const double spacing = screen_space_            ? 1.0 / subcolumns_
                           : space_max > space_min ? (space_max - space_min) / (pixels * subcolumns_)
                                                   : 1.0;
    horizon_.build(space_, space_min, space_max, spacing, vertex_columns_);
}

void FloatingHorizon::classify_edge(uint32_t a, uint32_t b, uint32_t edge) {
    const SpacePoint& A = space_[a];
    const SpacePoint& B = space_[b];
    column_tests_ += horizon_.classify(a, b, A, B, pieces_);
    ++drawn_;
    // The parameter along the edge in 3D for the parameter s in the horizons' space, and the window
    // point of a parameter t in 3D (perspective-correct both ways).
    auto along = [&](double s) { return s <= 0 ? 0.0 : s >= 1 ? 1.0 : (s / B.w) / ((1 - s) / A.w + s / B.w); };
    const SpacePoint& WA = window_[a];
    const SpacePoint& WB = window_[b];
    auto point = [&](double t) {
        const double s = t <= 0 ? 0.0 : t >= 1 ? 1.0 : t * WB.w / ((1 - t) * WA.w + t * WB.w);
        return glm::vec2(float(WA.x + (WB.x - WA.x) * s), float(WA.h + (WB.h - WA.h) * s));
    };
    // Pieces shorter than kSliverPx in the image (the touching ends at shared corners leave such
    // slivers, and rounding can) join their neighbour, so no dot is drawn for them.
    if (pieces_.size() > 1) {
        merged_.clear();
        for (const Piece& piece : pieces_) {
            const bool sliver = glm::length(point(along(piece.s1)) - point(along(piece.s0))) < kSliverPx;
            if (!merged_.empty() && (sliver || merged_.back().visible == piece.visible)) {
                merged_.back().s1 = piece.s1;
            } else if (sliver && merged_.empty()) {
                merged_.push_back({piece.s0, piece.s1, !piece.visible});  // joins the next piece
            } else {
                merged_.push_back(piece);
            }
        }
        // A sliver first joined the piece after it; a short last piece may have ended up alone.
        pieces_.clear();
        for (const Piece& piece : merged_)
            if (!pieces_.empty() && pieces_.back().visible == piece.visible)
                pieces_.back().s1 = piece.s1;
            else
                pieces_.push_back(piece);
    }
    const uint32_t flags = request_->flags(edge);
    const bool hidden_too = request_->want_hidden();
    if (trace_->enabled()) {
        hsr::sdk::Trace::Event event{"edge-begin", edge, HSR_NO_FACE, HSR_NO_OBJECT, pieces_.front().visible ? 0 : -1, 0.0};
        event.phase = in_strip_ ? "strip" : "compare";
        trace_->emit(event);
    }
    for (size_t k = 0; k < pieces_.size(); ++k) {
        const Piece& piece = pieces_[k];
        const double t0 = along(piece.s0), t1 = along(piece.s1);
        if (k > 0) {
            ++crossings_;
            if (trace_->enabled()) {
                hsr::sdk::Trace::Event event{piece.visible ? "visible-from" : "hidden-from", edge, HSR_NO_FACE,
                                             HSR_NO_OBJECT, piece.visible ? 0 : -1, t0};
                event.phase = in_strip_ ? "strip" : "intersect";
                trace_->emit(event);
            }
        }
        if (piece.visible) {
            segments_->add(point(t0), point(t1), edge, flags, 0);
            ++visible_pieces_;
        }
        else if (hidden_too)
            segments_->add(point(t0), point(t1), edge, flags, -1);
    }
}

uint64_t FloatingHorizon::update_edge(uint32_t a, uint32_t b, uint32_t edge, hsr::sdk::Trace::Event& event) {
    double s_lo, s_hi;
    const SpacePoint& A = space_[a];
    const SpacePoint& B = space_[b];
    const uint64_t changed = horizon_.update(a, b, A, B, s_lo, s_hi);
    columns_updated_ += changed;
    if (changed > 0 && edge != HSR_NO_EDGE && trace_->enabled()) {
        auto along = [&](double s) { return (s / B.w) / ((1 - s) / A.w + s / B.w); };
        event = {"horizon-update", edge, HSR_NO_FACE, HSR_NO_OBJECT, -1, along(s_lo), along(s_hi),
                 in_strip_ ? "strip" : "update"};
    }
    return changed;
}

void FloatingHorizon::sort_step() const {
    const CurveOrder& o = order_;
    constexpr uint64_t kMostLines = uint64_t(1) << 16;  // of a dense grid, the nearest curves only
    const uint32_t shown = uint32_t(std::min<uint64_t>(o.layout.curves, kMostLines / (o.layout.along - 1) + 1));
    for (uint32_t n = 0; n < shown; ++n)
        for (uint32_t i = 0; i + 1 < o.layout.along; ++i) {
            const SpacePoint& a = window_[o.layout.vertex(i, o.curves[n])];
            const SpacePoint& b = window_[o.layout.vertex(i + 1, o.curves[n])];
            trace_->line(float(a.x), float(a.h), float(b.x), float(b.h), n == 0 ? HSR_STEP_SUBJECT : HSR_STEP_CONTEXT);
        }
    hsr::sdk::Trace::Event event{"sort"};
    event.phase = "sort";
    const unsigned long long curves = o.layout.curves, points = o.layout.along;
    if (trace_->russian())
        trace_->emit(event, "кривые упорядочены от ближней к дальней: %llu %s сетки, в каждой %llu %s; ближняя — %s %u",
                     curves,
                     o.layout.curves_are_rows ? russian_plural(curves, "строка", "строки", "строк")
                                              : russian_plural(curves, "столбец", "столбца", "столбцов"),
                     points, russian_plural(points, "точка", "точки", "точек"),
                     o.layout.curves_are_rows ? "строка" : "столбец", o.curves.front());
    else
        trace_->emit(event, "curves ordered nearest first: %llu grid %s of %llu points; the nearest is %s %u", curves,
                     o.layout.curves_are_rows ? "rows" : "columns", points, o.layout.curves_are_rows ? "row" : "column",
                     o.curves.front());
}

// A point (x, height) of the horizons' space is a ray from the eye (a line along the view, for an
// orthographic camera); its window point is that of any point on it: the one at distance 1 in depth
// (depth 0).
void FloatingHorizon::draw_curve_and_horizons(uint32_t j) const {
    const CurveOrder& o = order_;
    auto to_window = [&](double x, double h) {
        if (screen_space_) return glm::vec2(float(x), float(-h));
        double depth, lateral, height;
        if (o.view.perspective) {
            depth = o.view.eye_depth + o.view.depth_sign;
            lateral = o.view.eye_lateral + x;
            height = o.view.eye_height + h;
        } else {
            depth = 0;
            lateral = x;
            height = h;
        }
        const glm::dvec3 p = o.layout.curves_are_rows ? glm::dvec3(lateral, height, -depth) : glm::dvec3(depth, height, -lateral);
        const glm::dvec4 clip = view_projection_ * glm::dvec4(p, 1.0);
        return glm::vec2(float((clip.x / clip.w + 1.0) * 0.5 * image_width_), float((1.0 - clip.y / clip.w) * 0.5 * image_height_));
    };
    bool have = false;
    glm::vec2 upper_at, lower_at;
    horizon_.for_each_column([&](double x, double upper, double lower) {
        if (!(upper > -kInf)) {
            have = false;
            return;
        }
        const glm::vec2 u = to_window(x, upper), l = to_window(x, lower);
        if (have) {
            trace_->line(upper_at.x, upper_at.y, u.x, u.y, HSR_STEP_CONTEXT);
            trace_->line(lower_at.x, lower_at.y, l.x, l.y, HSR_STEP_CONTEXT);
        }
        upper_at = u;
        lower_at = l;
        have = true;
    });
    for (uint32_t i = 0; i + 1 < o.layout.along; ++i) {
        const SpacePoint& a = window_[o.layout.vertex(i, j)];
        const SpacePoint& b = window_[o.layout.vertex(i + 1, j)];
        trace_->line(float(a.x), float(a.h), float(b.x), float(b.h), HSR_STEP_SUBJECT);
    }
}

}  // namespace

HSR_EXPORT_PLUGIN(FloatingHorizon)
