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
// docs/algorithms/floating-horizon.md describes the steps, the counters and the limits.
#include "hsr/sdk.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace {

using hsr::sdk::ParamSpec;

constexpr double kInf = std::numeric_limits<double>::infinity();
// A point of a curve counts as on the horizon (and so visible) within this distance, in the
// horizons' units (a billionth of a pixel in the image's columns; in the vertical space, whose unit
// is the distance in depth, around a millionth of a pixel at usual sizes): an edge whose ends are shared with edges already
// drawn can lie exactly along the horizon they made (the outline of the grid drawn so far), and
// rounding must not hide it.
constexpr double kEpsilon = 1e-9;
// Visible or hidden pieces shorter than this in the image, in pixels, join their neighbours.
constexpr double kSliverPx = 1e-3;
constexpr double kMaxHorizonColumns = double(uint64_t(1) << 24);

// ------------------------------------------------------------------------------------------------
// The grid (the layout of hsr/surface.hpp, checked as hsr::find_surface_grid checks it; a plugin
// links only the SDK, so the rule is restated here).

struct GridShape {
    uint32_t columns = 0, rows = 0;
};

std::string grid_problem(const hsr::sdk::Scene& s, GridShape& out) {
    const uint32_t V = s.vertex_count(), T = s.triangle_count();
    if (V < 4) return "fewer than 4 vertices";
    const float* p = s.raw().positions;
    uint32_t C = 1;
    while (C < V && p[3 * C + 2] == p[2]) ++C;
    if (C < 2) return "its first row has fewer than 2 vertices";
    if (V % C != 0) return std::to_string(V) + " vertices are not rows of " + std::to_string(C);
    const uint32_t R = V / C;
    if (R < 2) return "fewer than 2 rows";
    if (uint64_t(T) != 2 * uint64_t(C - 1) * (R - 1))
        return std::to_string(T) + " triangles, but a " + std::to_string(C) + "x" + std::to_string(R) + " grid has " +
               std::to_string(2 * uint64_t(C - 1) * (R - 1));
    for (uint32_t r = 0; r < R; ++r)
        for (uint32_t c = 0; c < C; ++c) {
            const size_t v = size_t(r) * C + c;
            if (!std::isfinite(p[3 * v + 1])) return "vertex " + std::to_string(v) + " has a height that is not finite";
            if (p[3 * v] != p[3 * c] || !(c == 0 || p[3 * v] > p[3 * v - 3]))
                return "vertex " + std::to_string(v) + " is off the lattice in x";
            if (p[3 * v + 2] != p[3 * size_t(r) * C + 2] || !(r == 0 || p[3 * v + 2] < p[3 * (v - C) + 2]))
                return "vertex " + std::to_string(v) + " is off the lattice in z";
        }
    for (uint32_t r = 0; r + 1 < R; ++r)
        for (uint32_t c = 0; c + 1 < C; ++c) {
            const uint32_t v00 = r * C + c, v10 = v00 + 1, v01 = v00 + C, v11 = v01 + 1;
            const uint32_t t = 2 * (r * (C - 1) + c);
            if (s.index(t, 0) != v00 || s.index(t, 1) != v10 || s.index(t, 2) != v11 ||
                s.index(t + 1, 0) != v00 || s.index(t + 1, 1) != v11 || s.index(t + 1, 2) != v01)
                return "triangles " + std::to_string(t) + " and " + std::to_string(t + 1) + " are not cell (" +
                       std::to_string(c) + ", " + std::to_string(r) + ")";
        }
    out = {C, R};
    return {};
}

// ------------------------------------------------------------------------------------------------
// The horizons.

// A vertex in the space of the horizons: column coordinate X, height H (larger is higher), and the
// projective weight W > 0 of the map that produced them (for parameters along an edge in 3D).
struct SpacePoint {
    double x;
    double h;
    double w;
};

struct Piece {
    double s0, s1;  // parameters along the segment in the horizons' space
    bool visible;
};

