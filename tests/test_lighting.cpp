// Lighting plugins (lambert, phong, blinn-phong, facecolor) loaded through the real ABI and checked
// against values worked out by hand on one- and two-triangle scenes built here; gooch too where
// every model must behave alike (its colours: test_gooch.cpp).
#include "hsr/abi.h"
#include "hsr/error.hpp"
#include "hsr/plugin_registry.hpp"
#include "hsr/scene.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace {

using Settings = std::vector<hsr::Setting>;

// A scene built triangle by triangle; SceneData owns the arrays hsr_scene points to.
struct TestScene : hsr::SceneData {
    // Corners CCW seen from the front; corner normals default to the face normal.
    void add_triangle(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 color,
                      std::vector<glm::vec3> normals = {}) {
        const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
        if (normals.empty()) normals = {n, n, n};
        const auto base = static_cast<uint32_t>(positions.size() / 3);
        if (base == 0) {
            bounds_min = bounds_max = a;
            object_names = {"test"};
        }
        for (glm::vec3 p : {a, b, c}) {
            positions.insert(positions.end(), {p.x, p.y, p.z});
            bounds_min = glm::min(bounds_min, p);
            bounds_max = glm::max(bounds_max, p);
        }
        indices.insert(indices.end(), {base, base + 1, base + 2});
        face_normals.insert(face_normals.end(), {n.x, n.y, n.z});
        for (glm::vec3 cn : normals) corner_normals.insert(corner_normals.end(), {cn.x, cn.y, cn.z});
        face_colors.insert(face_colors.end(), {color.r, color.g, color.b});
        edge_neighbors.insert(edge_neighbors.end(), {HSR_NO_NEIGHBOR, HSR_NO_NEIGHBOR, HSR_NO_NEIGHBOR});
        face_object.push_back(0);
    }
    glm::vec3 corner(uint32_t t, int k) const {
        const uint32_t v = indices[3 * t + k];
        return {positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]};
    }
    glm::vec3 corner_normal(uint32_t t, int k) const {
        const float* n = &corner_normals[9 * t + 3 * k];
        return {n[0], n[1], n[2]};
    }
    hsr_scene raw() const { return view(); }
};

struct Fragment {
    uint32_t face;
    float b1, b2;
    glm::vec3 position;
    glm::vec3 normal;
};

// What the host does: the point at barycentrics (b1, b2) and the renormalised interpolated normal.
Fragment fragment_at(const TestScene& scene, uint32_t face, float b1, float b2) {
    const float b0 = 1.0f - b1 - b2;
    const glm::vec3 p = b0 * scene.corner(face, 0) + b1 * scene.corner(face, 1) + b2 * scene.corner(face, 2);
    const glm::vec3 n = b0 * scene.corner_normal(face, 0) + b1 * scene.corner_normal(face, 1) +
                        b2 * scene.corner_normal(face, 2);
    return {face, b1, b2, p, glm::normalize(n)};
}

// A fragment with its position and normal given directly (b1 = b2 = 0).
Fragment fragment(uint32_t face, glm::vec3 position, glm::vec3 normal) { return {face, 0, 0, position, normal}; }

hsr_light directional(glm::vec3 toward_light, glm::vec3 color = glm::vec3(1), float intensity = 1) {
    const glm::vec3 d = glm::normalize(toward_light);
    return {sizeof(hsr_light), HSR_LIGHT_DIRECTIONAL, {d.x, d.y, d.z}, {color.r, color.g, color.b}, intensity};
}
hsr_light point_light(glm::vec3 position, glm::vec3 color = glm::vec3(1), float intensity = 1) {
    return {sizeof(hsr_light), HSR_LIGHT_POINT, {position.x, position.y, position.z}, {color.r, color.g, color.b}, intensity};
}

hsr_shading_context perspective(const std::vector<hsr_light>& lights, glm::vec3 eye) {
    hsr_shading_context c{};
    c.struct_size = sizeof(hsr_shading_context);
    c.lights = lights.data();
    c.light_count = static_cast<uint32_t>(lights.size());
    c.projection_type = HSR_PROJECTION_PERSPECTIVE;
    c.eye[0] = eye.x, c.eye[1] = eye.y, c.eye[2] = eye.z;
    const glm::vec3 forward = -glm::normalize(eye);  // looking at the origin; not used for perspective
    c.view_direction[0] = forward.x, c.view_direction[1] = forward.y, c.view_direction[2] = forward.z;
    return c;
}

hsr_shading_context orthographic(const std::vector<hsr_light>& lights, glm::vec3 view_direction,
                                 glm::vec3 eye = glm::vec3(123, -45, 67)) {
    hsr_shading_context c = perspective(lights, eye);
    c.projection_type = HSR_PROJECTION_ORTHOGRAPHIC;
    c.view_direction[0] = view_direction.x, c.view_direction[1] = view_direction.y;
    c.view_direction[2] = view_direction.z;
    return c;
}

