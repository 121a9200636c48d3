#include "penalty/mechanics/fem.hpp"
#include "tetrahedron_large_blocks.hpp"
#include "tetrahedron_large_element.hpp"

#include "penalty/core/first_error.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"
#include "sofa_vector_ops.hpp"

#include <tbb/task_arena.h>
#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <variant>

namespace penalty {

namespace {
constexpr std::size_t kElementsPerInitTask = 1024;  // init_from on TBB's threads (a large mesh)
}  // namespace

Eigen::Matrix<double, 6, 6> isotropic_elasticity(double e, double nu) {
    const double lambda = e * nu / ((1 + nu) * (1 - 2 * nu));
    const double mu = e / (2 * (1 + nu));
    Eigen::Matrix<double, 6, 6> d = Eigen::Matrix<double, 6, 6>::Zero();
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) d(i, j) = lambda;
        d(i, i) = lambda + 2 * mu;
        d(i + 3, i + 3) = mu;
    }
    return d;
}

namespace {
/// Strain-displacement rows for one node with shape-function gradient g (Voigt, engineering shear).
void fill_b(Eigen::Matrix<double, 6, Eigen::Dynamic>& b, int node, const Vec3& g) {
    const int c = 3 * node;
    b(0, c) = g.x();
    b(1, c + 1) = g.y();
    b(2, c + 2) = g.z();
    b(3, c) = g.y();
    b(3, c + 1) = g.x();
    b(4, c + 1) = g.z();
    b(4, c + 2) = g.y();
    b(5, c) = g.z();
    b(5, c + 2) = g.x();
}
}  // namespace

template <int N>
LinearElementForceField<N>::LinearElementForceField(Vec3Object& state, std::vector<Element> elements, double young,
                                                    double poisson, FemMethod method, const char* component)
    : ForceField<Vec3Types>(state),
      elements_(std::move(elements)),
      young_(young),
      poisson_(poisson),
      method_(method),
      component_(component) {
    if (!std::isfinite(young) || young <= 0)
        throw_invalid_argument(component, ": youngModulus must be finite and > 0, got ", young);
    if (!std::isfinite(poisson) || poisson <= -1.0 || poisson >= 0.5)
        throw_invalid_argument(component, ": poissonRatio must be in (-1, 0.5), got ", poisson);
}

template <int N>
void LinearElementForceField<N>::init() {
    init_from(0);
}

template <int N>
void LinearElementForceField<N>::init_from(std::size_t first) {
    const auto& x0 = state_->rest_position;
    const Eigen::Matrix<double, 6, 6> d = isotropic_elasticity(young_, poisson_);
    const bool keep_rotations = keeps_rotations();
    product_scatter_.clear();  // made again for these elements at the next product on threads
    const bool stiffness_now = element_stiffness_at_init();
    if (stiffness_now) {
        ke_.resize(elements_.size());
        stiffness_rest_.clear();  // (only for K^e on demand)
    } else {
        ke_.clear();  // (made again, for every element, when next asked for)
        stiffness_rest_.resize(elements_.size());
    }
    rest_local_.resize(elements_.size());
    if (keep_rotations) rotation_.resize(elements_.size(), Mat3::Identity());
    // each element its own rotation, rest shape and K^e (a large mesh's on TBB's threads); the
    // error raised is the first element's in order
    const auto init_element = [&](std::size_t e) {
        std::array<Vec3, N> p;
        for (int k = 0; k < N; ++k) {
            const PointId v = elements_[e][static_cast<std::size_t>(k)];
            if (v < 0 || static_cast<std::size_t>(v) >= x0.size())
                throw_invalid_argument(component_, ": element ", e, " uses vertex ", v, " out of range (", x0.size(),
                                       " DOFs)");
            p[static_cast<std::size_t>(k)] = x0[static_cast<std::size_t>(v)];
        }
        const Mat3 r = method_ != FemMethod::Small ? element_rotation(p) : Mat3::Identity();
        if (keep_rotations) rotation_[e] = r;
        for (int k = 0; k < N; ++k)
            rest_local_[e][static_cast<std::size_t>(k)] = r * (p[static_cast<std::size_t>(k)] - p[0]);
        if (stiffness_now) {
            ke_[e] = compute_stiffness(rest_local_[e], d, e);
        } else {
            check_rest_element(rest_local_[e], e);
            stiffness_rest_[e] = rest_local_[e];
        }
    };
    FirstErrorInOrder failure;
    detail::for_each_range(elements_.size() - std::min(first, elements_.size()), kElementsPerInitTask,
                           [&](std::size_t begin, std::size_t end) {
                               for (std::size_t e = first + begin; e < first + end; ++e)
                                   if (!failure.run(e, [&] { init_element(e); })) return;
                           });
    failure.rethrow_if_any();
}

