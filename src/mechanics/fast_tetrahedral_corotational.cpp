// SOFA's FastTetrahedralCorotationalForceField (header: the formulas). Every product and sum is
// written in the order of SOFA's type::Vec / type::Mat operations (sofa_vector_ops.hpp and the
// 3×3 products below), so that a scene gives SOFA's states to the last bits.
#include "penalty/mechanics/fast_tetrahedral_corotational.hpp"

#include "penalty/mechanics/fem.hpp"
#include "sofa_vector_ops.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdint>
#include <limits>

namespace penalty {

namespace {

using sofa_vec::cross;
using sofa_vec::dot3;
using sofa_vec::times;
using sofa_vec::transpose_times;

constexpr auto kLocalEdges = MeshTopology::kTetraEdges;  // SOFA's edgesInTetrahedronArray
constexpr std::size_t kEdgesPerTask = 4096;              // the edges zeroed on threads

/// a·b, entry (i, j) = a(i,0)b(0,j) + a(i,1)b(1,j) + a(i,2)b(2,j) (type::operator*(Mat<3,3>, Mat<3,3>)).
Mat3 product(const Mat3& a, const Mat3& b) {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r(i, j) = a(i, 0) * b(0, j) + a(i, 1) * b(1, j) + a(i, 2) * b(2, j);
    return r;
}
/// aᵀ·b, entry (i, j) = a(0,i)b(0,j) + a(1,i)b(1,j) + a(2,i)b(2,j) (type::multTranspose(Mat<3,3>, Mat<3,3>)).
Mat3 transpose_product(const Mat3& a, const Mat3& b) {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r(i, j) = a(0, i) * b(0, j) + a(1, i) * b(1, j) + a(2, i) * b(2, j);
    return r;
}

/// FastTetrahedralCorotationalForceField::computeQRRotation: rows x̂ = e0/|e0|, ẑ = (x̂ × e1)/|x̂ × e1|,
/// ŷ = ẑ × x̂.
Mat3 qr_frame(const Vec3& e0, const Vec3& e1) {
    const Vec3 x = sofa_vec::normalized(e0);
    const Vec3 z = sofa_vec::normalized(cross(x, e1));
    const Vec3 y = cross(z, x);
    Mat3 r;
    r.row(0) = x.transpose();
    r.row(1) = y.transpose();
    r.row(2) = z.transpose();
    return r;
}

/// BaseLinearElasticityFEMForceField::getVecRealInElement: value t, else the first.
double value_in_element(const std::vector<double>& values, std::size_t t) {
    return values.size() > t ? values[t] : values.front();
}

}  // namespace

FastTetrahedralCorotationalForceField::FastTetrahedralCorotationalForceField(Vec3Object& state,
                                                                             const MeshTopology& topology,
                                                                             FastTetrahedralCorotationalParameters p)
    : ForceField(state), topology_(&topology), p_(std::move(p)) {
    if (p_.young_modulus.empty() || p_.poisson_ratio.empty())
        throw_invalid_argument("FastTetrahedralCorotationalForceField: youngModulus and poissonRatio need a value");
    for (double v : p_.young_modulus)
        if (!std::isfinite(v))
            throw_invalid_argument("FastTetrahedralCorotationalForceField: youngModulus must be finite, got ", v);
    for (double v : p_.poisson_ratio)
        if (!std::isfinite(v))
            throw_invalid_argument("FastTetrahedralCorotationalForceField: poissonRatio must be finite, got ", v);
}

FastTetrahedralCorotationalForceField::RestTetrahedron FastTetrahedralCorotationalForceField::rest_information(
    std::size_t t) const {
    // createTetrahedronRestInformation
    const Tetrahedron& tet = topology_->tetrahedra()[t];
    const auto& x0 = state_->rest_position;
    std::array<Vec3, 4> p;
    for (std::size_t j = 0; j < 4; ++j) p[j] = x0[static_cast<std::size_t>(tet[j])];
    RestTetrahedron r;
    // Lamé coefficients (toLameParameters, 3D): μ = E/(2(1+ν)), λ = Eν/((1+ν)(1−2ν)), Pa
    const double young = value_in_element(p_.young_modulus, t), poisson = value_in_element(p_.poisson_ratio, t);
    double mu = young / (2 * (1 + poisson));
    double lambda = young * poisson / ((1 + poisson) * (1 - 2 * poisson));
    // V = −signedVolume = −((p1−p0) × (p2−p0))·(p3−p0)/6
    const double volume = -(dot3(cross(p[1] - p[0], p[2] - p[0]), p[3] - p[0]) / 6.0);
    const double scale = std::max({(p[1] - p[0]).norm(), (p[2] - p[0]).norm(), (p[3] - p[0]).norm()});
    // SOFA divides by the volume (infinite stiffness); penalty refuses the element.
    if (!std::isfinite(volume) || std::abs(volume) <= 1e-12 / 6 * scale * scale * scale)
        throw_invalid_argument("FastTetrahedralCorotationalForceField: tetrahedron ", t, " is degenerate (volume ",
                               volume, ")");
    r.rest_volume = volume;
    mu *= std::fabs(volume);
    lambda *= std::fabs(volume);
    for (std::size_t j = 0; j < 4; ++j) {
        const Vec3 c = cross(p[(j + 2) % 4] - p[(j + 1) % 4], p[(j + 3) % 4] - p[(j + 1) % 4]);
        const double six_v = volume * 6;
        r.shape_vector[j] = (j % 2 == 0) ? Vec3(c[0] / six_v, c[1] / six_v, c[2] / six_v)
                                         : Vec3(-c[0] / six_v, -c[1] / six_v, -c[2] / six_v);
    }
    for (std::size_t j = 0; j < 4; ++j) {  // D_j = (λ + μ) s sᵀ + μ |s|² I, summed as SOFA
        const Vec3& s = r.shape_vector[j];
        const double val = mu * dot3(s, s);
        Mat3& d = r.vertex_block[j];
        for (int m = 0; m < 3; ++m)
            for (int n = m; n < 3; ++n) {
                d(m, n) = lambda * s[n] * s[m] + mu * s[n] * s[m];
                if (m == n) d(m, m) += val;
                else d(n, m) = d(m, n);
            }
    }
    for (std::size_t j = 0; j < 6; ++j) {  // L_j = λ s_l s_kᵀ + μ s_k s_lᵀ + μ (s_l·s_k) I
        const auto k = static_cast<std::size_t>(kLocalEdges[j][0]), l = static_cast<std::size_t>(kLocalEdges[j][1]);
        r.rest_edge[j] = p[l] - p[k];
        const Vec3 &sk = r.shape_vector[k], &sl = r.shape_vector[l];
        const double val = mu * dot3(sl, sk);
        Mat3& b = r.edge_block[j];
        for (int m = 0; m < 3; ++m)
            for (int n = 0; n < 3; ++n) {
                b(m, n) = lambda * sk[n] * sl[m] + mu * sl[n] * sk[m];
                if (m == n) b(m, m) += val;
            }
    }
    if (p_.rotation == FastTetrahedralRotation::qr) {
        r.rest_rotation = qr_frame(r.rest_edge[0], r.rest_edge[1]);
    } else if (p_.rotation == FastTetrahedralRotation::polar_modified) {
        Mat3 edges;
        for (int j = 0; j < 3; ++j) edges.row(j) = (p[static_cast<std::size_t>(j) + 1] - p[0]).transpose();
        r.rest_rotation = polar_rotation(edges);
    }
    // updateTopologyInformation: the global edges and their orientation
    const auto& edges = topology_->edges();
    for (std::size_t j = 0; j < 6; ++j) {
        const PointId a = tet[static_cast<std::size_t>(kLocalEdges[j][0])],
                      b = tet[static_cast<std::size_t>(kLocalEdges[j][1])];
        const std::int32_t e = topology_->edge_index(a, b);
        if (e < 0)
            throw_invalid_argument("FastTetrahedralCorotationalForceField: edge (", a, ", ", b, ") of tetrahedron ", t,
                                   " is not in the topology");
        r.edge[j] = e;
        r.edge_orientation[j] = edges[static_cast<std::size_t>(e)][0] == a ? 1.0 : -1.0;
    }
    r.rotation = Mat3::Zero();  // SOFA's Mat3x3 before the first addForce
    return r;
}

void FastTetrahedralCorotationalForceField::init() {
    const auto& tetrahedra = topology_->tetrahedra();
    const std::size_t n = state_->rest_position.size();
    for (const Tetrahedron& t : tetrahedra)
        for (PointId v : t)
            if (v < 0 || static_cast<std::size_t>(v) >= n)
                throw_invalid_argument("FastTetrahedralCorotationalForceField: tetrahedron vertex ", v,
                                       " outside the state's ", n, " points");
    rest_.clear();
    rest_.reserve(tetrahedra.size());
    for (std::size_t t = 0; t < tetrahedra.size(); ++t) rest_.push_back(rest_information(t));
    edge_dfdx_.assign(topology_->edges().size(), Mat3::Zero());
    // made again for these elements at the next force or product on threads
    force_scatter_.clear();
    edge_scatter_.clear();
    product_scatter_.clear();
}

Mat3 FastTetrahedralCorotationalForceField::rotation_of(const RestTetrahedron& r, const std::array<Vec3, 6>& d) const {
    switch (p_.rotation) {
        case FastTetrahedralRotation::polar: {
            // deformation gradient F = Σ_{j<3} d_j s_{j+1}ᵀ, summed from j = 0
            Mat3 f;
            for (int k = 0; k < 3; ++k)
                for (int l = 0; l < 3; ++l) f(k, l) = d[0][k] * r.shape_vector[1][l];
            for (std::size_t j = 1; j < 3; ++j)
                for (int k = 0; k < 3; ++k)
                    for (int l = 0; l < 3; ++l) f(k, l) += d[j][k] * r.shape_vector[j + 1][l];
            return polar_rotation(f);
        }
        case FastTetrahedralRotation::qr:
            return transpose_product(qr_frame(d[0], d[1]), r.rest_rotation);
        case FastTetrahedralRotation::polar_modified: {
            Mat3 s;
            for (int j = 0; j < 3; ++j) s.row(j) = d[static_cast<std::size_t>(j)].transpose();
            const Mat3 q = polar_rotation(s);
            return product(q.transpose(), r.rest_rotation);
        }
        case FastTetrahedralRotation::linear:
            break;
    }
    return Mat3::Identity();
}

void FastTetrahedralCorotationalForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x,
                                                      std::span<const Vec3>) {
    // addForce, then updateMatrix's E_e = Σ R L_j Rᵀ over the tetrahedra on edge e in
    // tetrahedron order (SOFA builds them at the next addDForce from these rotations), in one
    // pass: each tetrahedron's terms right after its rotation
    PENALTY_DEMAND(rest_.size() == topology_->tetrahedra().size());
    const std::span<const Tetrahedron> tetrahedra(topology_->tetrahedra());
    if (!detail::OrderedScatter::worth_threads(tetrahedra.size())) {
        for (Mat3& e : edge_dfdx_) e.setZero();
        force_range(0, tetrahedra.size(), f, x, detail::NoDeferredTerms{},
                    [&](std::size_t i, std::size_t j, const Mat3& term) {
                        edge_dfdx_[static_cast<std::size_t>(rest_[i].edge[j])] += term;
                    });
        return;
    }
    // On TBB's threads: chunks of tetrahedra; a vertex's (an edge's) first chunk adds its terms,
    // the others' are stored and added in tetrahedron order after (OrderedScatter), the same
    // chunks for both.
    force_scatter_.prepare(tetrahedra, 1);
    if (edge_scatter_.element_count() != tetrahedra.size() ||
        edge_scatter_.requested_chunks() != force_scatter_.requested_chunks()) {
        std::vector<std::array<PointId, 6>> edges_of(rest_.size());
        for (std::size_t i = 0; i < rest_.size(); ++i)
            for (std::size_t j = 0; j < 6; ++j) edges_of[i][j] = rest_[i].edge[j];
        edge_scatter_.build(std::span<const std::array<PointId, 6>>(edges_of), force_scatter_.requested_chunks(), 1);
        deferred_edge_terms_.resize(edge_scatter_.deferred_terms());
    }
    PENALTY_DEMAND(edge_scatter_.chunk_count() == force_scatter_.chunk_count());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, edge_dfdx_.size(), kEdgesPerTask),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t e = r.begin(); e < r.end(); ++e) edge_dfdx_[e].setZero();
                      });
    const detail::DeferredTerms deferred = force_scatter_.deferred();
    const std::uint8_t* edge_deferred = edge_scatter_.deferred_mask();
    force_scatter_.for_each_chunk([&](std::size_t first, std::size_t end) {
        force_range(first, end, f, x, deferred, [&](std::size_t i, std::size_t j, const Mat3& term) {
            if ((edge_deferred[i] >> j) & 1U) deferred_edge_terms_[edge_scatter_.deferred_slot(i, j)] = term;
            else edge_dfdx_[static_cast<std::size_t>(rest_[i].edge[j])] += term;
        });
    });
    force_scatter_.add_deferred(f);
    edge_scatter_.for_each_deferred_slot(
        [&](std::size_t edge, std::size_t slot) { edge_dfdx_[edge] += deferred_edge_terms_[slot]; });
}

