// embree: the ray caster of raycast.cpp (Appel 1968: one ray per pixel centre, nearest hit) with
// Intel's Embree 3 as its ray-tracing kernel (Wald, Woop, Benthin, Johnson & Ernst, "Embree: A
// Kernel Framework for Efficient CPU Ray Tracing", ACM TOG 33(4), SIGGRAPH 2014): a third-party
// library as a hidden-surface plugin.
//
// Each distinct triangle range of the scene becomes an Embree scene of one triangle geometry (object
// space, built once per scene, robust mode: edges are not crossed by rays slipping between
// triangles), and each placement an instance of it in a top-level scene, rebuilt when only the
// instances change. Rays are made as raycast makes them (pixel centre, near to far plane, the
// inverse of view_projection in double), cast in float by rtcIntersect1 over tiles on `threads`
// threads. An intersection filter passes over hits outside the view volume (window depth, from
// view_projection in double, outside [0, 1]), cut away by a camera clip plane, or, with
// cull-backfaces, facing away, so Embree goes on to farther ones. Depth is computed in double from
// the hit's barycentrics. The filter also keeps the rules every plugin shares
// (hsr/visibility_rules.hpp): of hits at the same float depth the lower instance, then the lower
// face (after each hit it lets Embree look on to where the depth passes the next float), and a hit
// only where the rasterizers' fill rule gives its triangle the pixel centre. docs/algorithms/embree.md.
#include "hsr/scene_key.hpp"

#include "hsr/raster.hpp"
#include "hsr/sdk.hpp"
#include "hsr/tiles.hpp"

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

using hsr::sdk::russian_plural;

namespace embree_plugin {

using hsr::sdk::ParamSpec;
using hsr::sdk::InstanceKey;
using hsr::sdk::SceneKey;

class Embree;

// What the intersection filter of one object's geometry needs.
struct ObjectFilter {
    const Embree* plugin = nullptr;
    uint32_t first_triangle = 0;
};

struct TileStats {
    uint64_t rays = 0, hits = 0;
};

// One ray's query: Embree hands the filter the context, and the rest rides behind it. The filter
// keeps the nearest hit by the tie rule here, whatever order Embree reports hits in.
struct RayQuery {
    RTCIntersectContext context;
    glm::dvec4 clip_origin{0.0}, clip_step{0.0};  // the ray in clip space: clip_origin + t * clip_step
    int64_t sample_x = 0, sample_y = 0;           // the pixel centre on the rasterizers' grid
    float t_limit = 0.0f;                         // no hit beyond this can replace the one kept
    float depth = 0.0f, u = 0.0f, v = 0.0f;
    uint32_t face = HSR_NO_FACE, instance = 0;
    hsr::raster::SnappedCornerCache snapped;  // kept over the rays of a tile
};

// Hits a little beyond the depth of the one kept are still reported (Embree's t is float).
constexpr double kTSlack = 1e-6;

class Embree final : public hsr::sdk::StepwiseRemover<Embree> {
public:
    static constexpr hsr::sdk::PluginInfo info{
        "embree", "1.0.0", "ray casting with Intel Embree 3 (Wald et al. 2014) as the ray-tracing kernel"};
    static inline const ParamSpec params[] = {
        ParamSpec::integer("threads", "0", 0, 1024, "threads casting rays (0 = one per core)"),
        ParamSpec::integer("tile-size", "16", 1, 4096, "side in pixels of the square tiles the threads take"),
        ParamSpec::boolean("cull-backfaces", false, "skip triangles whose back faces the camera"),
    };
    // ABI 1.5: the phases of ray casting through Embree's hierarchy.
    static inline const hsr::sdk::PhaseSpec phases[] = {
        {"build", "let Embree build its bounding volume hierarchy"},
        {"cast", "cast a ray through each pixel centre and keep its nearest hit"},
    };