hsr::Plugin load(const std::string& name) {
    std::vector<hsr::Plugin> plugins = hsr::load_plugin_library(std::string(HSR_PLUGIN_DIR) + "/hsr-" + name + ".so");
    REQUIRE(plugins.size() == 1);
    REQUIRE(plugins[0].descriptor.kind == HSR_KIND_LIGHTING_MODEL);
    REQUIRE(std::string(plugins[0].descriptor.name) == name);
    return plugins[0];
}

// Runs one batch through an already prepared model and returns the colours.
std::vector<glm::vec3> shade_batch(const hsr::LightingModel& model, const std::vector<Fragment>& fragments) {
    const size_t count = fragments.size();
    std::vector<uint32_t> face(count), pixel(count);
    std::vector<float> bary(2 * count), position(3 * count), normal(3 * count);
    std::vector<float> color(3 * count, -1.0f);
    for (size_t i = 0; i < count; ++i) {
        const Fragment& f = fragments[i];
        face[i] = f.face;
        pixel[i] = static_cast<uint32_t>(i);
        bary[2 * i] = f.b1, bary[2 * i + 1] = f.b2;
        for (int a = 0; a < 3; ++a) {
            position[3 * i + a] = f.position[a];
            normal[3 * i + a] = f.normal[a];
        }
    }
    hsr_fragment_batch batch{};
    batch.struct_size = sizeof(hsr_fragment_batch);
    batch.count = static_cast<uint32_t>(count);
    batch.face = face.data();
    batch.bary = bary.data();
    batch.position = position.data();
    batch.normal = normal.data();
    batch.pixel = pixel.data();
    batch.color = color.data();
    model.shade(batch);
    std::vector<glm::vec3> out(count);
    for (size_t i = 0; i < count; ++i) out[i] = {color[3 * i], color[3 * i + 1], color[3 * i + 2]};
    return out;
}

std::vector<glm::vec3> shade(const std::string& plugin, const Settings& settings, const TestScene& scene,
                             const hsr_shading_context& context, const std::vector<Fragment>& fragments) {
    hsr::LightingModel model(load(plugin), settings);
    const hsr_scene raw = scene.raw();
    model.prepare(raw, context);
    return shade_batch(model, fragments);
}

void check_color(glm::vec3 actual, glm::vec3 expected, double eps = 1e-5) {
    INFO("actual (" << actual.r << ", " << actual.g << ", " << actual.b << "), expected (" << expected.r << ", "
                    << expected.g << ", " << expected.b << ")");
    CHECK(actual.r == Approx(expected.r).margin(eps));
    CHECK(actual.g == Approx(expected.g).margin(eps));
    CHECK(actual.b == Approx(expected.b).margin(eps));
}

// One triangle in the plane z = 0 facing +z, big enough to hold the test points.
TestScene floor_triangle(glm::vec3 color = glm::vec3(1)) {
    TestScene s;
    s.add_triangle({0, 0, 0}, {4, 0, 0}, {0, 4, 0}, color);
    return s;
}

const glm::vec3 up{0, 0, 1};
const float sqrt_half = std::sqrt(0.5f);

}  // namespace

TEST_CASE("lambert: ka + kd * max(0, N.L), per channel of the face colour", "[lighting][lambert]") {
    const TestScene scene = floor_triangle({0.5f, 1.0f, 0.25f});
    const std::vector<Fragment> at_centre{fragment_at(scene, 0, 1.0f / 3, 1.0f / 3)};

    SECTION("light 60 degrees off the normal: N.L = cos 60 = 0.5") {
        const std::vector<hsr_light> lights{directional({std::sin(glm::radians(60.0f)), 0, 0.5f})};
        // defaults ka = 0.1, kd = 0.8: intensity 0.1 + 0.8 * 0.5 = 0.5, times C = (0.5, 1, 0.25)
        const auto c = shade("lambert", {}, scene, perspective(lights, {1, 1, 5}), at_centre);
        check_color(c[0], {0.25f, 0.5f, 0.125f});
        // ka = 0.2, kd = 0.6: 0.2 + 0.6 * 0.5 = 0.5 as well; ka = 0.3, kd = 0.2: 0.3 + 0.1 = 0.4
        check_color(shade("lambert", {{"ambient", "0.3"}, {"diffuse", "0.2"}}, scene,
                          perspective(lights, {1, 1, 5}), at_centre)[0],
                    {0.2f, 0.4f, 0.1f});
    }
    SECTION("light below the surface: ambient only") {
        const std::vector<hsr_light> lights{directional({1, 0, -0.2f})};
        // seen from above, the light is behind the face: 0.1 * C
        check_color(shade("lambert", {}, scene, perspective(lights, {1, 1, 5}), at_centre)[0],
                    {0.05f, 0.1f, 0.025f});
    }
    SECTION("light along the normal: ka + kd = 0.9") {
        const std::vector<hsr_light> lights{directional(up)};
        check_color(shade("lambert", {}, scene, perspective(lights, {1, 1, 5}), at_centre)[0],
                    {0.45f, 0.9f, 0.225f});
    }
}

