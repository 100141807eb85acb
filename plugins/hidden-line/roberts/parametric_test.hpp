// Roberts' parametric visibility test of a line against one convex body (Rogers, "Procedural
// Elements for Computer Graphics", 2nd ed., section 4.3).
//
// The line is P(t) = S + t·D (homogeneous: S = (x, y, z, 1), D = (dx, dy, dz, 0)); the eye is E,
// (eye, 1) for a perspective eye point or (toward the viewer, 0) for an eye at infinity. The points
// h(t, a) = S + t·D + a·E, a >= 0, run from P(t) toward the eye (in homogeneous coordinates the line
// through P(t) and E, on the side of E). Against column j of the body matrix,
//
//     h_j(t, a) = h(t, a) · V_j = p_j + t·q_j + a·w_j,   p_j = S·V_j,  q_j = D·V_j,  w_j = E·V_j,
//
// and h(t, a) lies inside the body exactly when h_j > 0 for every j (the homogeneous weight 1 + a·E_w
// is positive, so it does not change signs). P(t) is hidden when some a >= 0 puts h inside. The
// region {(t, a) : every h_j > 0, a >= 0, t in range} is a convex polygon, so the hidden values of t
// form one interval: its projection on the t axis. It is found by eliminating a (Fourier–Motzkin):
//
//   - w_j > 0 (the eye is on the inner side of plane j: a back face) bounds a from below,
//     a > -(p_j + t·q_j) / w_j; a >= 0 is one more lower bound;
//   - w_k < 0 (a front face) bounds a from above, a < (p_k + t·q_k) / -w_k;
//   - w_j = 0 (a face seen edge-on) does not involve a: p_j + t·q_j > 0.
//
// Some a exists exactly when every lower bound is below every upper bound. Each pair (j, k) gives,
// multiplied out by w_j·(-w_k) > 0, one linear condition on t alone:
//
//     (p_k·w_j - p_j·w_k) + t·(q_k·w_j - q_j·w_k) > 0,      and with a >= 0:  p_k + t·q_k > 0,
//
// and each condition r + s·t > 0 cuts the interval at t = -r/s from below (s > 0) or above (s < 0).
//
// The planes may come in moved inward by `shrink` (p_j reduced by shrink, w_j by shrink·E_w): the
// same test then asks whether the line of sight passes through the body shrunk by that much, that
// is, more than `shrink` deep inside it. roberts.cpp uses that only to decide whether a hidden
// interval is real (a line on or touching the surface is not hidden by it); the interval itself is
// always computed with the true planes (shrink = 0), so its end points are the exact silhouette
// crossings.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace roberts {

struct Interval {
    double t0 = 0, t1 = 0;
    bool empty() const { return !(t0 < t1); }
};

// One body's planes for one camera, sorted into front faces (w < 0), faces seen edge-on (w = 0) and
// back faces (w > 0): `order` lists plane indices in that order.
struct BodyPlanes {
    const glm::dvec4* planes;  // all planes of the scene, indexed by `order`
    const uint32_t* order;
    uint32_t front_count, edge_on_count, back_count;
    const double* eye_weight;  // w_j of the planes as moved by `shrink`, indexed like `planes`
    double shrink;             // how far the planes are moved inward (0: the true body)
};

class ParametricTest {
public:
    // Room for a body of up to this many planes (call once per frame, not per test).
    void reserve(size_t plane_count) {
        if (back_p_.size() < plane_count) {
            back_p_.resize(plane_count);
            back_q_.resize(plane_count);
        }
    }

    // The open interval of t in (t_begin, t_end) where P(t) = start + t·direction is hidden by the
    // body; empty when nothing is.
    Interval hidden(const BodyPlanes& body, glm::dvec3 start, glm::dvec3 direction, double t_begin,
                    double t_end) {
        double low = t_begin, high = t_end;
        // r + s·t > 0, intersected into (low, high); false once nothing is left.
        const auto keep = [&](double r, double s) {
            if (s > 0)
                low = std::max(low, -r / s);
            else if (s < 0)
                high = std::min(high, -r / s);
            else if (!(r > 0))
                return false;
            return low < high;
        };
        const glm::dvec4 S(start, 1.0), D(direction, 0.0);
        const uint32_t* order = body.order;
        const uint32_t back_begin = body.front_count + body.edge_on_count;
        for (uint32_t k = body.front_count; k < back_begin; ++k) {
            const glm::dvec4& V = body.planes[order[k]];
            if (!keep(glm::dot(S, V) - body.shrink, glm::dot(D, V))) return {};
        }
        for (uint32_t k = 0; k < body.back_count; ++k) {
            const glm::dvec4& V = body.planes[order[back_begin + k]];
            back_p_[k] = glm::dot(S, V) - body.shrink;
            back_q_[k] = glm::dot(D, V);
        }
        for (uint32_t k = 0; k < body.front_count; ++k) {
            const uint32_t plane = order[k];
            const glm::dvec4& V = body.planes[plane];
            const double p_k = glm::dot(S, V) - body.shrink, q_k = glm::dot(D, V), w_k = body.eye_weight[plane];
            if (!keep(p_k, q_k)) return {};  // with a >= 0
            for (uint32_t j = 0; j < body.back_count; ++j) {
                const double w_j = body.eye_weight[order[back_begin + j]];
                if (!keep(p_k * w_j - back_p_[j] * w_k, q_k * w_j - back_q_[j] * w_k)) return {};
            }
        }
        return {low, high};
    }

    // The front face through which the line of sight from P(t) leaves the body toward the eye (the
    // smallest upper bound on a); kNoPlane-like UINT32_MAX when the body has no front face.
    static uint32_t exit_plane(const BodyPlanes& body, glm::dvec3 start, glm::dvec3 direction, double t) {
        const glm::dvec4 P(start + t * direction, 1.0);
        uint32_t best = UINT32_MAX;
        double best_a = 0;
        for (uint32_t k = 0; k < body.front_count; ++k) {
            const uint32_t plane = body.order[k];
            const double a = (glm::dot(P, body.planes[plane]) - body.shrink) / -body.eye_weight[plane];
            if (best == UINT32_MAX || a < best_a) {
                best = plane;
                best_a = a;
            }
        }
        return best;
    }

private:
    std::vector<double> back_p_, back_q_;
};

}  // namespace roberts
