// Cameras checked by projecting known points through the hsr_camera matrices with abi.h's window
// rules and comparing with positions worked out by hand: the model centre at the image centre,
// which side of the image a point offset along an axis lands on, the bounding sphere's outline
// inside the image, pixel-camera coordinates, and lights carried from camera to world space.
#include "hsr/camera.hpp"
#include "hsr/scene_file.hpp"
#include "hsr/error.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstring>
#include <vector>

namespace {

glm::dmat4 matrix(const float (&m)[16]) {
    glm::mat4 f;
    std::memcpy(glm::value_ptr(f), m, sizeof m);
    return glm::dmat4(f);
}

struct Window {
    double x, y, depth, w;
};

// abi.h: x_win = (x_ndc + 1) / 2 * W, y_win = (1 - y_ndc) / 2 * H, depth = (z_ndc + 1) / 2.
Window project(const hsr_camera& c, glm::dvec3 p) {
    const glm::dvec4 clip = matrix(c.view_projection) * glm::dvec4(p, 1.0);
    const glm::dvec3 ndc = glm::dvec3(clip) / clip.w;
    return {(ndc.x + 1) / 2 * c.width, (1 - ndc.y) / 2 * c.height, (ndc.z + 1) / 2, clip.w};
}

glm::dvec3 vec(const float (&v)[3]) { return {v[0], v[1], v[2]}; }

// Points spread evenly over a sphere (golden-angle spiral).
std::vector<glm::dvec3> sphere_points(glm::dvec3 centre, double radius, int count) {
    std::vector<glm::dvec3> points;
    const double golden = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < count; ++i) {
        const double y = 1.0 - 2.0 * (i + 0.5) / count;
        const double r = std::sqrt(1.0 - y * y);
        points.push_back(centre + radius * glm::dvec3(r * std::cos(golden * i), y, r * std::sin(golden * i)));
    }
    return points;
}

const glm::vec3 box_min(-1.0f, 2.0f, -3.0f), box_max(3.0f, 4.0f, 1.0f);  // centre (1, 3, -1)
const glm::dvec3 box_centre(1.0, 3.0, -1.0);
const double box_radius = std::sqrt(16.0 + 4.0 + 16.0) / 2.0;  // half the diagonal: 3

}  // namespace

TEST_CASE("orbit camera: every field filled and consistent", "[camera]") {
    for (bool ortho : {false, true}) {
        hsr::CameraSettings s;
        s.orthographic = ortho;
        s.width = 640;
        s.height = 480;
        s.yaw_degrees = 30;
        s.pitch_degrees = 20;
        const hsr_camera c = hsr::make_orbit_camera(box_min, box_max, s);
        INFO("orthographic " << ortho);
        CHECK(c.struct_size == sizeof(hsr_camera));
        CHECK(c.width == 640);
        CHECK(c.height == 480);
        CHECK(c.projection_type == (ortho ? HSR_PROJECTION_ORTHOGRAPHIC : HSR_PROJECTION_PERSPECTIVE));
        const glm::dmat4 vp = matrix(c.projection) * matrix(c.view);
        for (int col = 0; col < 4; ++col)
            for (int row = 0; row < 4; ++row) CHECK(matrix(c.view_projection)[col][row] == Approx(vp[col][row]).margin(1e-5));
        // The eye is the origin of view space, and the view direction is view space's -z.
        const glm::dvec4 eye_in_view = matrix(c.view) * glm::dvec4(vec(c.eye), 1.0);
        CHECK(glm::length(glm::dvec3(eye_in_view)) < 1e-4);
        const glm::dvec3 dir = vec(c.view_direction);
        CHECK(glm::length(dir) == Approx(1.0));
        const glm::dvec3 dir_in_view = glm::dmat3(matrix(c.view)) * dir;
        CHECK(glm::length(dir_in_view - glm::dvec3(0, 0, -1)) < 1e-5);
        // The eye looks at the centre.
        CHECK(glm::length(glm::normalize(box_centre - vec(c.eye)) - dir) < 1e-5);
        // Near and far enclose the bounding sphere, tightly, with near > 0.
        const double distance = glm::length(box_centre - vec(c.eye));
        CHECK(c.near_plane > 0.0f);
        CHECK(c.near_plane < distance - box_radius);
        CHECK(c.far_plane > distance + box_radius);
        CHECK(c.near_plane > 0.9 * (distance - box_radius));
        CHECK(c.far_plane < 1.1 * (distance + box_radius));
    }
}

