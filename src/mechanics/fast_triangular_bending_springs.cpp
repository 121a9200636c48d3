#include "penalty/mechanics/fast_triangular_bending_springs.hpp"

#include "sofa_vector_ops.hpp"

#include <cmath>
#include <cstdint>
#include <optional>

namespace penalty {

using sofa_vec::cross;
using sofa_vec::dot3;
using sofa_vec::scaled;

namespace {

using sofa_vec::norm;

/// EdgeSpring::setEdgeSpring on rest positions p.
FastTriangularBendingSprings::Element make_element(std::span<const Vec3> p, std::array<Index, 4> vid,
                                                   double stiffness) {
    FastTriangularBendingSprings::Element e;
    e.vid = vid;
    const auto at = [&](int k) -> const Vec3& { return p[static_cast<std::size_t>(vid[static_cast<std::size_t>(k)])]; };
    const Vec3 na = cross(at(0) - at(2), at(0) - at(3));
    const Vec3 nb = cross(at(1) - at(3), at(1) - at(2));
    const Vec3 nc = cross(at(2) - at(1), at(2) - at(0));
    const Vec3 nd = cross(at(3) - at(0), at(3) - at(1));
    e.alpha[0] = norm(nb) / (norm(na) + norm(nb));
    e.alpha[1] = norm(na) / (norm(na) + norm(nb));
    e.alpha[2] = -norm(nd) / (norm(nc) + norm(nd));
    e.alpha[3] = -norm(nc) / (norm(nc) + norm(nd));
    const Vec3 edge_dir = sofa_vec::normalized(at(2) - at(3));
    const Vec3 ac = at(2) - at(0), bc = at(2) - at(1);
    const double ha = norm(ac - scaled(edge_dir, dot3(ac, edge_dir)));
    const double hb = norm(bc - scaled(edge_dir, dot3(bc, edge_dir)));
    const double l = norm(at(2) - at(3));
    e.lambda = (2. / 3) * (ha + hb) / (ha * ha * hb * hb) * l * stiffness;
    return e;
}

}  // namespace

// FastTriangularBendingSprings::reinit → applyTriangleCreation over every triangle in order.
void FastTriangularBendingSprings::init() {
    const std::span<const Vec3> p = state_->rest_position;
    const auto& triangles = topology_->triangles();
    const auto& edges = topology_->edges();
    const auto& edges_in = topology_->edges_in_triangle();
    const auto& around = topology_->triangles_around_edge();
    for (const Triangle& t : triangles)
        for (PointId v : t)
            if (v < 0 || static_cast<std::size_t>(v) >= p.size())
                throw_invalid_argument("FastTriangularBendingSprings: triangle point ", v, " out of range (", p.size(),
                                       " points)");
    const double eps2 = min_dist_ * min_dist_;
    std::vector<std::optional<Element>> per_edge(edges.size());
    for (std::size_t i = 0; i < triangles.size(); ++i)
        for (int j = 0; j < 3; ++j) {
            const auto edge = static_cast<std::size_t>(edges_in[i][static_cast<std::size_t>(j)]);
            const auto& shell = around[edge];
            if (shell.size() != 2) {
                per_edge[edge].reset();
                continue;
            }
            const auto other = static_cast<std::size_t>(shell[0] == static_cast<std::int32_t>(i) ? shell[1] : shell[0]);
            const auto index_in = [&](std::size_t tri) {
                for (std::size_t k = 0; k < 3; ++k)
                    if (static_cast<std::size_t>(edges_in[tri][k]) == edge) return k;
                return std::size_t{0};
            };
            const Index v1 = triangles[other][index_in(other)], v2 = triangles[i][index_in(i)];
            const Index e1 = edges[edge][0], e2 = edges[edge][1];
            const Vec3 vp = p[static_cast<std::size_t>(v2)] - p[static_cast<std::size_t>(v1)];
            const Vec3 ve = p[static_cast<std::size_t>(e2)] - p[static_cast<std::size_t>(e1)];
            if (dot3(vp, vp) > eps2 && dot3(ve, ve) > eps2)
                per_edge[edge] = make_element(p, {v1, v2, e1, e2}, stiffness_);
            // else: SOFA leaves the element as it was (the other triangle's pass may have made it)
        }
    elements_.clear();
    points_.clear();
    for (const auto& e : per_edge)
        if (e) {
            elements_.push_back(*e);
            points_.push_back({PointId(e->vid[0]), PointId(e->vid[1]), PointId(e->vid[2]), PointId(e->vid[3])});
        }
    scatter_.clear();
}

// EdgeSpring::addForce: R = Σ α_k x_k, f_k −= (R λ) α_k, E += ½ λ R·R; from
// OrderedScatter::kMinElements elements on TBB's threads with the bits of one thread.
void FastTriangularBendingSprings::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> /*v*/) {
    const auto pass = [&](std::size_t first, std::size_t end, const auto& deferred, double* energies) {
        double energy = 0.0;
        for (std::size_t i = first; i < end; ++i) {
            const Element& e = elements_[i];
            const auto at = [&](std::size_t k) { return static_cast<std::size_t>(e.vid[k]); };
            const Vec3 r = scaled(x[at(0)], e.alpha[0]) + scaled(x[at(1)], e.alpha[1]) + scaled(x[at(2)], e.alpha[2]) +
                           scaled(x[at(3)], e.alpha[3]);
            const Vec3 rl = scaled(r, e.lambda);
            const std::array<Vec3, 4> terms = {scaled(rl, e.alpha[0]), scaled(rl, e.alpha[1]), scaled(rl, e.alpha[2]),
                                               scaled(rl, e.alpha[3])};
            detail::store_or_apply(deferred, i, terms, [&](std::size_t k, const Vec3& t) { f[at(k)] -= t; });
            const double element_energy = dot3(r, r) * e.lambda * 0.5;
            if (energies != nullptr) energies[i] = element_energy;
            else energy += element_energy;
        }
        return energy;
    };
    energy_ = detail::force_in_order</*Add=*/false>(scatter_, std::span<const std::array<PointId, 4>>(points_), f, 1,
                                                    energies_, pass);
}

