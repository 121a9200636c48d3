#pragma once
// Shared fixtures for the collision tests: small meshes and states.
#include "penalty/collision/intersection.hpp"
#include "penalty/collision/models.hpp"
#include "penalty_test/random_draws.hpp"

#include <memory>
#include <random>
#include <vector>

namespace penalty::test {

inline CollisionModelParams named(const char* n) {
    CollisionModelParams p;
    p.name = n;
    return p;
}

inline Vec3State make_state(const std::vector<Vec3>& pts) {
    Vec3State s;
    s.resize(pts.size());
    s.position = pts;
    return s;
}

inline Rigid3State make_rigid_state(const std::vector<RigidFrame>& frames) {
    Rigid3State s;
    s.resize(frames.size());
    s.position = frames;
    return s;
}

/// A mesh (state + topology) kept alive together; models point into it.
struct Mesh {
    Vec3State state;
    MeshTopology topo;
};

inline std::unique_ptr<Mesh> triangle_mesh(const std::vector<Vec3>& pts, std::vector<Triangle> tris) {
    auto m = std::make_unique<Mesh>();
    m->state = make_state(pts);
    m->topo.set_num_points(pts.size());
    m->topo.set_triangles(std::move(tris));
    return m;
}

/// Closed octahedron (6 vertices, 8 outward triangles, 12 edges), centred at c, radius s.
inline std::unique_ptr<Mesh> octahedron(const Vec3& c = Vec3::Zero(), double s = 1.0) {
    std::vector<Vec3> p = {c + s * Vec3(1, 0, 0),  c + s * Vec3(-1, 0, 0), c + s * Vec3(0, 1, 0),
                           c + s * Vec3(0, -1, 0), c + s * Vec3(0, 0, 1),  c + s * Vec3(0, 0, -1)};
    std::vector<Triangle> t = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    return triangle_mesh(p, t);
}

inline Vec3 rand_vec(std::mt19937& g, double s) {
    std::uniform_real_distribution<double> u(-s, s);
    return draw_vec3(u, g);
}

inline Vec3 rand_unit(std::mt19937& g) {
    Vec3 v;
    do {
        v = rand_vec(g, 1.0);
    } while (v.squaredNorm() < 1e-3 || v.squaredNorm() > 1.0);
    return v.normalized();
}

inline Quat rand_quat(std::mt19937& g) {
    std::uniform_real_distribution<double> a(0.0, 6.283185307179586);
    const Vec3 axis = rand_unit(g);  // drawn before the angle, as g++ evaluates the call
    return Quat(Eigen::AngleAxisd(a(g), axis));
}

}  // namespace penalty::test
