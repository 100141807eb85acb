// The ray tests of the raycast plugin, in float or double (Real): the watertight ray/triangle test
// of Woop, Benthin & Wald, "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013, and a slab test
// against a node's box made conservative after Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013.
//
// The watertight test shears and scales the scene so that the ray runs along +z from the origin;
// the 2D edge functions U, V, W of the triangle's projected corners then decide the hit. Two
// triangles sharing an edge compute that edge's function from the same two corners, the same way,
// to the same value with opposite signs, so no ray passes between them; a ray exactly through the
// edge hits both. In float, an edge function that comes out exactly 0 is computed again in double
// (the paper's fallback), so the sign is the true one.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace raycast {

// A ray origin + t * direction, prepared for the tests.
template <class Real>
struct Ray {
    Real origin[3];
    Real direction[3];
    Real inverse[3];  // 1 / direction (infinite along an axis it does not move on)
    int kx, ky, kz;   // the axis the ray runs most along is kz; kx, ky span the plane across it
    Real sx, sy, sz;  // the shear and scale that take the ray to +z

    void prepare(const double o[3], const double d[3]) {
        for (int a = 0; a < 3; ++a) {
            origin[a] = Real(o[a]);
            direction[a] = Real(d[a]);
            inverse[a] = Real(1) / direction[a];
        }
        kz = 0;
        for (int a = 1; a < 3; ++a)
            if (std::abs(direction[a]) > std::abs(direction[kz])) kz = a;
        kx = kz == 2 ? 0 : kz + 1;
        ky = kx == 2 ? 0 : kx + 1;
        if (direction[kz] < Real(0)) std::swap(kx, ky);  // keeps the corners' winding
        sx = direction[kx] / direction[kz];
        sy = direction[ky] / direction[kz];
        sz = Real(1) / direction[kz];
    }
};

// A hit of a triangle: the ray parameter t and the barycentric weights of corners 1 and 2.
struct TriangleHit {
    double t, b1, b2;
    bool front;  // the corners are counter-clockwise seen from the ray's origin
};

// What the test found: a miss, a hit (edges included), or a near miss: the ray passes outside the
// triangle but within kNearMiss of a barycentric unit from it, where the rasterizers' grid-snapped
// corners may still put the pixel centre inside (TriangleHit then holds the point on the
// triangle's plane, its barycentrics a little outside [0, 1]).
enum class Meets { kMiss, kHit, kNearMiss };
inline constexpr double kNearMiss = 1.0 / 16.0;

template <class Real>
inline Meets intersect(const Ray<Real>& ray, const float* p0, const float* p1, const float* p2, TriangleHit& hit) {
    const Real a[3] = {Real(p0[0]) - ray.origin[0], Real(p0[1]) - ray.origin[1], Real(p0[2]) - ray.origin[2]};
    const Real b[3] = {Real(p1[0]) - ray.origin[0], Real(p1[1]) - ray.origin[1], Real(p1[2]) - ray.origin[2]};
    const Real c[3] = {Real(p2[0]) - ray.origin[0], Real(p2[1]) - ray.origin[1], Real(p2[2]) - ray.origin[2]};
    const int kx = ray.kx, ky = ray.ky, kz = ray.kz;
    const Real ax = a[kx] - ray.sx * a[kz], ay = a[ky] - ray.sy * a[kz];
    const Real bx = b[kx] - ray.sx * b[kz], by = b[ky] - ray.sy * b[kz];
    const Real cx = c[kx] - ray.sx * c[kz], cy = c[ky] - ray.sy * c[kz];
    Real u = cx * by - cy * bx;
    Real v = ax * cy - ay * cx;
    Real w = bx * ay - by * ax;
    if constexpr (sizeof(Real) < sizeof(double)) {
        if (u == Real(0) || v == Real(0) || w == Real(0)) {
            u = Real(double(cx) * double(by) - double(cy) * double(bx));
            v = Real(double(ax) * double(cy) - double(ay) * double(cx));
            w = Real(double(bx) * double(ay) - double(by) * double(ax));
        }
    }
    const Real det = u + v + w;
    if (det == Real(0)) return Meets::kMiss;  // edge-on, or a degenerate triangle
    Meets meets = Meets::kHit;
    if ((u < Real(0) || v < Real(0) || w < Real(0)) && (u > Real(0) || v > Real(0) || w > Real(0))) {
        const Real margin = Real(kNearMiss) * det;  // the sign of det: inside is on its side
        const bool near = det > Real(0) ? (u >= -margin && v >= -margin && w >= -margin)
                                        : (u <= -margin && v <= -margin && w <= -margin);
        if (!near) return Meets::kMiss;
        meets = Meets::kNearMiss;
    }
    const Real az = ray.sz * a[kz], bz = ray.sz * b[kz], cz = ray.sz * c[kz];
    const Real t_scaled = u * az + v * bz + w * cz;
    const double inverse_det = 1.0 / double(det);
    hit.t = double(t_scaled) * inverse_det;
    hit.b1 = double(v) * inverse_det;
    hit.b2 = double(w) * inverse_det;
    hit.front = det > Real(0);
    return meets;
}

// The entry parameter of the ray into the box when it meets it within [t_min, t_max], else +inf.
// The far distances are widened by 2 * gamma(3) (Ize 2013) so that rounding never misses a box
// holding a hit; slabs the ray lies exactly in (0 * inf = NaN) do not restrict it.
template <class Real>
inline Real enter_box(const Ray<Real>& ray, const float* lo, const float* hi, Real t_min, Real t_max) {
    constexpr Real eps = std::numeric_limits<Real>::epsilon() * Real(0.5);
    constexpr Real widening = Real(2) * (Real(3) * eps) / (Real(1) - Real(3) * eps);
    for (int a = 0; a < 3; ++a) {
        Real t0 = (Real(lo[a]) - ray.origin[a]) * ray.inverse[a];
        Real t1 = (Real(hi[a]) - ray.origin[a]) * ray.inverse[a];
        if (t0 > t1) std::swap(t0, t1);
        t1 *= t1 > Real(0) ? Real(1) + widening : Real(1) - widening;  // infinities stay
        t_min = t0 > t_min ? t0 : t_min;
        t_max = t1 < t_max ? t1 : t_max;
    }
    return t_min <= t_max ? t_min : std::numeric_limits<Real>::infinity();
}

}  // namespace raycast