template <int N>
const std::vector<typename LinearElementForceField<N>::ElementMatrix>& LinearElementForceField<N>::element_stiffness()
    const {
    const std::lock_guard lock(stiffness_mutex_);
    const std::size_t n = elements_.size();
    if (ke_.size() != n && stiffness_rest_.size() == n) {
        // on demand: init's compute_stiffness of the same rest coordinates and material (the
        // element checks passed at init); isolated, so that a thread waiting here for the ranges
        // takes no outer task that could ask again
        const Eigen::Matrix<double, 6, 6> d = isotropic_elasticity(young_, poisson_);
        ke_.resize(n);
        tbb::this_task_arena::isolate([&] {
            detail::for_each_range(n, kElementsPerInitTask, [&](std::size_t begin, std::size_t end) {
                for (std::size_t e = begin; e < end; ++e) ke_[e] = compute_stiffness(stiffness_rest_[e], d, e);
            });
        });
    }
    return ke_;
}

template <int N>
void LinearElementForceField<N>::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3>) {
    PENALTY_DEMAND(ke_.size() == elements_.size());
    // u = R·(p_k − p_0) − r_k (small: p_k − x⁰_k), f_k −= Rᵀ·(K^e·u)_k, energy ½ uᵀK^e u
    energy_ = force_in_order</*Add=*/false>(
        f, 1, [&](std::size_t first, std::size_t end, const auto& deferred, double* energies) {
            double total = 0.0;
            Eigen::Matrix<double, 3 * N, 1> u;
            for (std::size_t e = first; e < end; ++e) {
                const auto& el = elements_[e];
                std::array<Vec3, N> p;
                for (int k = 0; k < N; ++k)
                    p[static_cast<std::size_t>(k)] = x[static_cast<std::size_t>(el[static_cast<std::size_t>(k)])];
                if (method_ != FemMethod::Small) {
                    rotation_[e] = element_rotation_of(p, e);
                    for (int k = 0; k < N; ++k)
                        u.template segment<3>(3 * k) = rotation_[e] * (p[static_cast<std::size_t>(k)] - p[0]) -
                                                       rest_local_[e][static_cast<std::size_t>(k)];
                } else {
                    for (int k = 0; k < N; ++k)
                        u.template segment<3>(3 * k) =
                            p[static_cast<std::size_t>(k)] -
                            state_->rest_position[static_cast<std::size_t>(el[static_cast<std::size_t>(k)])];
                }
                const Eigen::Matrix<double, 3 * N, 1> fl = ke_[e] * u;
                const double energy = 0.5 * u.dot(fl);
                if (energies) energies[e] = energy;
                else total += energy;
                std::array<Vec3, N> terms;
                for (int k = 0; k < N; ++k)
                    terms[static_cast<std::size_t>(k)] = rotation_[e].transpose() * fl.template segment<3>(3 * k);
                detail::store_or_apply(deferred, e, terms, [&](std::size_t k, const Vec3& term) {
                    f[static_cast<std::size_t>(el[k])] -= term;
                });
            }
            return total;
        });
}

template <int N>
void LinearElementForceField<N>::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                            double) const {
    // df_k −= k·(Rᵀ·(K^e·(R·dx))_k)
    scatter_in_order</*Add=*/false>(df, 1, [&](std::size_t first, std::size_t end, const auto& deferred) {
        Eigen::Matrix<double, 3 * N, 1> u;
        for (std::size_t e = first; e < end; ++e) {
            const auto& el = elements_[e];
            for (int k = 0; k < N; ++k)
                u.template segment<3>(3 * k) =
                    rotation_[e] * dx[static_cast<std::size_t>(el[static_cast<std::size_t>(k)])];
            const Eigen::Matrix<double, 3 * N, 1> fl = ke_[e] * u;
            std::array<Vec3, N> terms;
            for (int k = 0; k < N; ++k)
                terms[static_cast<std::size_t>(k)] =
                    k_factor * (rotation_[e].transpose() * fl.template segment<3>(3 * k));
            detail::store_or_apply(deferred, e, terms, [&](std::size_t k, const Vec3& term) {
                df[static_cast<std::size_t>(el[k])] -= term;
            });
        }
    });
}

