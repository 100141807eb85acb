// bsp: hidden surfaces by a binary space-partitioning tree, after Henry Fuchs, Zvi M. Kedem and
// Bruce F. Naylor, "On Visible Surface Generation by A Priori Tree Structures", SIGGRAPH 1980
// (Computer Graphics 14(3), pp. 124-133).
//
// The tree (bsp_tree.hpp) is built once per scene in world space, over every placement's
// triangles, and reused for every frame and camera until the scene or an instance transform
// changes. A frame walks it from the eye: at each node the subtree on the far side of its plane,
// then the node's own polygons, then the near subtree (back to front, painting over what is drawn),
// or the reverse (front to back, with a per-pixel coverage mask: a pixel once written is never
// written again). A node polygon is drawn as its triangle, taken to clip space (view_projection *
// world) and through the SDK's polygon rasterizer (hsr/raster.hpp: clipping to near/far, the guard
// band and the camera's clip planes, the z-buffer's setup, coverage, depth and perspective-correct
// barycentrics), at the pixel centres the piece's cuts keep. Rasterizing the pieces' own corners
// instead would leave cracks: a cut's corner on a triangle's edge, snapped to the subpixel grid,
// is off its unsplit neighbour's edge (a T-junction). The coverage mask is right with clip planes
// only because what a plane cuts away is never rasterized. docs/algorithms/bsp.md describes the
// steps and counters.
#include "bsp_tree.hpp"

#include "hsr/raster.hpp"
#include "hsr/scene_key.hpp"
#include "hsr/sdk.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

using hsr::sdk::russian_plural;

namespace {

namespace raster = hsr::raster;
using hsr::sdk::ParamSpec;
using hsr::sdk::InstanceKey;
using hsr::sdk::SceneKey;

// Pixel bounds of what a polygon's setups covered (steps only).
struct Rect {
    int32_t x0 = INT32_MAX, y0 = INT32_MAX, x1 = INT32_MIN, y1 = INT32_MIN;
    bool empty() const { return x0 > x1; }
};

// A window coordinate held to [-1, size] as a pixel index (NaN: -1).
inline int32_t pixel(double v, int32_t size) {
    return v >= -1.0 ? int32_t(std::min(v, double(size))) : -1;
}

struct FrameStats {
    uint64_t nodes_visited = 0;
    uint64_t polygons_drawn = 0;  // rasterized with at least one pixel centre in the image
    uint64_t polygons_culled = 0;  // back faces, with cull-backfaces
    uint64_t pixels_painted = 0;
    uint64_t pixels_skipped = 0;  // front to back: already covered
};

// One pixel centre of a node polygon's triangle: skipped unless the piece's cuts keep it, then
// painted over (back to front) or written only where the coverage mask is clear (front to back);
// either way a surface at exactly the stored depth takes the pixel only by the tie rule.
// `painted` counts the pixel centres back to front paints, and front to back writes first;
// `skipped` those front to back finds covered (a tie it wins is written over all the same).
// kMirror: the mask is also kept as floats, for the steps' buffer.
template <bool kFrontToBack, bool kCountTests, bool kMirror>
struct PixelWriter {
    raster::PixelBuffers b;
    uint8_t* covered;
    float* covered_view;
    const bsp::Cut* cuts;
    uint32_t cut_count;
    uint32_t face_id;
    uint32_t instance_id;
    uint64_t painted = 0;
    uint64_t skipped = 0;

