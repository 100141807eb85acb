// SceneBuilder: objects from model files, planar polygons and triangle lists, merged into the
// world-space arrays of one SceneData. Corner normals are angle-weighted averages of the face
// normals around a vertex (Thürmer & Wüthrich, "Computing vertex normals from polygonal facets",
// JGT 1998), limited to faces within a crease angle of the corner's own face, so hard edges stay
// hard.
#include "hsr/error.hpp"
#include "hsr/instancing.hpp"
#include "hsr/limits.hpp"
#include "hsr/scene_builder.hpp"

#include "gltf_reader.hpp"
#include "model_reader.hpp"
#include "polygon_triangulation.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cfloat>
#include <cmath>
#include <limits>
#include <tuple>

namespace hsr {
namespace {

// A triangle by its corners' positions, turned to start at the smallest corner (so that a copy
// listed from another corner matches) but not reversed: a triangle and its back face stay two.
using TriangleKey = std::array<glm::vec3, 3>;

bool position_less(const glm::vec3& p, const glm::vec3& q) {
    return std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
}

TriangleKey triangle_key(const std::vector<glm::vec3>& positions, const uint32_t* corners) {
    TriangleKey key{positions[corners[0]], positions[corners[1]], positions[corners[2]]};
    const auto smallest = std::min_element(key.begin(), key.end(), position_less);
    std::rotate(key.begin(), smallest, key.end());
    return key;
}

uint64_t triangle_key_hash(const TriangleKey& key) {
    uint64_t hash = 0;
    for (const glm::vec3& p : key)
        for (int k = 0; k < 3; ++k) {
            const float value = p[k] == 0.0f ? 0.0f : p[k];  // -0 and +0 are equal: one hash
            hash = (hash ^ std::bit_cast<uint32_t>(value)) * 0x100000001b3ull;
        }
    return hash ^ (hash >> 29);
}

// The triangles of one object met so far, by key: open addressing with linear probing in a
// power-of-two table whose slots hold the upper half of a key's hash beside the triangle's number.
// Keys are not stored: when the hashes agree, the stored triangle's key is made again (key_of), which
// a table of 70,000 triangles does a handful of times, against 2.5 MB of keys kept.
class SeenTriangles {
public:
    explicit SeenTriangles(std::size_t triangles) : slots_(std::bit_ceil(2 * triangles + 2), empty) {}
    // Asks the processor to fetch the slot where a key with this hash starts probing: each insert
    // of a large object would otherwise wait for its slot to come from memory.
    void prefetch(uint64_t hash) const { __builtin_prefetch(&slots_[hash & (slots_.size() - 1)]); }
    // False if a triangle with an equal key (whose hash this is) was met before; otherwise remembers
    // this one.
    template <class KeyOf>
    bool insert(uint32_t triangle, uint64_t hash, const KeyOf& key_of) {
        const uint64_t tag = hash & 0xffffffff00000000ull;
        const std::size_t mask = slots_.size() - 1;
        for (std::size_t slot = hash & mask;; slot = (slot + 1) & mask) {
            const uint64_t stored = slots_[slot];
            if (stored == empty) {
                slots_[slot] = tag | triangle;
                return true;
            }
            if ((stored & 0xffffffff00000000ull) == tag && key_of(uint32_t(stored)) == key_of(triangle)) return false;
        }
    }

private:
    static constexpr uint64_t empty = ~0ull;  // no triangle has number 2^32 - 1 (at most 2^32 / 3 triangles)
    std::vector<uint64_t> slots_;
};

using Object = SceneBuilder::Object;

// work(begin, end) over [0, count) in pieces of at least `grain` items, on the threads oneTBB allows
// (the host bounds them with --threads). Each item's result depends on that item alone, so the scene
// is the same for any number of threads.
template <class Work>
void in_parallel(std::size_t count, std::size_t grain, Work&& work) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, grain),
                      [&](const tbb::blocked_range<std::size_t>& range) { work(range.begin(), range.end()); });
}

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

