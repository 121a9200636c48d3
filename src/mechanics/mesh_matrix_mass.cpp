#include "penalty/mechanics/mesh_matrix_mass.hpp"

#include "penalty/mechanics/element_measures.hpp"
#include "penalty/mechanics/topology_container.hpp"
#include "penalty/mechanics/topology_data.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace penalty {

namespace {
constexpr std::size_t kVerticesPerTask = 4096;  // add_mdx's vertex terms on threads
}  // namespace

namespace {

void check_masses(const std::vector<double>& values, const char* parameter) {
    for (double v : values)
        if (!std::isfinite(v) || v < 0.0)
            throw_invalid_argument("MeshMatrixMass: ", parameter, " must be finite and >= 0, got ", v);
}

/// The divisors (d_v, d_e) of an element's measure for a vertex and an edge mass, and the lumping
/// coefficient c (MeshMatrixMass::applyVertexMass*Creation, applyEdgeMass*Creation, computeMass).
struct ElementShares {
    double vertex_divisor;
    double edge_divisor;
    double lumping;
};

ElementShares shares_of(LumpedElementKind kind) {
    switch (kind) {
        case LumpedElementKind::triangle:
            return {6.0, 12.0, 2.0};
        case LumpedElementKind::quad:
            return {8.0, 16.0, 2.0};
        case LumpedElementKind::tetrahedron:
            return {10.0, 20.0, 2.5};
        case LumpedElementKind::hexahedron:
            return {20.0, 40.0, 2.5};
        case LumpedElementKind::edge:
            return {3.0, 6.0, 1.5};  // beyond SOFA: the linear bar
    }
    return {1.0, 1.0, 1.0};
}

/// Adds each element's shares: for every element in order, its edges (not lumped) then, in
/// SOFA's order, its vertices (computeMass calls the edge creation before the vertex creation for
/// the whole mesh). Returns the total as SOFA's d_totalMass accumulates it.
template <std::size_t N, std::size_t E, class Measure>
double add_element_shares(const std::vector<std::array<PointId, N>>& elements,
                          const std::array<std::array<int, 2>, E>& local_edges, const MeshTopology& topology,
                          std::span<const Vec3> x, const std::vector<double>& density, bool lumped,
                          const ElementShares& shares, std::vector<double>& vertex, std::vector<double>& edge,
                          Measure measure) {
    auto points = [&](const std::array<PointId, N>& e) {
        std::array<Vec3, N> p;
        for (std::size_t k = 0; k < N; ++k) {
            const auto i = static_cast<std::size_t>(e[k]);
            if (i >= x.size() || i >= vertex.size())
                throw_invalid_argument("MeshMatrixMass: element vertex ", i, " is out of range (", x.size(),
                                       " positions, ", vertex.size(), " DOFs)");
            p[k] = x[i];
        }
        return p;
    };
    double total = 0.0;
    if (!lumped) {
        for (std::size_t el = 0; el < elements.size(); ++el) {
            const double mass = (density[el] * measure(points(elements[el]))) / shares.edge_divisor;
            for (const auto& [a, b] : local_edges) {
                const std::int32_t index = topology.edge_index(elements[el][static_cast<std::size_t>(a)],
                                                               elements[el][static_cast<std::size_t>(b)]);
                if (index < 0)
                    throw_invalid_argument("MeshMatrixMass: the edge (", elements[el][static_cast<std::size_t>(a)],
                                           ", ", elements[el][static_cast<std::size_t>(b)], ") of element ", el,
                                           " is not an edge of the topology");
                edge[static_cast<std::size_t>(index)] += mass;
            }
            total += double(E) * mass * 2.0;  // ×2: each edge mass sits at two places of M
        }
    }
    for (std::size_t el = 0; el < elements.size(); ++el) {
        const double mass = (density[el] * measure(points(elements[el]))) / shares.vertex_divisor;
        for (std::size_t k = 0; k < N; ++k) vertex[static_cast<std::size_t>(elements[el][k])] += mass;
        total += lumped ? double(N) * mass * shares.lumping : double(N) * mass;
    }
    return total;
}

constexpr std::array<std::array<int, 2>, 3> kTriangleEdges{{{1, 2}, {2, 0}, {0, 1}}};
constexpr std::array<std::array<int, 2>, 4> kQuadEdges{{{0, 1}, {1, 2}, {2, 3}, {3, 0}}};
constexpr std::array<std::array<int, 2>, 1> kEdgeEdges{{{0, 1}}};

}  // namespace