    void operator()(const raster::TriangleSetup& s, int32_t x, int32_t y, double i, double j) {
        glm::vec2 bary(0.0f);
        if (cut_count > 0) {
            bary = raster::barycentrics_at(s, i, j);
            for (uint32_t k = 0; k < cut_count; ++k) {
                const glm::dvec3& f = cuts[k].value;
                if ((f.x + f.y * double(bary.x) + f.z * double(bary.y) >= 0.0) != cuts[k].front) return;
            }
        }
        const size_t p = size_t(y) * b.stride + size_t(x);
        if constexpr (kCountTests) ++b.tests[p];
        const float depth = raster::depth_at(s, i, j);
        // The tie rule (hsr/visibility_rules.hpp): at exactly the depth already there, the surface
        // earlier in the scene's order keeps the pixel, whichever of the two the walk met first.
        const bool tie = b.face[p] != HSR_NO_FACE && depth == b.depth[p];
        const bool drawn_before =
            tie && raster::drawn_before(instance_id, face_id, b.instance != nullptr ? b.instance[p] : 0, b.face[p]);
        if constexpr (kFrontToBack) {
            if (covered[p]) {
                ++skipped;
                if (!drawn_before) return;
            } else {
                covered[p] = 1;
                if constexpr (kMirror) covered_view[p] = 1.0f;
                ++painted;
            }
        } else {
            ++painted;
            if (tie && !drawn_before) return;
        }
        if (cut_count == 0) bary = raster::barycentrics_at(s, i, j);
        b.depth[p] = depth;
        b.face[p] = face_id;
        if (b.instance != nullptr) b.instance[p] = instance_id;
        b.bary[2 * p] = bary.x;
        b.bary[2 * p + 1] = bary.y;
    }
};

class Bsp final : public hsr::sdk::StepwiseRemover<Bsp> {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "bsp", "1.0.0", "BSP tree (Fuchs, Kedem & Naylor 1980): built once per scene, drawn in order from the eye"};
    static inline const ParamSpec params[] = {
        ParamSpec::choice("order", "back-to-front", "back-to-front|front-to-back",
                          "paint from the back (overwriting), or from the front with a coverage mask"),
        ParamSpec::choice("split", "fewest-splits", "fewest-splits|first",
                          "splitting plane of a node: of `samples` candidates the one cutting fewest polygons, "
                          "or the first polygon's"),
        ParamSpec::integer("samples", "8", 1, 1024, "candidate planes tried per node with split=fewest-splits"),
        ParamSpec::integer("max-polygons", "1000000", 1, 100000000,
                           "refuse a scene needing more polygons after splits (bounds memory: about 600 bytes each)"),
        ParamSpec::boolean("cull-backfaces", false, "skip polygons whose back faces the camera"),
    };

    // The build is one step (it happens once per scene, before any frame); the walk takes a step
    // at each node, where the eye's side of its plane decides the order, and one per polygon drawn.
    static inline const hsr::sdk::PhaseSpec phases[] = {
        {"build", "build the tree: choose a splitter, split the polygons"},
        {"traverse", "at a node: far subtree, node, near subtree"},
        {"draw", "draw the node's polygons"},
    };