template <int N>
void LinearElementForceField<N>::add_stiffness_triplets(TripletList& t, Index offset, double factor) const {
    (void)element_stiffness();  // (made on demand: add_element_triplets reads it)
    for (std::size_t e = 0; e < elements_.size(); ++e) add_element_triplets(t, offset, factor, e, rotation_[e]);
}

template <int N>
void LinearElementForceField<N>::add_element_triplets(TripletList& t, Index offset, double factor, std::size_t e,
                                                      const Mat3& r) const {
    const auto& el = elements_[e];
    for (int a = 0; a < N; ++a)
        for (int b = 0; b < N; ++b) {
            const Mat3 blk = -factor * r.transpose() * ke_[e].template block<3, 3>(3 * a, 3 * b) * r;
            const Index ra = offset + 3 * el[static_cast<std::size_t>(a)];
            const Index cb = offset + 3 * el[static_cast<std::size_t>(b)];
            for (Index row = 0; row < 3; ++row)
                for (Index c = 0; c < 3; ++c) t.emplace_back(ra + row, cb + c, blk(row, c));
        }
}

template class LinearElementForceField<4>;
template class LinearElementForceField<8>;

Mat3 polar_rotation(const Mat3& m) {
    // helper::Decompose::polarDecomposition: Higham's iteration on Mk = Mᵀ, SOFA's sums left to
    // right (oneNorm, infNorm, the determinant as a row·cofactor product)
    const auto one_norm = [](const Mat3& a) {
        double norm = 0.0;
        for (int i = 0; i < 3; ++i) norm = std::max(norm, std::abs(a(0, i)) + std::abs(a(1, i)) + std::abs(a(2, i)));
        return norm;
    };
    const auto inf_norm = [](const Mat3& a) {
        double norm = 0.0;
        for (int i = 0; i < 3; ++i) norm = std::max(norm, std::abs(a(i, 0)) + std::abs(a(i, 1)) + std::abs(a(i, 2)));
        return norm;
    };
    const auto row = [](const Mat3& a, int i) { return Vec3(a(i, 0), a(i, 1), a(i, 2)); };
    Mat3 x = m.transpose();
    double x_one = one_norm(x), x_inf = inf_norm(x);
    for (int iteration = 0; iteration < 100; ++iteration) {
        Mat3 cofactor;
        cofactor.row(0) = sofa_vec::cross(row(x, 1), row(x, 2));
        cofactor.row(1) = sofa_vec::cross(row(x, 2), row(x, 0));
        cofactor.row(2) = sofa_vec::cross(row(x, 0), row(x, 1));
        const double det = sofa_vec::dot3(row(x, 0), row(cofactor, 0));
        if (det == 0.0) break;
        const double gamma =
            std::sqrt(std::sqrt((one_norm(cofactor) * inf_norm(cofactor)) / (x_one * x_inf)) / std::abs(det));
        const Mat3 next = x * (gamma * 0.5) + cofactor * (0.5 / (gamma * det));
        const double change = one_norm(x - next);
        x = next;
        x_one = one_norm(x);
        x_inf = inf_norm(x);
        if (!(change > x_one * 1e-8)) break;
    }
    return x.transpose();
}

// ---- tetrahedron --------------------------------------------------------------------------------
namespace {
std::vector<Tetrahedron> tetrahedra_of(const MeshTopology& topo, int nx, int ny) {
    if (!topo.tetrahedra().empty()) return topo.tetrahedra();
    return tetrahedra_from_hexahedra(topo.hexahedra(), nx, ny);
}
}  // namespace

TetrahedronFEMForceField::TetrahedronFEMForceField(Vec3Object& state, const MeshTopology& topology, double young,
                                                   double poisson, FemMethod method)
    : LinearElementForceField<4>(state, tetrahedra_of(topology, 2, 1), young, poisson, method,
                                 "TetrahedronFEMForceField") {}

TetrahedronFEMForceField::TetrahedronFEMForceField(Vec3Object& state, const RegularGridTopology& grid, double young,
                                                   double poisson, FemMethod method)
    : LinearElementForceField<4>(state, tetrahedra_of(grid.mesh(), grid.cells_x(), grid.cells_y()), young, poisson,
                                 method, "TetrahedronFEMForceField") {}