TEST_CASE("phong: specular ks * (R.V)^n with the mirror vector", "[lighting][phong]") {
    const TestScene scene = floor_triangle();
    const std::vector<Fragment> at_origin{fragment(0, {0, 0, 0}, up)};
    // L = (1, 0, 1)/sqrt2, N = (0, 0, 1): N.L = sqrt(1/2) = 0.707107.
    // R = 2 (N.L) N - L = (0, 0, 1.414214) - (0.707107, 0, 0.707107) = (-0.707107, 0, 0.707107).
    // Orthographic view along -z: V = (0, 0, 1), R.V = 0.707107; (R.V)^10 = (1/2)^5 = 0.03125.
    const std::vector<hsr_light> lights{directional({1, 0, 1})};
    const hsr_shading_context from_above = orthographic(lights, {0, 0, -1});

    SECTION("specular term alone") {
        const auto c = shade("phong", {{"ambient", "0"}, {"diffuse", "0"}, {"specular", "1"}, {"shininess", "10"}},
                             scene, from_above, at_origin);
        check_color(c[0], glm::vec3(0.03125f));
    }
    SECTION("all three terms, red highlight on a white face") {
        // ka = 0.1, kd = 0.8, ks = 0.5, S = (1, 0, 0):
        // red   = 0.1 + 0.8 * 0.707107 + 0.5 * 0.03125 = 0.1 + 0.565685 + 0.015625 = 0.681310
        // green = blue = 0.1 + 0.565685 = 0.665685
        const auto c = shade("phong", {{"shininess", "10"}, {"specular-color", "1/0/0"}}, scene, from_above, at_origin);
        check_color(c[0], {0.681310f, 0.665685f, 0.665685f});
    }
    SECTION("viewer along R: (R.V)^n = 1 whatever n") {
        // perspective eye on the mirror ray from the origin: V = R
        const auto c = shade("phong", {{"ambient", "0"}, {"diffuse", "0"}, {"specular", "1"}, {"shininess", "500"}},
                             scene, perspective(lights, {-2, 0, 2}), at_origin);
        check_color(c[0], glm::vec3(1.0f));
    }
    SECTION("no highlight when the light is behind the surface") {
        // L = (1, 0, -1)/sqrt2 reflects to R = (-0.707, 0, -0.707); viewer below along the mirror ray,
        // two-sided off so N stays (0, 0, 1): N.L < 0 => no diffuse, no specular, ambient 0.
        const std::vector<hsr_light> below{directional({1, 0, -1})};
        const auto c = shade("phong",
                             {{"ambient", "0"}, {"specular", "1"}, {"shininess", "1"}, {"two-sided", "false"}},
                             scene, perspective(below, {-2, 0, -2}), at_origin);
        check_color(c[0], glm::vec3(0.0f));
    }
}

TEST_CASE("blinn-phong: specular ks * (N.H)^n with the half vector", "[lighting][blinn-phong]") {
    const TestScene scene = floor_triangle();
    const std::vector<Fragment> at_origin{fragment(0, {0, 0, 0}, up)};
    // L = (1, 0, 1)/sqrt2, V = (0, 0, 1): L + V = (0.707107, 0, 1.707107), |L + V| = 1.847759,
    // H = (0.382683, 0, 0.923880), N.H = cos 22.5 deg = 0.923880, (N.H)^2 = (1 + cos 45)/2 = 0.853553.
    const std::vector<hsr_light> lights{directional({1, 0, 1})};
    const Settings specular_only{{"ambient", "0"}, {"diffuse", "0"}, {"specular", "1"}, {"shininess", "2"}};

    SECTION("half vector between L and V") {
        check_color(shade("blinn-phong", specular_only, scene, orthographic(lights, {0, 0, -1}), at_origin)[0],
                    glm::vec3(0.853553f));
        // Phong's R.V for the same geometry is 0.707107, squared 0.5: the two models differ.
        check_color(shade("phong", specular_only, scene, orthographic(lights, {0, 0, -1}), at_origin)[0],
                    glm::vec3(0.5f));
    }
    SECTION("viewer on the mirror ray: H = N, full highlight") {
        check_color(shade("blinn-phong", specular_only, scene, perspective(lights, {-3, 0, 3}), at_origin)[0],
                    glm::vec3(1.0f));
    }
    SECTION("with ambient, diffuse and a coloured highlight") {
        // 0.1 + 0.8 * 0.707107 + 0.5 * S * 0.853553 with S = (0, 1, 0.5)
        // red 0.665685, green 0.665685 + 0.426777 = 1.092462 -> clamped 1, blue 0.665685 + 0.213388 = 0.879073
        const auto c = shade("blinn-phong", {{"shininess", "2"}, {"specular-color", "0/1/0.5"}}, scene,
                             orthographic(lights, {0, 0, -1}), at_origin);
        check_color(c[0], {0.665685f, 1.0f, 0.879073f});
    }
}