TEST_CASE("orbit camera: the default view looks at the front (+z) with +y up", "[camera]") {
    for (bool ortho : {false, true}) {
        INFO("orthographic " << ortho);
        hsr::CameraSettings s;
        s.orthographic = ortho;
        s.width = 200;
        s.height = 100;
        const hsr_camera c = hsr::make_orbit_camera(box_min, box_max, s);
        const Window centre = project(c, box_centre);
        CHECK(centre.x == Approx(100.0));
        CHECK(centre.y == Approx(50.0));
        CHECK(centre.depth > 0.0);
        CHECK(centre.depth < 1.0);
        CHECK(glm::length(vec(c.view_direction) - glm::dvec3(0, 0, -1)) < 1e-6);
        CHECK(c.eye[2] > box_max.z);
        // +x to the right, +y up (smaller row), +z nearer.
        CHECK(project(c, box_centre + glm::dvec3(1, 0, 0)).x > 101.0);
        CHECK(project(c, box_centre + glm::dvec3(0, 1, 0)).y < 49.0);
        CHECK(project(c, box_centre + glm::dvec3(0, 0, 1)).depth < centre.depth);
        CHECK(project(c, box_centre - glm::dvec3(0, 0, 1)).depth > centre.depth);
    }
}

TEST_CASE("orbit camera: yaw turns about the vertical, positive pitch looks from above", "[camera]") {
    hsr::CameraSettings s;
    s.yaw_degrees = 90;
    hsr_camera c = hsr::make_orbit_camera(box_min, box_max, s);
    // Eye on the +x side, looking toward -x; +z then appears on the left, +y still up.
    CHECK(glm::length(vec(c.view_direction) - glm::dvec3(-1, 0, 0)) < 1e-6);
    CHECK(project(c, box_centre + glm::dvec3(1, 0, 0)).depth < project(c, box_centre).depth);
    CHECK(project(c, box_centre + glm::dvec3(0, 0, 1)).x < 511.0);
    CHECK(project(c, box_centre + glm::dvec3(0, 1, 0)).y < 511.0);

    s.yaw_degrees = 0;
    s.pitch_degrees = 60;
    c = hsr::make_orbit_camera(box_min, box_max, s);
    CHECK(c.eye[1] > box_centre.y);
    CHECK(glm::length(vec(c.view_direction) - glm::dvec3(0, -std::sin(glm::radians(60.0)), -0.5)) < 1e-6);
    CHECK(project(c, box_centre + glm::dvec3(0, 1, 0)).depth < project(c, box_centre - glm::dvec3(0, 1, 0)).depth);
    // Looking down, the far side of the top (-z) appears higher in the image than the near side.
    CHECK(project(c, box_centre + glm::dvec3(0, 0, -1)).y < project(c, box_centre + glm::dvec3(0, 0, 1)).y);

    s.pitch_degrees = 90;  // straight down: still a valid camera, +y of the model points at the eye
    c = hsr::make_orbit_camera(box_min, box_max, s);
    CHECK(glm::length(vec(c.view_direction) - glm::dvec3(0, -1, 0)) < 1e-6);
    const Window w = project(c, box_centre);
    CHECK(w.x == Approx(512.0));
    CHECK(w.y == Approx(512.0));
}

TEST_CASE("orbit camera: the bounding sphere fits the image at zoom 1 for any direction and aspect", "[camera]") {
    const std::vector<glm::dvec3> outline = sphere_points(box_centre, box_radius, 2000);
    for (bool ortho : {false, true})
        for (auto [width, height] : {std::pair{1024u, 1024u}, std::pair{800u, 400u}, std::pair{300u, 600u}})
            for (float yaw : {0.0f, 37.0f, 90.0f, -120.0f, 400.0f})
                for (float pitch : {0.0f, 30.0f, -60.0f, 89.0f}) {
                    hsr::CameraSettings s;
                    s.orthographic = ortho;
                    s.width = width;
                    s.height = height;
                    s.yaw_degrees = yaw;
                    s.pitch_degrees = pitch;
                    const hsr_camera c = hsr::make_orbit_camera(box_min, box_max, s);
                    INFO("ortho " << ortho << " " << width << "x" << height << " yaw " << yaw << " pitch " << pitch);
                    double reach = 0;  // furthest a sphere point lands from the image centre
                    bool inside = true;
                    for (const glm::dvec3& p : outline) {
                        const Window w = project(c, p);
                        inside = inside && w.w > 0 && w.x >= 0 && w.x <= width && w.y >= 0 && w.y <= height &&
                                 w.depth >= 0 && w.depth <= 1;
                        reach = std::max(reach, std::hypot(w.x - width / 2.0, w.y - height / 2.0));
                    }
                    CHECK(inside);
                    // Fills the smaller side, but for the small margin.
                    CHECK(reach > 0.9 * std::min(width, height) / 2.0);
                    CHECK(reach < std::min(width, height) / 2.0);
                }
}

