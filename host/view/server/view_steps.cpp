// The step details of hsr view's frames (view_steps.hpp): clipping in homogeneous coordinates
// (Sutherland and Hodgman, "Reentrant polygon clipping", CACM 1974) against the near side w > 0,
// then segments clipped to the image rectangle (Liang and Barsky, "A new concept and method for line
// clipping", ACM TOG 1984).
#include "view/server/view_steps.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace {

constexpr float min_w = 1e-5f;

glm::mat4 matrix(const float* m) {
    glm::mat4 out;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) out[c][r] = m[4 * c + r];
    return out;
}

// Clips the segment to [0, width] x [0, height]; false when nothing is left.
bool clip_to_image(glm::vec2& a, glm::vec2& b, float width, float height) {
    float t0 = 0.0f, t1 = 1.0f;
    const glm::vec2 d = b - a;
    const float p[4] = {-d.x, d.x, -d.y, d.y};
    const float q[4] = {a.x, width - a.x, a.y, height - a.y};
    for (int k = 0; k < 4; ++k) {
        if (p[k] == 0.0f) {
            if (q[k] < 0.0f) return false;
            continue;
        }
        const float t = q[k] / p[k];
        if (p[k] < 0.0f)
            t0 = std::max(t0, t);
        else
            t1 = std::min(t1, t);
        if (t0 > t1) return false;
    }
    const glm::vec2 start = a;
    a = start + t0 * d;
    b = start + t1 * d;
    return true;
}

glm::vec2 to_window(const glm::vec4& clip, const hsr_camera& camera) {
    return {(clip.x / clip.w + 1.0f) * 0.5f * float(camera.width), (1.0f - clip.y / clip.w) * 0.5f * float(camera.height)};
}

// The closed polygon of clip-space points, cut to w >= min_w, as window-space segments in the image.
nlohmann::json outline_of(const std::vector<glm::vec4>& polygon, const hsr_camera& camera) {
    std::vector<glm::vec4> kept;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
        const glm::vec4& p = polygon[i];
        const glm::vec4& q = polygon[(i + 1) % polygon.size()];
        const bool p_in = p.w >= min_w, q_in = q.w >= min_w;
        if (p_in) kept.push_back(p);
        if (p_in != q_in) kept.push_back(p + (q - p) * ((min_w - p.w) / (q.w - p.w)));
    }
    nlohmann::json lines = nlohmann::json::array();
    const bool closed = kept.size() > 2;
    for (std::size_t i = 0; i + (closed ? 0 : 1) < kept.size(); ++i) {
        glm::vec2 a = to_window(kept[i], camera), b = to_window(kept[(i + 1) % kept.size()], camera);
        if (!std::isfinite(a.x + a.y + b.x + b.y)) continue;
        if (clip_to_image(a, b, float(camera.width), float(camera.height))) lines.push_back({a.x, a.y, b.x, b.y});
    }
    return lines;
}

}  // namespace

nlohmann::json hsr::host::triangle_outline(const hsr_scene& scene, const hsr_camera& camera, uint32_t face,
                                           uint32_t instance) {
    if (face >= scene.triangle_count) return nlohmann::json::array();
    glm::mat4 transform = matrix(camera.view_projection);
    if (scene.instance_count > 0) {
        if (instance >= scene.instance_count) return nlohmann::json::array();
        transform = transform * matrix(HSR_ELEMENT(hsr_instance, scene.instances, instance)->transform);
    }
    std::vector<glm::vec4> corners;
    for (int k = 0; k < 3; ++k) {
        const float* p = scene.positions + 3 * size_t(scene.indices[3 * size_t(face) + k]);
        corners.push_back(transform * glm::vec4(p[0], p[1], p[2], 1.0f));
    }
    return outline_of(corners, camera);
}