TEST_CASE("light colour and intensity scale the reflected light, not the ambient", "[lighting]") {
    const TestScene scene = floor_triangle({1.0f, 0.5f, 1.0f});
    const std::vector<Fragment> at_origin{fragment(0, {0, 0, 0}, up)};
    // N.L = 1; E = (1, 0.5, 0) * 0.8 = (0.8, 0.4, 0); C = (1, 0.5, 1); ka = 0.1, kd = 1:
    // colour = 0.1 C + E * C = (0.1 + 0.8, 0.05 + 0.2, 0.1 + 0) = (0.9, 0.25, 0.1)
    const std::vector<hsr_light> lights{directional(up, {1.0f, 0.5f, 0.0f}, 0.8f)};
    const hsr_shading_context context = orthographic(lights, {1, 0, -1});  // V = (-1, 0, 1)/sqrt2
    const Settings s{{"diffuse", "1"}, {"interpolation", "phong"}};
    check_color(shade("lambert", s, scene, context, at_origin)[0], {0.9f, 0.25f, 0.1f});
    // The highlight is scaled by E as well (S white, ks = 0.5). phong: R = N, R.V = 0.707107,
    // (R.V)^32 = 2^-16 = 1.5e-5: + 0.5 * E * 1.5e-5 = (0.000006, 0.000003, 0).
    check_color(shade("phong", s, scene, context, at_origin)[0], {0.900006f, 0.250003f, 0.1f});
    // blinn-phong: H = normalize(N + V) at 22.5 degrees from N, cos(22.5)^64 = 0.006301:
    // + 0.5 * E * 0.006301 = (0.002520, 0.001260, 0).
    check_color(shade("blinn-phong", s, scene, context, at_origin)[0], {0.902520f, 0.251260f, 0.1f}, 2e-6);
}

TEST_CASE("point light: the light direction depends on the shaded point, no distance falloff",
          "[lighting][point]") {
    const TestScene scene = floor_triangle();
    const Settings diffuse_only{{"ambient", "0"}, {"diffuse", "1"}, {"interpolation", "phong"}};
    const std::vector<hsr_light> lights{point_light({0, 0, 1})};
    // P = (0,0,0): L = (0,0,1), N.L = 1. P = (1,0,0): L = (-1,0,1)/sqrt2, N.L = 0.707107.
    // P = (1,1,0): L = (-1,-1,1)/sqrt3, N.L = 0.577350.
    const auto c = shade("lambert", diffuse_only, scene, perspective(lights, {0, 0, 5}),
                         {fragment(0, {0, 0, 0}, up), fragment(0, {1, 0, 0}, up), fragment(0, {1, 1, 0}, up)});
    check_color(c[0], glm::vec3(1.0f));
    check_color(c[1], glm::vec3(0.707107f));
    check_color(c[2], glm::vec3(0.577350f));
    // Ten times farther away along the normal: still N.L = 1, no attenuation.
    const std::vector<hsr_light> far{point_light({0, 0, 10})};
    check_color(shade("lambert", diffuse_only, scene, perspective(far, {0, 0, 5}), {fragment(0, {0, 0, 0}, up)})[0],
                glm::vec3(1.0f));
}

TEST_CASE("viewer vector: perspective uses the eye point, orthographic the view direction", "[lighting]") {
    const TestScene scene = floor_triangle();
    const Settings specular_only{{"ambient", "0"}, {"diffuse", "0"}, {"specular", "1"}, {"shininess", "2"}};
    const std::vector<hsr_light> lights{directional({1, 0, 1})};  // R = (-1, 0, 1)/sqrt2 everywhere
    const std::vector<Fragment> fragments{fragment(0, {0, 0, 0}, up), fragment(0, {1, 0, 0}, up)};

    // Perspective, eye (-1, 0, 1): at P = 0, V = (-1,0,1)/sqrt2 = R, (R.V)^2 = 1.
    // At P = (1,0,0): V = (-2,0,1)/sqrt5, R.V = (2 + 1)/(sqrt2 sqrt5) = 3/sqrt10, squared 0.9.
    const auto p = shade("phong", specular_only, scene, perspective(lights, {-1, 0, 1}), fragments);
    check_color(p[0], glm::vec3(1.0f));
    check_color(p[1], glm::vec3(0.9f));

    // Orthographic looking down -z (the eye point is ignored): V = (0,0,1) at both points, R.V = 0.707107,
    // squared 0.5.
    const auto o = shade("phong", specular_only, scene, orthographic(lights, {0, 0, -1}, {-1, 0, 1}), fragments);
    check_color(o[0], glm::vec3(0.5f));
    check_color(o[1], glm::vec3(0.5f));
    // The view direction need not be unit length: (0, 0, -7) is the same direction.
    check_color(shade("phong", specular_only, scene, orthographic(lights, {0, 0, -7}), fragments)[1],
                glm::vec3(0.5f));
}