TEST_CASE("orbit camera: zoom 2 makes everything twice as large", "[camera]") {
    for (bool ortho : {false, true}) {
        hsr::CameraSettings s;
        s.orthographic = ortho;
        s.yaw_degrees = 20;
        const hsr_camera one = hsr::make_orbit_camera(box_min, box_max, s);
        s.zoom = 2;
        const hsr_camera two = hsr::make_orbit_camera(box_min, box_max, s);
        for (glm::dvec3 offset : {glm::dvec3(1, 0, 0), glm::dvec3(0, -0.7, 0.3), glm::dvec3(0.5, 0.5, -2)}) {
            const Window a = project(one, box_centre + offset), b = project(two, box_centre + offset);
            CHECK(b.x - 512.0 == Approx(2.0 * (a.x - 512.0)).margin(1e-3));
            CHECK(b.y - 512.0 == Approx(2.0 * (a.y - 512.0)).margin(1e-3));
        }
        // Zoomed far in, the near plane is still in front of the eye.
        s.zoom = 1000;
        const hsr_camera close = hsr::make_orbit_camera(box_min, box_max, s);
        CHECK(close.near_plane > 0.0f);
        CHECK(close.far_plane > close.near_plane);
    }
}

TEST_CASE("orbit camera: pixels are square whatever the aspect ratio", "[camera]") {
    // A small square facing the camera, centred on the model, must come out square in pixels.
    for (bool ortho : {false, true})
        for (auto [width, height] : {std::pair{800u, 400u}, std::pair{300u, 600u}}) {
            hsr::CameraSettings s;
            s.orthographic = ortho;
            s.width = width;
            s.height = height;
            const hsr_camera c = hsr::make_orbit_camera(box_min, box_max, s);
            const Window left = project(c, box_centre - glm::dvec3(0.5, 0, 0));
            const Window right = project(c, box_centre + glm::dvec3(0.5, 0, 0));
            const Window bottom = project(c, box_centre - glm::dvec3(0, 0.5, 0));
            const Window top = project(c, box_centre + glm::dvec3(0, 0.5, 0));
            CHECK(right.x - left.x == Approx(bottom.y - top.y));
            CHECK(left.x + right.x == Approx(double(width)));
            CHECK(top.y + bottom.y == Approx(double(height)));
        }
}

TEST_CASE("orbit camera: degenerate bounds and bad settings", "[camera]") {
    hsr::CameraSettings s;
    // A single point: still a usable camera looking at it.
    const hsr_camera point = hsr::make_orbit_camera(glm::vec3(2, 2, 2), glm::vec3(2, 2, 2), s);
    const Window w = project(point, {2, 2, 2});
    CHECK(w.x == Approx(512.0));
    CHECK(w.y == Approx(512.0));
    CHECK(w.depth > 0.0);
    CHECK(w.depth < 1.0);
    // A flat model (zero depth extent) still gets near < far around it.
    const hsr_camera flat = hsr::make_orbit_camera(glm::vec3(0, 0, 0), glm::vec3(10, 10, 0), s);
    CHECK(project(flat, {5, 5, 0}).depth > 0.0);
    CHECK(project(flat, {5, 5, 0}).depth < 1.0);

    using Catch::Contains;
    auto error = [](auto f) -> std::string {
        try {
            f();
        } catch (const hsr::Error& e) {
            return e.what();
        }
        return "no error";
    };
    hsr::CameraSettings bad = s;
    bad.width = 0;
    CHECK_THAT(error([&] { hsr::make_orbit_camera(box_min, box_max, bad); }), Contains("image size"));
    bad = s;
    bad.zoom = 0;
    CHECK_THAT(error([&] { hsr::make_orbit_camera(box_min, box_max, bad); }), Contains("zoom"));
    bad = s;
    bad.zoom = NAN;
    CHECK_THAT(error([&] { hsr::make_orbit_camera(box_min, box_max, bad); }), Contains("zoom"));
    bad = s;
    bad.fov_y_degrees = 180;
    CHECK_THAT(error([&] { hsr::make_orbit_camera(box_min, box_max, bad); }), Contains("field of view"));
    CHECK_THAT(error([&] { hsr::make_orbit_camera(box_max, box_min, s); }), Contains("bounds"));
    CHECK_THAT(error([&] { hsr::make_pixel_camera(0, 10, 0, 1); }), Contains("image size"));
    CHECK_THAT(error([&] { hsr::make_pixel_camera(10, 10, 2, 1); }), Contains("depth range"));
    // Bounds near the largest float: the eye and the matrices would overflow single precision.
    CHECK_THAT(error([&] { hsr::make_orbit_camera(glm::vec3(-3e38f), glm::vec3(3e38f), s); }), Contains("too large"));
    CHECK_THAT(error([&] { hsr::make_pixel_camera(10, 10, -3e38f, 3e38f); }), Contains("too large"));
}

