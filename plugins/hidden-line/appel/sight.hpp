// The geometric questions Appel's algorithm asks, all "seen from the eye": on which side of the
// plane through the eye and a line does a point lie (sight planes), and on which side of a face's
// plane (face planes). Double precision from the scene's float positions.
//
// Exact ties are broken as if the eye had moved by an infinitesimal amount along one fixed
// direction (simulation of simplicity, Edelsbrunner & Muecke 1990): a point exactly on a sight
// plane, such as a vertex whose image lies exactly on a contour edge, is consistently put on one
// side, so that the two edges meeting there see the same thing and no change of QI is counted
// twice or lost. Planes through the same two vertices are always built from the vertices in the
// same order (lower index first), so every use of one plane gives bit-identical answers.
#pragma once

#include "hsr/abi.h"
#include "hsr/sdk.hpp"

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>

namespace appel {

inline int sign_of(double v) { return (v > 0.0) - (v < 0.0); }

// The direction of the infinitesimal eye motion; irrational-looking so that no normal made from small
// integer coordinates is perpendicular to it.
inline constexpr glm::dvec3 kTieDirection{0.5773502691896258, 0.3141592653589793, 0.7548776662466927};

class Viewer {
public:
    explicit Viewer(const hsr_camera& camera)
        : perspective_(camera.projection_type == HSR_PROJECTION_PERSPECTIVE),
          eye_(camera.eye[0], camera.eye[1], camera.eye[2]),
          view_direction_(glm::normalize(
              glm::dvec3(camera.view_direction[0], camera.view_direction[1], camera.view_direction[2]))) {}

    bool perspective() const { return perspective_; }
    const glm::dvec3& eye() const { return eye_; }
    glm::dvec3 toward_viewer() const { return -view_direction_; }
    // Larger is farther; compares points on one line of sight.
    double distance(const glm::dvec3& p) const {
        return perspective_ ? glm::length(p - eye_) : glm::dot(p - eye_, view_direction_);
    }

private:
    bool perspective_;
    glm::dvec3 eye_;
    glm::dvec3 view_direction_;
};

// The plane through the eye and the line through two vertices (orthographic: through the line,
// parallel to the viewing direction). value(r) is the orientation determinant |p-E, q-E, r-E| for
// the vertices in the order they were given.
struct SightPlane {
    glm::dvec3 normal{0.0};
    glm::dvec3 origin{0.0};
    glm::dvec3 tie_axis{0.0};    // q - p, lower vertex index first
    glm::dvec3 tie_origin{0.0};  // p
    double orientation = 1.0;    // -1 when the vertices were given higher index first

    double value(const glm::dvec3& r) const { return orientation * glm::dot(normal, r - origin); }
    // The derivative of value(r) when the eye moves along kTieDirection.
    double tie_value(const glm::dvec3& r) const {
        return -orientation * glm::dot(kTieDirection, glm::cross(tie_axis, r - tie_origin));
    }
    // +1 or -1; 0 only when r lies on the line itself.
    int side(const glm::dvec3& r) const {
        const double v = value(r);
        return v != 0.0 ? sign_of(v) : sign_of(tie_value(r));
    }
    // Where the segment from p to q (on opposite sides) crosses this plane, as a parameter in [0, 1].
    double crossing(const glm::dvec3& p, const glm::dvec3& q) const {
        double vp = value(p), vq = value(q);
        if (vp == 0.0 && vq == 0.0) {
            vp = tie_value(p);
            vq = tie_value(q);
        }
        const double d = vp - vq;
        if (d == 0.0) return 0.5;
        const double t = vp / d;
        return t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    }
};

inline SightPlane sight_plane(const Viewer& viewer, uint32_t i, const glm::dvec3& pi, uint32_t j,
                              const glm::dvec3& pj) {
    const bool in_order = i < j;
    const glm::dvec3& lo = in_order ? pi : pj;
    const glm::dvec3& hi = in_order ? pj : pi;
    SightPlane s;
    if (viewer.perspective()) {
        s.normal = glm::cross(lo - viewer.eye(), hi - viewer.eye());
        s.origin = viewer.eye();
    } else {
        s.normal = glm::cross(hi - lo, viewer.toward_viewer());
        s.origin = lo;
    }
    s.tie_axis = hi - lo;
    s.tie_origin = lo;
    s.orientation = in_order ? 1.0 : -1.0;
    return s;
}

// The plane of a triangle, and which side of it the eye is on (+1: the side the normal points to;
// 0: a triangle without area, which hides nothing).
struct FacePlane {
    glm::dvec3 normal{0.0};  // (c1 - c0) x (c2 - c0)
    glm::dvec3 corner{0.0};  // c0
    int eye_side = 0;

    // Strictly on the far side from the eye.
    bool hides(const glm::dvec3& r) const {
        return eye_side != 0 && sign_of(glm::dot(normal, r - corner)) == -eye_side;
    }
};

inline FacePlane face_plane(const Viewer& viewer, const glm::dvec3& c0, const glm::dvec3& c1, const glm::dvec3& c2) {
    FacePlane f;
    f.normal = glm::cross(c1 - c0, c2 - c0);
    f.corner = c0;
    const double toward_eye = viewer.perspective() ? glm::dot(f.normal, viewer.eye() - c0)
                                                   : glm::dot(f.normal, viewer.toward_viewer());
    f.eye_side = toward_eye != 0.0 ? sign_of(toward_eye) : sign_of(glm::dot(f.normal, kTieDirection));
    return f;
}

}  // namespace appel
