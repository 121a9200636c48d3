#pragma once
// Internal: the element intersectors ("kernels") of every method, called through the dispatch
// table in intersection.cpp. Each kernel receives the two models in registered order.

#include "penalty/collision/intersection.hpp"
#include "penalty/collision/models.hpp"

#include <cmath>

namespace penalty::detail {

/// Everything a kernel needs for one element pair.
struct PairCtx {
    const IntersectionParams& p;
    CollisionModel& m1;
    CollisionModel& m2;
    Index e1;
    Index e2;
    DetectionOutputList& out;
};

using KernelFn = int (*)(PairCtx&);

/// A sphere element of either SphereModel or RigidSphereModel.
struct SphereElem {
    Vec3 c;
    double r;
    bool rigid;
    /// SOFA's getContactPointByNormal(n): Vec3 sphere → centre; rigid sphere → c − n r.
    [[nodiscard]] Vec3 point_by_normal(const Vec3& n) const { return rigid ? Vec3(c - n * r) : c; }
};

inline SphereElem sphere_elem(const CollisionModel& m, Index i) {
    if (m.type() == ModelType::RigidSphere) {
        const auto& s = static_cast<const RigidSphereModel&>(m);
        return {s.center(i), s.radius(i), true};
    }
    const auto& s = static_cast<const SphereModel&>(m);
    return {s.center(i), s.radius(i), false};
}

inline double skins(const PairCtx& c) {
    return c.m1.params().contact_distance + c.m2.params().contact_distance;
}

/// SOFA's "id_big": index of the element of the model with more elements (ties → e2).
inline std::int64_t id_big(const PairCtx& c) {
    return c.m1.size() > c.m2.size() ? std::int64_t(c.e1) : std::int64_t(c.e2);
}

/// Whether SOFA's routine has the 1e-15 zero-distance guard (→ (1,0,0)).
enum class Guard : std::uint8_t { None, Sofa };

/// Unit normal d/len. Guard::Sofa: (1,0,0) if len ≤ 1e-15 (SOFA's behaviour). Guard::None:
/// SOFA divides blindly; for len == 0 apply the zero-distance policy. Returns false if the
/// output must be dropped.
inline bool unit_normal(const PairCtx& c, const Vec3& d, double len, Guard g, Vec3& n) {
    if (g == Guard::Sofa) {
        n = len > 1e-15 ? Vec3(d / len) : Vec3::UnitX();
        return true;
    }
    if (len > 0.0) {
        n = d / len;
        if (n.allFinite()) return true;
    }
    switch (c.p.quirks.zero_distance_normal) {
        case ZeroDistanceNormal::FallbackX: n = Vec3::UnitX(); return true;
        case ZeroDistanceNormal::Drop: return false;
        case ZeroDistanceNormal::SofaNaN: n = d / len; return true;
    }
    return false;
}

inline int push(PairCtx& c, std::int64_t id, const Vec3& p0, const Vec3& p1, const Vec3& n, double value) {
    DetectionOutput o;
    o.elem1 = c.e1;
    o.elem2 = c.e2;
    o.id = id;
    o.point = {p0, p1};
    o.normal = n;
    o.value = value;
    c.out.push_back(o);
    return 1;
}

// ---- kernels, by method (definitions in the kernels_*.cpp files) ----
// NewProximity
int np_sphere_sphere(PairCtx&);     // Sphere/RigidSphere pairs (centres)
int np_sphere_point(PairCtx&);      // Sphere–Point, RigidSphere–Point
int np_point_point(PairCtx&);
int np_line_point(PairCtx&);
int np_line_line(PairCtx&);
int np_line_sphere(PairCtx&);       // Line–Sphere, Line–RigidSphere
int np_triangle_point(PairCtx&);
int np_triangle_sphere(PairCtx&);   // Triangle–Sphere, Triangle–RigidSphere
int np_triangle_line(PairCtx&);
int np_triangle_triangle(PairCtx&);
// MinProximity
int min_sphere_sphere(PairCtx&);
int min_sphere_point(PairCtx&);
int min_point_point(PairCtx&);
int min_line_point(PairCtx&);
int min_line_line(PairCtx&);
int min_line_sphere(PairCtx&);
int min_triangle_point(PairCtx&);
int min_triangle_sphere(PairCtx&);
// Discrete
int discrete_sphere_sphere(PairCtx&);
int discrete_triangle_line(PairCtx&);
// LocalMinDistance
int lmd_sphere_sphere(PairCtx&);    // Sphere–Sphere (Vec3); rigid pairs use the Discrete routine
int lmd_rigid_sphere_pair(PairCtx&);
int lmd_sphere_point(PairCtx&);
int lmd_point_point(PairCtx&);
int lmd_line_point(PairCtx&);
int lmd_line_line(PairCtx&);
int lmd_line_sphere(PairCtx&);
int lmd_triangle_point(PairCtx&);
int lmd_triangle_sphere(PairCtx&);
// Beyond SOFA
int cylinder_sphere(PairCtx&);      // Cylinder–Sphere, Cylinder–RigidSphere
int cylinder_cylinder(PairCtx&);
int cylinder_triangle(PairCtx&);
int tetrahedron_point(PairCtx&);

}  // namespace penalty::detail
