#include "penalty/mechanics/diagonal_mass.hpp"
#include "penalty/mechanics/element_measures.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"

#include <cmath>
#include <numeric>

namespace penalty {

namespace {

constexpr std::size_t kDiagonalMassDofsPerTask = 4096;  // add_mdx on threads (a large state)

void check_nonnegative(double value, const char* parameter) {
    if (!std::isfinite(value) || value < 0.0)
        throw_invalid_argument("DiagonalMass: ", parameter, " must be finite and >= 0, got ", value);
}

/// Adds density·measure / N to each of the N vertices of every element; returns the sum of the
/// shares, accumulated vertex by vertex as SOFA's computeVertexMass does.
template <std::size_t N, class Measure>
double lump(const std::vector<std::array<PointId, N>>& elements, std::span<const Vec3> x, double density,
            std::vector<double>& masses, Measure measure) {
    double total = 0.0;
    for (const auto& e : elements) {
        std::array<Vec3, N> p;
        for (std::size_t k = 0; k < N; ++k) {
            const auto i = static_cast<std::size_t>(e[k]);
            if (i >= x.size() || i >= masses.size())
                throw_invalid_argument("DiagonalMass: element vertex ", i, " is out of range (", x.size(),
                                       " positions, ", masses.size(), " DOFs)");
            p[k] = x[i];
        }
        const double share = (density * measure(p)) / static_cast<double>(N);
        for (std::size_t k = 0; k < N; ++k) {
            masses[static_cast<std::size_t>(e[k])] += share;
            total += share;
        }
    }
    return total;
}

}  // namespace

LumpedElementKind lumped_element_kind(const MeshTopology& t) {
    if (!t.hexahedra().empty()) return LumpedElementKind::hexahedron;
    if (!t.tetrahedra().empty()) return LumpedElementKind::tetrahedron;
    if (!t.quads().empty()) return LumpedElementKind::quad;
    if (!t.triangles().empty()) return LumpedElementKind::triangle;
    if (!t.edges().empty()) return LumpedElementKind::edge;
    throw_invalid_argument("DiagonalMass: the topology has no element (SOFA: 'Topology empty')");
}

const char* lumped_element_name(LumpedElementKind kind) {
    switch (kind) {
        case LumpedElementKind::hexahedron:
            return "hexahedra";
        case LumpedElementKind::tetrahedron:
            return "tetrahedra";
        case LumpedElementKind::quad:
            return "quads";
        case LumpedElementKind::triangle:
            return "triangles";
        case LumpedElementKind::edge:
            return "edges";
    }
    return "?";
}

ElementType element_type_of(LumpedElementKind kind) {
    switch (kind) {
        case LumpedElementKind::hexahedron:
            return ElementType::hexahedron;
        case LumpedElementKind::tetrahedron:
            return ElementType::tetrahedron;
        case LumpedElementKind::quad:
            return ElementType::quad;
        case LumpedElementKind::triangle:
            return ElementType::triangle;
        case LumpedElementKind::edge:
            return ElementType::edge;
    }
    return ElementType::edge;
}

double lump_vertex_masses(const MeshTopology& t, LumpedElementKind kind, std::span<const Vec3> x, double density,
                          std::size_t num_points, std::vector<double>& masses) {
    masses.assign(num_points, 0.0);
    switch (kind) {
        case LumpedElementKind::edge:
            return lump(t.edges(), x, density, masses, [](const auto& p) { return (p[1] - p[0]).norm(); });
        case LumpedElementKind::triangle:
            return lump(t.triangles(), x, density, masses,
                        [](const auto& p) { return triangle_area(p[0], p[1], p[2]); });
        case LumpedElementKind::quad:
            return lump(t.quads(), x, density, masses, [](const auto& p) { return quad_area(p[0], p[1], p[2], p[3]); });
        case LumpedElementKind::tetrahedron:
            return lump(t.tetrahedra(), x, density, masses,
                        [](const auto& p) { return tetrahedron_volume(p[0], p[1], p[2], p[3]); });
        case LumpedElementKind::hexahedron:
            return lump(t.hexahedra(), x, density, masses, [](const auto& p) { return hexahedron_volume(p); });
    }
    return 0.0;
}

double lumped_element_measure(LumpedElementKind kind, std::span<const Vec3> p) {
    switch (kind) {
        case LumpedElementKind::edge:
            return (p[1] - p[0]).norm();
        case LumpedElementKind::triangle:
            return triangle_area(p[0], p[1], p[2]);
        case LumpedElementKind::quad:
            return triangle_area(p[0], p[1], p[2]) + triangle_area(p[0], p[2], p[3]);
        case LumpedElementKind::tetrahedron:
            return tetrahedron_volume(p[0], p[1], p[2], p[3]);
        case LumpedElementKind::hexahedron: {
            std::array<Vec3, 8> n;
            std::copy(p.begin(), p.begin() + 8, n.begin());
            return hexahedron_volume(n);
        }
    }
    return 0.0;
}

void DiagonalMass::set_mass_density(double density) {
    check_nonnegative(density, "massDensity");
    given_density_ = density;
}

void DiagonalMass::set_total_mass(double total) {
    check_nonnegative(total, "totalMass");
    given_total_ = total;
}

void DiagonalMass::set_vertex_masses(std::vector<double> masses) {
    for (double m : masses) check_nonnegative(m, "vertexMass");
    given_masses_ = std::move(masses);
}

// SOFA's DiagonalMass::init → massInitialization: totalMass wins, then massDensity, then
// vertexMass; none gives totalMass = 1. ρ is deduced as total / Σ(shares at ρ = 1), or 1 when that
// sum is below machine epsilon.
void DiagonalMass::init() {
    kind_ = lumped_element_kind(*topology_);
    const std::size_t n = state_->num_dofs();
    const std::span<const Vec3> x0(state_->rest_position);
    auto density_for = [](double total, double sum) {
        return sum < std::numeric_limits<double>::epsilon() ? 1.0 : total / sum;
    };
    if (given_total_ || (!given_density_ && !given_masses_)) {
        total_ = given_total_.value_or(1.0);
        density_ = density_for(total_, lump_vertex_masses(*topology_, kind_, x0, 1.0, n, masses_));
        for (double& m : masses_) m *= density_;
    } else if (given_density_) {
        density_ = *given_density_;
        total_ = lump_vertex_masses(*topology_, kind_, x0, density_, n, masses_);
    } else {
        std::vector<double> given = *given_masses_;
        if (given.size() > n)
            throw_invalid_argument("DiagonalMass: vertexMass has ", given.size(), " values for ", n, " DOFs");
        if (given.empty()) throw_invalid_argument("DiagonalMass: vertexMass is empty");
        given.resize(n, given.back());  // SOFA's init pads a short list with its last value
        total_ = std::accumulate(given.begin(), given.end(), 0.0);
        density_ = density_for(total_, lump_vertex_masses(*topology_, kind_, x0, 1.0, n, masses_));
        masses_ = std::move(given);
    }
}

// DiagonalMass::addForce: f_i += g·m_i.
void DiagonalMass::add_gravity_force(const Vec3& g) {
    for (std::size_t i = 0; i < masses_.size(); ++i) state_->force[i] += g * masses_[i];
}

// DiagonalMass::addMDx: df_i += dx_i·m_i (times factor when factor ≠ 1).
void DiagonalMass::add_mdx(double factor) {
    // (each DOF its own: on TBB's threads for a large state, the same bits)
    Vec3* df = state_->df.data();
    const Vec3* dx = state_->dx.data();
    const double* m = masses_.data();
    detail::for_each_range(masses_.size(), kDiagonalMassDofsPerTask, [=](std::size_t first, std::size_t end) {
        // (locals: a store through df could otherwise alias the closure's copies, read again each time)
        Vec3* const out = df;
        const Vec3* const in = dx;
        const double* const mass = m;
        const double f = factor;
        if (f == 1.0) {
            for (std::size_t i = first; i < end; ++i) out[i] += in[i] * mass[i];
        } else {
            for (std::size_t i = first; i < end; ++i) out[i] += (in[i] * mass[i]) * f;
        }
    });
}

// DiagonalMass::accFromF: a_i = f_i / m_i.
void DiagonalMass::apply_inverse(const Eigen::Ref<const Eigen::VectorXd>& in, Eigen::Ref<Eigen::VectorXd> out) const {
    for (std::size_t i = 0; i < masses_.size(); ++i) {
        const auto k = static_cast<Eigen::Index>(3 * i);
        out.segment<3>(k) = in.segment<3>(k) / masses_[i];
    }
}

void DiagonalMass::add_mass_triplets(TripletList& t, Index offset, double factor) const {
    for (std::size_t i = 0; i < masses_.size(); ++i)
        for (Index a = 0; a < 3; ++a)
            t.emplace_back(offset + 3 * static_cast<Index>(i) + a, offset + 3 * static_cast<Index>(i) + a,
                           masses_[i] * factor);
}

// DiagonalMass::getKineticEnergy: ½ Σ (v_i m_i)·v_i.
double DiagonalMass::kinetic_energy() const {
    double e = 0.0;
    for (std::size_t i = 0; i < masses_.size(); ++i) e += (state_->velocity[i] * masses_[i]).dot(state_->velocity[i]);
    return e / 2;
}

// DiagonalMass::getPotentialEnergy: −Σ (g·x_i) m_i.
double DiagonalMass::gravity_potential_energy(const Vec3& g) const {
    double e = 0.0;
    for (std::size_t i = 0; i < masses_.size(); ++i) e -= g.dot(state_->position[i]) * masses_[i];
    return e;
}

}  // namespace penalty