TEST_CASE("two-sided lighting flips the normal toward the viewer", "[lighting][two-sided]") {
    const TestScene scene = floor_triangle();  // face normal +z
    const std::vector<hsr_light> from_below{directional({0, 0, -1})};
    const std::vector<hsr_light> from_above{directional({0, 0, 1})};
    const glm::vec3 eye_below{1, 1, -5}, eye_above{1, 1, 5};

    for (const char* mode : {"flat", "gouraud", "phong"}) {
        INFO("interpolation " << mode);
        const std::vector<Fragment> f{fragment_at(scene, 0, 0.25f, 0.25f)};
        auto run = [&](const char* two_sided, const std::vector<hsr_light>& lights, glm::vec3 eye) {
            return shade("lambert", {{"interpolation", mode}, {"two-sided", two_sided}}, scene,
                         perspective(lights, eye), f)[0];
        };
        // Seen from below, lit from below: two-sided uses N = -z, N.L = 1 -> 0.1 + 0.8 = 0.9;
        // one-sided keeps N = +z, N.L = -1 -> ambient 0.1.
        check_color(run("true", from_below, eye_below), glm::vec3(0.9f));
        check_color(run("false", from_below, eye_below), glm::vec3(0.1f));
        // Seen from below, lit from above: the visible back is dark when two-sided (0.1), lit when not (0.9).
        check_color(run("true", from_above, eye_below), glm::vec3(0.1f));
        check_color(run("false", from_above, eye_below), glm::vec3(0.9f));
        // Seen from the front nothing changes.
        check_color(run("true", from_above, eye_above), glm::vec3(0.9f));
        check_color(run("false", from_above, eye_above), glm::vec3(0.9f));
    }
    // Orthographic viewer looking up (+z): V = -z, the back is seen.
    check_color(shade("phong", {{"specular", "0"}}, scene, orthographic(from_below, {0, 0, 1}),
                      {fragment(0, {1, 1, 0}, up)})[0],
                glm::vec3(0.9f));
}

namespace {

// Equilateral triangle in z = 0 around the origin, corners at angles 0, 120, 240 degrees (CCW from +z),
// each corner normal tilted 30 degrees outward: n_k = (sin30 d_k, cos30) = (0.5 d_k, 0.866025).
TestScene dome_triangle() {
    const float r3 = std::sqrt(3.0f) / 2;
    const glm::vec2 d[3] = {{1, 0}, {-0.5f, r3}, {-0.5f, -r3}};
    std::vector<glm::vec3> normals;
    for (glm::vec2 dk : d) normals.push_back({0.5f * dk.x, 0.5f * dk.y, r3});
    TestScene s;
    s.add_triangle({d[0], 0}, {d[1], 0}, {d[2], 0}, glm::vec3(1), normals);
    return s;
}

}  // namespace