// The upper and lower horizon, sampled at a sorted set of positions x ("columns") and linear between
// neighbouring samples. The columns are evenly spaced ones (`spacing` apart, on multiples of it)
// covering the grid and, with vertex columns on, also the x of every grid vertex (to about 1e-9 of
// the spacing): every segment then starts and ends on a column, so a kink of the horizon at a vertex
// is never cut off by the interpolation, and a segment upright in this space still reaches the
// horizon. With vertex columns off, each vertex is moved to the nearest even column instead (at
// most half a column): fewer columns on a grid denser than the pixels, at some cost in accuracy.
//
// Each column keeps three values of each horizon: the limit from its left and the limit from its
// right (what the segments reaching into the intervals on either side give there), and the value at
// the column itself (everything that touches it, upright segments included). Where a segment ends,
// the horizon steps; with one value per column the step would be smeared over the neighbouring
// interval, and an edge running through that interval (typically one nearly upright, starting where
// the step is) would be judged against a slope that is not there.
class Horizon {
public:
    void build(const std::vector<SpacePoint>& points, double x_min, double x_max, double spacing,
               bool vertex_columns) {
        // Positions are the first even column plus whole multiples of a quantum: the spacing, or
        // about a billionth of it (kept relative to the first column, so the integers stay small).
        const int64_t per_spacing = vertex_columns ? int64_t(1) << 30 : 1;
        const double quantum = spacing / double(per_spacing);
        const int64_t first = int64_t(std::floor(x_min / spacing)), last = int64_t(std::ceil(x_max / spacing));
        const double origin = double(first) * spacing;
        auto key = [&](double x) { return std::llround((x - origin) / quantum); };
        std::vector<int64_t> keys;
        keys.reserve(size_t(last - first + 1) + points.size());
        for (int64_t k = 0; k <= last - first; ++k) keys.push_back(k * per_spacing);
        for (const SpacePoint& p : points) keys.push_back(key(p.x));
        std::sort(keys.begin(), keys.end());
        keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
        x_.resize(keys.size());
        for (size_t k = 0; k < keys.size(); ++k) x_[k] = origin + double(keys[k]) * quantum;
        column_of_.resize(points.size());
        for (size_t v = 0; v < points.size(); ++v)
            column_of_[v] = uint32_t(std::lower_bound(keys.begin(), keys.end(), key(points[v].x)) - keys.begin());
        for (Side side : {kLeft, kRight, kAt}) {
            upper_[side].assign(x_.size(), -kInf);
            lower_[side].assign(x_.size(), kInf);
        }
    }
    size_t size() const { return x_.size(); }

