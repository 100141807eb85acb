// raycast: one ray per pixel centre, the nearest surface it meets is the visible one (Arthur Appel,
// "Some Techniques for Shading Machine Renderings of Solids", AFIPS Spring Joint Computer
// Conference 1968, ray casting for visibility).
//
// Each ray runs from the near plane to the far plane through a pixel centre: the window points
// (x + 0.5, y + 0.5, depth 0) and (..., depth 1) taken back to the world by the inverse of the
// camera's view_projection, which serves perspective and orthographic cameras alike; its parameter
// t runs from 0 to 1, and since every space the ray is carried into is an affine image of the world,
// t is the same there. The ray goes down a hierarchy over the placements (world space), and for each
// placement it reaches, carried into object space, down that object's hierarchy (bvh.hpp: binned
// SAH, built once per scene and shared by every placement of the object), nearer child first, with
// the watertight ray/triangle test (ray_triangle.hpp, Woop, Benthin & Wald 2013). The nearest hit
// whose window depth (from view_projection, in double) lies in [0, 1] and which every camera clip
// plane keeps is the pixel's; hits that fail either are passed over, so the search goes on to
// farther ones. "Nearest" is judged in the float depth the buffer stores, and hits at the same float
// depth go to the lower instance, then the lower face (as the z-buffer keeps the surface it draws
// first), whatever the traversal order: after each hit the search goes on to the ray parameter
// where the depth passes the next float. A hit counts only where the rasterizers' fill rule gives
// its triangle the pixel centre (the corners snapped to their 1/256-pixel grid, the top-left rule):
// a centre on an edge is drawn as the z-buffer draws it. Both rules are hsr/visibility_rules.hpp's.
//
// The hit test runs in double (the default: the reference other algorithms are judged by) or float.
// The image is cut into tiles, cast by `threads` threads; each pixel's answer depends on nothing else,
// so any number of threads gives the same buffers. docs/algorithms/raycast.md describes the steps.
#include "bvh.hpp"
#include "ray_triangle.hpp"
#include "hsr/scene_key.hpp"

#include "hsr/raster.hpp"
#include "hsr/sdk.hpp"
#include "hsr/tiles.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <vector>

using hsr::sdk::russian_plural;

namespace raycast {

using hsr::sdk::ParamSpec;

// A triangle in object space, stored in its hierarchy's leaf order.
struct Triangle {
    float corner[3][3];
    uint32_t face;  // the scene's triangle id
};

// The hierarchy of one distinct triangle range of the scene.
struct ObjectBvh {
    uint32_t root = 0;
    bool has_root = false;  // false when no triangle of the range has finite corners
};

// A placement the top-level hierarchy holds.
struct PlacedObject {
    uint32_t placement = 0;
    uint32_t instance = 0;
    uint32_t root = 0;       // of its object's hierarchy
    bool identity = true;    // object space is world space
    bool mirrored = false;   // the transform turns counter-clockwise into clockwise
    glm::dmat4 world_from_object{1.0};
    glm::dmat4 object_from_world{1.0};
};

struct RayStats {
    uint64_t rays = 0, hits = 0, triangle_tests = 0, nodes_visited = 0;
    RayStats& operator+=(const RayStats& o) {
        rays += o.rays;
        hits += o.hits;
        triangle_tests += o.triangle_tests;
        nodes_visited += o.nodes_visited;
        return *this;
    }
};

// The nearest acceptable hit so far of one ray, and how far the search must still look.
struct Nearest {
    double t_limit;                 // no hit beyond this ray parameter can replace this one
    glm::dvec4 clip_origin{0.0};    // the ray in clip space: clip_origin + t * clip_step
    glm::dvec4 clip_step{0.0};
    double b1 = 0.0, b2 = 0.0;
    float depth = 0.0f;             // window depth, rounded to what the buffer stores
    uint32_t face = HSR_NO_FACE, instance = 0;
    int64_t sample_x = 0, sample_y = 0;  // the pixel centre on the rasterizers' 1/256-pixel grid
    hsr::raster::SnappedCornerCache* snapped = nullptr;  // the casting thread's
};

// Hits a little outside t in [0, 1] (rounding at the near and far planes) are still looked at; the
// window depth, from view_projection, decides. The same relative slack widens the search limit.
constexpr double kTSlack = 1e-6;

class Raycast final : public hsr::sdk::StepwiseRemover<Raycast> {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "raycast", "1.0.0",
        "ray casting (Appel 1968): one ray per pixel centre, binned-SAH BVH, watertight ray/triangle test"};
    static inline const ParamSpec params[] = {
        ParamSpec::choice("precision", "double", "double|float", "arithmetic of the ray/triangle and ray/box tests"),
        ParamSpec::integer("threads", "0", 0, 1024, "threads casting rays (0 = one per core)"),
        ParamSpec::integer("tile-size", "16", 1, 4096, "side in pixels of the square tiles the threads take"),
        ParamSpec::integer("leaf-triangles", "4", 1, 256, "a hierarchy node with at most this many triangles is a leaf"),
        ParamSpec::boolean("cull-backfaces", false, "skip triangles whose back faces the camera"),
    };
    // ABI 1.5: the phases of ray casting, as a textbook writes it.
    static inline const hsr::sdk::PhaseSpec phases[] = {
        {"build", "build the bounding volume hierarchy over the triangles"},
        {"cast", "cast a ray through each pixel centre and keep its nearest hit"},
    };