TEST_CASE("interpolation modes: flat is constant, gouraud mixes corner colours, phong per pixel",
          "[lighting][interpolation]") {
    const TestScene scene = dome_triangle();
    // L = (0, 0.6, 0.8). Corner N.L: n0 = (0.5, 0, 0.866): 0.8 * 0.866025 = 0.692820;
    // n1 = (-0.25, 0.433013, 0.866): 0.6 * 0.433013 + 0.692820 = 0.952628; n2: -0.259808 + 0.692820 = 0.433013.
    // Lambert ka = 0.1, kd = 0.8 at the corners: c0 = 0.654256, c1 = 0.862102, c2 = 0.446410.
    // Face normal (0, 0, 1): N.L = 0.8, flat colour 0.1 + 0.64 = 0.74.
    const std::vector<hsr_light> lights{directional({0, 0.6f, 0.8f})};
    const hsr_shading_context context = orthographic(lights, {0, 0, -1});
    const std::vector<Fragment> fragments{
        fragment_at(scene, 0, 0, 0),       fragment_at(scene, 0, 1, 0),          fragment_at(scene, 0, 0, 1),
        fragment_at(scene, 0, 0.3f, 0.5f), fragment_at(scene, 0, 1.0f / 3, 1.0f / 3)};

    SECTION("flat: one colour for the whole face, from the face normal") {
        for (glm::vec3 c : shade("lambert", {{"interpolation", "flat"}}, scene, context, fragments))
            check_color(c, glm::vec3(0.74f));
    }
    SECTION("gouraud: the corner colours, and their barycentric mix inside") {
        const auto c = shade("lambert", {{"interpolation", "gouraud"}}, scene, context, fragments);
        check_color(c[0], glm::vec3(0.654256f));
        check_color(c[1], glm::vec3(0.862102f));
        check_color(c[2], glm::vec3(0.446410f));
        // b = (0.2, 0.3, 0.5): 0.2 * 0.654256 + 0.3 * 0.862102 + 0.5 * 0.446410 = 0.612687
        check_color(c[3], glm::vec3(0.612687f));
        // centroid: (0.654256 + 0.862102 + 0.446410) / 3 = 0.654256
        check_color(c[4], glm::vec3(0.654256f));
    }
    SECTION("phong: evaluated with the interpolated normal") {
        const auto c = shade("lambert", {{"interpolation", "phong"}}, scene, context, fragments);
        // at the corners the interpolated normal is the corner normal: same as gouraud there
        check_color(c[0], glm::vec3(0.654256f));
        check_color(c[1], glm::vec3(0.862102f));
        check_color(c[2], glm::vec3(0.446410f));
        // centroid: the tilts cancel, N = (0, 0, 1), N.L = 0.8 -> 0.74 (gouraud gave 0.654256)
        check_color(c[4], glm::vec3(0.74f));
    }
}

TEST_CASE("gouraud misses a highlight in the middle of a triangle, phong shading keeps it",
          "[lighting][interpolation]") {
    const TestScene scene = dome_triangle();
    // Light and viewer straight above: L = V = (0, 0, 1). ka = 0, kd = ks = 0.5, n = 20.
    // Corners: N.L = cos30 = 0.866025, R.V = cos60 = 0.5, 0.5^20 = 9.5e-7:
    //   colour = 0.5 * 0.866025 + 0.5 * 9.5e-7 = 0.433013 at every corner.
    // Centroid with the interpolated normal (0, 0, 1): R = V, colour = 0.5 + 0.5 = 1.
    // Near corner 0, b = (0.8, 0.1, 0.1): N = normalize(0.35, 0, 0.866025) = (0.374701, 0, 0.927146),
    //   N.L = 0.927146, R.V = 2 * 0.927146^2 - 1 = 0.719198, ^20 = 0.001370: 0.463573 + 0.000685 = 0.464258.
    const std::vector<hsr_light> lights{directional(up)};
    const hsr_shading_context context = orthographic(lights, {0, 0, -1});
    const std::vector<Fragment> fragments{fragment_at(scene, 0, 1.0f / 3, 1.0f / 3), fragment_at(scene, 0, 0.1f, 0.1f)};
    const Settings material{{"ambient", "0"}, {"diffuse", "0.5"}, {"specular", "0.5"}, {"shininess", "20"}};
    auto with = [&](const char* mode) {
        Settings s = material;
        s.emplace_back("interpolation", mode);
        return s;
    };

    const auto gouraud = shade("phong", with("gouraud"), scene, context, fragments);
    const auto phong = shade("phong", with("phong"), scene, context, fragments);
    const auto flat = shade("phong", with("flat"), scene, context, fragments);
    check_color(gouraud[0], glm::vec3(0.433013f));
    check_color(gouraud[1], glm::vec3(0.433013f));
    check_color(phong[0], glm::vec3(1.0f));
    check_color(phong[1], glm::vec3(0.464258f));
    // flat uses the face normal (0, 0, 1) everywhere: the highlight over the whole face
    check_color(flat[0], glm::vec3(1.0f));
    check_color(flat[1], glm::vec3(1.0f));
    // the same holds for Blinn-Phong: at the centroid H = N
    check_color(shade("blinn-phong", with("phong"), scene, context, fragments)[0], glm::vec3(1.0f));
    CHECK(shade("blinn-phong", with("gouraud"), scene, context, fragments)[0].r < 0.5f);
}