// EdgeSpring::addDForce (LOCAL_OPTIM): d_k = ((dx_k λ) k) α_k, df_j −= d_k α_j for j, then k.
// Vertex j takes four subtractions an element: on threads, a deferred vertex's four terms are
// stored together (at OrderedScatter::deferred_slot) and subtracted in element order after.
void FastTriangularBendingSprings::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                              double /*b_factor*/) const {
    const auto pass = [&](std::size_t first, std::size_t end, const std::uint8_t* deferred_mask) {
        for (std::size_t i = first; i < end; ++i) {
            const Element& e = elements_[i];
            std::array<Vec3, 4> d;
            for (std::size_t k = 0; k < 4; ++k)
                d[k] = scaled(scaled(scaled(dx[static_cast<std::size_t>(e.vid[k])], e.lambda), k_factor), e.alpha[k]);
            const unsigned mask = deferred_mask != nullptr ? deferred_mask[i] : 0U;
            for (std::size_t j = 0; j < 4; ++j) {
                if ((mask >> j) & 1U) {
                    VertexTerms& stored = deferred_terms_[scatter_.deferred_slot(i, j)];
                    for (std::size_t k = 0; k < 4; ++k) stored[k] = scaled(d[k], e.alpha[j]);
                    continue;
                }
                Vec3& out = df[static_cast<std::size_t>(e.vid[j])];
                for (std::size_t k = 0; k < 4; ++k) out -= scaled(d[k], e.alpha[j]);
            }
        }
    };
    detail::scatter_stored_in_order(scatter_, std::span<const std::array<PointId, 4>>(points_), deferred_terms_, pass,
                                    [&](std::size_t vertex, const VertexTerms& terms) {
                                        for (const Vec3& t : terms) df[vertex] -= t;
                                    });
}

void FastTriangularBendingSprings::add_stiffness_triplets(TripletList& t, Index offset, double factor) const {
    for (const Element& e : elements_)
        for (std::size_t j = 0; j < 4; ++j)
            for (std::size_t k = 0; k < 4; ++k) {
                const double v = -e.lambda * e.alpha[j] * e.alpha[k] * factor;
                for (Index c = 0; c < 3; ++c) t.emplace_back(offset + 3 * e.vid[j] + c, offset + 3 * e.vid[k] + c, v);
            }
}

}  // namespace penalty