    static constexpr hsr::sdk::TranslationSpec own_translations[] = {
        {"ru", "description", "метод бросания лучей с библиотекой Intel Embree 3 (Вальд и др., 2014) в роли ядра трассировки"},
        {"ru", "param:threads", "число потоков"},
        {"ru", "help:threads", "сколько потоков бросают лучи (0 — по одному на ядро)"},
        {"ru", "param:tile-size", "размер тайла"},
        {"ru", "help:tile-size", "сторона в пикселях квадратных тайлов, которые разбирают потоки"},
        {"ru", "param:cull-backfaces", "отбрасывать нелицевые грани"},
        {"ru", "help:cull-backfaces", "не рисовать треугольники, повёрнутые к камере нелицевой стороной"},
        {"ru", "phase:build", "поручить Embree построить свою иерархию ограничивающих объёмов"},
        {"ru", "phase:cast", "бросить луч через центр каждого пикселя и оставить ближайшее пересечение"},
        {"ru", "counter:rays", "лучей брошено"},
        {"ru", "counter:hits", "попаданий лучей"},
        {"ru", "step:build", "построение иерархии Embree"},
        {"ru", "step:tile", "тайл"},
    };
    static constexpr auto translations = hsr::sdk::join_translations(
        own_translations, hsr::sdk::build_time_counter_translations);

    explicit Embree(const hsr::sdk::Params& p)
        : threads_(uint32_t(p.integer("threads"))),
          tile_size_(uint32_t(p.integer("tile-size"))),
          cull_backfaces_(p.boolean("cull-backfaces")) {
        device_ = rtcNewDevice("threads=1");
        if (device_ == nullptr) throw hsr::sdk::Unsupported("embree: rtcNewDevice failed");
    }
    ~Embree() override {
        release_scenes();
        rtcReleaseDevice(device_);
    }
    Embree(const Embree&) = delete;
    Embree& operator=(const Embree&) = delete;

    // render_steps (from StepwiseRemover) takes a step for the hierarchy (phase "build"), then one step
    // per tile (phase "cast"), tiles in rows from the top left, all cast on the calling thread.

    // The intersection filter: passes over hits outside the view volume, cut away, facing away,
    // not nearer than the hit kept by the tie rule, or not the triangle's by the fill rule; a hit it
    // keeps becomes the query's, and Embree looks on to where the depth passes the next float.
    // (rtcIntersect1 asks about one ray, so N is 1.)
    static void filter(const RTCFilterFunctionNArguments* args) {
        const auto* object = static_cast<const ObjectFilter*>(args->geometryUserPtr);
        auto* query = reinterpret_cast<RayQuery*>(args->context);
        for (unsigned i = 0; i < args->N; ++i) {
            if (args->valid[i] == 0) continue;
            args->valid[i] = 0;
            const uint32_t face = object->first_triangle + RTCHitN_primID(args->hit, args->N, i);
            const uint32_t placement = RTCHitN_instID(args->hit, args->N, i, 0);
            const glm::dvec3 direction(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                                       RTCRayN_dir_z(args->ray, args->N, i));
            const float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
            float depth;
            const Embree& plugin = *object->plugin;
            if (!plugin.keeps(face, placement, u, v, direction, depth)) continue;
            const uint32_t instance = plugin.placed_[placement].instance;
            if (!hsr::raster::replaces(depth, instance, face, query->depth, query->instance, query->face)) continue;
            if (!plugin.covers_pixel_centre(face, placement, *query)) continue;
            args->valid[i] = -1;
            query->depth = depth;
            query->face = face;
            query->instance = instance;
            query->u = u;
            query->v = v;
            // Embree set tfar to this hit's t; a farther hit at the same float depth may still win.
            float& tfar = RTCRayN_tfar(args->ray, args->N, i);
            double limit = std::max(double(tfar), ray_parameter_at(*query, std::nextafter(depth, 2.0f)));
            limit += kTSlack * std::abs(limit);
            query->t_limit = tfar = std::min(query->t_limit, float(limit));
        }
    }

private:
    struct Placed {
        uint32_t instance = 0;
        uint32_t first_triangle = 0;
        bool identity = true;
        bool mirrored = false;
        glm::dmat4 world_from_object{1.0};
        glm::dmat4 clip_from_object{1.0};  // per frame
    };

    friend class hsr::sdk::StepwiseRemover<Embree>;