    static constexpr hsr::sdk::TranslationSpec own_translations[] = {
        {"ru", "description",
         "метод бросания лучей (Аппель, 1968): луч через центр каждого пикселя, иерархия ограничивающих объёмов "
         "по эвристике площади поверхности (SAH), «водонепроницаемый» тест пересечения луча с треугольником"},
        {"ru", "param:precision", "точность вычислений"},
        {"ru", "help:precision", "арифметика тестов пересечения луча с треугольником и с параллелепипедом"},
        {"ru", "choice:precision:double", "двойная (double)"},
        {"ru", "choice:precision:float", "одинарная (float)"},
        {"ru", "param:threads", "число потоков"},
        {"ru", "help:threads", "сколько потоков бросают лучи (0 — по одному на ядро)"},
        {"ru", "param:tile-size", "размер тайла"},
        {"ru", "help:tile-size", "сторона в пикселях квадратных тайлов, которые разбирают потоки"},
        {"ru", "param:leaf-triangles", "треугольников в листе"},
        {"ru", "help:leaf-triangles", "узел иерархии, в котором не больше стольких треугольников, становится листом"},
        {"ru", "param:cull-backfaces", "отбрасывать нелицевые грани"},
        {"ru", "help:cull-backfaces", "не рисовать треугольники, повёрнутые к камере нелицевой стороной"},
        {"ru", "phase:build", "построить иерархию ограничивающих объёмов над треугольниками"},
        {"ru", "phase:cast", "бросить луч через центр каждого пикселя и оставить ближайшее пересечение"},
        {"ru", "counter:rays", "лучей брошено"},
        {"ru", "counter:hits", "попаданий лучей"},
        {"ru", "counter:bvh-nodes", "узлов иерархии ограничивающих объёмов"},
        {"ru", "counter:triangle-tests", "тестов пересечения луча с треугольником"},
        {"ru", "counter:nodes-visited", "узлов иерархии посещено"},
        {"ru", "step:build", "построение иерархии объёмов"},
        {"ru", "step:tile", "тайл"},
    };
    static constexpr auto translations = hsr::sdk::join_translations(
        own_translations, hsr::sdk::build_time_counter_translations);

    explicit Raycast(const hsr::sdk::Params& p)
        : double_precision_(p.choice("precision") == 0),
          threads_(uint32_t(p.integer("threads"))),
          tile_size_(uint32_t(p.integer("tile-size"))),
          leaf_triangles_(uint32_t(p.integer("leaf-triangles"))),
          cull_backfaces_(p.boolean("cull-backfaces")) {}

    // render_steps (from StepwiseRemover) takes a step for the hierarchy (phase "build"), then one step
    // per tile (phase "cast"), tiles in rows from the top left, all cast on the calling thread.

private:
    friend class hsr::sdk::StepwiseRemover<Raycast>;

