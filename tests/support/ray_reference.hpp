// The tests' independent answer for hidden surfaces: casting one ray in double precision through a
// window point and intersecting it with triangles by Cramer's rule, with nothing shared with the
// rasterizers (test_zbuffer, test_sections, test_a_buffer).
#pragma once

#include "hsr/abi.h"
#include "hsr/sdk.hpp"

#include <glm/glm.hpp>

#include <cmath>
#include <limits>
#include <utility>

namespace ray_reference {

struct Ray {
    glm::dvec3 origin;     // on the near plane
    glm::dvec3 direction;  // origin + direction is on the far plane
};

// The segment of view volume seen through window point (wx, wy), from unprojecting NDC depth -1 and 1.
Ray window_ray(const hsr_camera& camera, double wx, double wy) {
    glm::dmat4 view_projection;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) view_projection[c][r] = camera.view_projection[4 * c + r];
    const glm::dmat4 inverse = glm::inverse(view_projection);
    const double x = 2.0 * wx / camera.width - 1.0, y = 1.0 - 2.0 * wy / camera.height;
    const glm::dvec4 near = inverse * glm::dvec4(x, y, -1.0, 1.0);
    const glm::dvec4 far = inverse * glm::dvec4(x, y, 1.0, 1.0);
    const glm::dvec3 a = glm::dvec3(near) / near.w, b = glm::dvec3(far) / far.w;
    return {a, b - a};
}

struct Hit {
    bool hit = false;
    double b1 = 0, b2 = 0;  // barycentric weights of corners 1 and 2
    glm::dvec3 point{};
};

// Ray-triangle intersection by solving origin + t d = a + b1 (b - a) + b2 (c - a) with Cramer's
// rule; a hit needs the point inside the triangle and between the near and far planes (t in [0, 1]).
Hit intersect(const Ray& ray, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
    const glm::dvec3 e1 = b - a, e2 = c - a, s = ray.origin - a;
    const glm::dmat3 m(-ray.direction, e1, e2);  // columns
    const double det = glm::determinant(m);
    Hit h;
    if (std::abs(det) < 1e-300) return h;
    const double t = glm::determinant(glm::dmat3(s, e1, e2)) / det;
    const double b1 = glm::determinant(glm::dmat3(-ray.direction, s, e2)) / det;
    const double b2 = glm::determinant(glm::dmat3(-ray.direction, e1, s)) / det;
    h.hit = t >= 0 && t <= 1 && b1 >= 0 && b2 >= 0 && b1 + b2 <= 1;
    h.b1 = b1;
    h.b2 = b2;
    h.point = ray.origin + t * ray.direction;
    return h;
}

// The surface a ray through window point (wx, wy) meets first among every placement's triangles,
// skipping what the camera's clip planes cut away: (face, instance), or (HSR_NO_FACE, 0).
inline std::pair<uint32_t, uint32_t> nearest_surface(const hsr_scene& raw, const hsr_camera& camera, double wx,
                                                     double wy) {
    const hsr::sdk::Scene scene(raw);
    const hsr::sdk::ClipPlanes planes(camera);
    const Ray ray = window_ray(camera, wx, wy);
    double nearest = std::numeric_limits<double>::infinity();
    std::pair<uint32_t, uint32_t> found{HSR_NO_FACE, 0};
    for (uint32_t k = 0; k < scene.placement_count(); ++k) {
        const hsr::sdk::Placement p = scene.placement(k);
        const glm::dmat4 m(p.transform);
        auto corner = [&](uint32_t t, int c) { return glm::dvec3(m * glm::dvec4(scene.corner_position(t, c), 1.0)); };
        for (uint32_t t = p.first_triangle; t < p.first_triangle + p.triangle_count; ++t) {
            const Hit h = intersect(ray, corner(t, 0), corner(t, 1), corner(t, 2));
            if (!h.hit || !planes.keeps(h.point)) continue;
            const double along = glm::dot(h.point - ray.origin, ray.direction);
            if (along < nearest) {
                nearest = along;
                found = {t, p.instance};
            }
        }
    }
    return found;
}

}  // namespace ray_reference
