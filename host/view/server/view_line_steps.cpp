// The figure of a hidden-line step (view_line_steps.hpp): flat faces found by a flood fill over
// coplanar neighbours, their outlines chained from the sides no other triangle of the face shares,
// and everything projected with the camera and cut at the near plane (w > 0).
#include "view/server/view_line_steps.hpp"

#include "hsr/edges.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>

namespace {

constexpr float kMinW = 1e-5f;
constexpr std::size_t kMostLabels = 300;  // of each kind; more is no longer readable

glm::dvec3 corner(const hsr_scene& s, uint32_t t, int k) {
    const float* p = s.positions + 3 * std::size_t(s.indices[3 * std::size_t(t) + k]);
    return {p[0], p[1], p[2]};
}

glm::dvec3 unit_normal(const hsr_scene& s, uint32_t t) {
    const glm::dvec3 n = glm::cross(corner(s, t, 1) - corner(s, t, 0), corner(s, t, 2) - corner(s, t, 0));
    const double length = glm::length(n);
    return length > 0.0 ? n / length : n;
}

glm::mat4 matrix(const float* m) {
    glm::mat4 out;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) out[c][r] = m[4 * c + r];
    return out;
}

glm::vec2 to_window(const glm::vec4& clip, const hsr_camera& camera) {
    return {(clip.x / clip.w + 1.0f) * 0.5f * float(camera.width), (1.0f - clip.y / clip.w) * 0.5f * float(camera.height)};
}

// The ring of world points projected and cut to w >= kMinW (Sutherland and Hodgman against one
// plane); empty when nothing is in front.
std::vector<glm::vec2> project_ring(const std::vector<glm::vec3>& ring, const hsr_camera& camera) {
    const glm::mat4 vp = matrix(camera.view_projection);
    std::vector<glm::vec4> clip;
    for (const glm::vec3& p : ring) clip.push_back(vp * glm::vec4(p, 1.0f));
    std::vector<glm::vec2> out;
    for (std::size_t i = 0; i < clip.size(); ++i) {
        const glm::vec4& p = clip[i];
        const glm::vec4& q = clip[(i + 1) % clip.size()];
        const bool p_in = p.w >= kMinW, q_in = q.w >= kMinW;
        if (p_in) out.push_back(to_window(p, camera));
        if (p_in != q_in) out.push_back(to_window(p + (q - p) * ((kMinW - p.w) / (q.w - p.w)), camera));
    }
    std::erase_if(out, [](glm::vec2 v) { return !std::isfinite(v.x + v.y); });
    return out;
}

nlohmann::json point_json(glm::vec2 p) { return nlohmann::json::array({p.x, p.y}); }

// The mean of a polygon's projected corners: where its number goes.
std::optional<glm::vec2> centre(const std::vector<std::vector<glm::vec2>>& loops) {
    glm::vec2 sum(0.0f);
    std::size_t count = 0;
    for (const auto& loop : loops)
        for (glm::vec2 p : loop) sum += p, ++count;
    if (count == 0) return std::nullopt;
    return sum / float(count);
}

std::optional<glm::vec2> edge_middle(const hsr_scene& s, const hsr_camera& camera, uint32_t v0, uint32_t v1) {
    const float* a = s.positions + 3 * std::size_t(v0);
    const float* b = s.positions + 3 * std::size_t(v1);
    const glm::vec4 clip = matrix(camera.view_projection) *
                           glm::vec4(0.5f * (a[0] + b[0]), 0.5f * (a[1] + b[1]), 0.5f * (a[2] + b[2]), 1.0f);
    if (!(clip.w >= kMinW)) return std::nullopt;
    const glm::vec2 p = to_window(clip, camera);
    if (!std::isfinite(p.x + p.y)) return std::nullopt;
    return p;
}

}  // namespace