    static constexpr hsr::sdk::TranslationSpec own_translations[] = {
        {"ru", "description",
         "дерево двоичного разбиения пространства (Фукс, Кедем и Нейлор, 1980): строится один раз для сцены, "
         "при выводе обходится в порядке, который задаёт положение наблюдателя"},
        {"ru", "param:order", "порядок вывода"},
        {"ru", "help:order",
         "от дальних к ближним, закрашивая поверх уже нарисованного, или от ближних к дальним с маской покрытия"},
        {"ru", "choice:order:back-to-front", "от дальних к ближним"},
        {"ru", "choice:order:front-to-back", "от ближних к дальним"},
        {"ru", "param:split", "выбор разбивающей плоскости"},
        {"ru", "help:split",
         "плоскость, которая разбивает узел: из кандидатов (их число задаёт «число кандидатов») та, что рассекает "
         "меньше всего многоугольников, или плоскость первого многоугольника"},
        {"ru", "choice:split:fewest-splits", "меньше всего разрезаний"},
        {"ru", "choice:split:first", "первый многоугольник"},
        {"ru", "param:samples", "число кандидатов"},
        {"ru", "help:samples",
         "сколько плоскостей-кандидатов пробовать в каждом узле при выборе по наименьшему числу разрезаний"},
        {"ru", "param:max-polygons", "предельное число многоугольников"},
        {"ru", "help:max-polygons",
         "отказаться от сцены, которой после разрезаний нужно больше многоугольников (это ограничивает память: "
         "около 600 байт на многоугольник)"},
        {"ru", "param:cull-backfaces", "отбрасывать нелицевые грани"},
        {"ru", "help:cull-backfaces", "не выводить многоугольники, обращённые к камере обратной стороной"},
        {"ru", "phase:build", "построить дерево: выбрать разбивающую плоскость, рассечь ею многоугольники"},
        {"ru", "phase:traverse", "в узле: дальнее поддерево, сам узел, ближнее поддерево"},
        {"ru", "phase:draw", "нарисовать многоугольники узла"},
        {"ru", "counter:bsp-nodes", "узлов дерева"},
        {"ru", "counter:polygons-in", "многоугольников на входе"},
        {"ru", "counter:polygons-split", "разрезаний многоугольников"},
        {"ru", "counter:polygons-after-splits", "многоугольников после разбиения"},
        {"ru", "counter:tree-depth", "глубина дерева"},
        {"ru", "counter:nodes-visited", "узлов обойдено"},
        {"ru", "counter:polygons-drawn", "многоугольников нарисовано"},
        {"ru", "counter:polygons-backface-culled", "нелицевых многоугольников отброшено"},
        {"ru", "counter:pixels-painted", "пикселей закрашено"},
        {"ru", "counter:pixels-skipped-covered", "пикселей пропущено как уже закрытые"},
        {"ru", "buffer:coverage", "маска покрытия"},
        {"ru", "step:build", "построение BSP-дерева"},
        {"ru", "step:node", "узел дерева"},
        {"ru", "step:polygon", "многоугольник"},
    };
    static constexpr auto translations = hsr::sdk::join_translations(own_translations, hsr::sdk::build_time_counter_translations);

    explicit Bsp(const hsr::sdk::Params& p)
        : front_to_back_(p.choice("order") == 1), cull_backfaces_(p.boolean("cull-backfaces")) {
        build_params_.choice = p.choice("split") == 1 ? bsp::SplitChoice::kFirst : bsp::SplitChoice::kFewestSplits;
        build_params_.samples = uint32_t(p.integer("samples"));
        build_params_.max_polygons = uint64_t(p.integer("max-polygons"));
    }

    // render_steps (from StepwiseRemover) takes one step for the tree, then in drawing order one per
    // node visited and one per node polygon.

private:
    friend class hsr::sdk::StepwiseRemover<Bsp>;

    template <class Steps>
    void render_with(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                     hsr::sdk::Counters& counters, Steps& steps) {
        raster::validate_frame(info.name, scene.raw(), camera, target.raw());

        hsr::sdk::timed_build(counters, [&] { return prepare(scene); });

        begin_frame(camera, target);
        stats_ = FrameStats{};
        try {
            if constexpr (Steps::enabled) build_step(steps);
            if (!tree_.nodes.empty()) draw(steps);
        } catch (const hsr::sdk::StepLimitReached&) {
            report(counters);
            throw;
        }
        report(counters);
    }

    void report(hsr::sdk::Counters& counters) const {
        counters.set("bsp-nodes", tree_.nodes.size());
        counters.set("polygons-in", tree_.stats.polygons_in);
        counters.set("polygons-split", tree_.stats.polygons_split);
        counters.set("polygons-after-splits", tree_.stats.polygons_after_splits);
        counters.set("tree-depth", tree_.stats.depth);
        counters.set("nodes-visited", stats_.nodes_visited);
        counters.set("polygons-drawn", stats_.polygons_drawn);
        counters.set("polygons-backface-culled", stats_.polygons_culled);
        counters.set("pixels-painted", stats_.pixels_painted);
        if (front_to_back_) counters.set("pixels-skipped-covered", stats_.pixels_skipped);
    }