nlohmann::json hsr::host::projected_segment(const hsr_camera& camera, glm::vec3 a, glm::vec3 b) {
    const glm::mat4 transform = matrix(camera.view_projection);
    return outline_of({transform * glm::vec4(a, 1.0f), transform * glm::vec4(b, 1.0f)}, camera);
}

hsr::host::StepPixels hsr::host::step_pixels(const hsr::Frame& before, const hsr::Frame& after, std::size_t cap) {
    const std::size_t pixels = std::size_t(after.width) * after.height;
    const bool first = before.face.empty();
    const bool tests = !after.depth_tests.empty() && (first || before.depth_tests.size() == pixels);
    std::vector<uint32_t> written, rejected;
    for (std::size_t p = 0; p < pixels; ++p) {
        const uint32_t face_before = first ? HSR_NO_FACE : before.face[p];
        const float depth_before = first ? INFINITY : before.depth[p];
        const bool instance_changed = !after.instance.empty() && !first && before.instance[p] != after.instance[p];
        const bool changed = face_before != after.face[p] || instance_changed ||
                             !(depth_before == after.depth[p] || (std::isinf(depth_before) && std::isinf(after.depth[p])));
        const uint32_t tested = tests ? after.depth_tests[p] - (first ? 0u : before.depth_tests[p]) : 0u;
        if (changed) {
            if (written.size() <= cap) written.push_back(uint32_t(p));
        } else if (tested > 0) {
            if (rejected.size() <= cap) rejected.push_back(uint32_t(p));
        }
    }
    auto as_json = [&](const std::vector<uint32_t>& list) {
        if (list.size() > cap) return nlohmann::json(nullptr);
        nlohmann::json out = nlohmann::json::array();
        for (uint32_t p : list) out.push_back({p % after.width, p / after.width});
        return out;
    };
    return {as_json(written), tests ? as_json(rejected) : nlohmann::json(nullptr)};
}

std::string hsr::host::describe_trace_event(const hsr::TraceEventRecord& e, const std::string& language) {
    std::string text = e.type;
    std::vector<std::string> fields;
    if (language == "ru") {
        if (e.edge != HSR_NO_EDGE) fields.push_back(fmt::format("ребро {}", e.edge));
        if (e.face != HSR_NO_FACE) fields.push_back(fmt::format("грань {}", e.face));
        if (e.object != HSR_NO_OBJECT) fields.push_back(fmt::format("объект {}", e.object));
        if (e.qi >= 0) fields.push_back(fmt::format("количественная невидимость {}", e.qi));
        if (std::isfinite(e.t0) && std::isfinite(e.t1))
            fields.push_back(fmt::format("t от {:.4g} до {:.4g}", e.t0, e.t1));
    } else {
        if (e.edge != HSR_NO_EDGE) fields.push_back(fmt::format("edge {}", e.edge));
        if (e.face != HSR_NO_FACE) fields.push_back(fmt::format("face {}", e.face));
        if (e.object != HSR_NO_OBJECT) fields.push_back(fmt::format("object {}", e.object));
        if (e.qi >= 0) fields.push_back(fmt::format("qi {}", e.qi));
        if (std::isfinite(e.t0) && std::isfinite(e.t1)) fields.push_back(fmt::format("t {:.4g} to {:.4g}", e.t0, e.t1));
    }
    if (!(std::isfinite(e.t0) && std::isfinite(e.t1)) && std::isfinite(e.t0)) fields.push_back(fmt::format("t {:.4g}", e.t0));
    for (std::size_t i = 0; i < fields.size(); ++i) text += (i == 0 ? ": " : ", ") + fields[i];
    return text;
}

std::string hsr::host::no_steps_text(bool plugin_reported_none, const std::string& language) {
    if (language == "ru")
        return plugin_reported_none ? "шагов нет: модуль не сообщил ни об одном" : "шагов нет: алгоритму нечего было делать";
    return plugin_reported_none ? "no steps: the plugin reported none" : "no steps: the algorithm had nothing to do";
}