TEST_CASE("orbit camera: a tiny model fills the view as a large one does", "[camera]") {
    // The box of the other tests scaled down: its corners land where the full-size box's do.
    hsr::CameraSettings s;
    s.yaw_degrees = 30;
    s.pitch_degrees = 20;
    const hsr_camera large = hsr::make_orbit_camera(box_min, box_max, s);
    for (double scale : {1e-6, 1e-12, 1e-18}) {
        INFO("scale " << scale);
        const hsr_camera tiny = hsr::make_orbit_camera(glm::vec3(glm::dvec3(box_min) * scale),
                                                       glm::vec3(glm::dvec3(box_max) * scale), s);
        for (int corner = 0; corner < 8; ++corner) {
            const glm::dvec3 p(corner & 1 ? box_max.x : box_min.x, corner & 2 ? box_max.y : box_min.y,
                               corner & 4 ? box_max.z : box_min.z);
            const Window a = project(large, p), b = project(tiny, p * scale);
            CHECK(b.x == Approx(a.x).margin(0.01));
            CHECK(b.y == Approx(a.y).margin(0.01));
        }
    }
}

TEST_CASE("look-at camera: a hand-worked projection", "[camera][look-at]") {
    // Eye on +z at distance 5 from the origin, 90 degrees of field of view, 100 x 100 pixels: the
    // plane through the origin spans x, y in [-5, 5], so (1, 0, 0) lands 1/5 of the half-width right
    // of the centre, (0, 1, 0) 1/5 above it.
    hsr::CameraSettings s;
    s.width = s.height = 100;
    s.fov_y_degrees = 90;
    s.look_at = hsr::LookAt{{0, 0, 5}, glm::vec3(0, 0, 0), {0, 1, 0}};
    const hsr_camera c = hsr::make_camera(glm::vec3(-1), glm::vec3(1), s);
    CHECK(project(c, {0, 0, 0}).x == Approx(50.0));
    CHECK(project(c, {0, 0, 0}).y == Approx(50.0));
    CHECK(project(c, {1, 0, 0}).x == Approx(60.0));
    CHECK(project(c, {0, 1, 0}).y == Approx(40.0));
    CHECK(project(c, {0, 0, 0}).w == Approx(5.0));  // clip w is the distance along the line of sight
    CHECK(project(c, {1, 0, 2.5}).x == Approx(70.0));  // half as far: twice as far from the centre
    CHECK(glm::length(vec(c.eye) - glm::dvec3(0, 0, 5)) < 1e-6);
    CHECK(glm::length(vec(c.view_direction) - glm::dvec3(0, 0, -1)) < 1e-6);
    // The near and far planes enclose the bounding sphere (radius sqrt 3) seen from the eye.
    CHECK(c.far_plane == Approx(5.0 + 1.02 * std::sqrt(3.0)));
    CHECK(c.near_plane == Approx(5.0 - 1.02 * std::sqrt(3.0)));
    // Zoom 2 halves the field of view's tangent.
    s.zoom = 2;
    CHECK(hsr::make_camera(glm::vec3(-1), glm::vec3(1), s).projection[0] == Approx(2.0f));
}