std::vector<uint32_t> hsr::host::polygon_faces(const hsr_scene& s) {
    std::vector<uint32_t> polygon_of(s.triangle_count, HSR_NO_FACE);
    std::vector<uint32_t> stack, members;
    for (uint32_t seed = 0; seed < s.triangle_count; ++seed) {
        if (polygon_of[seed] != HSR_NO_FACE) continue;
        polygon_of[seed] = seed;  // the lowest: seeds are taken in order
        if (s.edge_neighbors == nullptr) continue;
        const glm::dvec3 n = unit_normal(s, seed);
        if (n == glm::dvec3(0.0)) continue;
        stack.assign(1, seed);
        while (!stack.empty()) {
            const uint32_t t = stack.back();
            stack.pop_back();
            for (int i = 0; i < 3; ++i) {
                const int32_t u = s.edge_neighbors[3 * std::size_t(t) + i];
                if (u == HSR_NO_NEIGHBOR || uint32_t(u) >= s.triangle_count || polygon_of[uint32_t(u)] != HSR_NO_FACE)
                    continue;
                if (s.face_object != nullptr && s.face_object[uint32_t(u)] != s.face_object[seed]) continue;
                if (glm::dot(unit_normal(s, uint32_t(u)), n) < kCoplanarCosine) continue;
                polygon_of[uint32_t(u)] = seed;
                stack.push_back(uint32_t(u));
            }
        }
    }
    return polygon_of;
}

namespace {

// The outlines of the polygon made of `triangles` (polygon_of names it for each).
std::vector<std::vector<glm::vec3>> loops_of(const hsr_scene& s, const std::vector<uint32_t>& polygon_of,
                                             std::span<const uint32_t> triangles) {
    std::vector<std::vector<glm::vec3>> loops;
    if (triangles.empty()) return loops;
    const uint32_t polygon = polygon_of[triangles[0]];
    // The sides of the polygon's triangles that no other of them shares, as (from, to) vertices in
    // the triangles' counter-clockwise order.
    std::vector<std::pair<uint32_t, uint32_t>> sides;
    for (const uint32_t t : triangles) {
        for (int i = 0; i < 3; ++i) {
            const int32_t u = s.edge_neighbors != nullptr ? s.edge_neighbors[3 * std::size_t(t) + i] : HSR_NO_NEIGHBOR;
            if (u != HSR_NO_NEIGHBOR && uint32_t(u) < s.triangle_count && polygon_of[uint32_t(u)] == polygon) continue;
            sides.emplace_back(s.indices[3 * std::size_t(t) + i], s.indices[3 * std::size_t(t) + (i + 1) % 3]);
        }
    }
    std::vector<uint8_t> used(sides.size(), 0);
    for (std::size_t start = 0; start < sides.size(); ++start) {
        if (used[start]) continue;
        std::vector<glm::vec3> loop;
        std::size_t at = start;
        while (true) {
            used[at] = 1;
            const float* p = s.positions + 3 * std::size_t(sides[at].first);
            loop.emplace_back(p[0], p[1], p[2]);
            std::size_t next = sides.size();
            for (std::size_t k = 0; k < sides.size(); ++k)
                if (!used[k] && sides[k].first == sides[at].second) {
                    next = k;
                    break;
                }
            if (next == sides.size()) break;
            at = next;
        }
        if (loop.size() >= 3) loops.push_back(std::move(loop));
    }
    return loops;
}

}  // namespace

std::vector<std::vector<glm::vec3>> hsr::host::polygon_loops(const hsr_scene& s, const std::vector<uint32_t>& polygon_of,
                                                             uint32_t face) {
    if (face >= s.triangle_count || polygon_of.size() != s.triangle_count) return {};
    std::vector<uint32_t> triangles;
    for (uint32_t t = polygon_of[face]; t < s.triangle_count; ++t)
        if (polygon_of[t] == polygon_of[face]) triangles.push_back(t);
    return loops_of(s, polygon_of, triangles);
}