    // The visible pieces of the segment from vertex a to vertex b against the horizons, merged, in
    // order of s. Returns the number of column intervals looked at.
    uint64_t classify(uint32_t a, uint32_t b, const SpacePoint& A, const SpacePoint& B,
                      std::vector<Piece>& pieces) const {
        pieces.clear();
        const int64_t ka = column_of_[a], kb = column_of_[b];
        const double ax = x_[size_t(ka)], dx = x_[size_t(kb)] - ax, dh = B.h - A.h;
        auto add = [&](double s0, double s1, bool visible) {
            if (!(s1 > s0)) return;
            if (!pieces.empty() && pieces.back().visible == visible)
                pieces.back().s1 = s1;
            else
                pieces.push_back({s0, s1, visible});
        };
        // Over [s0, s1] the segment runs from column k0 (value on side0) to column k1 (side1); the
        // same column for a segment upright here. The curve and both horizons are linear in s there.
        auto interval = [&](int64_t k0, Side side0, int64_t k1, Side side1, double s0, double s1) {
            const double u0 = upper_[side0][size_t(k0)], u1 = upper_[side1][size_t(k1)];
            if (!(u0 > -kInf && u1 > -kInf)) {  // nothing drawn here yet
                add(s0, s1, true);
                return;
            }
            const double h0 = A.h + dh * s0, h1 = A.h + dh * s1;
            // On or above the upper horizon (du >= 0), or on or below the lower one (dl >= 0).
            const double du0 = h0 - u0 + kEpsilon, du1 = h1 - u1 + kEpsilon;
            const double dl0 = lower_[side0][size_t(k0)] - h0 + kEpsilon, dl1 = lower_[side1][size_t(k1)] - h1 + kEpsilon;
            double cuts[4] = {s0, 0, 0, 0};
            int n = 1;
            for (const auto& [d0, d1] : {std::pair{du0, du1}, std::pair{dl0, dl1}})
                if ((d0 >= 0) != (d1 >= 0)) {
                    // Where the curve's segment crosses the horizon's segment.
                    const double s = s0 + (s1 - s0) * d0 / (d0 - d1);
                    if (s > s0 && s < s1) cuts[n++] = s;
                }
            if (n == 3 && cuts[2] < cuts[1]) std::swap(cuts[1], cuts[2]);
            cuts[n++] = s1;
            for (int i = 0; i + 1 < n; ++i) {
                const double f = (0.5 * (cuts[i] + cuts[i + 1]) - s0) / (s1 - s0);
                add(cuts[i], cuts[i + 1], du0 + (du1 - du0) * f >= 0 || dl0 + (dl1 - dl0) * f >= 0);
            }
        };
        if (ka == kb) {
            interval(ka, kAt, ka, kAt, 0.0, 1.0);
            return 1;
        }
        const int64_t step = kb > ka ? 1 : -1;
        // Leaving a column to the right, its right-hand values count; arriving, the left-hand ones.
        const Side leaving = step > 0 ? kRight : kLeft, arriving = step > 0 ? kLeft : kRight;
        double s = 0;
        for (int64_t k = ka; k != kb; k += step) {
            const double next = k + step == kb ? 1.0 : std::clamp((x_[size_t(k + step)] - ax) / dx, s, 1.0);
            interval(k, leaving, k + step, arriving, s, next);
            s = next;
        }
        return uint64_t(std::abs(kb - ka));
    }

    // Raises the upper and lowers the lower horizon with the segment from vertex a to vertex b at the
    // columns it spans. Returns the number of column values changed and, in s_lo .. s_hi, the
    // parameters where it changed any.
    uint64_t update(uint32_t a, uint32_t b, const SpacePoint& A, const SpacePoint& B, double& s_lo, double& s_hi) {
        const int64_t ka = column_of_[a], kb = column_of_[b], k0 = std::min(ka, kb), k1 = std::max(ka, kb);
        uint64_t changed = 0;
        s_lo = kInf;
        s_hi = -kInf;
        auto raise = [&](Side side, size_t k, double top, double bottom) {
            bool any = false;
            if (top > upper_[side][k]) {
                upper_[side][k] = top;
                any = true;
            }
            if (bottom < lower_[side][k]) {
                lower_[side][k] = bottom;
                any = true;
            }
            return any;
        };
        for (int64_t k = k0; k <= k1; ++k) {
            double top, bottom, s;
            if (ka == kb) {  // upright: only the column itself
                top = std::max(A.h, B.h);
                bottom = std::min(A.h, B.h);
                s = 0.5;
            } else {
                s = k == ka ? 0.0 : k == kb ? 1.0 : std::clamp((x_[size_t(k)] - x_[size_t(ka)]) / (x_[size_t(kb)] - x_[size_t(ka)]), 0.0, 1.0);
                top = bottom = A.h + (B.h - A.h) * s;
            }
            bool any = raise(kAt, size_t(k), top, bottom);
            if (k > k0) any = raise(kLeft, size_t(k), top, bottom) || any;
            if (k < k1) any = raise(kRight, size_t(k), top, bottom) || any;
            if (any) {
                ++changed;
                s_lo = std::min(s_lo, ka == kb ? 0.0 : s);
                s_hi = std::max(s_hi, ka == kb ? 1.0 : s);
            }
        }
        return changed;
    }

private:
    enum Side { kLeft = 0, kRight = 1, kAt = 2 };
    std::vector<double> x_;            // the columns, sorted
    std::vector<uint32_t> column_of_;  // per vertex, the column at its x
    std::vector<double> upper_[3], lower_[3];  // per side, per column
};