TEST_CASE("look-at camera: the textbook eye at (40, 40, 40) looking at the origin", "[camera][look-at]") {
    hsr::CameraSettings s;
    s.width = s.height = 64;
    s.look_at = hsr::LookAt{{40, 40, 40}, glm::vec3(0, 0, 0), {0, 1, 0}};
    const hsr_camera c = hsr::make_camera(glm::vec3(-1), glm::vec3(1), s);
    CHECK(glm::length(vec(c.view_direction) + glm::normalize(glm::dvec3(1, 1, 1))) < 1e-6);
    CHECK(project(c, {0, 0, 0}).x == Approx(32.0));
    CHECK(project(c, {0, 0, 0}).y == Approx(32.0));
    CHECK(project(c, {0, 0, 0}).w == Approx(40.0 * std::sqrt(3.0)));
    // +y stays up on screen; the corner (1, 1, 1) is nearest, (-1, -1, -1) farthest, both on the centre.
    CHECK(project(c, {0, 1, 0}).y < 32.0);
    CHECK(project(c, {1, 1, 1}).x == Approx(32.0));
    CHECK(project(c, {1, 1, 1}).depth < project(c, {0, 0, 0}).depth);
    CHECK(project(c, {-1, -1, -1}).depth > project(c, {0, 0, 0}).depth);
    // Without a target it looks at the centre of the bounds.
    s.look_at->target.reset();
    const hsr_camera centred = hsr::make_camera(glm::vec3(1, 1, 1), glm::vec3(3, 3, 3), s);
    CHECK(project(centred, {2, 2, 2}).x == Approx(32.0));
    CHECK(project(centred, {2, 2, 2}).y == Approx(32.0));
}

TEST_CASE("look-at camera: from the orbit camera's eye it is the orbit camera", "[camera][look-at]") {
    for (bool ortho : {false, true}) {
        for (float yaw : {0.0f, 40.0f, -130.0f}) {
            INFO("orthographic " << ortho << ", yaw " << yaw);
            hsr::CameraSettings s;
            s.orthographic = ortho;
            s.width = 200;
            s.height = 120;
            s.yaw_degrees = yaw;
            s.pitch_degrees = 25;
            s.zoom = 1.5f;
            const hsr_camera orbit = hsr::make_orbit_camera(box_min, box_max, s);
            s.look_at = hsr::LookAt{{orbit.eye[0], orbit.eye[1], orbit.eye[2]}, std::nullopt, {0, 1, 0}};
            const hsr_camera look = hsr::make_camera(box_min, box_max, s);
            for (int k = 0; k < 16; ++k) {
                CHECK(look.view[k] == Approx(orbit.view[k]).margin(1e-5));
                CHECK(look.projection[k] == Approx(orbit.projection[k]).margin(1e-5));
            }
            CHECK(look.near_plane == Approx(orbit.near_plane));
            CHECK(look.far_plane == Approx(orbit.far_plane));
            CHECK(look.projection_type == orbit.projection_type);
        }
    }
}

TEST_CASE("look-at camera: an eye on the target, an up along the line of sight, numbers too large",
          "[camera][look-at]") {
    hsr::CameraSettings s;
    s.look_at = hsr::LookAt{{0, 0, 0}, glm::vec3(0, 0, 0), {0, 1, 0}};
    CHECK_THROWS_WITH(hsr::make_camera(box_min, box_max, s), "look-at camera: the eye and the target are the same point");
    s.look_at = hsr::LookAt{{0, 5, 0}, glm::vec3(0, 0, 0), {0, 1, 0}};
    CHECK_THROWS_WITH(hsr::make_camera(box_min, box_max, s),
                      "look-at camera: the up vector (0, 1, 0) is zero or along the line of sight");
    s.look_at->up = {0, 0, 0};
    CHECK_THROWS_WITH(hsr::make_camera(box_min, box_max, s), Catch::Contains("is zero or along the line of sight"));
    s.look_at->up = {0, 0, 1};
    CHECK_NOTHROW(hsr::make_camera(box_min, box_max, s));  // looking straight down, +z up on screen
    s.look_at->eye = {1e30f, 0, 0};
    CHECK_THROWS_WITH(hsr::make_camera(box_min, box_max, s),
                      Catch::StartsWith("look-at camera: the eye is too far from the scene for single precision"));
    s.look_at->eye = {NAN, 0, 0};
    CHECK_THROWS_WITH(hsr::make_camera(box_min, box_max, s),
                      "look-at camera: the eye, target and up must be finite numbers");
}