double corner_angle(const glm::dvec3& p, const glm::dvec3& next, const glm::dvec3& prev) {
    glm::dvec3 u = next - p, v = prev - p;
    return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}

void push3(std::vector<float>& out, glm::dvec3 v) {
    out.push_back(static_cast<float>(v.x));
    out.push_back(static_cast<float>(v.y));
    out.push_back(static_cast<float>(v.z));
}

// Room in the merged arrays for every triangle and vertex of the objects.
void reserve_for(const std::vector<Object>& objects, SceneData& scene, std::vector<glm::dvec3>& world,
                 std::vector<glm::dvec3>& normals) {
    std::size_t total_triangles = 0;
    for (const Object& object : objects) total_triangles += object.indices.size() / 3;
    scene.indices.reserve(3 * total_triangles);
    scene.edge_neighbors.reserve(3 * total_triangles);
    scene.face_normals.reserve(3 * total_triangles);
    scene.face_colors.reserve(3 * total_triangles);
    scene.face_object.reserve(total_triangles);
    std::size_t total_positions = 0;
    for (const Object& object : objects) total_positions += object.positions.size();
    world.reserve(total_positions);
    normals.reserve(total_triangles);
}

// An object's options: a finite transform, a crease angle in [0, 180] degrees, a colour in [0, 1].
void check_options(const MeshOptions& options, Language language) {
    const std::string& name = options.name;
    for (int c = 0; c < 4; ++c)
        if (!finite(glm::vec3(options.transform[c])) || !std::isfinite(options.transform[c][3]))
            throw Error(say(language, "{}: the transform has a value that is not a finite number",
                            "{}: в преобразовании есть значение, которое не является конечным числом", name));
    if (!(options.crease_angle_degrees >= 0.0f && options.crease_angle_degrees <= 180.0f))
        throw Error(say(language, "{}: crease angle {} is outside [0, 180] degrees", "{}: угол излома {} вне [0, 180] градусов", name,
                        options.crease_angle_degrees));
    for (int k = 0; k < 3; ++k)
        if (!(options.color[k] >= 0.0f && options.color[k] <= 1.0f))
            throw Error(say(language, "{}: colour channel {} is outside [0, 1]",
                            "{}: компонента цвета {} вне [0, 1]", name, options.color[k]));
}

// The object's vertices in world space, each within float range.
std::vector<glm::dvec3> to_world(const Object& object, const glm::dmat4& transform, Language language) {
    std::vector<glm::dvec3> local_world(object.positions.size());
    for (std::size_t v = 0; v < object.positions.size(); ++v) {
        glm::dvec4 p = transform * glm::dvec4(glm::dvec3(object.positions[v]), 1.0);
        local_world[v] = glm::dvec3(p) / p.w;
        if (!std::isfinite(local_world[v].x) || !std::isfinite(local_world[v].y) ||
            !std::isfinite(local_world[v].z) || std::fabs(local_world[v].x) > FLT_MAX ||
            std::fabs(local_world[v].y) > FLT_MAX || std::fabs(local_world[v].z) > FLT_MAX)
            throw Error(say(language, "{}: the transform moves vertex {} to a non-finite position",
                            "{}: преобразование уводит вершину {} в бесконечность", object.options.name, v));
    }
    return local_world;
}

// Which triangles of an object enter the scene, and how many were dropped for each reason.
struct KeptTriangles {
    std::vector<int32_t> new_triangle;  // per triangle of the object: its number in the scene, or -1
    uint32_t without_area = 0, repeated = 0;
};