    template <class Steps>
    void render_with(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target,
                     hsr::sdk::Counters& counters, Steps& steps) {
        hsr::raster::validate_frame(info.name, scene.raw(), camera, target.raw());
        bool built = false;
        hsr::sdk::timed_build(counters, [&] { return built = prepare(scene); });

        begin_frame(scene, camera, target);
        TileStats total;
        auto report = [&] {
            counters.set("rays", total.rays);
            counters.set("hits", total.hits);
        };
        if constexpr (Steps::enabled) {
            try {
                build_step(steps, built);
                for (uint32_t k = 0; k < tiles().count(); ++k) {
                    TileStats tile;
                    cast_tile(k, tile);
                    total.rays += tile.rays;
                    total.hits += tile.hits;
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
    // Steps (ABI 1.3; phases and languages, ABI 1.5)

    // The hierarchy Embree built (or kept from the last frame of the same scene), drawn as the screen
    // rectangle of the scene's bounds.
    template <class Steps>
    void build_step(Steps& steps, bool built) const {
        if (top_ != nullptr) {
            RTCBounds b;
            rtcGetSceneBounds(top_, &b);
            float x0 = std::numeric_limits<float>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
            bool in_front = true;
            for (int c = 0; c < 8 && in_front; ++c) {
                const glm::dvec4 clip = view_projection_ * glm::dvec4((c & 1) ? b.upper_x : b.lower_x,
                                                                      (c & 2) ? b.upper_y : b.lower_y,
                                                                      (c & 4) ? b.upper_z : b.lower_z, 1.0);
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
        unsigned long long triangles = 0;
        for (const auto& entry : object_of_range_) triangles += entry.first[1];
        const unsigned long long objects = objects_.size(), instances = placed_.size();
        const hsr::sdk::Steps::Event event{"build", HSR_NO_FACE, 0, HSR_NO_LEVEL, 0, 0, "build"};
        if (steps.russian())
            steps.step(event, "иерархия Embree %s: %llu %s в %llu %s, %llu %s на сцене",
                       built ? "построена" : "взята с прошлого кадра", triangles,
                       russian_plural(triangles, "треугольник", "треугольника", "треугольников"), objects,
                       russian_plural(objects, "иерархии объекта", "иерархиях объектов", "иерархиях объектов"),
                       instances, russian_plural(instances, "экземпляр", "экземпляра", "экземпляров"));
        else
            steps.step(event, "Embree's hierarchy %s: %llu triangle%s in %llu object hierarch%s, %llu instance%s placed",
                       built ? "built" : "kept from the last frame", triangles, triangles == 1 ? "" : "s", objects,
                       objects == 1 ? "y" : "ies", instances, instances == 1 ? "" : "s");
    }

    template <class Steps>
    void tile_step(Steps& steps, uint32_t k, const TileStats& tile) const {
        uint32_t x0, y0, x1, y1;
        tiles().rect(k, x0, y0, x1, y1);
        steps.box(float(x0), float(y0), float(x1), float(y1), HSR_STEP_SUBJECT);
        const hsr::sdk::Steps::Event event{"tile", HSR_NO_FACE, 0, HSR_NO_LEVEL, tile.hits, 0, "cast"};
        const unsigned long long rays = tile.rays, hits = tile.hits;
        if (steps.russian())
            steps.step(event, "тайл %u (%u,%u)–(%u,%u): %llu %s, %llu %s", k, x0, y0, x1 - 1, y1 - 1, rays,
                       russian_plural(rays, "луч", "луча", "лучей"), hits,
                       russian_plural(hits, "попадание", "попадания", "попаданий"));
        else
            steps.step(event, "tile %u (%u,%u)-(%u,%u): %llu rays, %llu hits", k, x0, y0, x1 - 1, y1 - 1, rays, hits);
    }

    // ------------------------------------------------------------------------------------------ //
    // Build (once per scene; only the top level again when only the placements changed)

    void release_scenes() {
        if (top_ != nullptr) rtcReleaseScene(top_);
        top_ = nullptr;
        for (RTCScene s : objects_) rtcReleaseScene(s);
        objects_.clear();
        object_filters_.clear();
        object_of_range_.clear();
    }

    void check_device(const char* what) const {
        const RTCError error = rtcGetDeviceError(device_);
        if (error != RTC_ERROR_NONE)
            throw hsr::sdk::Unsupported(std::string("embree: ") + what + " failed (Embree error " +
                                        std::to_string(int(error)) + ")");
    }

    bool prepare(const hsr::sdk::Scene& scene) {
        const SceneKey skey = hsr::sdk::scene_key(scene);
        const InstanceKey ikey = hsr::sdk::instance_key(scene);
        if (has_built_ && skey == scene_key_ && ikey == instance_key_) return false;
        const bool same_geometry = has_built_ && skey == scene_key_;
        has_built_ = false;
        if (!same_geometry) {
            release_scenes();
        } else if (top_ != nullptr) {
            rtcReleaseScene(top_);
            top_ = nullptr;
        }
        top_ = rtcNewScene(device_);
        rtcSetSceneFlags(top_, RTC_SCENE_FLAG_ROBUST);
        placed_.assign(scene.placement_count(), Placed{});
        for (uint32_t k = 0; k < scene.placement_count(); ++k) {
            const hsr::sdk::Placement p = scene.placement(k);
            const std::array<uint32_t, 4> range{p.first_triangle, p.triangle_count, p.first_vertex, p.vertex_count};
            auto found = object_of_range_.find(range);
            if (found == object_of_range_.end()) found = object_of_range_.emplace(range, build_object(scene, p)).first;
            Placed& placed = placed_[k];
            placed.instance = p.instance;
            placed.first_triangle = p.first_triangle;
            placed.identity = p.identity;
            placed.world_from_object = p.identity ? glm::dmat4(1.0) : glm::dmat4(p.transform);
            placed.mirrored = glm::determinant(placed.world_from_object) < 0.0;
            RTCGeometry instance = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
            rtcSetGeometryInstancedScene(instance, objects_[found->second]);
            const glm::mat4 m = p.identity ? glm::mat4(1.0f) : p.transform;
            rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &m[0][0]);
            rtcCommitGeometry(instance);
            rtcAttachGeometryByID(top_, instance, k);
            rtcReleaseGeometry(instance);
        }
        rtcCommitScene(top_);
        check_device("building the scene");
        scene_key_ = skey;
        instance_key_ = ikey;
        has_built_ = true;
        return true;
    }

    // One object's triangles as an Embree scene of one geometry, in object space.
    uint32_t build_object(const hsr::sdk::Scene& scene, const hsr::sdk::Placement& p) {
        RTCScene object = rtcNewScene(device_);
        rtcSetSceneFlags(object, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(object, RTC_BUILD_QUALITY_HIGH);
        objects_.push_back(object);
        if (p.triangle_count > 0) add_geometry(scene, p, object);
        rtcCommitScene(object);
        return uint32_t(objects_.size() - 1);
    }

    void add_geometry(const hsr::sdk::Scene& scene, const hsr::sdk::Placement& p, RTCScene object) {
        RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), p.vertex_count));
        auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), p.triangle_count));
        if (vertices == nullptr || indices == nullptr) {
            rtcReleaseGeometry(geometry);
            check_device("allocating geometry");
            throw hsr::sdk::Unsupported("embree: could not allocate the geometry");
        }
        const float* positions = scene.raw().positions;
        std::copy(positions + 3 * size_t(p.first_vertex), positions + 3 * (size_t(p.first_vertex) + p.vertex_count),
                  vertices);
        for (uint32_t t = 0; t < p.triangle_count; ++t)
            for (int c = 0; c < 3; ++c) indices[3 * t + c] = scene.index(p.first_triangle + t, c) - p.first_vertex;
        object_filters_.push_back(std::make_unique<ObjectFilter>(ObjectFilter{this, p.first_triangle}));
        rtcSetGeometryUserData(geometry, object_filters_.back().get());
        rtcSetGeometryIntersectFilterFunction(geometry, &Embree::filter);
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(object, geometry);
        rtcReleaseGeometry(geometry);
    }