TEST_CASE("gouraud evaluates point lights and the viewer at the corner positions", "[lighting][interpolation]") {
    const TestScene scene = floor_triangle();  // corners (0,0,0), (4,0,0), (0,4,0), normal +z
    // Point light at (0, 0, 4): corner 0: L = (0,0,1), N.L = 1; corners 1 and 2: L = (-1,0,1)/sqrt2 etc.,
    // N.L = 0.707107. ka = 0, kd = 1: corner colours 1, 0.707107, 0.707107; at b = (0.5, 0.25, 0.25):
    // 0.5 + 0.5 * 0.707107 = 0.853553.
    const std::vector<hsr_light> lights{point_light({0, 0, 4})};
    const auto c = shade("lambert", {{"ambient", "0"}, {"diffuse", "1"}, {"interpolation", "gouraud"}}, scene,
                         perspective(lights, {1, 1, 5}), {fragment_at(scene, 0, 0.25f, 0.25f)});
    check_color(c[0], glm::vec3(0.853553f));
    // Flat: at the centroid (4/3, 4/3, 0): L = (-4/3, -4/3, 4)/|.|, |.| = 4.422166, N.L = 4/4.422166 = 0.904534.
    const auto f = shade("lambert", {{"ambient", "0"}, {"diffuse", "1"}}, scene, perspective(lights, {1, 1, 5}),
                         {fragment_at(scene, 0, 0.25f, 0.25f)});
    check_color(f[0], glm::vec3(0.904534f));
}

TEST_CASE("several lights add up", "[lighting]") {
    const TestScene scene = floor_triangle();
    const std::vector<Fragment> at_origin{fragment(0, {0, 0, 0}, up)};
    // N.L: 0.5 (60 degrees), 1 (along N), 0.707107 (point light at (1, 0, 1)), 0 (below: adds nothing).
    // ka = 0, kd = 0.3: 0.3 * (0.5 + 1 + 0.707107) = 0.662132
    const std::vector<hsr_light> lights{directional({std::sin(glm::radians(60.0f)), 0, 0.5f}), directional(up),
                                        point_light({1, 0, 1}), directional({0, 1, -1})};
    const Settings s{{"ambient", "0"}, {"diffuse", "0.3"}, {"interpolation", "phong"}};
    check_color(shade("lambert", s, scene, perspective(lights, {0, 0, 3}), at_origin)[0], glm::vec3(0.662132f));
    // No light at all: ambient only.
    check_color(shade("lambert", {}, scene, perspective({}, {0, 0, 3}), at_origin)[0], glm::vec3(0.1f));
}

TEST_CASE("output is clamped to [0, 1]", "[lighting]") {
    const TestScene scene = floor_triangle({0.5f, 1.0f, 0.0f});
    const std::vector<Fragment> at_origin{fragment(0, {0, 0, 0}, up)};
    // intensity 5: 0.1 C + 0.8 * 5 C = 4.1 C = (2.05, 4.1, 0) -> (1, 1, 0)
    // phong and blinn-phong add the white highlight ks * 5 * 1 = 2.5 (V = L = N) to every channel:
    // (4.55, 6.6, 2.5) -> (1, 1, 1).
    const std::vector<hsr_light> bright{directional(up, glm::vec3(1), 5.0f)};
    for (const char* model : {"lambert", "phong", "blinn-phong"}) {
        for (const char* mode : {"flat", "gouraud", "phong"}) {
            INFO(model << " " << mode);
            const auto c = shade(model, {{"interpolation", mode}}, scene, orthographic(bright, {0, 0, -1}), at_origin);
            check_color(c[0], {1.0f, 1.0f, std::string(model) == "lambert" ? 0.0f : 1.0f});
        }
    }
    // A negative intensity (a "light sink") would give 0.1 C - 0.8 C < 0: clamped to 0.
    const std::vector<hsr_light> sink{directional(up, glm::vec3(1), -1.0f)};
    check_color(shade("phong", {}, scene, perspective(sink, {0, 0, 3}), at_origin)[0], glm::vec3(0.0f));
}

TEST_CASE("facecolor returns each fragment's face colour exactly", "[lighting][facecolor]") {
    TestScene scene;
    scene.add_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2f, 0.4f, 0.6f});
    scene.add_triangle({0, 0, 1}, {0, 1, 1}, {1, 0, 1}, {1.0f, 0.0f, 0.5f});  // facing -z
    const std::vector<hsr_light> lights{directional({0, 0, -1}, glm::vec3(1), 3.0f)};
    const auto c = shade("facecolor", {}, scene, perspective(lights, {0, 0, 5}),
                         {fragment_at(scene, 1, 0.2f, 0.2f), fragment_at(scene, 0, 0.5f, 0.1f),
                          fragment_at(scene, 1, 0, 0)});
    CHECK(c[0] == glm::vec3(1.0f, 0.0f, 0.5f));
    CHECK(c[1] == glm::vec3(0.2f, 0.4f, 0.6f));
    CHECK(c[2] == glm::vec3(1.0f, 0.0f, 0.5f));
    // One parameter, by, whose default (given) is the scene's colours, as above.
    CHECK(load("facecolor").descriptor.param_count == 1);
}