    template <class Steps>
    void render_with(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                     hsr::sdk::Counters& counters, Steps& steps) {
        hsr::raster::validate_frame(info.name, scene.raw(), camera, target.raw());

        bool built = false;
        hsr::sdk::timed_build(counters, [&] { return built = prepare(scene); });
        counters.set("bvh-nodes", nodes_.size() + top_nodes_.size());

        begin_frame(camera, target);
        RayStats total;
        auto report = [&] {
            counters.set("rays", total.rays);
            counters.set("hits", total.hits);
            counters.set("triangle-tests", total.triangle_tests);
            counters.set("nodes-visited", total.nodes_visited);
        };
        if constexpr (Steps::enabled) {
            try {
                build_step(steps, built);
                for (uint32_t k = 0; k < tiles().count(); ++k) {
                    RayStats tile;
                    cast_tile(k, tile);
                    total += tile;
                    tile_step(steps, k, tile);
                }
            } catch (const hsr::sdk::StepLimitReached&) {
                report();
                throw;
            }
        } else {
            cast_all(total);
        }
        report();
    }

    // ------------------------------------------------------------------------------------------ //
    // Build (once per scene; only the top level again when only the placements changed)

    bool prepare(const hsr::sdk::Scene& scene) {
        const hsr::sdk::SceneKey skey = hsr::sdk::scene_key(scene);
        const hsr::sdk::InstanceKey ikey = hsr::sdk::instance_key(scene);
        if (has_built_ && skey == scene_key_ && ikey == instance_key_) return false;
        const bool same_geometry = has_built_ && skey == scene_key_;
        has_built_ = false;  // until everything below is done (it may throw bad_alloc)
        if (!same_geometry) {
            nodes_.clear();
            triangles_.clear();
            objects_.clear();
            object_of_range_.clear();
        }
        std::vector<PlacedObject> placed;
        std::vector<PrimitiveRef> refs;
        for (uint32_t k = 0; k < scene.placement_count(); ++k) {
            const hsr::sdk::Placement p = scene.placement(k);
            const std::array<uint32_t, 4> range{p.first_triangle, p.triangle_count, p.first_vertex, p.vertex_count};
            auto found = object_of_range_.find(range);
            if (found == object_of_range_.end())
                found = object_of_range_.emplace(range, build_object(scene, p.first_triangle, p.triangle_count)).first;
            const ObjectBvh& object = objects_[found->second];
            if (!object.has_root) continue;
            PlacedObject o;
            o.placement = k;
            o.instance = p.instance;
            o.root = object.root;
            o.identity = p.identity;
            o.world_from_object = p.identity ? glm::dmat4(1.0) : glm::dmat4(p.transform);
            o.object_from_world = glm::inverse(o.world_from_object);
            o.mirrored = glm::determinant(o.world_from_object) < 0.0;
            refs.push_back(make_ref(world_box(nodes_[object.root].box, o.world_from_object), uint32_t(placed.size())));
            placed.push_back(o);
        }
        top_nodes_.clear();
        placed_.clear();
        if (!refs.empty()) {
            build_bvh(refs, 1, top_nodes_);
            for (const PrimitiveRef& r : refs) placed_.push_back(placed[r.id]);
        }
        clip_from_object_.resize(placed_.size());
        scene_key_ = skey;
        instance_key_ = ikey;
        has_built_ = true;
        return true;
    }

    // Builds the hierarchy of triangles [first, first + count) into nodes_ and triangles_.
    uint32_t build_object(const hsr::sdk::Scene& scene, uint32_t first, uint32_t count) {
        std::vector<PrimitiveRef> refs;
        refs.reserve(count);
        for (uint32_t t = first; t < first + count; ++t) {
            Box box;
            bool finite = true;
            for (int c = 0; c < 3; ++c) {
                const glm::vec3 p = scene.corner_position(t, c);
                finite = finite && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
                box.add(&p.x);
            }
            if (finite) refs.push_back(make_ref(box, t));
        }
        ObjectBvh object;
        if (!refs.empty()) {
            const uint32_t base_node = uint32_t(nodes_.size());
            const uint32_t base_triangle = uint32_t(triangles_.size());
            build_bvh(refs, leaf_triangles_, nodes_);
            for (uint32_t n = base_node; n < nodes_.size(); ++n)
                if (nodes_[n].is_leaf()) nodes_[n].first += base_triangle;
            for (const PrimitiveRef& r : refs) {
                Triangle tri;
                for (int c = 0; c < 3; ++c) {
                    const glm::vec3 p = scene.corner_position(r.id, c);
                    tri.corner[c][0] = p.x;
                    tri.corner[c][1] = p.y;
                    tri.corner[c][2] = p.z;
                }
                tri.face = r.id;
                triangles_.push_back(tri);
            }
            object.root = base_node;
            object.has_root = true;
        }
        objects_.push_back(object);
        return uint32_t(objects_.size() - 1);
    }