    // ------------------------------------------------------------------------------------------ //
    // Per frame

    void begin_frame(const hsr::sdk::Scene& scene, const hsr_camera& camera, hsr::sdk::VisibilityBuffer& target) {
        scene_ = &scene;
        width_ = camera.width;
        height_ = camera.height;
        view_projection_ = glm::dmat4(hsr::sdk::load_matrix(camera.view_projection));
        window_to_world_ = glm::inverse(view_projection_);
        planes_ = hsr::sdk::ClipPlanes(camera);
        viewport_ = hsr::raster::Viewport(width_, height_);
        guard_ = hsr::raster::GuardBand(width_, height_);
        for (Placed& p : placed_) p.clip_from_object = view_projection_ * p.world_from_object;
        depth_ = target.depth();
        face_ = target.face();
        bary_ = target.bary();
        instance_ = target.instance();
        tests_ = target.depth_tests();
    }

    // The filter's test of a hit: in the view volume, kept by every clip plane, and (with
    // cull-backfaces) facing the ray, whose direction here is in object space; `depth_out` gets its
    // window depth as the buffer stores it.
    bool keeps(uint32_t face, uint32_t placement, float u, float v, const glm::dvec3& direction,
               float& depth_out) const {
        const Placed& p = placed_[placement];
        glm::dvec3 corner[3];
        for (int c = 0; c < 3; ++c) corner[c] = glm::dvec3(scene_->corner_position(face, c));
        if (cull_backfaces_) {
            const bool front = glm::dot(glm::cross(corner[1] - corner[0], corner[2] - corner[0]), direction) < 0.0;
            if (front == p.mirrored) return false;
        }
        const glm::dvec3 point = corner[0] + double(u) * (corner[1] - corner[0]) + double(v) * (corner[2] - corner[0]);
        const glm::dvec4 clip = p.clip_from_object * glm::dvec4(point, 1.0);
        const double depth = (clip.z / clip.w + 1.0) * 0.5;
        if (!(depth >= 0.0 && depth <= 1.0)) return false;
        if (planes_.count > 0) {
            const glm::dvec3 world = p.identity ? point : glm::dvec3(p.world_from_object * glm::dvec4(point, 1.0));
            if (!planes_.keeps(world)) return false;
        }
        depth_out = float(depth);
        return true;
    }