    // Builds the tree unless it was built for this very scene; true when it built.
    bool prepare(const hsr::sdk::Scene& scene) {
        const SceneKey skey = hsr::sdk::scene_key(scene);
        const InstanceKey ikey = hsr::sdk::instance_key(scene);
        if (has_built_ && skey == scene_key_ && ikey == instance_key_) return false;
        has_built_ = false;
        try {
            tree_.build(scene, build_params_);
        } catch (...) {  // refused (Unsupported) or out of memory: keep nothing half built
            tree_.clear();
            tree_.nodes.shrink_to_fit();
            tree_.triangles.shrink_to_fit();
            tree_.polygons.shrink_to_fit();
            tree_.corners.shrink_to_fit();
            tree_.cuts.shrink_to_fit();
            throw;
        }
        scene_key_ = skey;
        instance_key_ = ikey;
        has_built_ = true;
        return true;
    }

    void begin_frame(const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target) {
        // The geometry stage only rasterizes node polygons: no vertices of its own to transform
        // (an empty scene), and facing is judged per polygon (draw_polygon).
        geometry_.begin_frame(hsr_scene{}, camera, false);
        view_projection_ = glm::dmat4(hsr::sdk::load_matrix(camera.view_projection));
        perspective_ = camera.projection_type == HSR_PROJECTION_PERSPECTIVE;
        // The eye and the direction toward the viewer, from the view matrix (world = inverse(view) * eye).
        const glm::dmat4 view(hsr::sdk::load_matrix(camera.view));
        const glm::dmat4 inverse_view = glm::inverse(view);
        eye_ = glm::dvec3(inverse_view[3]) / inverse_view[3][3];
        toward_viewer_ = glm::dvec3(view[0][2], view[1][2], view[2][2]);
        width_ = int32_t(camera.width);
        height_ = int32_t(camera.height);
        buffers_ = raster::PixelBuffers(target);
        if (front_to_back_) covered_.assign(size_t(width_) * size_t(height_), 0);  // keeps its capacity
    }

    template <class Steps>
    void build_step(Steps& steps) const {
        const bsp::BuildStats& b = tree_.stats;
        const unsigned long long in = b.polygons_in, split = b.polygons_split, pieces = b.polygons_after_splits,
                                 nodes = tree_.nodes.size(), depth = b.depth;
        hsr::sdk::Steps::Event event{"build"};
        event.phase = "build";
        if (steps.russian())
            steps.step(event,
                       "BSP-дерево строится один раз для сцены и от положения наблюдателя не зависит: %llu %s, "
                       "рассечено %llu; частей %llu, узлов %llu, глубина %llu",
                       in, russian_plural(in, "многоугольник", "многоугольника", "многоугольников"), split, pieces,
                       nodes, depth);
        else
            steps.step(event,
                       "the BSP tree is built once per scene, whatever the eye: %llu polygon%s, %llu split; "
                       "%llu pieces in %llu nodes, depth %llu",
                       in, in == 1 ? "" : "s", split, pieces, nodes, depth);
    }