void MeshMatrixMass::set_mass_density(std::vector<double> density) {
    if (density.empty()) throw_invalid_argument("MeshMatrixMass: massDensity is empty");
    check_masses(density, "massDensity");
    given_density_ = std::move(density);
}

void MeshMatrixMass::set_total_mass(double total) {
    check_masses({total}, "totalMass");
    given_total_ = total;
}

void MeshMatrixMass::set_vertex_masses(std::vector<double> masses) {
    check_masses(masses, "vertexMass");
    given_vertex_masses_ = std::move(masses);
}

void MeshMatrixMass::set_edge_masses(std::vector<double> masses) {
    check_masses(masses, "edgeMass");
    given_edge_masses_ = std::move(masses);
}

std::size_t MeshMatrixMass::element_count() const {
    switch (kind_) {
        case LumpedElementKind::hexahedron:
            return topology_->hexahedra().size();
        case LumpedElementKind::tetrahedron:
            return topology_->tetrahedra().size();
        case LumpedElementKind::quad:
            return topology_->quads().size();
        case LumpedElementKind::triangle:
            return topology_->triangles().size();
        case LumpedElementKind::edge:
            return topology_->edges().size();
    }
    return 0;
}

double MeshMatrixMass::compute_masses() {
    const std::size_t n = state_->num_dofs();
    vertex_masses_.assign(n, 0.0);
    edge_masses_.assign(topology_->edges().size(), 0.0);
    const std::span<const Vec3> x(on_rest_ ? state_->rest_position : state_->position);
    const ElementShares shares = shares_of(kind_);
    const MeshTopology& t = *topology_;
    switch (kind_) {
        case LumpedElementKind::triangle:
            return add_element_shares(t.triangles(), kTriangleEdges, t, x, density_, lumping_, shares, vertex_masses_,
                                      edge_masses_, [](const auto& p) { return triangle_area(p[0], p[1], p[2]); });
        case LumpedElementKind::quad:
            return add_element_shares(t.quads(), kQuadEdges, t, x, density_, lumping_, shares, vertex_masses_,
                                      edge_masses_, [](const auto& p) { return quad_area(p[0], p[1], p[2], p[3]); });
        case LumpedElementKind::tetrahedron:
            return add_element_shares(t.tetrahedra(), MeshTopology::kTetraEdges, t, x, density_, lumping_, shares,
                                      vertex_masses_, edge_masses_,
                                      [](const auto& p) { return tetrahedron_volume(p[0], p[1], p[2], p[3]); });
        case LumpedElementKind::hexahedron:
            return add_element_shares(t.hexahedra(), MeshTopology::kHexaEdges, t, x, density_, lumping_, shares,
                                      vertex_masses_, edge_masses_, [](const auto& p) { return hexahedron_volume(p); });
        case LumpedElementKind::edge:
            // SOFA's computeMass has no branch for edges: every mass stays 0.
            if (!edge_elements_) return 0.0;
            return add_element_shares(t.edges(), kEdgeEdges, t, x, density_, lumping_, shares, vertex_masses_,
                                      edge_masses_, [](const auto& p) { return (p[1] - p[0]).norm(); });
    }
    return 0.0;
}