// ------------------------------------------------------------------------------------------------

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
    };

    explicit FloatingHorizon(const hsr::sdk::Params& p)
        : subcolumns_(int(p.integer("subcolumns"))),
          diagonals_(p.boolean("diagonals")),
          vertex_columns_(p.boolean("vertex-columns")),
          screen_space_(p.choice("space") == 1) {}

    void render_lines(const hsr::sdk::Scene& scene, const hsr_camera& camera, const hsr::sdk::LineRequest& request,
                      hsr::sdk::SegmentWriter& segments, const hsr::sdk::Trace& trace,
                      hsr::sdk::Counters& counters) override;

private:
    // The grid seen as curves (index j, processed nearest first) of points along them (index i).
    struct Layout {
        bool curves_are_rows = true;     // rows of constant y; otherwise columns of constant x
        uint32_t columns = 0;            // of the grid
        uint32_t along = 0, curves = 0;  // points per curve (nI), curves (nJ)
        uint32_t vertex(uint32_t i, uint32_t j) const { return curves_are_rows ? j * columns + i : i * columns + j; }
    };
    // How the camera sees the grid, in grid coordinates: depth across the curves, lateral along them.
    struct View {
        bool perspective = true;
        double eye_depth = 0, eye_lateral = 0, eye_height = 0;  // perspective
        double depth_sign = 1;  // +1 when depth grows away from the eye
        double ray_depth = 0, ray_lateral = 0, ray_height = 0;  // orthographic: the view direction
    };
    enum class Kind { curve, cross, diagonal };
    struct Element {
        Kind kind;
        uint32_t i;  // position along the curves
    };

    void choose_order(const hsr::sdk::Scene& scene, const hsr_camera& camera, const GridShape& grid);
    void map_request(const hsr::sdk::LineRequest& request, const GridShape& grid);
    void project(const hsr::sdk::Scene& scene, const hsr_camera& camera);
    // Tests a requested edge against the horizons and returns its pieces; adds an edge to them.
    void classify_edge(uint32_t a, uint32_t b, uint32_t edge);
    void update_edge(uint32_t a, uint32_t b, uint32_t edge);
    uint32_t& request_of(Kind kind, uint32_t i, uint32_t j);

    int subcolumns_;
    bool diagonals_;
    bool vertex_columns_;
    bool screen_space_;

    // Per call.
    Layout layout_;
    View view_;
    std::vector<SpacePoint> window_;  // the output image: x, y (down), clip w
    std::vector<SpacePoint> space_;   // the horizons' space: column x, height, weight
    std::vector<uint32_t> curve_edge_, cross_edge_, diagonal_edge_;  // request index or HSR_NO_EDGE
    std::vector<Element> strip_order_;
    std::vector<uint32_t> curve_order_;
    Horizon horizon_;
    std::vector<Piece> pieces_, merged_;
    const hsr::sdk::LineRequest* request_ = nullptr;
    hsr::sdk::SegmentWriter* segments_ = nullptr;
    const hsr::sdk::Trace* trace_ = nullptr;
    uint64_t crossings_ = 0, columns_updated_ = 0, column_tests_ = 0, drawn_ = 0;
};

uint32_t& FloatingHorizon::request_of(Kind kind, uint32_t i, uint32_t j) {
    switch (kind) {
    case Kind::curve: return curve_edge_[size_t(j) * (layout_.along - 1) + i];
    case Kind::cross: return cross_edge_[size_t(j) * layout_.along + i];
    default: return diagonal_edge_[size_t(j) * (layout_.along - 1) + i];
    }
}