    // At a node: the order its subtrees and polygons are drawn in, from the eye's side of its plane.
    template <bool kFrontToBack, class Steps>
    void node_step(uint32_t index, bool eye_in_front, Steps& steps) const {
        const bsp::Node& node = tree_.nodes[index];
        for (uint32_t k = 0; k < node.polygon_count; ++k)
            outline_piece(steps, tree_.polygons[node.first_polygon + k], HSR_STEP_SUBJECT);
        // The side drawn first: back to front the far one, front to back the near one.
        const bool front_first = kFrontToBack == eye_in_front;
        const bool first_empty = (front_first ? node.front : node.back) == bsp::kNoNode;
        const bool last_empty = (front_first ? node.back : node.front) == bsp::kNoNode;
        const unsigned n = index, count = node.polygon_count;
        hsr::sdk::Steps::Event event{"node"};
        event.phase = "traverse";
        if (steps.russian()) {
            const char* first = front_first ? "переднее" : "заднее";
            const char* last = front_first ? "заднее" : "переднее";
            steps.step(event, "узел %u: наблюдатель %s его плоскостью; порядок: %s поддерево%s, %u %s узла, %s%s",
                       n, eye_in_front ? "перед" : "за", first, first_empty ? " (пусто)" : "", count,
                       russian_plural(count, "многоугольник", "многоугольника", "многоугольников"), last,
                       last_empty ? " (пусто)" : "");
        } else {
            const char* first = front_first ? "front" : "back";
            const char* last = front_first ? "back" : "front";
            steps.step(event, "node %u: the eye is %s its plane; order: %s subtree%s, the node's %u polygon%s, %s%s",
                       n, eye_in_front ? "in front of" : "behind", first, first_empty ? " (empty)" : "", count,
                       count == 1 ? "" : "s", last, last_empty ? " (empty)" : "");
        }
    }

    // The outline of a node polygon, when it lies in front of the eye and near the image.
    template <class Steps>
    void outline_piece(Steps& steps, const bsp::Polygon& polygon, hsr_step_role role) const {
        const int count = int(polygon.corner_count);
        glm::dvec3 window[raster::kMaxPieceVertices];
        for (int k = 0; k < count; ++k) {
            const glm::dvec4 clip = view_projection_ * glm::dvec4(tree_.corners[polygon.first_corner + k], 1.0);
            if (!(clip.w > 0.0)) return;
            window[k] = geometry_.viewport().project(clip);
            if (!(window[k].x >= -1.0 && window[k].x <= width_ + 1.0 && window[k].y >= -1.0 &&
                  window[k].y <= height_ + 1.0))
                return;
        }
        for (int k = 0; k < count; ++k) {
            const glm::dvec3& a = window[k];
            const glm::dvec3& b = window[k + 1 == count ? 0 : k + 1];
            steps.line(float(a.x), float(a.y), float(b.x), float(b.y), role);
        }
    }

    // Signed: positive where the eye (or, orthographic, the viewer at infinity) is in front of the plane.
    double eye_side(const glm::dvec4& plane) const {
        const glm::dvec3 normal(plane);
        return perspective_ ? glm::dot(normal, eye_) + plane.w : glm::dot(normal, toward_viewer_);
    }

    // The walk of the tree from the eye, without recursion (a tree can be thousands of nodes deep).
    template <class Steps>
    void draw(Steps& steps) {
        const bool count_tests = buffers_.tests != nullptr;
        if (front_to_back_) {
            if (count_tests)
                walk<true, true>(steps);
            else
                walk<true, false>(steps);
        } else {
            if (count_tests)
                walk<false, true>(steps);
            else
                walk<false, false>(steps);
        }
    }

    template <bool kFrontToBack, bool kCountTests, class Steps>
    void walk(Steps& steps) {
        if constexpr (Steps::enabled)
            if (kFrontToBack) covered_view_.assign(size_t(width_) * size_t(height_), 0.0f);
        stack_.clear();
        stack_.push_back({0, false});
        while (!stack_.empty()) {
            const Visit visit = stack_.back();
            stack_.pop_back();
            const bsp::Node& node = tree_.nodes[visit.node];
            if (visit.polygons) {
                // Kept in z-buffer order (lower instance, then face first): back to front, the
                // first of them must paint last.
                for (uint32_t k = 0; k < node.polygon_count; ++k) {
                    const uint32_t at = kFrontToBack ? k : node.polygon_count - 1 - k;
                    draw_polygon<kFrontToBack, kCountTests>(node.first_polygon + at, visit.node, steps);
                }
                continue;
            }
            ++stats_.nodes_visited;
            // The eye on the plane: neither side hides the other, either order is right.
            const bool eye_in_front = eye_side(node.plane) >= 0.0;
            if constexpr (Steps::enabled) node_step<kFrontToBack>(visit.node, eye_in_front, steps);
            const uint32_t near = eye_in_front ? node.front : node.back;
            const uint32_t far = eye_in_front ? node.back : node.front;
            // Last in, first out: push in the reverse of the drawing order.
            const uint32_t first = kFrontToBack ? near : far, last = kFrontToBack ? far : near;
            if (last != bsp::kNoNode) stack_.push_back({last, false});
            if (node.polygon_count > 0) stack_.push_back({visit.node, true});
            if (first != bsp::kNoNode) stack_.push_back({first, false});
        }
    }