// MeshMatrixMass::init → checkTopology, massInitialization.
void MeshMatrixMass::init() {
    scatter_.clear();  // made again for the topology's edges at the next product on threads
    kind_ = lumped_element_kind(*topology_);
    lumping_coefficient_ = kind_ == LumpedElementKind::edge && !edge_elements_ ? 0.0 : shares_of(kind_).lumping;
    const std::size_t elements = element_count();
    const auto uniform_density = [&](double rho) { density_.assign(elements, rho); };
    const auto from_total = [&](double total) {
        // initFromTotalMass: masses at ρ = 1, ρ = M / Σ (1 when Σ < ε), masses × ρ.
        uniform_density(1.0);
        const double sum = compute_masses();
        const double rho = sum > std::numeric_limits<double>::epsilon() ? total / sum : 1.0;
        uniform_density(rho);
        for (double& m : vertex_masses_) m *= rho;
        for (double& m : edge_masses_) m *= rho;
        total_ = total;
    };
    if (given_total_ || (!given_density_ && !given_vertex_masses_)) {
        from_total(given_total_.value_or(1.0));
    } else if (given_density_) {
        // checkMassDensity, initFromMassDensity.
        if (given_density_->size() == 1) {
            uniform_density(given_density_->front());
        } else if (given_density_->size() == elements) {
            density_ = *given_density_;
        } else {
            throw_invalid_argument("MeshMatrixMass: massDensity has ", given_density_->size(),
                                   " values, expected 1 or one per element (", elements, ")");
        }
        compute_masses();
        double sum = std::accumulate(vertex_masses_.begin(), vertex_masses_.end(), 0.0);
        if (!lumping_) sum += std::accumulate(edge_masses_.begin(), edge_masses_.end(), 0.0) * 2.0;
        else sum *= lumping_coefficient_;
        total_ = sum;
    } else {
        // initFromVertexMass (lumping) or initFromVertexAndEdgeMass.
        const std::vector<double>& vertex = *given_vertex_masses_;
        if (vertex.size() != state_->num_dofs())
            throw_invalid_argument("MeshMatrixMass: vertexMass has ", vertex.size(), " values for ", state_->num_dofs(),
                                   " points");
        if (!given_edge_masses_ && !lumping_)
            throw_invalid_argument(
                "MeshMatrixMass: vertexMass needs lumping or edgeMass (SOFA: 'Initialization "
                "using vertexMass requires the lumping option or the edgeMass information')");
        if (given_edge_masses_ && given_edge_masses_->size() != topology_->edges().size())
            throw_invalid_argument("MeshMatrixMass: edgeMass has ", given_edge_masses_->size(), " values for ",
                                   topology_->edges().size(), " edges");
        double total = std::accumulate(vertex.begin(), vertex.end(), 0.0);
        if (given_edge_masses_) total = std::accumulate(given_edge_masses_->begin(), given_edge_masses_->end(), total);
        uniform_density(1.0);
        compute_masses();
        double volume = 0.0;
        for (double m : vertex_masses_) volume += m * lumping_coefficient_;
        uniform_density(total / volume);
        vertex_masses_ = vertex;
        if (given_edge_masses_) edge_masses_ = *given_edge_masses_;
        total_ = total;
    }
    if (lumping_) edge_masses_.clear();
}

// MeshMatrixMass::addForce: f_i += g·m_i·c.
void MeshMatrixMass::add_gravity_force(const Vec3& g) {
    for (std::size_t i = 0; i < vertex_masses_.size(); ++i)
        state_->force[i] += g * vertex_masses_[i] * lumping_coefficient_;
}

// MeshMatrixMass::addMDx: lumped df_i += dx_i·m_i·c·factor; else df_i += dx_i·m_i·factor, then per
// edge (a, b) with m = m_e·factor: df_a += dx_b·m, df_b += dx_a·m.
void MeshMatrixMass::add_mdx(double factor) {
    auto& df = state_->df;
    const auto& dx = state_->dx;
    if (lumping_) {
        for (std::size_t i = 0; i < vertex_masses_.size(); ++i)
            df[i] += dx[i] * vertex_masses_[i] * lumping_coefficient_ * factor;
        return;
    }
    const std::vector<Edge>& edges = topology_->edges();
    PENALTY_DEMAND(edge_masses_.size() == edges.size());
    // On several threads, from OrderedScatter::kMinElements vertices or edges: the vertices' terms
    // in ranges, then the edges' split in chunks (each vertex's sum in edge order: the bits of one
    // thread)
    const auto vertices = [&](std::size_t first, std::size_t end) {
        for (std::size_t i = first; i < end; ++i) df[i] += dx[i] * vertex_masses_[i] * factor;
    };
    detail::for_each_range(vertex_masses_.size(), kVerticesPerTask, vertices);
    detail::scatter_in_order</*Add=*/true>(
        scatter_, std::span<const Edge>(edges), df, 1, [&](std::size_t first, std::size_t end, const auto& deferred) {
            for (std::size_t j = first; j < end; ++j) {
                const double m = edge_masses_[j] * factor;
                const auto a = static_cast<std::size_t>(edges[j][0]);
                const auto b = static_cast<std::size_t>(edges[j][1]);
                // (dx·m component by component, as Eigen's product: Eigen's expression is not
                // always inlined here)
                const std::array<Vec3, 2> terms{Vec3(dx[b][0] * m, dx[b][1] * m, dx[b][2] * m),
                                                Vec3(dx[a][0] * m, dx[a][1] * m, dx[a][2] * m)};
                detail::store_or_apply(deferred, j, terms,
                                       [&](std::size_t k, const Vec3& term) { df[k == 0 ? a : b] += term; });
            }
        });
}