    // An object box carried into the world, rounded outward (anywhere, when it overflows float).
    static Box world_box(const Box& b, const glm::dmat4& m) {
        glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
        for (int c = 0; c < 8; ++c) {
            const glm::dvec4 w =
                m * glm::dvec4((c & 1) ? b.hi[0] : b.lo[0], (c & 2) ? b.hi[1] : b.lo[1], (c & 4) ? b.hi[2] : b.lo[2], 1.0);
            lo = glm::min(lo, glm::dvec3(w));
            hi = glm::max(hi, glm::dvec3(w));
        }
        Box out;
        for (int a = 0; a < 3; ++a) {
            out.lo[a] = std::nextafter(float(lo[a]), -std::numeric_limits<float>::infinity());
            out.hi[a] = std::nextafter(float(hi[a]), std::numeric_limits<float>::infinity());
            if (!(std::isfinite(out.lo[a]) && std::isfinite(out.hi[a]))) {
                out.lo[a] = -std::numeric_limits<float>::max();
                out.hi[a] = std::numeric_limits<float>::max();
            }
        }
        return out;
    }

    // ------------------------------------------------------------------------------------------ //
    // Per frame

    void begin_frame(const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target) {
        width_ = camera.width;
        height_ = camera.height;
        view_projection_ = glm::dmat4(hsr::sdk::load_matrix(camera.view_projection));
        window_to_world_ = glm::inverse(view_projection_);
        planes_ = hsr::sdk::ClipPlanes(camera);
        viewport_ = hsr::raster::Viewport(width_, height_);
        guard_ = hsr::raster::GuardBand(width_, height_);
        for (size_t k = 0; k < placed_.size(); ++k)
            clip_from_object_[k] = view_projection_ * placed_[k].world_from_object;
        depth_ = target.depth();
        face_ = target.face();
        bary_ = target.bary();
        instance_ = target.instance();
        tests_ = target.depth_tests();
    }

    hsr::sdk::TileGrid tiles() const { return {width_, height_, tile_size_}; }

    // Every tile, by the threads asked for, each taking the next tile left.
    void cast_all(RayStats& total) {
        const std::vector<RayStats> stats = hsr::sdk::share_tiles<RayStats>(
            tiles().count(), threads_, [this](uint32_t k, RayStats& s) { cast_tile(k, s); });
        for (const RayStats& s : stats) total += s;
    }

    void cast_tile(uint32_t k, RayStats& stats) const {
        if (double_precision_)
            cast_tile<double>(k, stats);
        else
            cast_tile<float>(k, stats);
    }

    template <class Real>
    void cast_tile(uint32_t k, RayStats& stats) const {
        uint32_t x0, y0, x1, y1;
        tiles().rect(k, x0, y0, x1, y1);
        hsr::raster::SnappedCornerCache snapped;
        for (uint32_t y = y0; y < y1; ++y)
            for (uint32_t x = x0; x < x1; ++x) cast_pixel<Real>(x, y, stats, snapped);
    }