template <class Deferred, class EdgeTerm>
void FastTetrahedralCorotationalForceField::force_range(std::size_t first, std::size_t end, std::span<Vec3> f,
                                                        std::span<const Vec3> x, const Deferred& deferred,
                                                        const EdgeTerm& edge_term_of) {
    const auto& tetrahedra = topology_->tetrahedra();
    for (std::size_t i = first; i < end; ++i) {
        RestTetrahedron& r = rest_[i];
        const Tetrahedron& tet = tetrahedra[i];
        std::array<Vec3, 4> vertex;
        for (std::size_t j = 0; j < 4; ++j) vertex[j] = x[static_cast<std::size_t>(tet[j])];
        std::array<Vec3, 6> d;
        for (std::size_t j = 0; j < 6; ++j)
            d[j] = vertex[static_cast<std::size_t>(kLocalEdges[j][1])] -
                   vertex[static_cast<std::size_t>(kLocalEdges[j][0])];
        const Mat3 rot = rotation_of(r, d);
        r.rotation = rot.transpose();
        std::array<Vec3, 4> force{Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
        for (std::size_t j = 0; j < 6; ++j) {
            const Vec3 u = times(r.rotation, d[j]) - r.rest_edge[j];  // rest-frame edge displacement, m
            force[static_cast<std::size_t>(kLocalEdges[j][1])] += times(r.edge_block[j], u);
            force[static_cast<std::size_t>(kLocalEdges[j][0])] -= transpose_times(r.edge_block[j], u);
        }
        std::array<Vec3, 4> terms;
        for (std::size_t j = 0; j < 4; ++j) terms[j] = times(rot, force[j]);
        detail::store_or_apply(deferred, i, terms,
                               [&](std::size_t j, const Vec3& term) { f[static_cast<std::size_t>(tet[j])] += term; });
        // updateMatrix: R L_j Rᵀ (rotation = Rᵀ), transposed when the local edge runs against the
        // global one
        for (std::size_t j = 0; j < 6; ++j) {
            const Mat3 tmp = product(r.edge_block[j], r.rotation);
            edge_term_of(
                i, j,
                r.edge_orientation[j] == 1.0 ? transpose_product(r.rotation, tmp) : transpose_product(tmp, r.rotation));
        }
    }
}

void FastTetrahedralCorotationalForceField::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                                       double) const {
    // df_b += E_e·δ, df_a −= E_eᵀ·δ with δ = (dx_b − dx_a)·k, edge by edge: the terms
    // (−E_eᵀ·δ, E_e·δ) added (a − t and a + (−t) are the same bits)
    const auto& edges = topology_->edges();
    PENALTY_DEMAND(edge_dfdx_.size() == edges.size());
    detail::scatter_in_order</*Add=*/true>(
        product_scatter_, std::span<const Edge>(edges), df, 1,
        [&](std::size_t first, std::size_t end, const auto& deferred) {
            for (std::size_t i = first; i < end; ++i) {
                const auto a = static_cast<std::size_t>(edges[i][0]), b = static_cast<std::size_t>(edges[i][1]);
                const Vec3 delta = (dx[b] - dx[a]) * k_factor;
                const std::array<Vec3, 2> terms{-transpose_times(edge_dfdx_[i], delta), times(edge_dfdx_[i], delta)};
                detail::store_or_apply(deferred, i, terms, [&](std::size_t k, const Vec3& term) {
                    df[static_cast<std::size_t>(edges[i][k])] += term;
                });
            }
        });
}