TEST_CASE("an empty batch is fine, also with NULL arrays", "[lighting]") {
    const TestScene scene = floor_triangle();
    const std::vector<hsr_light> lights{directional(up)};
    for (const char* name : {"lambert", "phong", "blinn-phong", "facecolor", "gooch"}) {
        INFO(name);
        hsr::LightingModel model(load(name), {});
        const hsr_scene raw = scene.raw();
        model.prepare(raw, perspective(lights, {0, 0, 3}));
        CHECK(shade_batch(model, {}).empty());
        hsr_fragment_batch empty{};
        empty.struct_size = sizeof(hsr_fragment_batch);
        CHECK_NOTHROW(model.shade(empty));
    }
}

TEST_CASE("bad input is a clear error, not a crash", "[lighting][errors]") {
    const TestScene scene = floor_triangle();
    const hsr_scene raw = scene.raw();
    const std::vector<hsr_light> lights{directional(up)};
    for (const char* name : {"lambert", "phong", "blinn-phong", "facecolor", "gooch"}) {
        INFO(name);
        hsr::LightingModel model(load(name), {});
        CHECK_THROWS_WITH(shade_batch(model, {fragment(0, {0, 0, 0}, up)}),
                          Catch::Contains("before a successful prepare"));
        model.prepare(raw, perspective(lights, {0, 0, 3}));
        CHECK_THROWS_WITH(shade_batch(model, {fragment(7, {0, 0, 0}, up)}), Catch::Contains("face index 7"));
    }
    hsr::LightingModel phong(load("phong"), {});
    phong.prepare(raw, perspective(lights, {0, 0, 3}));
    CHECK(shade_batch(phong, {fragment(0, {0, 0, 0}, up)}).size() == 1);
    hsr_light zero = directional(up);
    zero.vector[2] = 0;
    const std::vector<hsr_light> bad{zero};
    CHECK_THROWS_WITH(phong.prepare(raw, perspective(bad, {0, 0, 3})), Catch::Contains("zero direction"));
    CHECK_THROWS_WITH(phong.prepare(raw, orthographic(lights, {0, 0, 0})), Catch::Contains("view_direction"));
    // A failed prepare leaves the model unprepared.
    CHECK_THROWS_WITH(shade_batch(phong, {fragment(0, {0, 0, 0}, up)}), Catch::Contains("before a successful prepare"));
    // Parameters are validated by the host against the schema.
    CHECK_THROWS_AS(hsr::LightingModel(load("phong"), {{"shininess", "0"}}), hsr::Error);
    CHECK_THROWS_AS(hsr::LightingModel(load("lambert"), {{"interpolation", "smooth"}}), hsr::Error);
    CHECK_THROWS_AS(hsr::LightingModel(load("lambert"), {{"shininess", "10"}}), hsr::Error);
}

TEST_CASE("defaults: lambert flat, phong and blinn-phong per-pixel with exponents 32 and 64", "[lighting]") {
    auto default_of = [](const hsr::Plugin& plugin, const std::string& param) {
        for (uint32_t i = 0; i < plugin.descriptor.param_count; ++i)
            if (param == plugin.descriptor.params[i].name) return std::string(plugin.descriptor.params[i].default_value);
        return std::string("<absent>");
    };
    const hsr::Plugin lambert = load("lambert"), phong = load("phong"), blinn = load("blinn-phong");
    CHECK(default_of(lambert, "interpolation") == "flat");
    CHECK(default_of(lambert, "specular") == "<absent>");
    CHECK(default_of(phong, "interpolation") == "phong");
    CHECK(default_of(blinn, "interpolation") == "phong");
    CHECK(default_of(phong, "shininess") == "32");
    CHECK(default_of(blinn, "shininess") == "64");
    CHECK(default_of(phong, "two-sided") == "true");

    // Behaviour of the default phong model: ka 0.1, kd 0.8, ks 0.5, n 32. Light and viewer along N:
    // 0.1 + 0.8 + 0.5 = 1.4 -> 1. Light at 60 degrees, viewer along N: R.V = cos 60 = 0.5, 0.5^32 ~ 2e-10:
    // 0.1 + 0.8 * 0.5 = 0.5.
    const TestScene scene = floor_triangle();
    const std::vector<hsr_light> tilted{directional({std::sin(glm::radians(60.0f)), 0, 0.5f})};
    check_color(shade("phong", {}, scene, orthographic(tilted, {0, 0, -1}), {fragment(0, {1, 1, 0}, up)})[0],
                glm::vec3(0.5f));
    // Lambert by default ignores the fragment's normal (flat): a tilted batch normal changes nothing.
    check_color(shade("lambert", {}, scene, orthographic(tilted, {0, 0, -1}),
                      {fragment(0, {1, 1, 0}, glm::normalize(glm::vec3(1, 0, 1)))})[0],
                glm::vec3(0.5f));
}