    template <class Real>
    void cast_pixel(uint32_t x, uint32_t y, RayStats& stats, hsr::raster::SnappedCornerCache& snapped) const {
        const double ndc_x = 2.0 * (x + 0.5) / width_ - 1.0;
        const double ndc_y = 1.0 - 2.0 * (y + 0.5) / height_;
        const glm::dvec4 near_h = window_to_world_ * glm::dvec4(ndc_x, ndc_y, -1.0, 1.0);
        const glm::dvec4 far_h = window_to_world_ * glm::dvec4(ndc_x, ndc_y, 1.0, 1.0);
        const glm::dvec3 origin = glm::dvec3(near_h) / near_h.w;
        const glm::dvec3 direction = glm::dvec3(far_h) / far_h.w - origin;
        const size_t p = size_t(y) * width_ + x;
        ++stats.rays;
        Nearest hit{1.0 + kTSlack, view_projection_ * glm::dvec4(origin, 1.0),
                    view_projection_ * glm::dvec4(direction, 0.0)};
        hit.sample_x = int64_t(x) * hsr::raster::kSubpixelScale + hsr::raster::kHalfPixel;
        hit.sample_y = int64_t(y) * hsr::raster::kSubpixelScale + hsr::raster::kHalfPixel;
        hit.snapped = &snapped;
        uint64_t tests = 0;
        if (std::isfinite(origin.x + origin.y + origin.z + direction.x + direction.y + direction.z) && !placed_.empty())
            tests = cast<Real>(origin, direction, hit, stats);
        if (tests_ != nullptr) tests_[p] = uint32_t(std::min<uint64_t>(tests, UINT32_MAX));
        if (hit.face == HSR_NO_FACE) return;
        ++stats.hits;
        depth_[p] = hit.depth;
        face_[p] = hit.face;
        bary_[2 * p] = float(hit.b1);
        bary_[2 * p + 1] = float(hit.b2);
        if (instance_ != nullptr) instance_[p] = hit.instance;
    }

    // Down the hierarchy over the placements; returns the ray/triangle tests made.
    template <class Real>
    uint64_t cast(const glm::dvec3& origin, const glm::dvec3& direction, Nearest& hit, RayStats& stats) const {
        Ray<double> ray;
        ray.prepare(&origin.x, &direction.x);
        uint64_t tests = 0;
        struct Entry {
            uint32_t node;
            double t;
        };
        Entry stack[kStackSize];
        int size = 0;
        if (enter_box(ray, top_nodes_[0].box.lo, top_nodes_[0].box.hi, -kTSlack, hit.t_limit) <= hit.t_limit)
            stack[size++] = {0, 0.0};
        while (size > 0) {
            const Entry e = stack[--size];
            if (e.t > hit.t_limit) continue;
            const Node& node = top_nodes_[e.node];
            ++stats.nodes_visited;
            if (node.is_leaf()) {
                for (uint32_t k = node.first; k < node.first + node.count; ++k)
                    tests += cast_object<Real>(k, origin, direction, hit, stats);
                continue;
            }
            push_children(ray, top_nodes_, node, hit.t_limit, stack, size);
        }
        return tests;
    }

    // Pushes the children of `node` the ray enters before t_max, the nearer one on top.
    template <class Real, class Entry>
    static void push_children(const Ray<Real>& ray, const std::vector<Node>& nodes, const Node& node, double t_max,
                              Entry* stack, int& size) {
        const Node& left = nodes[node.first];
        const Node& right = nodes[node.first + 1];
        const Real limit = Real(t_max);
        const Real t_left = enter_box(ray, left.box.lo, left.box.hi, Real(-kTSlack), limit);
        const Real t_right = enter_box(ray, right.box.lo, right.box.hi, Real(-kTSlack), limit);
        const bool in_left = t_left <= limit, in_right = t_right <= limit;
        if (in_left && in_right) {
            const bool left_first = t_left <= t_right;
            stack[size++] = {left_first ? node.first + 1 : node.first, double(left_first ? t_right : t_left)};
            stack[size++] = {left_first ? node.first : node.first + 1, double(left_first ? t_left : t_right)};
        } else if (in_left) {
            stack[size++] = {node.first, double(t_left)};
        } else if (in_right) {
            stack[size++] = {node.first + 1, double(t_right)};
        }
    }

