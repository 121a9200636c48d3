#include "penalty/mechanics/spring_force_field.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "kernels/mechanics/springs.hpp"
#include "penalty/core/index_types.hpp"
#include "penalty/core/vertex_list_hash.hpp"

namespace penalty {

void SpringForceField::add_spring(const Spring& s) {
    if (!std::isfinite(s.ks) || s.ks < 0)
        throw_invalid_argument("SpringForceField: stiffness must be finite and >= 0, got ", s.ks);
    if (!std::isfinite(s.kd) || s.kd < 0)
        throw_invalid_argument("SpringForceField: damping must be finite and >= 0, got ", s.kd);
    if (!std::isfinite(s.rest_length) || s.rest_length < 0)
        throw_invalid_argument("SpringForceField: rest length must be finite and >= 0, got ", s.rest_length);
    if (s.a < 0 || s.b < 0) throw_invalid_argument("SpringForceField: negative spring index (", s.a, ", ", s.b, ")");
    // no state has that many DOFs (init checks the real sizes); keeps a·sizeof(Vec3) in range
    constexpr auto kLargestIndex = std::numeric_limits<std::ptrdiff_t>::max() / std::ptrdiff_t(sizeof(Vec3));
    if (s.a > kLargestIndex || s.b > kLargestIndex)
        throw_invalid_argument("SpringForceField: spring index (", s.a, ", ", s.b, ") larger than any state");
    springs_.push_back(s);
    ends_.clear();  // (on one thread until init makes them again)
    end_offsets_.push_back({static_cast<std::ptrdiff_t>(s.a) * std::ptrdiff_t(sizeof(Vec3)),
                            static_cast<std::ptrdiff_t>(s.b) * std::ptrdiff_t(sizeof(Vec3))});
}

void SpringForceField::init() {
    for (const auto& s : springs_) {
        if (static_cast<std::size_t>(s.a) >= s1_->num_dofs() || static_cast<std::size_t>(s.b) >= s2_->num_dofs()) {
            throw_invalid_argument("SpringForceField: spring (", s.a, ", ", s.b, ") out of range for states of ",
                                   s1_->num_dofs(), " and ", s2_->num_dofs(), " DOFs");
        }
    }
    dfdx_.assign(springs_.size(), StiffnessColumns{});
    // each spring's ends for the split on threads; between two states the second state's
    // points are numbered after the first's (detail::ScatterTarget)
    ends_.clear();
    scatter_.clear();
    second_state_first_ = s1_ == s2_ ? 0 : s1_->num_dofs();
    const std::size_t points = second_state_first_ + s2_->num_dofs();
    if (springs_.size() >= detail::OrderedScatter::kMinElements &&
        points <= static_cast<std::size_t>(std::numeric_limits<PointId>::max())) {
        ends_.reserve(springs_.size());
        for (const Spring& s : springs_)
            ends_.push_back({static_cast<PointId>(s.a), static_cast<PointId>(second_state_first_ + std::size_t(s.b))});
    }
}

void SpringForceField::set_kernel_path(KernelPath path) {
    kernel_path_ = checked_kernel_path(path, "SpringForceField", /*has_avx512=*/false);
}

ForceFieldStates SpringForceField::states() const {
    if (s1_ == s2_) return ForceFieldStates(s1_);
    return {s1_, s2_};
}

bool SpringForceField::runs_on_threads(std::size_t first_state_points) const {
    // split by OrderedScatter over the springs' ends (the first state as init numbered it)
    return ends_.size() == springs_.size() && (s1_ == s2_ || first_state_points == second_state_first_) &&
           detail::OrderedScatter::worth_threads(springs_.size());
}

detail::ScatterTarget SpringForceField::scatter_target(Vec3Span out1, Vec3Span out2) const {
    if (s1_ == s2_) return {out1};
    return {out1, out2};
}

void SpringForceField::add_force(Vec3Span f1, Vec3Span f2, ConstVec3Span x1, ConstVec3Span x2, ConstVec3Span v1,
                                 ConstVec3Span v2) {
    dfdx_.resize(springs_.size());
    const auto pass = [&](std::size_t first, std::size_t end, const detail::DeferredTerms& deferred, double* energies) {
        double energy = 0.0;
        detail::spring_forces(kernel_path_, arithmetic_, springs_, {first, end, deferred, energies}, null_length_,
                              f1.data(), f2.data(), x1.data(), x2.data(), v1.data(), v2.data(), dfdx_.data(), energy);
        return energy;
    };
    if (!runs_on_threads(f1.size())) {
        energy_ = pass(0, springs_.size(), {}, nullptr);
        return;
    }
    // the chunks' first springs on the avx path's blocks of four
    energy_ = detail::force_in_order</*Add=*/true>(scatter_, std::span<const std::array<PointId, 2>>(ends_),
                                                   scatter_target(f1, f2), 4, spring_energies_, pass);
}

void SpringForceField::add_dforce(Vec3Span df1, Vec3Span df2, ConstVec3Span dx1, ConstVec3Span dx2, double k_factor,
                                  double /*b_factor*/) const {
    PENALTY_DEMAND(dfdx_.size() == springs_.size() && end_offsets_.size() == springs_.size());
    const auto pass = [&](std::size_t first, std::size_t end, const detail::DeferredTerms& deferred) {
        detail::spring_dforces(kernel_path_, arithmetic_, springs_, {first, end, deferred, nullptr},
                               end_offsets_.data(), dfdx_.data(), df1.data(), df2.data(), dx1.data(), dx2.data(),
                               k_factor);
    };
    if (!runs_on_threads(df1.size())) {
        pass(0, springs_.size(), {});
        return;
    }
    detail::scatter_in_order</*Add=*/true>(scatter_, std::span<const std::array<PointId, 2>>(ends_),
                                           scatter_target(df1, df2), 4, pass);
}

void SpringForceField::add_stiffness_triplets(TripletList& t, Index o1, Index o2, double factor) const {
    PENALTY_DEMAND(dfdx_.size() == springs_.size());
    for (std::size_t i = 0; i < springs_.size(); ++i) {
        const Index ra = o1 + 3 * springs_[i].a;
        const Index rb = o2 + 3 * springs_[i].b;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) {
                const double v = factor * dfdx_[i](r, c);
                t.emplace_back(ra + r, ra + c, -v);
                t.emplace_back(ra + r, rb + c, v);
                t.emplace_back(rb + r, ra + c, v);
                t.emplace_back(rb + r, rb + c, -v);
            }
    }
}