// Which curves run across the view, and the nearest-first orders of the curves and, within a strip,
// of its cross edges and diagonals.
//
// In grid coordinates (u = world x, v = -world z, so v grows with the row), a point P can be hidden
// only by surface between P and the eye. Curves of constant v have a nearest-first order exactly
// when the eye's v lies outside the grid's v range (perspective), or the view direction has a v
// component (orthographic): then every ray from a point toward the eye runs to smaller (or larger)
// v, and only nearer curves and the strips between them can hide a curve. Within a strip, the ray
// also moves toward the eye's u, so cross edges and diagonals are taken in order of their distance
// in u from the eye (from the viewer's side for an orthographic view): a cell's diagonal after the
// nearer cross edge of its cell and before the farther one, and the diagonal of the cell under the
// eye first. The same holds with u and v exchanged (curves of constant u).
void FloatingHorizon::choose_order(const hsr::sdk::Scene& scene, const hsr_camera& camera, const GridShape& grid) {
    const float* p = scene.raw().positions;
    const uint32_t C = grid.columns, R = grid.rows;
    const double u0 = p[0], u1 = p[3 * (C - 1)];
    const double v0 = -double(p[2]), v1 = -double(p[3 * size_t(C) * (R - 1) + 2]);
    const glm::dvec3 direction(camera.view_direction[0], camera.view_direction[1], camera.view_direction[2]);
    const bool perspective = camera.projection_type == HSR_PROJECTION_PERSPECTIVE;
    const double eye_u = camera.eye[0], eye_v = -double(camera.eye[2]), eye_y = camera.eye[1];
    // The view direction in (u, v); components this small count as none.
    const double ray_u = direction.x, ray_v = -direction.z;
    const double tiny = 1e-9;
    const bool rows_ok = perspective ? (eye_v < v0 || eye_v > v1) : std::abs(ray_v) > tiny;
    const bool columns_ok = perspective ? (eye_u < u0 || eye_u > u1) : std::abs(ray_u) > tiny;
    if (!rows_ok && !columns_ok) {
        if (perspective)
            throw hsr::sdk::InvalidArgument(
                "floating-horizon: the eye is above or below the grid's area (at x = " + std::to_string(eye_u) +
                ", y = " + std::to_string(eye_v) + "; the grid covers x " + std::to_string(u0) + " to " +
                std::to_string(u1) + ", y " + std::to_string(v0) + " to " + std::to_string(v1) +
                "), so no order of its curves runs from the nearest to the farthest; lower the pitch until the eye "
                "is outside the grid in x or y");
        throw hsr::sdk::InvalidArgument(
            "floating-horizon: the orthographic view looks straight down (or up) on the grid, so its curves have no "
            "order from the nearest to the farthest; tilt the view");
    }
    const bool rows = rows_ok && (!columns_ok || std::abs(ray_v) >= std::abs(ray_u));
    layout_.curves_are_rows = rows;
    layout_.columns = C;
    layout_.along = rows ? C : R;
    layout_.curves = rows ? R : C;

    view_.perspective = perspective;
    view_.eye_depth = rows ? eye_v : eye_u;
    view_.eye_lateral = rows ? eye_u : eye_v;
    view_.eye_height = eye_y;
    view_.ray_depth = rows ? ray_v : ray_u;
    view_.ray_lateral = rows ? ray_u : ray_v;
    view_.ray_height = direction.y;
    const double depth_first = rows ? v0 : u0;
    const bool first_is_nearest = perspective ? view_.eye_depth < depth_first : view_.ray_depth > 0;
    view_.depth_sign = first_is_nearest ? 1.0 : -1.0;
    curve_order_.resize(layout_.curves);
    for (uint32_t j = 0; j < layout_.curves; ++j) curve_order_[j] = first_is_nearest ? j : layout_.curves - 1 - j;

    std::vector<double> lateral(layout_.along);
    for (uint32_t i = 0; i < layout_.along; ++i) lateral[i] = rows ? double(p[3 * i]) : -double(p[3 * size_t(i) * C + 2]);
    // Distance along the curves from the eye: |lateral - eye| for a perspective eye; from the end the
    // viewer is on for an orthographic view. An orthographic view along the curves' normal (no lateral
    // component) moves no ray along the curves: a strip's cross edges and diagonals cannot hide each
    // other, and all its cross edges go first (key 0, diagonals key 1), so that a cross edge, upright
    // in the horizons' space, is never compared with the end of the diagonal that meets it at its top.
    const bool along_normal = !perspective && std::abs(view_.ray_lateral) <= tiny;
    auto key = [&](double l) {
        if (perspective) return std::abs(l - view_.eye_lateral);
        if (along_normal) return 0.0;
        return view_.ray_lateral < 0 ? lateral.back() - l : l - lateral.front();
    };
    struct Keyed {
        double key;
        Element element;
    };
    std::vector<Keyed> keyed;
    for (uint32_t i = 0; i < layout_.along; ++i) keyed.push_back({key(lateral[i]), {Kind::cross, i}});
    for (uint32_t m = 0; m + 1 < layout_.along; ++m) {
        const bool under_eye = perspective && lateral[m] <= view_.eye_lateral && view_.eye_lateral <= lateral[m + 1];
        const double k = along_normal ? 1.0 : under_eye ? 0.0 : std::min(key(lateral[m]), key(lateral[m + 1]));
        keyed.push_back({k, {Kind::diagonal, m}});
    }
    // Ties: a cross edge before the diagonal of the cell it bounds on the eye's side.
    std::stable_sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& b) {
        if (a.key != b.key) return a.key < b.key;
        return a.element.kind == Kind::cross && b.element.kind != Kind::cross;
    });
    strip_order_.clear();
    for (const Keyed& k : keyed) strip_order_.push_back(k.element);
}