    // The fill rule (hsr/visibility_rules.hpp) at the query's pixel centre: the triangle's corners
    // taken to the window and snapped to the 1/256-pixel grid exactly as the z-buffer snaps them. A
    // triangle the rasterizers clip first (a corner beyond the near or far plane or the guard band)
    // keeps Embree's answer.
    bool covers_pixel_centre(uint32_t face, uint32_t placement, RayQuery& query) const {
        // Neighbouring pixels mostly meet the same few triangles: their snapped corners are kept.
        const auto& snapped = query.snapped.find(placement, face, [&](int64_t(&x)[3], int64_t(&y)[3]) {
            const Placed& p = placed_[placement];
            glm::dvec4 clip[3];
            for (int c = 0; c < 3; ++c)
                clip[c] = p.clip_from_object * glm::dvec4(glm::dvec3(scene_->corner_position(face, c)), 1.0);
            hsr::raster::WindowVertex w[3];
            if (!hsr::raster::unclipped_window_corners(clip, viewport_, guard_, w)) return false;
            for (int c = 0; c < 3; ++c) {
                x[c] = w[c].x;
                y[c] = w[c].y;
            }
            return true;
        });
        return !snapped.known || hsr::raster::covers_sample(snapped.x, snapped.y, query.sample_x, query.sample_y);
    }

    // Where the ray reaches window depth `depth` (+infinity when it never does): depth is
    // (z / w + 1) / 2 of the clip-space ray, solved for t.
    static double ray_parameter_at(const RayQuery& ray, double depth) {
        const double k = 2.0 * depth - 1.0;
        const double t = (k * ray.clip_origin.w - ray.clip_origin.z) / (ray.clip_step.z - k * ray.clip_step.w);
        return t >= 0.0 ? t : std::numeric_limits<double>::infinity();
    }

    hsr::sdk::TileGrid tiles() const { return {width_, height_, tile_size_}; }

