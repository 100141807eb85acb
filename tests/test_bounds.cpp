// hsr/bounds.hpp: the projection of an axis-aligned box, checked against cases worked by hand on a
// 100 x 100 image with a perspective projection (near 1, far 3, no field-of-view scaling) and an
// orthographic one (the same depth range).
#include "hsr/bounds.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

namespace raster = hsr::raster;

namespace {

// Eye at the origin looking down -z: clip = (x, y, -2z - 3, -z), so z = -1 is the near plane
// (z_ndc = -1) and z = -3 the far plane (z_ndc = 1).
glm::dmat4 perspective() {
    glm::dmat4 m(1.0);
    m[2][2] = -2.0;
    m[3][2] = -3.0;
    m[2][3] = -1.0;
    m[3][3] = 0.0;
    return m;
}

// clip = (x, y, -z - 2, 1): the same depth range without perspective.
glm::dmat4 orthographic() {
    glm::dmat4 m(1.0);
    m[2][2] = -1.0;
    m[3][2] = -2.0;
    return m;
}

const raster::Viewport kViewport(100, 100);  // window x = (x/w + 1) * 50, y = (1 - y/w) * 50

}  // namespace

TEST_CASE("project_box: a box wholly in front of the near plane") {
    // x in [-1, 1], y in [-1, 0.5], z in [-2, -1.5] (w = 2 or 1.5). x/w reaches -+2/3 at w = 1.5;
    // y/w ranges over -1/1.5 .. 0.5/1.5; depth (z_ndc + 1) / 2 is 0.5 at z = -1.5, 0.75 at z = -2.
    const raster::ProjectedBox box = raster::project_box(perspective(), {-1.0, -1.0, -2.0}, {1.0, 0.5, -1.5}, kViewport);
    CHECK(box.outside == 0);
    REQUIRE(box.in_front);
    CHECK(box.min_x == Approx(50.0 / 3.0));
    CHECK(box.max_x == Approx(250.0 / 3.0));
    CHECK(box.min_y == Approx(100.0 / 3.0));
    CHECK(box.max_y == Approx(250.0 / 3.0));
    CHECK(box.nearest == Approx(0.5));
    // Pixel centres px + 0.5 in [16.67, 83.33] x [33.33, 83.33].
    const raster::PixelRect r = box.pixel_centres(0.0, 100, 100);
    CHECK(r.x0 == 17);
    CHECK(r.x1 == 82);
    CHECK(r.y0 == 33);
    CHECK(r.y1 == 82);
    // A margin of a pixel takes in one more centre on each side; the image clips.
    const raster::PixelRect wide = box.pixel_centres(1.0, 100, 100);
    CHECK(wide.x0 == 16);
    CHECK(wide.x1 == 83);
    CHECK(box.pixel_centres(0.0, 60, 50).x1 == 59);
    CHECK(box.pixel_centres(0.0, 60, 50).y1 == 49);
}

TEST_CASE("project_box: a box straddling the near plane") {
    // z in [-2, -0.5]: the corners at z = -0.5 (z_ndc = (1 - 3) / 0.5 = -4) are on the eye's side of
    // the near plane, those at z = -2 inside the frustum: in view, but with no rectangle.
    const raster::ProjectedBox box =
        raster::project_box(perspective(), {-0.25, -0.25, -2.0}, {0.25, 0.25, -0.5}, kViewport);
    CHECK(box.outside == 0);
    CHECK_FALSE(box.in_front);

    // Moved back to z in [-2, -1] (the near plane itself counts as beyond it): x/w reaches -+0.25
    // at w = 1, so x 37.5..62.5, and the nearest depth is 0.
    const raster::ProjectedBox touching =
        raster::project_box(perspective(), {-0.25, -0.25, -2.0}, {0.25, 0.25, -1.0}, kViewport);
    REQUIRE(touching.in_front);
    CHECK(touching.min_x == Approx(37.5));
    CHECK(touching.max_x == Approx(62.5));
    CHECK(touching.nearest == Approx(0.0).margin(1e-12));
}