// Keep triangles with a well-defined normal that no earlier triangle of the object repeats;
// number them in the merged scene from first_triangle, appending their unit normals. A repeated
// triangle adds nothing to a picture, but each copy has edges of its own (the loader gives
// non-manifold faces their own vertices), which make the hidden-line algorithms quadratic: 3,388
// copies of one face took Appel 10 s.
KeptTriangles keep_triangles(const Object& object, const std::vector<glm::dvec3>& local_world, bool mirrored,
                             uint32_t first_triangle, std::vector<glm::dvec3>& normals) {
    const std::size_t triangle_count = object.indices.size() / 3;
    KeptTriangles kept{std::vector<int32_t>(triangle_count, -1)};
    SeenTriangles seen(triangle_count);
    const auto key_of = [&](uint32_t t) { return triangle_key(object.positions, &object.indices[3 * std::size_t(t)]); };
    std::vector<uint64_t> hashes(triangle_count);
    in_parallel(triangle_count, 4096, [&](std::size_t begin, std::size_t end) {
        for (std::size_t t = begin; t < end; ++t) hashes[t] = triangle_key_hash(key_of(uint32_t(t)));
    });
    constexpr std::size_t prefetch_ahead = 16;
    uint32_t count = 0;
    for (std::size_t t = 0; t < triangle_count; ++t) {
        if (t + prefetch_ahead < triangle_count) seen.prefetch(hashes[t + prefetch_ahead]);
        const glm::dvec3& a = local_world[object.indices[3 * t]];
        const glm::dvec3& b = local_world[object.indices[3 * t + 1]];
        const glm::dvec3& c = local_world[object.indices[3 * t + 2]];
        glm::dvec3 n = glm::cross(b - a, c - a);
        if (mirrored) n = -n;
        double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
        double length = glm::length(n);
        if (!(length > 1e-12 * longest * longest) || !std::isfinite(length)) {
            ++kept.without_area;
            continue;
        }
        if (!seen.insert(uint32_t(t), hashes[t], key_of)) {
            ++kept.repeated;
            continue;
        }
        kept.new_triangle[t] = static_cast<int32_t>(first_triangle + count++);
        normals.push_back(n / length);
    }
    return kept;
}

// One line each for what the reader noticed, the triangles dropped and the faces the loader
// separated.
void warn_about(const Object& object, const KeptTriangles& kept, std::vector<std::string>& warnings) {
    warnings.insert(warnings.end(), object.warnings.begin(), object.warnings.end());
    if (kept.without_area > 0)
        warnings.push_back(fmt::format("{}: {} triangle{} without area dropped", object.source, kept.without_area,
                                       kept.without_area == 1 ? "" : "s"));
    if (kept.repeated > 0)
        warnings.push_back(fmt::format("{}: {} triangle{} repeating an earlier one dropped", object.source,
                                       kept.repeated, kept.repeated == 1 ? "" : "s"));
    if (object.separated_faces > 0)
        warnings.push_back(fmt::format("{}: {} non-manifold face{} given separate vertices", object.source,
                                       object.separated_faces, object.separated_faces == 1 ? "" : "s"));
}

// The kept triangles of object number o into the scene: their corners, neighbours across their
// edges, object and colour. Only vertices of kept triangles enter the scene (and world).
void add_kept_triangles(const Object& object, uint32_t o, const std::vector<glm::dvec3>& local_world,
                        const std::vector<int32_t>& new_triangle, bool mirrored, std::vector<glm::dvec3>& world,
                        SceneData& scene) {
    const MeshOptions& options = object.options;
    const std::size_t triangle_count = object.indices.size() / 3;
    std::vector<int64_t> new_vertex(object.positions.size(), -1);
    for (std::size_t t = 0; t < triangle_count; ++t) {
        if (new_triangle[t] < 0) continue;
        std::array<uint32_t, 3> corner;
        std::array<int32_t, 3> across;
        for (int k = 0; k < 3; ++k) {
            uint32_t v = object.indices[3 * t + k];
            if (new_vertex[v] < 0) {
                new_vertex[v] = static_cast<int64_t>(world.size());
                world.push_back(local_world[v]);
            }
            corner[k] = static_cast<uint32_t>(new_vertex[v]);
            int32_t neighbor = object.neighbors[3 * t + k];
            across[k] = neighbor < 0 ? HSR_NO_NEIGHBOR : new_triangle[static_cast<std::size_t>(neighbor)];
        }
        if (mirrored) {  // (a, b, c) -> (a, c, b): edges a-c, c-b, b-a were edges 2, 1, 0
            std::swap(corner[1], corner[2]);
            std::swap(across[0], across[2]);
        }
        scene.indices.insert(scene.indices.end(), corner.begin(), corner.end());
        scene.edge_neighbors.insert(scene.edge_neighbors.end(), across.begin(), across.end());
        scene.face_object.push_back(o);
        const glm::vec3 color =
            object.face_colors.empty() || options.color_given ? options.color : object.face_colors[t];
        scene.face_colors.insert(scene.face_colors.end(), {color.r, color.g, color.b});
    }
}

