#pragma once
/// @file
/// SOFA's linear mappings that gather DOFs (Sofa/Component/Mapping/Linear):
///   - CenterOfMassMapping Rigid3 → Vec3: one output point, the mass-weighted centre of the input
///     frames, x = (Σ_i m_i·c_i)/M with M = Σ_i m_i and m_i the input node's mass's element mass
///     (kg); J: v = (Σ_i m_i·v_i)/M (linear velocities only); Jᵀ: f_i += f·(m_i/M), torques untouched.
///   - SubsetMultiMapping In → Out: output point k is DOF j_k of input s_k (SOFA's `indexPairs`
///     s_0 j_0 s_1 j_1 …), copied as core::eq does (Rigid3 → Vec3: the frame's centre, the linear
///     velocity); J a 0/1 selection; Jᵀ: f_in[s_k][j_k] += f_out[k] in k order (Rigid3 input from a
///     Vec3 output: the linear part).
///   - IdentityMultiMapping In → In: the inputs concatenated in order (SubsetMultiMapping with the
///     pairs (0, 0) … (0, n₀−1) (1, 0) …, made at init from the inputs' sizes).
/// Two inputs at most: from() and second_from() (the graph's Multi2Mapping hook).
/// Each follows SOFA's operation order (CenterOfMassMapping.inl, SubsetMultiMapping.inl,
/// IdentityMultiMapping.inl), so a mapped state agrees with SOFA's to the last bit.

#include "penalty/mechanics/mapping.hpp"

#include <vector>

namespace penalty {

/// The element masses of `mass` (SOFA's BaseMass::getElementMass): the diagonal entry of the
/// first scalar of each DOF of its assembled matrix (a state of `deriv_size` scalars per DOF).
[[nodiscard]] std::vector<double> element_masses(const BaseMass& mass, int deriv_size);

/// CenterOfMassMapping<Rigid3, Vec3> (SOFA's only 3-D instance).
class CenterOfMassMapping final : public Mapping<Rigid3Types, Vec3Types> {
public:
    /// `mass`: the mass of the input's node (SOFA: fromModel->getContext()->getMass()).
    CenterOfMassMapping(Rigid3Object& from, Vec3Object& to, BaseMass& mass) : Mapping(from, to), mass_(&mass) {}

    /// Initialises the mass (idempotent; SOFA's node initialises it before a child's mapping),
    /// reads the element masses (std::invalid_argument when their sum is not > 0), then maps.
    void init() override;
    void apply(std::span<Vec3> out, std::span<const RigidFrame> in) override;
    void apply_j(std::span<Vec3> out, std::span<const RigidDeriv> in) const override;
    void apply_jt(std::span<RigidDeriv> in, std::span<const Vec3> out) const override;
    void add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override;
    [[nodiscard]] std::size_t output_size() const override { return 1; }
    [[nodiscard]] double total_mass() const { return total_mass_; }

private:
    BaseMass* mass_;
    std::vector<double> masses_;  ///< m_i (kg)
    double total_mass_ = 0.0;     ///< M (kg)
};

/// One output DOF of a SubsetMultiMapping: DOF `index` of input `input`.
struct SubsetSource {
    unsigned input = 0;
    Index index = 0;
};

/// SubsetMultiMapping<In, Out> and IdentityMultiMapping<In, In> (one or two inputs of type In).
/// Instances: (Vec3, Vec3), (Rigid3, Rigid3), (Rigid3, Vec3).
template <class In, class Out>
class SubsetMultiMapping final : public Mapping<In, Out> {
public:
    using InCoord = typename In::Coord;
    using InDeriv = typename In::Deriv;
    using OutCoord = typename Out::Coord;
    using OutDeriv = typename Out::Deriv;

    /// `second` may be null (one input). `sources`: the output DOFs (SubsetMultiMapping's pairs).
    SubsetMultiMapping(MechanicalObject<In>& first, MechanicalObject<In>* second, MechanicalObject<Out>& to,
                       std::vector<SubsetSource> sources);
    /// IdentityMultiMapping: the inputs concatenated, the sources made at init.
    static SubsetMultiMapping concatenation(MechanicalObject<In>& first, MechanicalObject<In>* second,
                                            MechanicalObject<Out>& to);

    [[nodiscard]] BaseState* second_from() const override { return second_; }
    /// Checks every source (std::invalid_argument naming the pair out of range), then maps.
    void init() override;
    void apply_position() override;
    void apply_velocity() override;
    void apply_dx() override;
    void apply_jt_force() override;
    void apply_jt_df() override;
    /// The first input's block of J.
    void add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override;
    void add_second_input_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override;
    [[nodiscard]] std::size_t output_size() const override { return sources_.size(); }
    [[nodiscard]] const std::vector<SubsetSource>& sources() const { return sources_; }

    // Mapping<In, Out>'s single-input forms: the first input only (every source must read it).
    void apply(std::span<OutCoord> out, std::span<const InCoord> in) override;
    void apply_j(std::span<OutDeriv> out, std::span<const InDeriv> in) const override;
    void apply_jt(std::span<InDeriv> in, std::span<const OutDeriv> out) const override;

private:
    void add_block(TripletList& t, unsigned input, Index row_offset, Index col_offset) const;
    MechanicalObject<In>* second_;
    std::vector<SubsetSource> sources_;
    bool concatenate_ = false;  ///< IdentityMultiMapping: sources made at init
};

extern template class SubsetMultiMapping<Vec3Types, Vec3Types>;
extern template class SubsetMultiMapping<Rigid3Types, Rigid3Types>;
extern template class SubsetMultiMapping<Rigid3Types, Vec3Types>;

}  // namespace penalty