namespace {
/// The columns p1 − p0, p2 − p0, p3 − p0 of a tetrahedron's rest coordinates p;
/// std::invalid_argument naming element e when it is degenerate.
Mat3 checked_rest_edges(const std::array<Vec3, 4>& p, std::size_t e, const char* component) {
    Mat3 m;
    m << p[1] - p[0], p[2] - p[0], p[3] - p[0];
    const double det = m.determinant();
    const double scale = std::max({(p[1] - p[0]).norm(), (p[2] - p[0]).norm(), (p[3] - p[0]).norm()});
    if (!std::isfinite(det) || std::abs(det) <= 1e-12 * scale * scale * scale)
        throw_invalid_argument(component, ": tetrahedron ", e, " is degenerate (volume ", det / 6, ")");
    return m;
}
}  // namespace

void TetrahedronFEMForceField::check_rest_element(const std::array<Vec3, 4>& p, std::size_t e) const {
    (void)checked_rest_edges(p, e, component_);
}

TetrahedronFEMForceField::ElementMatrix TetrahedronFEMForceField::compute_stiffness(
    const std::array<Vec3, 4>& p, const Eigen::Matrix<double, 6, 6>& d, std::size_t e) const {
    const Mat3 m = checked_rest_edges(p, e, component_);
    const double det = m.determinant();
    const Mat3 inv = m.inverse();  // rows: gradients of N1, N2, N3
    const std::array<Vec3, 4> gradients{(-(inv.row(0) + inv.row(1) + inv.row(2))).transpose(), inv.row(0).transpose(),
                                        inv.row(1).transpose(), inv.row(2).transpose()};
    const double volume = std::abs(det) / 6.0;
    return tetrahedron_stiffness_from_gradients(gradients, d, volume);
}

Eigen::Matrix<double, 12, 12> tetrahedron_stiffness_from_gradients(const std::array<Vec3, 4>& gradients,
                                                                   const Eigen::Matrix<double, 6, 6>& d, double scale) {
    Eigen::Matrix<double, 6, Eigen::Dynamic> b = Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, 12);
    for (int k = 0; k < 4; ++k) fill_b(b, k, gradients[static_cast<std::size_t>(k)]);
    return scale * b.transpose() * d * b;
}

namespace {
/// Rows (x̂, ŷ, ẑ) of the element frame: x̂ along `first`, ẑ normal to (first, second), ŷ = ẑ × x̂
/// (SOFA's corotational frame for tetrahedra and hexahedra).
Mat3 frame_from_axes(const Vec3& first, const Vec3& second) {
    const Vec3 xh = first.normalized();
    const Vec3 zh = first.cross(second).normalized();
    Mat3 r;
    r.row(0) = xh;
    r.row(1) = zh.cross(xh);
    r.row(2) = zh;
    return r;
}
}  // namespace

Mat3 TetrahedronFEMForceField::element_rotation(const std::array<Vec3, 4>& p) const {
    return tetrahedron_rotation(p, method_);
}

void TetrahedronFEMForceField::init() { init_elements(0); }

void TetrahedronFEMForceField::init_elements(std::size_t first) {
    LinearElementForceField<4>::init_from(first);
    init_large(first);
    if (method_ != FemMethod::Svd) return;
    // TetrahedronFEMForceField::initSVD: A₀⁻¹ and R₀ = polar(A₀) of the rest edges
    const auto& x0 = state_->rest_position;
    rest_edges_inverse_.resize(elements_.size());
    rest_rotation_.resize(elements_.size());
    for (std::size_t e = first; e < elements_.size(); ++e) {
        std::array<Vec3, 4> p;
        for (std::size_t k = 0; k < 4; ++k) p[k] = x0[static_cast<std::size_t>(elements_[e][k])];
        const Mat3 a0 = detail::edge_rows(p[0], p[1], p[2], p[3]);
        if (a0.determinant() == 0.0)
            throw_invalid_argument(component_, ": tetrahedron ", e, " is flat at rest (method svd)");
        rest_edges_inverse_[e] = sofa_vec::inverse(a0);  // Mat::invert
        rest_rotation_[e] = polar_rotation(a0);
    }
}

// ---- tetrahedron, method large, in SOFA's operation order ----------------------------------------
Mat3 TetrahedronFEMForceField::large_rotation(std::size_t e) const { return detail::large_block_rotation(large_, e); }

void TetrahedronFEMForceField::copy_large(std::size_t from, std::size_t to) {
    detail::copy_large_element(large_, from, to);
}

bool TetrahedronFEMForceField::large_fits(std::size_t count) const {
    return detail::large_blocks_fit(large_, count, kernel_path_);
}

void TetrahedronFEMForceField::resize_large(std::size_t count) {
    detail::resize_large_blocks(large_, count, kernel_path_);
}

