// Penetration lines (see penetration.hpp).
#include "penetration.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace roberts {
namespace {

// Planes whose normals make an angle below about 1e-6 radians are taken as parallel: they meet in
// no line that could be found accurately (two parallel faces touch or do not meet at all).
constexpr double kParallelSine2 = 1e-12;

// Cuts the line x(s) = origin + s·direction, s in [s_low, s_high], to the side of `plane` where
// the value is >= 0. False when nothing is left, or when the line stays within `tolerance` of the
// plane along its whole length (it lies in the plane: surfaces that touch, not penetrate).
bool cut(const glm::dvec4& plane, glm::dvec3 origin, glm::dvec3 direction, double tolerance, double& s_low,
         double& s_high) {
    const double at_low = glm::dot(plane, glm::dvec4(origin + s_low * direction, 1.0));
    const double at_high = glm::dot(plane, glm::dvec4(origin + s_high * direction, 1.0));
    if (std::max(at_low, at_high) <= tolerance) return false;
    if (at_low < 0 || at_high < 0) {
        const double zero = s_low + (s_high - s_low) * at_low / (at_low - at_high);
        if (at_low < 0)
            s_low = zero;
        else
            s_high = zero;
    }
    return s_low < s_high;
}

}  // namespace

void find_penetration_lines(const BodySet& set, std::vector<PenetrationLine>& lines, PenetrationStats& stats) {
    lines.clear();
    const uint32_t body_count = uint32_t(set.bodies.size());
    for (uint32_t a = 0; a < body_count; ++a) {
        const Body& A = set.bodies[a];
        for (uint32_t b = a + 1; b < body_count; ++b) {
            const Body& B = set.bodies[b];
            const double tolerance = std::max(A.tolerance, B.tolerance);
            const glm::dvec3 low = glm::max(A.box_min, B.box_min) - tolerance;
            const glm::dvec3 high = glm::min(A.box_max, B.box_max) + tolerance;
            if (glm::any(glm::greaterThan(low, high))) continue;
            ++stats.body_pairs_overlapping;
            const glm::dvec3 centre = 0.5 * (low + high);
            for (uint32_t i = A.first_plane; i < A.first_plane + A.plane_count; ++i) {
                const glm::dvec4& Vi = set.planes[i];
                const glm::dvec3 ni(Vi);
                for (uint32_t j = B.first_plane; j < B.first_plane + B.plane_count; ++j) {
                    ++stats.plane_pairs_tested;
                    const glm::dvec4& Vj = set.planes[j];
                    const glm::dvec3 nj(Vj);
                    const glm::dvec3 along = glm::cross(ni, nj);
                    const double sine2 = glm::dot(along, along);
                    if (sine2 < kParallelSine2) continue;
                    // The point of both planes (n·x = -d) nearest the overlap box's centre.
                    glm::dvec3 origin = (-Vi.w * glm::cross(nj, along) - Vj.w * glm::cross(along, ni)) / sine2;
                    const glm::dvec3 direction = along / std::sqrt(sine2);
                    origin += glm::dot(centre - origin, direction) * direction;
                    // Inside the overlap of the two bounding boxes (slabs), then inside both faces.
                    double s_low = -std::numeric_limits<double>::infinity();
                    double s_high = std::numeric_limits<double>::infinity();
                    bool inside = true;
                    for (int axis = 0; axis < 3 && inside; ++axis) {
                        if (std::abs(direction[axis]) < 1e-12) {
                            inside = origin[axis] >= low[axis] && origin[axis] <= high[axis];
                            continue;
                        }
                        const double s0 = (low[axis] - origin[axis]) / direction[axis];
                        const double s1 = (high[axis] - origin[axis]) / direction[axis];
                        s_low = std::max(s_low, std::min(s0, s1));
                        s_high = std::min(s_high, std::max(s0, s1));
                        inside = s_low < s_high;
                    }
                    for (uint32_t k = A.first_plane; k < A.first_plane + A.plane_count && inside; ++k)
                        if (k != i) inside = cut(set.planes[k], origin, direction, A.shrink * 10, s_low, s_high);
                    for (uint32_t k = B.first_plane; k < B.first_plane + B.plane_count && inside; ++k)
                        if (k != j) inside = cut(set.planes[k], origin, direction, B.shrink * 10, s_low, s_high);
                    if (!inside || s_high - s_low <= tolerance) continue;
                    lines.push_back({origin + s_low * direction, origin + s_high * direction, a, b, i, j});
                }
            }
        }
    }
}

}  // namespace roberts