    // Down the hierarchy of placed object k, the ray carried into its object space.
    template <class Real>
    uint64_t cast_object(uint32_t k, const glm::dvec3& world_origin, const glm::dvec3& world_direction, Nearest& hit,
                         RayStats& stats) const {
        const PlacedObject& o = placed_[k];
        glm::dvec3 origin = world_origin, direction = world_direction;
        if (!o.identity) {
            origin = glm::dvec3(o.object_from_world * glm::dvec4(world_origin, 1.0));
            direction = glm::dvec3(o.object_from_world * glm::dvec4(world_direction, 0.0));
        }
        Ray<Real> ray;
        ray.prepare(&origin.x, &direction.x);
        struct Entry {
            uint32_t node;
            double t;
        };
        Entry stack[kStackSize];
        int size = 0;
        uint64_t tests = 0;
        stack[size++] = {o.root, -kTSlack};
        while (size > 0) {
            const Entry e = stack[--size];
            if (e.t > hit.t_limit) continue;
            const Node& node = nodes_[e.node];
            ++stats.nodes_visited;
            if (!node.is_leaf()) {
                push_children(ray, nodes_, node, hit.t_limit, stack, size);
                continue;
            }
            for (uint32_t i = node.first; i < node.first + node.count; ++i) {
                const Triangle& tri = triangles_[i];
                ++tests;
                TriangleHit h;
                const Meets meets = intersect(ray, tri.corner[0], tri.corner[1], tri.corner[2], h);
                if (meets == Meets::kMiss) continue;
                if (h.t < -kTSlack || h.t > hit.t_limit) continue;
                if (cull_backfaces_ && h.front == o.mirrored) continue;
                consider(k, tri, h, meets == Meets::kNearMiss, hit);
            }
        }
        stats.triangle_tests += tests;
        return tests;
    }

    // Makes h the nearest hit when its point lies in the view volume, on the kept side of every
    // clip plane, and nearer than the nearest so far in the depth the buffer stores; at the same
    // stored depth the lower instance, then the lower face wins (the tie rule of
    // hsr/visibility_rules.hpp: the surface the z-buffer draws first, and keeps on an equal depth);
    // and when the rasterizers' fill rule gives the triangle this pixel centre.
    void consider(uint32_t k, const Triangle& tri, const TriangleHit& h, bool near_miss, Nearest& hit) const {
        glm::dvec3 corner[3];
        for (int c = 0; c < 3; ++c) corner[c] = glm::dvec3(tri.corner[c][0], tri.corner[c][1], tri.corner[c][2]);
        const glm::dvec3 point = corner[0] + h.b1 * (corner[1] - corner[0]) + h.b2 * (corner[2] - corner[0]);
        const glm::dvec4 clip = clip_from_object_[k] * glm::dvec4(point, 1.0);
        const double exact_depth = (clip.z / clip.w + 1.0) * 0.5;
        if (!(exact_depth >= 0.0 && exact_depth <= 1.0)) return;
        const float depth = float(exact_depth);
        const PlacedObject& o = placed_[k];
        if (!hsr::raster::replaces(depth, o.instance, tri.face, hit.depth, hit.instance, hit.face)) return;
        if (planes_.count > 0) {
            const glm::dvec3 world = o.identity ? point : glm::dvec3(o.world_from_object * glm::dvec4(point, 1.0));
            if (!planes_.keeps(world)) return;
        }
        switch (fill_rule(k, tri, hit)) {
            case Fill::kCovered: break;
            case Fill::kNotCovered: return;
            case Fill::kUnknown:
                if (near_miss) return;
                break;
        }
        // A near miss the rasterizers cover: its barycentrics held inside the triangle, as theirs.
        double b1 = std::max(h.b1, 0.0), b2 = std::max(h.b2, 0.0);
        if (b1 + b2 > 1.0) {
            const double sum = b1 + b2;
            b1 /= sum;
            b2 /= sum;
        }
        hit.b1 = b1;
        hit.b2 = b2;
        hit.depth = depth;
        hit.face = tri.face;
        hit.instance = o.instance;
        hit.t_limit = std::max(h.t, ray_parameter_at(hit, std::nextafter(depth, 2.0f)));
        hit.t_limit += kTSlack * std::abs(hit.t_limit);
    }