// Object number o added to the scene: its kept triangles, their vertices (into world) and unit
// normals (into normals, and as floats into the scene), its name and warnings.
void add_object(const Object& object, uint32_t o, SceneData& scene, std::vector<glm::dvec3>& world,
                std::vector<glm::dvec3>& normals, Language language) {
    const MeshOptions& options = object.options;
    const glm::dmat4 transform(options.transform);
    check_options(options, language);
    if (!object.face_colors.empty() && object.face_colors.size() != object.indices.size() / 3)
        throw Error("{}: {} face colours for {} triangles", options.name, object.face_colors.size(), object.indices.size() / 3);
    for (const glm::vec3& c : object.face_colors)
        if (!(c.r >= 0.0f && c.r <= 1.0f && c.g >= 0.0f && c.g <= 1.0f && c.b >= 0.0f && c.b <= 1.0f))
            throw Error("{}: a face colour is outside [0, 1]", options.name);
    const bool mirrored = glm::determinant(glm::dmat3(transform)) < 0.0;
    const std::vector<glm::dvec3> local_world = to_world(object, transform, language);
    const uint32_t first_triangle = static_cast<uint32_t>(scene.indices.size() / 3);
    const KeptTriangles kept = keep_triangles(object, local_world, mirrored, first_triangle, normals);
    warn_about(object, kept, scene.warnings);
    add_kept_triangles(object, o, local_world, kept.new_triangle, mirrored, world, scene);
    for (std::size_t t = first_triangle; t < normals.size(); ++t) push3(scene.face_normals, normals[t]);
    scene.object_names.push_back(options.name);
}

// The scene's float positions and bounds, from the kept vertices.
void set_positions(const std::vector<glm::dvec3>& world, SceneData& scene) {
    scene.positions.reserve(3 * world.size());
    for (const glm::dvec3& p : world) push3(scene.positions, p);
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const glm::dvec3& p : world) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    scene.bounds_min = glm::vec3(lo);
    scene.bounds_max = glm::vec3(hi);
}

// For each vertex v, the (triangle, corner) pairs around it: corner ids 3t+k in
// around[start[v] .. start[v + 1]), in the order of the scene's triangles.
struct VertexFans {
    std::vector<uint32_t> start;
    std::vector<uint32_t> around;
};

VertexFans vertex_fans(const std::vector<uint32_t>& indices, std::size_t vertex_count) {
    VertexFans fans{std::vector<uint32_t>(vertex_count + 1, 0), std::vector<uint32_t>(indices.size())};
    std::vector<uint32_t>& start = fans.start;
    for (uint32_t v : indices) ++start[v + 1];
    for (std::size_t v = 0; v < vertex_count; ++v) start[v + 1] += start[v];
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (uint32_t corner = 0; corner < indices.size(); ++corner) fans.around[fill[indices[corner]]++] = corner;
    return fans;
}

// What corner_normals_of_fan reads, and the scratch space it reuses from vertex to vertex.
struct FanInput {
    const std::vector<glm::dvec3>& world;
    const std::vector<uint32_t>& indices;
    const std::vector<glm::dvec3>& normals;  // per triangle
};
struct FanScratch {
    std::vector<glm::dvec3> normals;
    std::vector<double> angles;
    std::vector<uint64_t> beyond_crease;  // per corner of the fan: bit j for corner j (fans up to 64)
};