void TetrahedronFEMForceField::init_large(std::size_t first) {
    // TetrahedronFEMForceField::reinit: computeMaterialStiffness then initSmall, initLarge,
    // initPolar or initSVD per element
    const auto& x0 = state_->rest_position;
    resize_large(elements_.size());
    // each element its own lanes, K^e and rest shape; a large mesh's in ranges on TBB's threads,
    // whole lane blocks a range (only a block that `first` splits is written by two ranges, each
    // its own lanes)
    static_assert(kElementsPerInitTask % 8 == 0);
    const auto init_element = [&](std::size_t e) {
        std::array<Vec3, 4> x;
        for (std::size_t k = 0; k < 4; ++k) x[k] = x0[static_cast<std::size_t>(elements_[e][k])];
        const double factor =
            young_factors_.empty() ? 1.0 : young_factors_[e * young_factors_.size() / elements_.size()];
        const double young = young_factors_.empty() ? young_ : factor * young_;
        if (!young_factors_.empty()) ke_[e] *= factor;  // the assembled K^e (linear in E)
        Mat3 r0;
        rest_local_[e] = detail::rest_coordinates(method_, x, r0);
        detail::store_large_element(large_, e, detail::material_over_volume(young, poisson_, x), rest_local_[e], r0);
    };
    const std::size_t from = std::min(first, elements_.size());
    detail::for_each_range(elements_.size() - from, kElementsPerInitTask, [&](std::size_t begin, std::size_t end) {
        for (std::size_t e = from + begin; e < from + end; ++e) init_element(e);
    });
}

void TetrahedronFEMForceField::set_kernel_path(KernelPath path) {
    kernel_path_ = checked_kernel_path(path, "TetrahedronFEMForceField", /*has_avx512=*/true);
    // after init: the data move to the path's width (before, init gives them that width)
    const bool initialised = std::visit([](const auto& blocks) { return !blocks.empty(); }, large_);
    if (initialised) resize_large(elements_.size());
}

void TetrahedronFEMForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> /*v*/) {
    PENALTY_DEMAND(large_fits(elements_.size()));
    if (method_ != FemMethod::Large) {
        energy_ = force_in_order</*Add=*/true>(
            f, 8, [&](std::size_t first, std::size_t end, const detail::DeferredTerms& deferred, double* energies) {
                return force_per_element(first, end, f, x, deferred, energies);
            });
        return;
    }
    if (plasticity_.max_threshold > 0) {  // (tetrahedron_plasticity.cpp)
        add_force_plastic(f, x);
        return;
    }
    // the chunks' first elements on a lane block's boundary (eight lanes, four dividing it)
    energy_ = force_in_order</*Add=*/true>(
        f, 8, [&](std::size_t first, std::size_t end, const detail::DeferredTerms& deferred, double* energies) {
            return large_force(first, end, f, x, deferred, energies);
        });
}

double TetrahedronFEMForceField::large_force(std::size_t first, std::size_t end, std::span<Vec3> f,
                                             std::span<const Vec3> x, const detail::DeferredTerms& deferred,
                                             double* energies) {
    return detail::large_blocks_force(large_, kernel_path_, rest_local_, elements_, {first, end}, f, x, deferred,
                                      energies);
}

double TetrahedronFEMForceField::force_per_element(std::size_t first, std::size_t end, std::span<Vec3> f,
                                                   std::span<const Vec3> x, const detail::DeferredTerms& deferred,
                                                   double* energies) {
    const detail::ElementRotationOf svd_rotation = [this](const std::array<Vec3, 4>& p, std::size_t e) {
        return element_rotation_of(p, e);
    };
    return detail::per_element_blocks_force(large_, method_, rest_local_, elements_, {first, end}, f, x, deferred,
                                            energies, method_ == FemMethod::Svd ? &svd_rotation : nullptr);
}

void TetrahedronFEMForceField::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                          double /*b_factor*/) const {
    PENALTY_DEMAND(large_fits(elements_.size()));
    scatter_in_order</*Add=*/false>(df, 8,
                                    [&](std::size_t first, std::size_t end, const detail::DeferredTerms& deferred) {
                                        // TetrahedronFEMForceField::applyStiffnessSmall: df −= F(dx, kFactor);
                                        // applyStiffnessCorotational (large, polar, svd): df −= Rᵀ·F(R·dx, kFactor)
                                        if (method_ == FemMethod::Small)
                                            small_dforce(first, end, df, dx, k_factor, deferred);
                                        else large_dforce(first, end, df, dx, k_factor, deferred);
                                    });
}