// Each requested edge becomes a curve segment, a cross edge or a diagonal of the grid.
void FloatingHorizon::map_request(const hsr::sdk::LineRequest& request, const GridShape& grid) {
    const uint32_t nI = layout_.along, nJ = layout_.curves;
    curve_edge_.assign(size_t(nJ) * (nI - 1), HSR_NO_EDGE);
    cross_edge_.assign(size_t(nJ - 1) * nI, HSR_NO_EDGE);
    diagonal_edge_.assign(size_t(nJ - 1) * (nI - 1), HSR_NO_EDGE);
    const uint32_t V = grid.columns * grid.rows;
    for (uint32_t e = 0; e < request.edge_count(); ++e) {
        const uint32_t a = request.vertex(e, 0), b = request.vertex(e, 1);
        if (a >= V || b >= V) continue;
        const uint32_t ca = a % grid.columns, ra = a / grid.columns, cb = b % grid.columns, rb = b / grid.columns;
        const int64_t ia = layout_.curves_are_rows ? ca : ra, ja = layout_.curves_are_rows ? ra : ca;
        const int64_t ib = layout_.curves_are_rows ? cb : rb, jb = layout_.curves_are_rows ? rb : cb;
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
            const double depth = layout_.curves_are_rows ? -p.z : p.x, lateral = layout_.curves_are_rows ? p.x : -p.z;
            if (view_.perspective) {
                const double distance = view_.depth_sign * (depth - view_.eye_depth);  // > 0 (choose_order)
                s = {(lateral - view_.eye_lateral) / distance, (p.y - view_.eye_height) / distance, distance};
            } else {
                const double along = depth / view_.ray_depth;  // the ray through p meets depth 0 here
                s = {lateral - along * view_.ray_lateral, p.y - along * view_.ray_height, 1.0};
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
    if (trace_->enabled())
        trace_->emit({"edge-begin", edge, HSR_NO_FACE, HSR_NO_OBJECT, pieces_.front().visible ? 0 : -1, 0.0});
    for (size_t k = 0; k < pieces_.size(); ++k) {
        const Piece& piece = pieces_[k];
        const double t0 = along(piece.s0), t1 = along(piece.s1);
        if (k > 0) {
            ++crossings_;
            if (trace_->enabled())
                trace_->emit({piece.visible ? "visible-from" : "hidden-from", edge, HSR_NO_FACE, HSR_NO_OBJECT,
                              piece.visible ? 0 : -1, t0});
        }
        if (piece.visible)
            segments_->add(point(t0), point(t1), edge, flags, 0);
        else if (hidden_too)
            segments_->add(point(t0), point(t1), edge, flags, -1);
    }
}

void FloatingHorizon::update_edge(uint32_t a, uint32_t b, uint32_t edge) {
    double s_lo, s_hi;
    const SpacePoint& A = space_[a];
    const SpacePoint& B = space_[b];
    const uint64_t changed = horizon_.update(a, b, A, B, s_lo, s_hi);
    columns_updated_ += changed;
    if (changed > 0 && edge != HSR_NO_EDGE && trace_->enabled()) {
        auto along = [&](double s) { return (s / B.w) / ((1 - s) / A.w + s / B.w); };
        trace_->emit({"horizon-update", edge, HSR_NO_FACE, HSR_NO_OBJECT, -1, along(s_lo), along(s_hi)});
    }
}

void FloatingHorizon::render_lines(const hsr::sdk::Scene& scene, const hsr_camera& camera,
                                   const hsr::sdk::LineRequest& request, hsr::sdk::SegmentWriter& segments,
                                   const hsr::sdk::Trace& trace, hsr::sdk::Counters& counters) {
    GridShape grid;
    const std::string problem = grid_problem(scene, grid);
    if (!problem.empty())
        throw hsr::sdk::InvalidArgument(
            "floating-horizon: the scene is not a regular grid surface (" + problem +
            "); this plugin draws only surfaces z = f(x, y) laid out as hsr/surface.hpp makes them (--surface, "
            "--heightmap)");
    if (camera.width == 0 || camera.height == 0) throw hsr::sdk::InvalidArgument("floating-horizon: empty image");
    choose_order(scene, camera, grid);
    map_request(request, grid);
    project(scene, camera);

    request_ = &request;
    segments_ = &segments;
    trace_ = &trace;
    crossings_ = columns_updated_ = column_tests_ = drawn_ = 0;
    const uint32_t nI = layout_.along, nJ = layout_.curves;
    // A grid edge from (i0, j0) to (i1, j1), in the request's direction when requested.
    auto ends = [&](uint32_t edge, uint32_t i0, uint32_t j0, uint32_t i1, uint32_t j1) {
        if (edge != HSR_NO_EDGE) return std::pair{request.vertex(edge, 0), request.vertex(edge, 1)};
        return std::pair{layout_.vertex(i0, j0), layout_.vertex(i1, j1)};
    };

    for (uint32_t n = 0; n < nJ; ++n) {
        const uint32_t j = curve_order_[n];
        if (trace.enabled()) {
            uint32_t first = HSR_NO_EDGE;
            for (uint32_t i = 0; i + 1 < nI && first == HSR_NO_EDGE; ++i) first = request_of(Kind::curve, i, j);
            trace.emit({"curve-begin", first});
        }
        // The curve is tested against the horizons of what is nearer as a whole (no part of a curve
        // can hide another part of it: the rays toward the eye leave it at once), then added.
        for (uint32_t i = 0; i + 1 < nI; ++i) {
            const uint32_t edge = request_of(Kind::curve, i, j);
            if (edge == HSR_NO_EDGE) continue;
            const auto [a, b] = ends(edge, i, j, i + 1, j);
            classify_edge(a, b, edge);
        }
        for (uint32_t i = 0; i + 1 < nI; ++i) {
            const uint32_t edge = request_of(Kind::curve, i, j);
            const auto [a, b] = ends(edge, i, j, i + 1, j);
            update_edge(a, b, edge);
        }
        if (n + 1 == nJ) break;
        // The strip between this curve and the next one: cross edges and diagonals, nearest first;
        // each is tested, then added, before the next.
        const uint32_t strip = std::min(j, curve_order_[n + 1]);
        for (const Element& element : strip_order_) {
            const uint32_t i = element.i;
            const bool cross = element.kind == Kind::cross;
            uint32_t edge = request_of(element.kind, i, strip);
            const auto [a, b] = cross ? ends(edge, i, strip, i, strip + 1) : ends(edge, i, strip, i + 1, strip + 1);
            if (edge != HSR_NO_EDGE && (cross || diagonals_)) classify_edge(a, b, edge);
            if (!cross && !diagonals_) edge = HSR_NO_EDGE;
            update_edge(a, b, edge);
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

}  // namespace

HSR_EXPORT_PLUGIN(FloatingHorizon)