// The corner normals of the `count` corners around[0 .. count) of one vertex, into corner_normals
// (9 per triangle). The normals and angles of its corners side by side, which pairs of them are
// within the crease limit (each pair tested once, the test being symmetric), and the sum over all of
// them, which is each corner's sum unless some face is beyond its crease. Every sum adds its terms
// in the order of `around`.
void corner_normals_of_fan(const FanInput& in, const uint32_t* around, uint32_t count, double limit,
                           FanScratch& fan, std::vector<float>& corner_normals) {
    const auto angle_at = [&](uint32_t corner) {
        const std::size_t t = corner / 3, k = corner % 3;
        return corner_angle(in.world[in.indices[3 * t + k]], in.world[in.indices[3 * t + (k + 1) % 3]],
                            in.world[in.indices[3 * t + (k + 2) % 3]]);
    };
    if (fan.normals.size() < count) {
        fan.normals.resize(count);
        fan.angles.resize(count);
    }
    for (uint32_t i = 0; i < count; ++i) {
        fan.normals[i] = in.normals[around[i] / 3];
        fan.angles[i] = angle_at(around[i]);
    }
    auto store = [&](uint32_t corner, glm::dvec3 sum) {
        const double length = glm::length(sum);
        const glm::dvec3 n = length > 1e-12 ? sum / length : in.normals[corner / 3];
        for (int k = 0; k < 3; ++k) corner_normals[3 * std::size_t(corner) + k] = static_cast<float>(n[k]);
    };
    if (count > 64) {
        for (uint32_t i = 0; i < count; ++i) {
            glm::dvec3 sum(0.0);
            for (uint32_t j = 0; j < count; ++j)
                if (glm::dot(fan.normals[i], fan.normals[j]) >= limit) sum += fan.angles[j] * fan.normals[j];
            store(around[i], sum);
        }
        return;
    }
    fan.beyond_crease.assign(count, 0);
    for (uint32_t i = 0; i < count; ++i)
        for (uint32_t j = i; j < count; ++j)
            if (!(glm::dot(fan.normals[i], fan.normals[j]) >= limit)) {
                fan.beyond_crease[i] |= uint64_t(1) << j;
                fan.beyond_crease[j] |= uint64_t(1) << i;
            }
    glm::dvec3 all(0.0);
    for (uint32_t j = 0; j < count; ++j) all += fan.angles[j] * fan.normals[j];
    for (uint32_t i = 0; i < count; ++i) {
        glm::dvec3 sum = all;
        if (fan.beyond_crease[i] != 0) {
            sum = glm::dvec3(0.0);
            for (uint32_t j = 0; j < count; ++j)
                if (!(fan.beyond_crease[i] >> j & 1)) sum += fan.angles[j] * fan.normals[j];
        }
        store(around[i], sum);
    }
}

// Corner normals, vertex by vertex (its corners all belong to one object, so share one crease
// limit): the crease_cosines are per object.
void set_corner_normals(const std::vector<glm::dvec3>& world, const std::vector<glm::dvec3>& normals,
                        const std::vector<float>& crease_cosines, SceneData& scene) {
    const VertexFans fans = vertex_fans(scene.indices, world.size());
    const FanInput in{world, scene.indices, normals};
    scene.corner_normals.resize(9 * std::size_t(scene.triangle_count()));
    in_parallel(world.size(), 2048, [&](std::size_t begin, std::size_t end) {
        FanScratch fan;
        for (std::size_t v = begin; v < end; ++v) {
            const uint32_t first = fans.start[v], count = fans.start[v + 1] - fans.start[v];
            if (count == 0) continue;
            const uint32_t* around = &fans.around[first];
            const double limit = static_cast<double>(crease_cosines[scene.face_object[around[0] / 3]]) - 1e-6;
            corner_normals_of_fan(in, around, count, limit, fan, scene.corner_normals);
        }
    });
}

