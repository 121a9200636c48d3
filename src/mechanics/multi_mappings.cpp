#include "penalty/mechanics/multi_mappings.hpp"

#include "penalty/core/error.hpp"

#include <cmath>

#include <string>

namespace penalty {

std::vector<double> element_masses(const BaseMass& mass, int deriv_size) {
    const std::size_t n = mass.state()->num_dofs();
    TripletList t;
    mass.add_mass_triplets(t, 0, 1.0);
    std::vector<double> m(n, 0.0);
    for (const auto& e : t)
        if (e.row() == e.col() && e.row() % deriv_size == 0 && std::size_t(e.row() / deriv_size) < n)
            m[std::size_t(e.row() / deriv_size)] += e.value();
    return m;
}

// ---- CenterOfMassMapping (CenterOfMassMapping::init / apply / applyJ / applyJT) -------------

void CenterOfMassMapping::init() {
    mass_->init();
    masses_ = element_masses(*mass_, Rigid3Types::kDerivSize);
    total_mass_ = 0.0;
    for (const double m : masses_) total_mass_ += m;
    if (!(total_mass_ > 0.0) || !std::isfinite(total_mass_))
        throw_invalid_argument("CenterOfMassMapping: the input's total mass must be > 0, got ", total_mass_);
    Mapping::init();
}

void CenterOfMassMapping::apply(std::span<Vec3> out, std::span<const RigidFrame> in) {
    Vec3 sum = Vec3::Zero();  // X = Σ x_i·m_i / M, summed in DOF order
    for (std::size_t i = 0; i < in.size(); ++i) sum += in[i].center * masses_[i];
    out[0] = sum / total_mass_;
}

void CenterOfMassMapping::apply_j(std::span<Vec3> out, std::span<const RigidDeriv> in) const {
    Vec3 sum = Vec3::Zero();
    for (std::size_t i = 0; i < in.size(); ++i) sum += in[i].linear * masses_[i];
    out[0] = sum / total_mass_;
}

void CenterOfMassMapping::apply_jt(std::span<RigidDeriv> in, std::span<const Vec3> out) const {
    for (std::size_t i = 0; i < in.size(); ++i) in[i].linear += out[0] * (masses_[i] / total_mass_);
}

void CenterOfMassMapping::add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const {
    for (std::size_t i = 0; i < masses_.size(); ++i)
        for (Index a = 0; a < 3; ++a)
            t.emplace_back(row_offset + a, col_offset + 6 * Index(i) + a, masses_[i] / total_mass_);
}

// ---- SubsetMultiMapping / IdentityMultiMapping ----------------------------------------------

namespace {

// core::eq and core::peq of SOFA's MappingHelper.h for the instances penalty builds.
void copy_to(Vec3& out, const Vec3& in) { out = in; }
void copy_to(Vec3& out, const RigidFrame& in) { out = in.center; }
void copy_to(RigidFrame& out, const RigidFrame& in) { out = in; }
void copy_to(Vec3& out, const RigidDeriv& in) { out = in.linear; }
void copy_to(RigidDeriv& out, const RigidDeriv& in) { out = in; }
void add_to(Vec3& in, const Vec3& out) { in += out; }
void add_to(RigidDeriv& in, const Vec3& out) { in.linear += out; }
void add_to(RigidDeriv& in, const RigidDeriv& out) {
    in.linear += out.linear;
    in.angular += out.angular;
}

}  // namespace

template <class In, class Out>
SubsetMultiMapping<In, Out>::SubsetMultiMapping(MechanicalObject<In>& first, MechanicalObject<In>* second,
                                                MechanicalObject<Out>& to, std::vector<SubsetSource> sources)
    : Mapping<In, Out>(first, to), second_(second), sources_(std::move(sources)) {
    if (second_ == &first) throw_invalid_argument("SubsetMultiMapping: the two inputs are the same state");
}

template <class In, class Out>
SubsetMultiMapping<In, Out> SubsetMultiMapping<In, Out>::concatenation(MechanicalObject<In>& first,
                                                                       MechanicalObject<In>* second,
                                                                       MechanicalObject<Out>& to) {
    SubsetMultiMapping m(first, second, to, {});
    m.concatenate_ = true;
    return m;
}

template <class In, class Out>
void SubsetMultiMapping<In, Out>::init() {
    if (concatenate_) {  // IdentityMultiMapping::init: the output is the inputs one after the other
        sources_.clear();
        for (unsigned s = 0; s < (second_ != nullptr ? 2U : 1U); ++s) {
            const std::size_t n = (s == 0 ? this->in_ : second_)->num_dofs();
            for (std::size_t j = 0; j < n; ++j) sources_.push_back({s, Index(j)});
        }
    }
    for (std::size_t k = 0; k < sources_.size(); ++k) {
        const SubsetSource& s = sources_[k];
        const MechanicalObject<In>* input = s.input == 0 ? this->in_ : s.input == 1 ? second_ : nullptr;
        if (input == nullptr)
            throw_invalid_argument("SubsetMultiMapping: pair ", k, " names input ", s.input, ", and there are ",
                                   second_ != nullptr ? 2 : 1, " inputs");
        if (s.index < 0 || std::size_t(s.index) >= input->num_dofs())
            throw_invalid_argument("SubsetMultiMapping: pair ", k, " names DOF ", s.index, " of input ", s.input,
                                   ", which has ", input->num_dofs(), " DOFs");
    }
    // Mapping::init with the two inputs: positions, rest positions, velocities
    auto& out = *this->out_;
    out.position.resize(sources_.size());
    apply_position();
    out.rest_position = out.position;
    out.velocity.resize(sources_.size());
    out.init();
    apply_position();  // (the output's init normalises its frames' quaternions: the copies again)
    apply_velocity();
}

template <class In, class Out>
void SubsetMultiMapping<In, Out>::apply_position() {
    auto& out = this->out_->position;
    for (std::size_t k = 0; k < sources_.size(); ++k) {
        const SubsetSource& s = sources_[k];
        copy_to(out[k], (s.input == 0 ? this->in_ : second_)->position[std::size_t(s.index)]);
    }
}

template <class In, class Out>
void SubsetMultiMapping<In, Out>::apply_velocity() {
    auto& out = this->out_->velocity;
    for (std::size_t k = 0; k < sources_.size(); ++k) {
        const SubsetSource& s = sources_[k];
        copy_to(out[k], (s.input == 0 ? this->in_ : second_)->velocity[std::size_t(s.index)]);
    }
}

template <class In, class Out>
void SubsetMultiMapping<In, Out>::apply_dx() {
    auto& out = this->out_->dx;
    for (std::size_t k = 0; k < sources_.size(); ++k) {
        const SubsetSource& s = sources_[k];
        copy_to(out[k], (s.input == 0 ? this->in_ : second_)->dx[std::size_t(s.index)]);
    }
}

template <class In, class Out>
void SubsetMultiMapping<In, Out>::apply_jt_force() {
    const auto& out = this->out_->force;
    for (std::size_t k = 0; k < sources_.size(); ++k) {
        const SubsetSource& s = sources_[k];
        add_to((s.input == 0 ? this->in_ : second_)->force[std::size_t(s.index)], out[k]);
    }
}

template <class In, class Out>
void SubsetMultiMapping<In, Out>::apply_jt_df() {
    const auto& out = this->out_->df;
    for (std::size_t k = 0; k < sources_.size(); ++k) {
        const SubsetSource& s = sources_[k];
        add_to((s.input == 0 ? this->in_ : second_)->df[std::size_t(s.index)], out[k]);
    }
}

template <class In, class Out>
void SubsetMultiMapping<In, Out>::apply(std::span<OutCoord> out, std::span<const InCoord> in) {
    for (std::size_t k = 0; k < sources_.size(); ++k) {
        PENALTY_DEMAND(sources_[k].input == 0);
        copy_to(out[k], in[std::size_t(sources_[k].index)]);
    }
}

template <class In, class Out>
void SubsetMultiMapping<In, Out>::apply_j(std::span<OutDeriv> out, std::span<const InDeriv> in) const {
    for (std::size_t k = 0; k < sources_.size(); ++k) {
        PENALTY_DEMAND(sources_[k].input == 0);
        copy_to(out[k], in[std::size_t(sources_[k].index)]);
    }
}

template <class In, class Out>
void SubsetMultiMapping<In, Out>::apply_jt(std::span<InDeriv> in, std::span<const OutDeriv> out) const {
    for (std::size_t k = 0; k < sources_.size(); ++k) {
        PENALTY_DEMAND(sources_[k].input == 0);
        add_to(in[std::size_t(sources_[k].index)], out[k]);
    }
}

template <class In, class Out>
void SubsetMultiMapping<In, Out>::add_block(TripletList& t, unsigned input, Index row_offset, Index col_offset) const {
    constexpr Index n_in = In::kDerivSize;
    constexpr Index n_out = Out::kDerivSize;
    constexpr Index n = n_in < n_out ? n_in : n_out;  // Rigid3 → Vec3: the linear part
    for (std::size_t k = 0; k < sources_.size(); ++k) {
        if (sources_[k].input != input) continue;
        for (Index a = 0; a < n; ++a)
            t.emplace_back(row_offset + n_out * Index(k) + a, col_offset + n_in * sources_[k].index + a, 1.0);
    }
}

template <class In, class Out>
void SubsetMultiMapping<In, Out>::add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const {
    add_block(t, 0, row_offset, col_offset);
}

template <class In, class Out>
void SubsetMultiMapping<In, Out>::add_second_input_jacobian_triplets(TripletList& t, Index row_offset,
                                                                     Index col_offset) const {
    if (second_ != nullptr) add_block(t, 1, row_offset, col_offset);
}

template class SubsetMultiMapping<Vec3Types, Vec3Types>;
template class SubsetMultiMapping<Rigid3Types, Rigid3Types>;
template class SubsetMultiMapping<Rigid3Types, Vec3Types>;

}  // namespace penalty