void FastTetrahedralCorotationalForceField::add_stiffness_triplets(TripletList& triplets, Index offset,
                                                                   double factor) const {
    // buildStiffnessMatrix: diagonal blocks −Σ R D_i Rᵀ, off-diagonal −E_eᵀ (row k, column l) and −E_e
    const auto add_block = [&](std::size_t row, std::size_t col, const Mat3& block) {
        for (int m = 0; m < 3; ++m)
            for (int n = 0; n < 3; ++n)
                triplets.emplace_back(offset + 3 * static_cast<Index>(row) + m,
                                      offset + 3 * static_cast<Index>(col) + n, -factor * block(m, n));
    };
    std::vector<Mat3> point_dfdx(state_->position.size(), Mat3::Zero());
    const auto& tetrahedra = topology_->tetrahedra();
    for (std::size_t i = 0; i < rest_.size(); ++i) {
        const RestTetrahedron& r = rest_[i];
        for (std::size_t j = 0; j < 4; ++j)
            point_dfdx[static_cast<std::size_t>(tetrahedra[i][j])] +=
                product(product(r.rotation.transpose(), r.vertex_block[j]), r.rotation);
    }
    for (std::size_t i = 0; i < point_dfdx.size(); ++i) add_block(i, i, point_dfdx[i]);
    const auto& edges = topology_->edges();
    for (std::size_t i = 0; i < edges.size(); ++i) {
        const auto a = static_cast<std::size_t>(edges[i][0]), b = static_cast<std::size_t>(edges[i][1]);
        add_block(a, b, edge_dfdx_[i].transpose());
        add_block(b, a, edge_dfdx_[i]);
    }
}

}  // namespace penalty