// ---------------------------------------------------------------------------------------------
// glTF models (gltf_reader.hpp): their meshes placed by their nodes.

// A placement's transform as an instance's similarity: rotation times a positive uniform scale.
std::optional<std::pair<glm::mat3, float>> similarity(const glm::dmat4& transform) {
    const glm::dmat3 a(transform);
    const double det = glm::determinant(a);
    if (!(det > 0) || !std::isfinite(det)) return std::nullopt;
    const double scale = std::cbrt(det);
    const glm::dmat3 rotation = a / scale;
    const glm::dmat3 should_be_identity = glm::transpose(rotation) * rotation;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (std::fabs(should_be_identity[c][r] - (c == r ? 1.0 : 0.0)) > 1e-5) return std::nullopt;
    return std::pair{glm::mat3(rotation), float(scale)};
}

// Each stored mesh once, in its own coordinates, and one instance per placement.
SceneData instanced_scene(const PlacedMeshes& model) {
    SceneBuilder builder;
    for (const MeshObject& mesh : model.meshes) {
        MeshObject copy = mesh;
        copy.options.transform = glm::mat4(1.0f);
        builder.add_read_object(std::move(copy));
    }
    SceneData scene = builder.build();
    struct Range {
        uint32_t first_triangle = UINT32_MAX, triangles = 0, first_vertex = UINT32_MAX, last_vertex = 0;
        glm::vec3 lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
    };
    std::vector<Range> ranges(model.meshes.size());
    for (uint32_t t = 0; t < scene.triangle_count(); ++t) {
        Range& range = ranges[scene.face_object[t]];
        range.first_triangle = std::min(range.first_triangle, t);
        ++range.triangles;
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = scene.indices[3 * t + k];
            range.first_vertex = std::min(range.first_vertex, v);
            range.last_vertex = std::max(range.last_vertex, v);
            const glm::vec3 p(scene.positions[3 * v], scene.positions[3 * v + 1], scene.positions[3 * v + 2]);
            range.lo = glm::min(range.lo, p);
            range.hi = glm::max(range.hi, p);
        }
    }
    glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
    for (const PlacedMeshes::Placement& placement : model.placements) {
        const Range& range = ranges[placement.mesh];
        if (range.triangles == 0) continue;  // every triangle dropped as without area
        const auto [rotation, scale] = *similarity(placement.transform);
        const hsr_instance instance =
            make_instance(range.first_triangle, range.triangles, range.first_vertex,
                          range.last_vertex - range.first_vertex + 1, rotation, scale,
                          glm::vec3(placement.transform[3]), range.lo, range.hi);
        for (int i = 0; i < 3; ++i) {
            lo[i] = std::min(lo[i], instance.bounds_min[i]);
            hi[i] = std::max(hi[i], instance.bounds_max[i]);
        }
        scene.instances.push_back(instance);
    }
    scene.bounds_min = lo;
    scene.bounds_max = hi;
    return scene;
}

}  // namespace

SceneData placed_meshes_scene(PlacedMeshes model, const MeshOptions& options) {
    std::vector<std::size_t> uses(model.meshes.size(), 0);
    for (const PlacedMeshes::Placement& placement : model.placements) ++uses[placement.mesh];
    const bool reused = std::any_of(uses.begin(), uses.end(), [](std::size_t n) { return n > 1; });
    const bool similar = std::all_of(model.placements.begin(), model.placements.end(),
                                     [](const PlacedMeshes::Placement& p) { return similarity(p.transform).has_value(); });
    SceneData scene;
    if (reused && similar) {
        scene = instanced_scene(model);
    } else {
        // Each placement its own transformed copy.
        uint64_t stored = 0;
        for (const PlacedMeshes::Placement& placement : model.placements)
            stored += model.meshes[placement.mesh].indices.size() / 3;
        check_limit(&Limits::stored_triangles, stored, model.meshes.front().source + ": the placed meshes");
        SceneBuilder builder;
        for (std::size_t p = 0; p < model.placements.size(); ++p) {
            const PlacedMeshes::Placement& placement = model.placements[p];
            MeshObject copy = uses[placement.mesh] > 1 || p + 1 < model.placements.size() ? model.meshes[placement.mesh]
                                                                                          : std::move(model.meshes[placement.mesh]);
            copy.options.transform = options.transform * glm::mat4(placement.transform);
            builder.add_read_object(std::move(copy));
        }
        scene = builder.build();
    }
    scene.warnings.insert(scene.warnings.begin(), model.notes.begin(), model.notes.end());
    return scene;
}