// MeshMatrixMass::accFromF (lumped): a_i = f_i / (m_i·c).
void MeshMatrixMass::apply_inverse(const Eigen::Ref<const Eigen::VectorXd>& in, Eigen::Ref<Eigen::VectorXd> out) const {
    if (!lumping_)
        throw_invalid_argument(
            "MeshMatrixMass: an explicit solver needs M⁻¹, which the consistent mass matrix does "
            "not give (SOFA's accFromF refuses it too): set lumping=\"1\"");
    for (std::size_t i = 0; i < vertex_masses_.size(); ++i) {
        const auto k = static_cast<Eigen::Index>(3 * i);
        out.segment<3>(k) = in.segment<3>(k) / (vertex_masses_[i] * lumping_coefficient_);
    }
}

void MeshMatrixMass::add_mass_triplets(TripletList& t, Index offset, double factor) const {
    const double vertex_scale = lumping_ ? lumping_coefficient_ : 1.0;
    for (std::size_t i = 0; i < vertex_masses_.size(); ++i)
        for (Index a = 0; a < 3; ++a) {
            const Index r = offset + 3 * static_cast<Index>(i) + a;
            t.emplace_back(r, r, vertex_masses_[i] * vertex_scale * factor);
        }
    const std::vector<Edge>& edges = topology_->edges();
    for (std::size_t j = 0; j < edge_masses_.size(); ++j) {
        const Index a = offset + 3 * Index(edges[j][0]);
        const Index b = offset + 3 * Index(edges[j][1]);
        for (Index c = 0; c < 3; ++c) {
            t.emplace_back(a + c, b + c, edge_masses_[j] * factor);
            t.emplace_back(b + c, a + c, edge_masses_[j] * factor);
        }
    }
}

// MeshMatrixMass::getKineticEnergy: ½ (Σ v_i·v_i m_i c' + Σ_edges 2 v_a·v_b m_e), c' = c lumped, 1 else.
double MeshMatrixMass::kinetic_energy() const {
    const auto& v = state_->velocity;
    const double scale = lumping_ ? lumping_coefficient_ : 1.0;
    double e = 0.0;
    for (std::size_t i = 0; i < vertex_masses_.size(); ++i) e += v[i].dot(v[i]) * vertex_masses_[i] * scale;
    const std::vector<Edge>& edges = topology_->edges();
    for (std::size_t j = 0; j < edge_masses_.size(); ++j)
        e += 2 * v[static_cast<std::size_t>(edges[j][0])].dot(v[static_cast<std::size_t>(edges[j][1])]) *
             edge_masses_[j];
    return e / 2;
}

// MeshMatrixMass::getPotentialEnergy: −Σ (g·x_i) m_i c.
double MeshMatrixMass::gravity_potential_energy(const Vec3& g) const {
    double e = 0.0;
    for (std::size_t i = 0; i < vertex_masses_.size(); ++i)
        e -= g.dot(state_->position[i]) * vertex_masses_[i] * lumping_coefficient_;
    return e;
}