    // The fill rule (hsr/visibility_rules.hpp) at the ray's pixel centre: the triangle's corners
    // taken to the window and snapped to the 1/256-pixel grid exactly as the z-buffer snaps them, so
    // that a centre on an edge, or within a snapping step of one, is drawn as the rasterizers draw it
    // (a centre on an edge two triangles share by one of them). Unknown for a triangle the
    // rasterizers clip first (a corner beyond the near or far plane or the guard band), or a
    // sliver that snapping reshapes (the area off by a factor of 2: the z-buffer then takes depth
    // from the snapped corners): the ray's own test decides.
    enum class Fill { kCovered, kNotCovered, kUnknown };
    Fill fill_rule(uint32_t k, const Triangle& tri, const Nearest& ray) const {
        // Neighbouring pixels mostly meet the same few triangles: their snapped corners are kept.
        const auto& snapped = ray.snapped->find(k, uint32_t(&tri - triangles_.data()),
                                                [&](int64_t(&x)[3], int64_t(&y)[3]) { return snap(k, tri, x, y); });
        if (!snapped.known) return Fill::kUnknown;
        return hsr::raster::covers_sample(snapped.x, snapped.y, ray.sample_x, ray.sample_y) ? Fill::kCovered
                                                                                             : Fill::kNotCovered;
    }