TEST_CASE("project_box: a box behind the eye, and one through the eye plane") {
    // z in [1, 2]: w = -z < 0 at every corner, and clip z = -2z - 3 < -w = z: all beyond the near
    // plane (and, with w < 0, on the far side of the four side planes too).
    const raster::ProjectedBox behind = raster::project_box(perspective(), {-0.25, -0.25, 1.0}, {0.25, 0.25, 2.0}, kViewport);
    CHECK_FALSE(behind.in_front);
    CHECK((behind.outside & raster::kOutsideNear) != 0);
    CHECK((behind.outside & raster::kOutsideFar) == 0);

    // z in [-1, 1]: corners on both sides of w = 0; the near ones are inside the frustum, so
    // nothing is shared, and the projection bounds nothing.
    const raster::ProjectedBox through = raster::project_box(perspective(), {-0.25, -0.25, -1.0}, {0.25, 0.25, 1.0}, kViewport);
    CHECK_FALSE(through.in_front);
    CHECK(through.outside == 0);

    // Corners a hair in front of w = 0 (w = 1e-9 against x = 1) are far on the eye's side of the near plane.
    const raster::ProjectedBox grazing = raster::project_box(perspective(), {-1.0, -1.0, -1.0}, {1.0, 1.0, -1e-9}, kViewport);
    CHECK_FALSE(grazing.in_front);

    // A corner so far out that its window coordinates overflow: nothing to bound with.
    const raster::ProjectedBox huge = raster::project_box(perspective(), {-1e308, 0.0, -2.0}, {1e308, 0.5, -1.5}, kViewport);
    CHECK_FALSE(huge.in_front);
}

TEST_CASE("project_box: orthographic") {
    // w = 1: x 25..75, y 25..75; depth (-z - 2 + 1) / 2 is 0.25 at z = -1.5, 0.75 at z = -2.5.
    const raster::ProjectedBox box =
        raster::project_box(orthographic(), {-0.5, -0.5, -2.5}, {0.5, 0.5, -1.5}, kViewport);
    CHECK(box.outside == 0);
    REQUIRE(box.in_front);
    CHECK(box.min_x == Approx(25.0));
    CHECK(box.max_x == Approx(75.0));
    CHECK(box.min_y == Approx(25.0));
    CHECK(box.max_y == Approx(75.0));
    CHECK(box.nearest == Approx(0.25));
    const raster::PixelRect r = box.pixel_centres(0.0, 100, 100);
    CHECK(r.x0 == 25);  // centre 25.5 is the first at or right of 25
    CHECK(r.x1 == 74);  // centre 74.5 the last at or left of 75

    // Behind the camera there is no eye plane, only the near plane: z in [1, 2] gives z_ndc -3 .. -4.
    const raster::ProjectedBox behind = raster::project_box(orthographic(), {-0.5, -0.5, 1.0}, {0.5, 0.5, 2.0}, kViewport);
    CHECK_FALSE(behind.in_front);
    CHECK(behind.outside == raster::kOutsideNear);

    // Left of the view volume (x < -w at every corner), and beyond the far plane.
    CHECK(raster::project_box(orthographic(), {-3.0, 0.0, -2.0}, {-2.0, 0.5, -1.5}, kViewport).outside ==
          raster::kOutsideLeft);
    CHECK(raster::project_box(orthographic(), {0.0, 0.0, -5.0}, {0.5, 0.5, -4.0}, kViewport).outside ==
          raster::kOutsideFar);
}

TEST_CASE("project_box: an empty box bounds nothing") {
    const raster::ProjectedBox box = raster::project_box(perspective(), {1.0, 0.0, -2.0}, {0.0, 1.0, -1.5}, kViewport);
    CHECK_FALSE(box.in_front);
    const raster::PixelRect none = raster::ProjectedBox{}.pixel_centres(0.0, 100, 100);
    CHECK(none.empty());  // the default box is the point (0, 0): no pixel centre lies on it
}