void TetrahedronFEMForceField::small_dforce(std::size_t first, std::size_t end, std::span<Vec3> df,
                                            std::span<const Vec3> dx, double k_factor,
                                            const detail::DeferredTerms& deferred) const {
    detail::small_blocks_dforce(large_, elements_, {first, end}, df, dx, k_factor, deferred);
}

void TetrahedronFEMForceField::large_dforce(std::size_t first, std::size_t end, std::span<Vec3> df,
                                            std::span<const Vec3> dx, double k_factor,
                                            const detail::DeferredTerms& deferred) const {
    detail::large_blocks_dforce(large_, kernel_path_, elements_, {first, end}, df, dx, k_factor, deferred);
}

void TetrahedronFEMForceField::add_stiffness_triplets(TripletList& t, Index offset, double factor) const {
    (void)element_stiffness();  // (made on demand: add_element_triplets reads it)
    for (std::size_t e = 0; e < elements_.size(); ++e) add_element_triplets(t, offset, factor, e, large_rotation(e));
}

Mat3 TetrahedronFEMForceField::element_rotation_of(const std::array<Vec3, 4>& p, std::size_t e) const {
    if (method_ != FemMethod::Svd) return element_rotation(p);
    const Mat3 a = detail::edge_rows(p[0], p[1], p[2], p[3]);
    const Mat3 f = a * rest_edges_inverse_[e];
    if (sofa_vec::determinant(f) < 1e-6) return stable_polar_rotation(f) * rest_rotation_[e];  // inverted or too flat
    return polar_rotation(a);
}

Mat3 stable_polar_rotation(const Mat3& f) {
    const Eigen::SelfAdjointEigenSolver<Mat3> eigen(f.transpose() * f);
    Mat3 v = eigen.eigenvectors();
    Vec3 s = eigen.eigenvalues();  // squared singular values
    if (v.determinant() < 0.0) v.col(0) = -v.col(0);
    int degenerated = 0;
    Vec3 s_inverse;
    for (int i = 0; i < 3; ++i) {
        if (s[i] < 1e-8) {
            ++degenerated;
            s[i] = 0.0;
            s_inverse[i] = 1.0;
        } else {
            s[i] = std::sqrt(s[i]);
            s_inverse[i] = 1.0 / s[i];
        }
    }
    // order[0] the smallest value, order[2] the largest (SOFA's Sorder, ties as SOFA)
    std::array<int, 3> order{};
    if (s[0] < s[1]) {
        if (s[0] < s[2]) order = s[1] < s[2] ? std::array<int, 3>{0, 1, 2} : std::array<int, 3>{0, 2, 1};
        else order = {2, 0, 1};
    } else {
        if (s[1] < s[2]) order = s[0] < s[2] ? std::array<int, 3>{1, 0, 2} : std::array<int, 3>{1, 2, 0};
        else order = {2, 1, 0};
    }
    Mat3 u = f * v * s_inverse.asDiagonal();
    if (degenerated == 1) {
        u.col(order[0]) = u.col(order[1]).cross(u.col(order[2]));
    } else if (degenerated == 2) {
        // SOFA's third edge mixes two columns' entries: (U(0, o2), U(1, o0), U(2, o0)), kept as SOFA
        const Vec3 edge2(u(0, order[2]), u(1, order[0]), u(2, order[0]));
        const Vec3 a = edge2.cwiseAbs();
        Vec3 edge0 =
            a[0] > a[1] ? (a[0] > a[2] ? Vec3(0, 1, 0) : Vec3(1, 0, 0)) : (a[1] > a[2] ? Vec3(0, 0, 1) : Vec3(1, 0, 0));
        const Vec3 edge1 = edge2.cross(edge0).normalized();
        edge0 = edge1.cross(edge2);
        u.col(order[0]) = edge0;
        u.col(order[1]) = edge1;
    } else if (degenerated == 3) {
        u.setIdentity();
    }
    if (u.determinant() < 0.0) u.col(order[0]) = -u.col(order[0]);
    return u * v.transpose();
}

Mat3 tetrahedron_rotation(const std::array<Vec3, 4>& p, FemMethod method) {
    if (method == FemMethod::Small) return Mat3::Identity();
    if (method == FemMethod::Polar || method == FemMethod::Svd)
        return polar_rotation(detail::edge_rows(p[0], p[1], p[2], p[3]));  // accumulateForcePolar's A
    return frame_from_axes(p[1] - p[0], p[2] - p[0]);
}

}  // namespace penalty
