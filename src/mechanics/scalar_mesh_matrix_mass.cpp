// MeshMatrixMass<Vec1d, Vec3d> (include/penalty/mechanics/scalar_mesh_matrix_mass.hpp): the
// masses of MeshMatrixMass<Vec3d> on the geometry, applied to one value per point, in the order
// of SOFA's MeshMatrixMass::addMDx / addForce / getKineticEnergy (mesh_matrix_mass.cpp).
#include "penalty/mechanics/scalar_mesh_matrix_mass.hpp"

#include "penalty/core/error.hpp"

namespace penalty {

ScalarMeshMatrixMass::ScalarMeshMatrixMass(Vec1Object& state, Vec3Object& geometry, const MeshTopology& topology)
    : state_(&state), geometry_(&geometry), masses_(std::make_unique<MeshMatrixMass>(geometry, topology)) {}

void ScalarMeshMatrixMass::init() {
    if (geometry_->num_dofs() != state_->num_dofs())
        throw_invalid_argument("MeshMatrixMass<Vec1d,Vec3d>: the geometry state has ", geometry_->num_dofs(),
                               " points, the state ", state_->num_dofs(), " values");
    masses_->init();
}

// f_i += g_x·m_i·c
void ScalarMeshMatrixMass::add_gravity_force(const Vec3& g) {
    const std::vector<double>& m = masses_->vertex_masses();
    const double c = masses_->lumping_coefficient();
    for (std::size_t i = 0; i < m.size(); ++i) state_->force[i] += g[0] * m[i] * c;
}

void ScalarMeshMatrixMass::add_mdx(double factor) {
    auto& df = state_->df;
    const auto& dx = state_->dx;
    const std::vector<double>& m = masses_->vertex_masses();
    if (masses_->lumping()) {
        const double c = masses_->lumping_coefficient();
        for (std::size_t i = 0; i < m.size(); ++i) df[i] += dx[i] * m[i] * c * factor;
        return;
    }
    for (std::size_t i = 0; i < m.size(); ++i) df[i] += dx[i] * m[i] * factor;
    const std::vector<double>& me = masses_->edge_masses();
    const std::vector<Edge>& edges = masses_->topology().edges();
    for (std::size_t j = 0; j < me.size(); ++j) {
        const double mj = me[j] * factor;
        const auto a = static_cast<std::size_t>(edges[j][0]);
        const auto b = static_cast<std::size_t>(edges[j][1]);
        df[a] += dx[b] * mj;
        df[b] += dx[a] * mj;
    }
}

void ScalarMeshMatrixMass::apply_inverse(const Eigen::Ref<const Eigen::VectorXd>& in,
                                         Eigen::Ref<Eigen::VectorXd> out) const {
    if (!masses_->lumping())
        throw_invalid_argument(
            "MeshMatrixMass<Vec1d,Vec3d>: an explicit solver needs M⁻¹, which the consistent mass "
            "matrix does not give (SOFA's accFromF refuses it too): set lumping=\"1\"");
    const std::vector<double>& m = masses_->vertex_masses();
    const double c = masses_->lumping_coefficient();
    for (std::size_t i = 0; i < m.size(); ++i) out[Eigen::Index(i)] = in[Eigen::Index(i)] / (m[i] * c);
}

void ScalarMeshMatrixMass::add_mass_triplets(TripletList& t, Index offset, double factor) const {
    const std::vector<double>& m = masses_->vertex_masses();
    const double scale = masses_->lumping() ? masses_->lumping_coefficient() : 1.0;
    for (std::size_t i = 0; i < m.size(); ++i)
        t.emplace_back(offset + Index(i), offset + Index(i), m[i] * scale * factor);
    const std::vector<double>& me = masses_->edge_masses();
    const std::vector<Edge>& edges = masses_->topology().edges();
    for (std::size_t j = 0; j < me.size(); ++j) {
        const Index a = offset + Index(edges[j][0]);
        const Index b = offset + Index(edges[j][1]);
        t.emplace_back(a, b, me[j] * factor);
        t.emplace_back(b, a, me[j] * factor);
    }
}

// ½ (Σ v_i² m_i c' + Σ_edges 2 v_a v_b m_e)
double ScalarMeshMatrixMass::kinetic_energy() const {
    const auto& v = state_->velocity;
    const std::vector<double>& m = masses_->vertex_masses();
    const double scale = masses_->lumping() ? masses_->lumping_coefficient() : 1.0;
    double e = 0.0;
    for (std::size_t i = 0; i < m.size(); ++i) e += v[i] * v[i] * m[i] * scale;
    const std::vector<double>& me = masses_->edge_masses();
    const std::vector<Edge>& edges = masses_->topology().edges();
    for (std::size_t j = 0; j < me.size(); ++j)
        e += 2 * v[std::size_t(edges[j][0])] * v[std::size_t(edges[j][1])] * me[j];
    return e / 2;
}

// −Σ g_x·x_i·m_i·c
double ScalarMeshMatrixMass::gravity_potential_energy(const Vec3& g) const {
    const std::vector<double>& m = masses_->vertex_masses();
    double e = 0.0;
    for (std::size_t i = 0; i < m.size(); ++i) e -= g[0] * state_->position[i] * m[i] * masses_->lumping_coefficient();
    return e;
}

}  // namespace penalty