nlohmann::json hsr::host::line_step_figure(const hsr_scene& s, const hsr_camera& camera, const hsr::LineDrawing& drawing,
                                           const hsr::TraceEventRecord& event, glm::vec3 background) {
    using nlohmann::json;
    const std::vector<uint32_t> polygon_of = polygon_faces(s);
    json figure;
    figure["background"] = {std::lround(255 * background.r), std::lround(255 * background.g), std::lround(255 * background.b)};

    figure["edge"] = nullptr;
    if (event.edge < drawing.edges.size()) {
        const uint32_t v0 = drawing.edges.vertices[2 * event.edge], v1 = drawing.edges.vertices[2 * event.edge + 1];
        const float* a = s.positions + 3 * std::size_t(v0);
        const float* b = s.positions + 3 * std::size_t(v1);
        const std::vector<glm::vec2> ends = project_ring({{a[0], a[1], a[2]}, {b[0], b[1], b[2]}}, camera);
        if (ends.size() == 2) {
            json edge{{"index", event.edge}, {"lines", json::array({{ends[0].x, ends[0].y, ends[1].x, ends[1].y}})}};
            edge["label"] = point_json(0.5f * (ends[0] + ends[1]));
            figure["edge"] = std::move(edge);
        }
    }

    figure["face"] = nullptr;
    if (event.face < s.triangle_count) {
        std::vector<std::vector<glm::vec2>> projected;
        for (const auto& loop : polygon_loops(s, polygon_of, event.face)) {
            std::vector<glm::vec2> ring = project_ring(loop, camera);
            if (ring.size() >= 3) projected.push_back(std::move(ring));
        }
        if (!projected.empty()) {
            json loops = json::array();
            for (const auto& ring : projected) {
                json points = json::array();
                for (glm::vec2 p : ring) points.push_back(point_json(p));
                loops.push_back(std::move(points));
            }
            const uint32_t index = polygon_of[event.face];
            figure["face"] = {{"index", index},
                              {"object", s.face_object != nullptr ? json(s.face_object[index]) : json(nullptr)},
                              {"loops", std::move(loops)},
                              {"label", point_json(*centre(projected))}};
        }
    }

    // The numbers: every requested edge at its middle, every face turned toward the eye at its centre.
    json edges = json::array(), faces = json::array();
    bool too_many = drawing.edges.size() > kMostLabels;
    for (uint32_t e = 0; e < drawing.edges.size() && !too_many; ++e)
        if (const auto at = edge_middle(s, camera, drawing.edges.vertices[2 * e], drawing.edges.vertices[2 * e + 1]))
            edges.push_back({e, at->x, at->y});
    const std::vector<uint8_t> front = hsr::front_facing_faces(s, camera);
    std::size_t front_polygons = 0;
    for (uint32_t t = 0; t < s.triangle_count; ++t) front_polygons += polygon_of[t] == t && front[t] ? 1 : 0;
    too_many = too_many || front_polygons > kMostLabels;
    if (!too_many) {
        // Each polygon's triangles together (a counting sort by polygon).
        std::vector<uint32_t> first(std::size_t(s.triangle_count) + 1, 0), order(s.triangle_count);
        for (uint32_t t = 0; t < s.triangle_count; ++t) ++first[polygon_of[t] + 1];
        for (uint32_t t = 0; t < s.triangle_count; ++t) first[t + 1] += first[t];
        std::vector<uint32_t> next(first.begin(), first.end() - 1);
        for (uint32_t t = 0; t < s.triangle_count; ++t) order[next[polygon_of[t]]++] = t;
        for (uint32_t t = 0; t < s.triangle_count; ++t) {
            if (polygon_of[t] != t || !front[t]) continue;
            std::vector<std::vector<glm::vec2>> projected;
            for (const auto& loop : loops_of(s, polygon_of, std::span(order).subspan(first[t], first[t + 1] - first[t])))
                projected.push_back(project_ring(loop, camera));
            if (const auto at = centre(projected)) faces.push_back({t, at->x, at->y});
        }
    }
    figure["labels"] = too_many ? json(nullptr) : json{{"edges", std::move(edges)}, {"faces", std::move(faces)}};
    return figure;
}