    // A node polygon: its triangle through the rasterizer (the z-buffer's clipping, setup and
    // coverage, bit for bit), within the piece's screen bounds, at the pixel centres its cuts keep.
    template <bool kFrontToBack, bool kCountTests, class Steps>
    void draw_polygon(uint32_t index, uint32_t node, Steps& steps) {
        const bsp::Polygon& polygon = tree_.polygons[index];
        const bsp::Triangle& triangle = tree_.triangles[polygon.triangle];
        const raster::ClipVertex corners[3] = {{view_projection_ * glm::dvec4(triangle.corner[0], 1.0), {0.0, 0.0}},
                                               {view_projection_ * glm::dvec4(triangle.corner[1], 1.0), {1.0, 0.0}},
                                               {view_projection_ * glm::dvec4(triangle.corner[2], 1.0), {0.0, 1.0}}};
        if (cull_backfaces_ &&
            !raster::is_front_facing(corners[0].position, corners[1].position, corners[2].position)) {
            ++stats_.polygons_culled;
            if constexpr (Steps::enabled) {
                hsr::sdk::Steps::Event event{"polygon", triangle.face, triangle.instance};
                event.phase = "draw";
                if (steps.russian())
                    steps.step(event, "узел %u, часть треугольника %u отброшена: нелицевая, обращена от камеры", node,
                               triangle.face);
                else
                    steps.step(event, "node %u, piece of triangle %u: culled, it faces away from the camera", node,
                               triangle.face);
            }
            return;
        }
        // The piece's pixel bounds, a pixel wider than its corners (all of them in front of the eye).
        Rect bounds{INT32_MIN, INT32_MIN, INT32_MAX, INT32_MAX};
        if (polygon.cut_count > 0) {
            Rect piece;
            bool in_front = true;
            for (uint32_t k = 0; k < polygon.corner_count && in_front; ++k) {
                const glm::dvec4 clip = view_projection_ * glm::dvec4(tree_.corners[polygon.first_corner + k], 1.0);
                in_front = clip.w > 0.0;
                const glm::dvec3 w = geometry_.viewport().project(clip);
                piece.x0 = std::min(piece.x0, pixel(std::floor(w.x) - 1.0, width_));
                piece.y0 = std::min(piece.y0, pixel(std::floor(w.y) - 1.0, height_));
                piece.x1 = std::max(piece.x1, pixel(std::ceil(w.x) + 1.0, width_));
                piece.y1 = std::max(piece.y1, pixel(std::ceil(w.y) + 1.0, height_));
            }
            if (in_front) bounds = piece;  // (NaN corners make empty bounds: nothing drawn)
        }
        PixelWriter<kFrontToBack, kCountTests, Steps::enabled> writer{
            buffers_,          covered_.data(),      covered_view_.data(), tree_.cuts.data() + polygon.first_cut,
            polygon.cut_count, triangle.face, triangle.instance};
        Rect box;
        bool drawn = false;
        geometry_.rasterize_polygon(corners, 3, [&](const raster::TriangleSetup& s) {
            const int32_t x0 = std::max(s.min_x, bounds.x0), y0 = std::max(s.min_y, bounds.y0);
            const int32_t x1 = std::min(s.max_x, bounds.x1), y1 = std::min(s.max_y, bounds.y1);
            if (x0 > x1 || y0 > y1) return;
            drawn = true;
            raster::for_each_covered_pixel_in(
                s, x0, y0, x1, y1, [&](int32_t x, int32_t y, double i, double j) { writer(s, x, y, i, j); });
            if constexpr (Steps::enabled) {
                box.x0 = std::min(box.x0, x0);
                box.y0 = std::min(box.y0, y0);
                box.x1 = std::max(box.x1, x1);
                box.y1 = std::max(box.y1, y1);
            }
        });
        stats_.polygons_drawn += drawn ? 1 : 0;
        stats_.pixels_painted += writer.painted;
        stats_.pixels_skipped += writer.skipped;
        if constexpr (Steps::enabled)
            polygon_step<kFrontToBack>(steps, polygon, triangle, node, box, writer.painted, writer.skipped);
    }