// ---- topological changes ----------------------------------------------------------------------
// MeshMatrixMass::initTopologyHandlers: vertexMass and edgeMass are TopologyData (creation: 0;
// destruction: the value leaves totalMass, an edge's only when not lumped; swap-and-pop), and the
// element events of the mass's own element type add or take each element's shares
// (applyVertexMass<Element>Creation/Destruction, then applyEdgeMass<Element>Creation/Destruction:
// ρ_e|e|/d_v at its vertices, ρ_e|e|/d_e at its edges, totalMass by the same amounts). The
// densities are no topology data: a new element whose index is past their end gets its ancestors'
// weighted density, or the first one (addMassDensity); a removal leaves them as they are, so a
// later element takes the density at its index (SOFA's).
void MeshMatrixMass::handle_topology_changes(const TopologyContainer& container,
                                             std::span<const TopologyChange> changes) {
    scatter_.clear();  // the edges change
    const ElementShares shares = shares_of(kind_);
    const ElementType type = element_type_of(kind_);
    // the element's measure from the current (or rest) positions, and its edges' indices
    const auto measure = [&](ElementId id) {
        const auto v = container.vertices(type, id);
        const std::span<const Vec3> x(on_rest_ ? state_->rest_position : state_->position);
        std::array<Vec3, 8> p;
        for (std::size_t k = 0; k < v.size(); ++k) p[k] = x[std::size_t(v[k])];
        switch (kind_) {
            case LumpedElementKind::triangle:
                return triangle_area(p[0], p[1], p[2]);
            case LumpedElementKind::quad:
                return quad_area(p[0], p[1], p[2], p[3]);
            case LumpedElementKind::tetrahedron:
                return tetrahedron_volume(p[0], p[1], p[2], p[3]);
            case LumpedElementKind::hexahedron:
                return hexahedron_volume(p);
            case LumpedElementKind::edge:
                break;
        }
        return 0.0;
    };
    const auto for_each_edge = [&](ElementId id, auto&& f) {
        const auto v = container.vertices(type, id);
        const auto visit = [&](const auto& local) {
            for (const auto& [a, b] : local) f(container.edge_index(v[std::size_t(a)], v[std::size_t(b)]));
        };
        switch (kind_) {
            case LumpedElementKind::triangle:
                visit(kTriangleEdges);
                break;
            case LumpedElementKind::quad:
                visit(kQuadEdges);
                break;
            case LumpedElementKind::tetrahedron:
                visit(MeshTopology::kTetraEdges);
                break;
            case LumpedElementKind::hexahedron:
                visit(MeshTopology::kHexaEdges);
                break;
            case LumpedElementKind::edge:
                break;
        }
    };
    const double vertex_count = double(vertices_per_element(type));
    const auto apply = [&](std::span<const ElementId> ids, double sign) {
        for (const ElementId id : ids) {  // applyVertexMass<Element>Creation/Destruction
            const double mass = (density_[std::size_t(id)] * measure(id)) / shares.vertex_divisor;
            for (const PointId v : container.vertices(type, id)) vertex_masses_[std::size_t(v)] += sign * mass;
            total_ += sign * (lumping_ ? vertex_count * mass * lumping_coefficient_ : vertex_count * mass);
        }
        if (lumping_) return;
        for (const ElementId id : ids) {  // applyEdgeMass<Element>Creation/Destruction
            const double mass = (density_[std::size_t(id)] * measure(id)) / shares.edge_divisor;
            double edges = 0;
            for_each_edge(id, [&](ElementId e) {
                edge_masses_[std::size_t(e)] += sign * mass;
                ++edges;
            });
            total_ += sign * (edges * mass * 2.0);
        }
    };
    for (const TopologyChange& c : changes) {
        if (c.element == ElementType::point) {
            if (c.kind == TopologyChangeKind::added)
                vertex_masses_.resize(vertex_masses_.size() + c.indices.size(), 0.0);
            else if (c.kind == TopologyChangeKind::removed)
                topology_data_remove(vertex_masses_, c.indices, [&](ElementId, double& m) { total_ -= m; });
            else if (c.kind == TopologyChangeKind::renumbered) topology_data_renumber(vertex_masses_, c.indices);
        } else if (c.element == ElementType::edge && !lumping_) {
            if (c.kind == TopologyChangeKind::added) edge_masses_.resize(edge_masses_.size() + c.indices.size(), 0.0);
            else if (c.kind == TopologyChangeKind::removed)
                topology_data_remove(edge_masses_, c.indices, [&](ElementId, double& m) { total_ -= m; });
        }
        if (c.element != type || kind_ == LumpedElementKind::edge) continue;
        if (c.kind == TopologyChangeKind::added) {
            if (density_.size() < container.count(type))  // addMassDensity
                for (std::size_t k = 0; k < c.indices.size(); ++k) {
                    const bool none = k >= c.ancestors.size() || c.ancestors[k].empty();
                    double rho = none ? density_.front() : 0.0;
                    if (!none)
                        for (std::size_t j = 0; j < c.ancestors[k].size(); ++j)
                            rho += density_[std::size_t(c.ancestors[k][j])] * c.coefficients[k][j];
                    density_.push_back(rho);
                }
            apply(c.indices, +1.0);
        } else if (c.kind == TopologyChangeKind::removed) {
            apply(c.indices, -1.0);
        }
    }
}

}  // namespace penalty
