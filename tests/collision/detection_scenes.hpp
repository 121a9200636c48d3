#pragma once
// Seeded scene generators for the broad/narrow phase tests and the detection benchmark.
#include "penalty/collision/models.hpp"
#include "penalty_test/random_draws.hpp"

#include <cmath>
#include <memory>
#include <random>
#include <vector>

namespace penalty::test {

/// A triangulated torus (major radius R, minor radius r, nu × nv quads split in two), centred at c,
/// vertices jittered by `jitter` (relative to the edge length). Closed manifold.
struct TorusMesh {
    Vec3State state;
    MeshTopology topo;
};

inline std::unique_ptr<TorusMesh> make_torus(int nu, int nv, double R, double r, const Vec3& c, std::mt19937& g,
                                             double jitter = 0.0) {
    auto m = std::make_unique<TorusMesh>();
    std::vector<Vec3> pts;
    pts.reserve(std::size_t(nu) * std::size_t(nv));
    const double pi2 = 6.283185307179586;
    const double h = std::min(pi2 * R / nu, pi2 * r / nv);
    std::uniform_real_distribution<double> u(-jitter * h, jitter * h);
    for (int i = 0; i < nu; ++i) {
        const double a = pi2 * i / nu;
        for (int j = 0; j < nv; ++j) {
            const double b = pi2 * j / nv;
            Vec3 p((R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a), r * std::sin(b));
            if (jitter > 0.0) p += test::draw_vec3(u, g);
            pts.push_back(c + p);
        }
    }
    std::vector<Triangle> tris;
    tris.reserve(2 * pts.size());
    auto id = [&](int i, int j) { return PointId(((i + nu) % nu) * nv + (j + nv) % nv); };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            tris.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            tris.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    m->state.resize(pts.size());
    m->state.position = std::move(pts);
    m->topo.set_num_points(m->state.size());
    m->topo.set_triangles(std::move(tris));
    return m;
}

/// n uniform random points in the cube [-s, s]^3.
inline Vec3State random_cloud(std::size_t n, double s, std::mt19937& g, const Vec3& c = Vec3::Zero()) {
    std::uniform_real_distribution<double> u(-s, s);
    Vec3State st;
    st.resize(n);
    for (auto& p : st.position) p = c + test::draw_vec3(u, g);
    return st;
}

/// Per-sphere radii uniform in [lo, hi].
inline std::vector<double> random_radii(std::size_t n, double lo, double hi, std::mt19937& g) {
    std::uniform_real_distribution<double> u(lo, hi);
    std::vector<double> r(n);
    for (auto& x : r) x = u(g);
    return r;
}

}  // namespace penalty::test