TEST_CASE("pixel camera: (x, y, z) lands on window (x, H - y), larger z nearer", "[camera][pixel]") {
    const hsr_camera c = hsr::make_pixel_camera(64, 48, -20.0f, 28.0f);
    CHECK(c.struct_size == sizeof(hsr_camera));
    CHECK(c.width == 64);
    CHECK(c.height == 48);
    CHECK(c.projection_type == HSR_PROJECTION_ORTHOGRAPHIC);
    CHECK(glm::length(vec(c.view_direction) - glm::dvec3(0, 0, -1)) < 1e-7);
    CHECK(c.near_plane > 0.0f);
    CHECK(c.far_plane > c.near_plane);

    const Window a = project(c, {10.5, 20.5, 3});
    CHECK(a.x == Approx(10.5).margin(1e-4));
    CHECK(a.y == Approx(48 - 20.5).margin(1e-4));
    // So the pixel is column 10, row 48 - 1 - 20 = 27 from the top.
    CHECK(std::floor(a.x) == 10);
    CHECK(std::floor(a.y) == 27);
    const Window corner = project(c, {0, 0, 0});
    CHECK(corner.x == Approx(0.0).margin(1e-4));
    CHECK(corner.y == Approx(48.0).margin(1e-4));
    const Window far_corner = project(c, {64, 48, 0});
    CHECK(far_corner.x == Approx(64.0).margin(1e-4));
    CHECK(far_corner.y == Approx(0.0).margin(1e-4));

    // Depth: nearer (larger z) is smaller, both ends of the range strictly inside, linear in z.
    const double d_near = project(c, {5, 5, 28}).depth, d_far = project(c, {5, 5, -20}).depth;
    const double d_mid = project(c, {5, 5, 4}).depth;
    CHECK(d_near > 0.0);
    CHECK(d_far < 1.0);
    CHECK(d_near < d_mid);
    CHECK(d_mid < d_far);
    CHECK(d_mid == Approx((d_near + d_far) / 2).margin(1e-6));
    CHECK(project(c, {5, 5, 0}).depth == Approx(project(c, {60, 40, 0}).depth).margin(1e-7));

    // A flat scene (z_min == z_max) is fine too.
    const hsr_camera flat = hsr::make_pixel_camera(10, 10, 0.0f, 0.0f);
    const double d = project(flat, {5, 5, 0}).depth;
    CHECK(d > 0.0);
    CHECK(d < 1.0);
}

TEST_CASE("lights: camera space follows the camera, world space stays", "[camera][lights]") {
    hsr::CameraSettings s;
    s.yaw_degrees = 90;  // eye on +x looking toward -x; camera right is world -z, camera up is +y
    const hsr_camera c = hsr::make_orbit_camera(box_min, box_max, s);

    const hsr_light toward_viewer = hsr::resolve_light(hsr::parse_light_spec("dir:0,0,1"), c);
    CHECK(toward_viewer.type == HSR_LIGHT_DIRECTIONAL);
    CHECK(glm::length(glm::dvec3(vec(toward_viewer.vector)) - glm::dvec3(1, 0, 0)) < 1e-5);
    const hsr_light right = hsr::resolve_light(hsr::parse_light_spec("dir:1,0,0"), c);
    CHECK(glm::length(vec(right.vector) - glm::dvec3(0, 0, -1)) < 1e-5);

    const hsr_light at_eye = hsr::resolve_light(hsr::parse_light_spec("point:0,0,0,intensity=0.5,color=1/0/0"), c);
    CHECK(at_eye.type == HSR_LIGHT_POINT);
    CHECK(glm::length(vec(at_eye.vector) - vec(c.eye)) < 1e-4);
    CHECK(at_eye.intensity == 0.5f);
    CHECK(glm::dvec3(vec(at_eye.color)) == glm::dvec3(1, 0, 0));
    const hsr_light above_eye = hsr::resolve_light(hsr::parse_light_spec("point:0,2,0"), c);
    CHECK(glm::length(vec(above_eye.vector) - (vec(c.eye) + glm::dvec3(0, 2, 0))) < 1e-4);

    const hsr_light world = hsr::resolve_light(hsr::parse_light_spec("point:1,2,3,space=world"), c);
    CHECK(glm::dvec3(vec(world.vector)) == glm::dvec3(1, 2, 3));

    // The pixel camera's camera space is world space moved to the eye: directions are unchanged.
    const hsr_camera pixel = hsr::make_pixel_camera(32, 32, 0, 1);
    const hsr_light dir = hsr::resolve_light(hsr::parse_light_spec("dir:0,1,1"), pixel);
    CHECK(glm::length(vec(dir.vector) - glm::normalize(glm::dvec3(0, 1, 1))) < 1e-6);
}
