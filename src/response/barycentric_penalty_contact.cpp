#include "penalty/response/barycentric_penalty_contact.hpp"

#include "penalty/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penalty {

void ContactResponseParameters::validate() const { penalty.validate(); }

double combined_contact_stiffness(StiffnessLaw law, double k1, double k2, double dist) {
    if (!std::isfinite(k1) || k1 < 0 || !std::isfinite(k2) || k2 < 0)
        throw_invalid_argument("combined_contact_stiffness: contact_stiffness must be finite and >= 0 (k1 = ", k1,
                               ", k2 = ", k2, ")");
    return combined_contact_stiffness_of_checked(law, k1, k2, dist);
}

double contact_critical_time_step(double ks, double m1, double m2) {
    if (!(ks >= 0) || !(m1 > 0) || !(m2 > 0))
        throw_invalid_argument("contact_critical_time_step: need ks >= 0 and masses > 0 (ks = ", ks, ", m1 = ", m1,
                               ", m2 = ", m2, ")");
    if (ks == 0.0) return std::numeric_limits<double>::infinity();
    double m;
    if (std::isinf(m1) && std::isinf(m2)) return std::numeric_limits<double>::infinity();
    else if (std::isinf(m1)) m = m2;
    else if (std::isinf(m2)) m = m1;
    else m = m1 * m2 / (m1 + m2);
    return std::sqrt(m / ks);
}

BarycentricPenaltyContact::BarycentricPenaltyContact(const CollisionModel& model1, const CollisionModel& model2,
                                                     double intersection_contact_distance,
                                                     const ContactResponseParameters& parameters)
    : model1_(&model1),
      model2_(&model2),
      intersection_cd_(intersection_contact_distance),
      parameters_(parameters),
      mapper1_(make_contact_mapper(model1, parameters.rigid_sphere_radius)),
      mapper2_(make_contact_mapper(model2, parameters.rigid_sphere_radius)),
      field_(parameters.penalty) {
    if (!std::isfinite(intersection_contact_distance) || intersection_contact_distance < 0)
        throw_invalid_argument("BarycentricPenaltyContact: models '", model1.name(), "' and '", model2.name(),
                               "': intersection contact_distance must be finite and >= 0, got ",
                               intersection_contact_distance);
    parameters_.validate();
}

void BarycentricPenaltyContact::set_detection_outputs(std::span<const DetectionOutput> outputs) {
    const std::span<const KeptOutput> kept = tracker_.update(outputs);
    field_.clear(kept.size());
    mapper1_->resize(kept.size());
    mapper2_->resize(kept.size());

    const auto& p1 = model1_->params();
    const auto& p2 = model2_->params();
    const double d0 = intersection_cd_ + p1.contact_distance + p2.contact_distance;
    const double mu = p1.contact_friction + p2.contact_friction;
    // the models' stiffnesses checked once (throws as for a contact), then used per contact
    if (!kept.empty())
        (void)combined_contact_stiffness(parameters_.stiffness_law, p1.contact_stiffness, p2.contact_stiffness, d0);
    for (const KeptOutput& k : kept) {
        const DetectionOutput& o = outputs[k.output];
        double r1 = 0.0, r2 = 0.0;
        const DofIndex m1 = mapper1_->add_point(o.point[0], o.elem1, r1);
        const DofIndex m2 = mapper2_->add_point(o.point[1], o.elem2, r2);
        const double dist = d0 + r1 + r2;
        const double ks = combined_contact_stiffness_of_checked(parameters_.stiffness_law, p1.contact_stiffness,
                                                                p2.contact_stiffness, dist);
        field_.add_contact(m1, m2, o.elem1, o.elem2, o.normal, dist, ks, mu, mu, k.old_index);
    }
    update_contact_points();
}

void BarycentricPenaltyContact::update_contact_points() {
    mapper1_->update();
    mapper2_->update();
}

void BarycentricPenaltyContact::add_force(std::span<double> parent_f1, std::span<double> parent_f2) {
    update_contact_points();
    f1_.assign(mapper1_->size(), Vec3::Zero());
    f2_.assign(mapper2_->size(), Vec3::Zero());
    field_.add_force(f1_, f2_, mapper1_->positions(), mapper2_->positions(), mapper1_->velocities(),
                     mapper2_->velocities());
    mapper1_->apply_jt(f1_, parent_f1);
    mapper2_->apply_jt(f2_, parent_f2);
}

void BarycentricPenaltyContact::add_dforce(std::span<double> parent_df1, std::span<double> parent_df2,
                                           std::span<const double> parent_dq1, std::span<const double> parent_dq2,
                                           double k_factor, double b_factor) {
    dx1_.resize(mapper1_->size());
    dx2_.resize(mapper2_->size());
    mapper1_->apply_j(parent_dq1, dx1_);
    mapper2_->apply_j(parent_dq2, dx2_);
    df1_.assign(dx1_.size(), Vec3::Zero());
    df2_.assign(dx2_.size(), Vec3::Zero());
    field_.add_dforce(df1_, df2_, dx1_, dx2_, k_factor, b_factor);
    mapper1_->apply_jt(df1_, parent_df1);
    mapper2_->apply_jt(df2_, parent_df2);
}

double BarycentricPenaltyContact::max_stiffness() const {
    double k = 0.0;
    for (const auto& c : field_.contacts()) k = std::max(k, c.ks);
    return k;
}

}  // namespace penalty