    void cast_all(TileStats& total) {
        const std::vector<TileStats> stats = hsr::sdk::share_tiles<TileStats>(
            tiles().count(), threads_, [this](uint32_t k, TileStats& s) { cast_tile(k, s); });
        for (const TileStats& s : stats) {
            total.rays += s.rays;
            total.hits += s.hits;
        }
    }

    void cast_tile(uint32_t k, TileStats& stats) const {
        uint32_t x0, y0, x1, y1;
        tiles().rect(k, x0, y0, x1, y1);
        RayQuery query;
        for (uint32_t y = y0; y < y1; ++y)
            for (uint32_t x = x0; x < x1; ++x) {
                ++stats.rays;
                const size_t p = size_t(y) * width_ + x;
                if (tests_ != nullptr) tests_[p] = 0;
                const double ndc_x = 2.0 * (x + 0.5) / width_ - 1.0;
                const double ndc_y = 1.0 - 2.0 * (y + 0.5) / height_;
                const glm::dvec4 near_h = window_to_world_ * glm::dvec4(ndc_x, ndc_y, -1.0, 1.0);
                const glm::dvec4 far_h = window_to_world_ * glm::dvec4(ndc_x, ndc_y, 1.0, 1.0);
                const glm::dvec3 origin = glm::dvec3(near_h) / near_h.w;
                const glm::dvec3 direction = glm::dvec3(far_h) / far_h.w - origin;
                if (!std::isfinite(origin.x + origin.y + origin.z + direction.x + direction.y + direction.z)) continue;
                RTCRayHit rh{};
                rh.ray.org_x = float(origin.x);
                rh.ray.org_y = float(origin.y);
                rh.ray.org_z = float(origin.z);
                rh.ray.dir_x = float(direction.x);
                rh.ray.dir_y = float(direction.y);
                rh.ray.dir_z = float(direction.z);
                rh.ray.tnear = 0.0f;
                rh.ray.tfar = 1.0f + float(kTSlack);
                rh.ray.mask = 0xFFFFFFFFu;
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                rtcInitIntersectContext(&query.context);
                query.clip_origin = view_projection_ * glm::dvec4(origin, 1.0);
                query.clip_step = view_projection_ * glm::dvec4(direction, 0.0);
                query.sample_x = int64_t(x) * hsr::raster::kSubpixelScale + hsr::raster::kHalfPixel;
                query.sample_y = int64_t(y) * hsr::raster::kSubpixelScale + hsr::raster::kHalfPixel;
                query.t_limit = rh.ray.tfar;
                query.face = HSR_NO_FACE;
                rtcIntersect1(top_, &query.context, &rh);
                if (query.face == HSR_NO_FACE) continue;
                ++stats.hits;
                depth_[p] = query.depth;
                face_[p] = query.face;
                bary_[2 * p] = query.u;
                bary_[2 * p + 1] = query.v;
                if (instance_ != nullptr) instance_[p] = query.instance;
            }
    }

    // Parameters
    uint32_t threads_;
    uint32_t tile_size_;
    bool cull_backfaces_;

    RTCDevice device_ = nullptr;

    // Built once per scene
    bool has_built_ = false;
    SceneKey scene_key_;
    InstanceKey instance_key_;
    std::vector<RTCScene> objects_;
    std::vector<std::unique_ptr<ObjectFilter>> object_filters_;
    std::map<std::array<uint32_t, 4>, uint32_t> object_of_range_;
    RTCScene top_ = nullptr;
    std::vector<Placed> placed_;

    // Per frame
    const hsr::sdk::Scene* scene_ = nullptr;
    uint32_t width_ = 0, height_ = 0;
    glm::dmat4 view_projection_{1.0}, window_to_world_{1.0};
    hsr::sdk::ClipPlanes planes_{hsr_camera{}};
    hsr::raster::Viewport viewport_;
    hsr::raster::GuardBand guard_;
    float* depth_ = nullptr;
    uint32_t* face_ = nullptr;
    float* bary_ = nullptr;
    uint32_t* instance_ = nullptr;
    uint32_t* tests_ = nullptr;
};

}  // namespace embree_plugin

HSR_EXPORT_PLUGIN(embree_plugin::Embree)