void SceneBuilder::add_model_file(const std::filesystem::path& file, const MeshOptions& options) {
    if (is_gltf_file(file)) {
        Object object = read_gltf_object(file);
        object.options = options;
        if (object.options.name.empty()) object.options.name = file.stem().string();
        objects_.push_back(std::move(object));
        return;
    }
    std::vector<Object> parts = read_model_objects(file);
    const bool split = parts.size() > 1;
    for (Object& part : parts) {
        const std::string group = part.options.name;
        part.options = options;
        if (part.options.name.empty()) part.options.name = file.stem().string();
        if (split) part.options.name += "/" + group;
        objects_.push_back(std::move(part));
    }
}

void SceneBuilder::add_triangles(std::span<const glm::vec3> positions, std::span<const uint32_t> indices,
                                 const MeshOptions& options) {
    std::string name = options.name.empty() ? fmt::format("object {}", objects_.size() + 1) : options.name;
    Object object = object_from_triangles(positions, indices, name);
    object.options = options;
    object.options.name = name;
    objects_.push_back(std::move(object));
}

void SceneBuilder::add_polygon(std::span<const glm::vec3> vertices, glm::vec3 color, const std::string& name) {
    std::string what = name.empty() ? fmt::format("polygon {}", objects_.size() + 1) : "polygon '" + name + "'";
    const std::string said = name.empty() ? say(language_, "polygon {}", "многоугольник {}", objects_.size() + 1)
                                          : say(language_, "polygon '{}'", "многоугольник «{}»", name);
    PolygonTriangles polygon = triangulate_polygon(vertices, said, language_);

    MeshOptions options;
    options.color = color;
    options.name = name.empty() ? fmt::format("polygon {}", objects_.size() + 1) : name;
    Object object = object_from_triangles(polygon.positions, polygon.indices, what);
    object.options = options;
    objects_.push_back(std::move(object));
}

SceneData SceneBuilder::build() const {
    SceneData scene;
    std::vector<glm::dvec3> world;      // all kept vertices, double precision for normals
    std::vector<glm::dvec3> normals;    // per kept triangle
    std::vector<float> crease_cosines;  // per object
    reserve_for(objects_, scene, world, normals);
    for (std::size_t o = 0; o < objects_.size(); ++o) {
        add_object(objects_[o], static_cast<uint32_t>(o), scene, world, normals, language_);
        const double crease_angle = double(objects_[o].options.crease_angle_degrees);
        crease_cosines.push_back(static_cast<float>(std::cos(glm::radians(crease_angle))));
    }
    if (scene.indices.empty()) throw Error(say(language_, "the scene has no triangles", "в сцене нет ни одного треугольника"));
    set_positions(world, scene);
    set_corner_normals(world, normals, crease_cosines, scene);
    return scene;
}

SceneData load_model(const std::filesystem::path& file, const MeshOptions& options, std::vector<ModelCamera>* cameras) {
    if (is_gltf_file(file)) {
        GltfModel model = read_gltf(file, options);
        if (cameras) *cameras = model.cameras;
        return placed_meshes_scene(std::move(model), options);
    }
    SceneBuilder builder;
    builder.add_model_file(file, options);
    return builder.build();
}

}  // namespace hsr