MeshSpringParameters MeshSpringParameters::uniform(double k, double d) {
    MeshSpringParameters p;
    p.lines_stiffness = p.triangles_stiffness = p.quads_stiffness = p.tetras_stiffness = p.cubes_stiffness = k;
    p.lines_damping = p.triangles_damping = p.quads_damping = p.tetras_damping = p.cubes_damping = d;
    return p;
}

namespace {
/// The vertex pairs with a spring so far, each (smaller, larger) (a hash set: the springs in the
/// elements' order, the first occurrence of a pair kept, as SOFA's std::set loop).
using KnownPairs = VertexListSet<PointId, 2>;

template <class Element>
void add_element_springs(const std::vector<Element>& elements, double ks, double kd, std::span<const Vec3> x0,
                         KnownPairs& seen, std::vector<Spring>& out) {
    if (ks == 0.0 && kd == 0.0) return;
    if (!std::isfinite(ks) || ks < 0 || !std::isfinite(kd) || kd < 0)
        throw_invalid_argument("MeshSpringForceField: stiffness and damping must be finite and >= 0, got ", ks, ", ",
                               kd);
    const std::size_t n = std::tuple_size<Element>::value;
    for (const auto& e : elements) {
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = i + 1; j < n; ++j) {
                const PointId a = e[i], b = e[j];
                if (!seen.insert({std::min(a, b), std::max(a, b)})) continue;
                if (static_cast<std::size_t>(std::max(a, b)) >= x0.size())
                    throw_invalid_argument("MeshSpringForceField: vertex ", std::max(a, b), " has no rest position");
                const double l = (x0[static_cast<std::size_t>(b)] - x0[static_cast<std::size_t>(a)]).norm();
                if (!(l > 0.0))
                    throw_invalid_argument("MeshSpringForceField: zero rest length between vertices ", a, " and ", b);
                out.push_back(Spring{a, b, ks / l, kd / l, l});
            }
    }
}
}  // namespace

std::vector<Spring> mesh_springs(const MeshTopology& topo, std::span<const Vec3> x0, const MeshSpringParameters& p) {
    std::vector<Spring> out;
    KnownPairs seen;
    // the distinct pairs are the mesh's edges when it lists them (a loader's mesh does); else a
    // guess (the set grows when there are more)
    seen.reserve(!topo.edges().empty() ? topo.edges().size()
                                       : (3 * topo.triangles().size() + 6 * topo.tetrahedra().size()) / 4);
    add_element_springs(topo.edges(), p.lines_stiffness, p.lines_damping, x0, seen, out);
    add_element_springs(topo.triangles(), p.triangles_stiffness, p.triangles_damping, x0, seen, out);
    add_element_springs(topo.quads(), p.quads_stiffness, p.quads_damping, x0, seen, out);
    add_element_springs(topo.tetrahedra(), p.tetras_stiffness, p.tetras_damping, x0, seen, out);
    add_element_springs(topo.hexahedra(), p.cubes_stiffness, p.cubes_damping, x0, seen, out);
    return out;
}

}  // namespace penalty