    // The triangle's corners snapped as the z-buffer snaps them; false when the rule cannot be
    // applied (see fill_rule).
    bool snap(uint32_t k, const Triangle& tri, int64_t (&x)[3], int64_t (&y)[3]) const {
        glm::dvec4 clip[3];
        for (int c = 0; c < 3; ++c)
            clip[c] = clip_from_object_[k] * glm::dvec4(tri.corner[c][0], tri.corner[c][1], tri.corner[c][2], 1.0);
        hsr::raster::WindowVertex w[3];
        if (!hsr::raster::unclipped_window_corners(clip, viewport_, guard_, w)) return false;
        double exact_x[3], exact_y[3];
        for (int c = 0; c < 3; ++c) {
            x[c] = w[c].x;
            y[c] = w[c].y;
            exact_x[c] = w[c].exact_x;
            exact_y[c] = w[c].exact_y;
        }
        const double grid_area = double((x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0])) /
                                 double(hsr::raster::kSubpixelScale * hsr::raster::kSubpixelScale);
        const double exact_area = (exact_x[1] - exact_x[0]) * (exact_y[2] - exact_y[0]) -
                                  (exact_x[2] - exact_x[0]) * (exact_y[1] - exact_y[0]);
        const double ratio = exact_area / grid_area;  // NaN for a triangle of no area on the grid
        return ratio > 0.5 && ratio < 2.0;
    }

    // Where the ray reaches window depth `depth` (+infinity when it never does): depth is
    // (z / w + 1) / 2 of the clip-space ray, solved for t.
    static double ray_parameter_at(const Nearest& ray, double depth) {
        const double k = 2.0 * depth - 1.0;
        const double t = (k * ray.clip_origin.w - ray.clip_origin.z) / (ray.clip_step.z - k * ray.clip_step.w);
        return t >= 0.0 ? t : std::numeric_limits<double>::infinity();
    }

    // ------------------------------------------------------------------------------------------ //
    // Steps (ABI 1.3; phases and languages, ABI 1.5)

    // The hierarchy just built (or kept from the last frame of the same scene): the screen rectangle
    // of each placed object's box, the leaves of the top level.
    template <class Steps>
    void build_step(Steps& steps, bool built) const {
        constexpr size_t kMostBoxes = 1024;
        for (size_t k = 0; k < placed_.size() && k < kMostBoxes; ++k) {
            const Node& root = nodes_[placed_[k].root];
            float x0 = std::numeric_limits<float>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
            bool in_front = true;
            for (int c = 0; c < 8 && in_front; ++c) {
                const glm::dvec4 clip =
                    clip_from_object_[k] * glm::dvec4((c & 1) ? root.box.hi[0] : root.box.lo[0],
                                                      (c & 2) ? root.box.hi[1] : root.box.lo[1],
                                                      (c & 4) ? root.box.hi[2] : root.box.lo[2], 1.0);
                in_front = clip.w > 0.0;
                const float x = float((clip.x / clip.w + 1.0) * 0.5 * width_);
                const float y = float((1.0 - clip.y / clip.w) * 0.5 * height_);
                x0 = std::min(x0, x);
                x1 = std::max(x1, x);
                y0 = std::min(y0, y);
                y1 = std::max(y1, y);
            }
            if (in_front && std::isfinite(x0 + x1 + y0 + y1)) steps.box(x0, y0, x1, y1, HSR_STEP_CONTEXT);
        }
        const hsr::sdk::Steps::Event event{"build", HSR_NO_FACE, 0, HSR_NO_LEVEL, 0, 0, "build"};
        const unsigned long long nodes = nodes_.size() + top_nodes_.size(), triangles = triangles_.size(),
                                 objects = placed_.size();
        if (steps.russian())
            steps.step(event, "иерархия ограничивающих объёмов %s: %llu %s, %llu %s в листьях, %llu %s на сцене",
                       built ? "построена" : "взята с прошлого кадра", nodes, russian_plural(nodes, "узел", "узла", "узлов"),
                       triangles, russian_plural(triangles, "треугольник", "треугольника", "треугольников"), objects,
                       russian_plural(objects, "объект", "объекта", "объектов"));
        else
            steps.step(event, "bounding volume hierarchy %s: %llu node%s, %llu triangle%s in its leaves, %llu object%s placed",
                       built ? "built" : "kept from the last frame", nodes, nodes == 1 ? "" : "s", triangles,
                       triangles == 1 ? "" : "s", objects, objects == 1 ? "" : "s");
    }

    template <class Steps>
    void tile_step(Steps& steps, uint32_t k, const RayStats& tile) const {
        uint32_t x0, y0, x1, y1;
        tiles().rect(k, x0, y0, x1, y1);
        steps.box(float(x0), float(y0), float(x1), float(y1), HSR_STEP_SUBJECT);
        const hsr::sdk::Steps::Event event{"tile", HSR_NO_FACE, 0, HSR_NO_LEVEL, tile.hits, 0, "cast"};
        const unsigned long long rays = tile.rays, hits = tile.hits, tests = tile.triangle_tests,
                                 nodes = tile.nodes_visited;
        if (steps.russian())
            steps.step(event, "тайл %u (%u,%u)–(%u,%u): %llu %s, %llu %s, %llu %s «луч — треугольник», %llu %s иерархии",
                       k, x0, y0, x1 - 1, y1 - 1, rays, russian_plural(rays, "луч", "луча", "лучей"), hits,
                       russian_plural(hits, "попадание", "попадания", "попаданий"), tests,
                       russian_plural(tests, "проверка", "проверки", "проверок"), nodes,
                       russian_plural(nodes, "узел", "узла", "узлов"));
        else
            steps.step(event, "tile %u (%u,%u)-(%u,%u): %llu rays, %llu hits, %llu ray/triangle tests, %llu nodes visited",
                       k, x0, y0, x1 - 1, y1 - 1, rays, hits, tests, nodes);
    }

    // Parameters
    bool double_precision_;
    uint32_t threads_;
    uint32_t tile_size_;
    uint32_t leaf_triangles_;
    bool cull_backfaces_;

    // Built once per scene
    bool has_built_ = false;
    hsr::sdk::SceneKey scene_key_;
    hsr::sdk::InstanceKey instance_key_;
    std::vector<Node> nodes_;           // every object's hierarchy
    std::vector<Triangle> triangles_;   // in leaf order
    std::vector<ObjectBvh> objects_;
    std::map<std::array<uint32_t, 4>, uint32_t> object_of_range_;  // triangle and vertex range -> objects_
    std::vector<Node> top_nodes_;       // over placed_ (root: node 0)
    std::vector<PlacedObject> placed_;  // in leaf order of top_nodes_

    // Per frame
    uint32_t width_ = 0, height_ = 0;
    glm::dmat4 view_projection_{1.0}, window_to_world_{1.0};
    hsr::sdk::ClipPlanes planes_{hsr_camera{}};
    hsr::raster::Viewport viewport_;
    hsr::raster::GuardBand guard_;
    std::vector<glm::dmat4> clip_from_object_;  // per placed_
    float* depth_ = nullptr;
    uint32_t* face_ = nullptr;
    float* bary_ = nullptr;
    uint32_t* instance_ = nullptr;
    uint32_t* tests_ = nullptr;
};

}  // namespace raycast

HSR_EXPORT_PLUGIN(raycast::Raycast)