    // The step of one node polygon: its outline (when it lies in front of the eye and near the
    // image), the pixel bounds of what it wrote, and in front-to-back order the coverage mask.
    template <bool kFrontToBack, class Steps>
    void polygon_step(Steps& steps, const bsp::Polygon& polygon, const bsp::Triangle& triangle, uint32_t node,
                      const Rect& box, uint64_t painted, uint64_t skipped) {
        outline_piece(steps, polygon, HSR_STEP_SUBJECT);
        if (!box.empty())
            raster::pixel_box_lines(steps, box.x0, box.y0, box.x1, box.y1, width_, height_,
                                    painted > 0 ? HSR_STEP_WRITTEN : HSR_STEP_REJECTED);
        const unsigned f = triangle.face, n = node;
        const unsigned long long w = painted, s = skipped;
        hsr::sdk::Steps::Event event{"polygon", triangle.face, triangle.instance, HSR_NO_LEVEL, painted, skipped};
        event.phase = "draw";
        const char* pixels = russian_plural(w, "пиксель", "пикселя", "пикселей");
        if (kFrontToBack) {
            steps.buffer("coverage", uint32_t(width_), uint32_t(height_), covered_view_.data());
            if (steps.russian())
                steps.step(event, "узел %u, часть треугольника %u: записано %llu %s, пропущено как уже закрытые: %llu",
                           n, f, w, pixels, s);
            else
                steps.step(event, "node %u, piece of triangle %u: %llu pixel%s written, %llu skipped as covered", n, f,
                           w, w == 1 ? "" : "s", s);
        } else {
            if (steps.russian())
                steps.step(event, "узел %u, часть треугольника %u: закрашено %llu %s", n, f, w, pixels);
            else
                steps.step(event, "node %u, piece of triangle %u: %llu pixel%s painted", n, f, w, w == 1 ? "" : "s");
        }
    }

    struct Visit {
        uint32_t node;
        bool polygons;  // draw the node's polygons (else: visit the node)
    };

    // Parameters
    bool front_to_back_;
    bool cull_backfaces_;
    bsp::BuildParams build_params_;

    // Built once per scene
    bool has_built_ = false;
    SceneKey scene_key_;
    InstanceKey instance_key_;
    bsp::Tree tree_;

    // Per frame (buffers keep their capacity between frames)
    raster::GeometryStage geometry_;
    FrameStats stats_;
    glm::dmat4 view_projection_{1.0};
    glm::dvec3 eye_{0.0}, toward_viewer_{0.0, 0.0, 1.0};
    bool perspective_ = true;
    int32_t width_ = 0, height_ = 0;
    raster::PixelBuffers buffers_;
    std::vector<uint8_t> covered_;      // front to back: 1 where a pixel is written
    std::vector<float> covered_view_;   // the same as floats, with steps only
    std::vector<Visit> stack_;
};

}  // namespace

HSR_EXPORT_PLUGIN(Bsp)
