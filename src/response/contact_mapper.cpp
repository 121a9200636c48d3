#include "penalty/response/contact_mapper.hpp"

#include "penalty/core/error.hpp"

#include "../mechanics/sofa_vector_ops.hpp"

#include <limits>

namespace penalty {

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

/// The error of a contact point that check_element refuses (out of line: the check, called for
/// every contact, stays a compare and a branch).
[[noreturn, gnu::cold, gnu::noinline]] void throw_bad_element(const CollisionModel& m, const char* function,
                                                              Index element, const Vec3& P) {
    if (element < 0 || static_cast<std::size_t>(element) >= m.size())
        throw_invalid_argument(function, ": model '", m.name(), "' (", model_type_name(m.type()), "): element ",
                               element, " out of range [0, ", m.size(), ")");
    throw_invalid_argument(function, ": model '", m.name(), "', element ", element, ": non-finite contact point P (",
                           P.transpose(), ")");
}

/// `element` must be one of the model's and P finite.
inline void check_element(const CollisionModel& m, const char* function, Index element, const Vec3& P) {
    if (element < 0 || static_cast<std::size_t>(element) >= m.size() || !P.allFinite()) [[unlikely]]
        throw_bad_element(m, function, element, P);
}

/// A flat parent vector as the per-DOF values it holds (Vec3: 3 scalars, RigidDeriv: 6; the
/// layout of flat_span).
template <class Deriv>
std::span<const Deriv> as_derivs(std::span<const double> v) {
    return {reinterpret_cast<const Deriv*>(v.data()), v.size() / (sizeof(Deriv) / sizeof(double))};
}
template <class Deriv>
std::span<Deriv> as_derivs(std::span<double> v) {
    return {reinterpret_cast<Deriv*>(v.data()), v.size() / (sizeof(Deriv) / sizeof(double))};
}

}  // namespace

void ContactMapper::check_sizes(const char* function, std::size_t contact_size, std::size_t parent_scalars) const {
    if (contact_size != size() || parent_scalars != parent_scalar_size())
        throw_invalid_argument(function, ": model '", model().name(), "': contact vector size ", contact_size,
                               " (expected ", size(), "), parent vector size ", parent_scalars, " (expected ",
                               parent_scalar_size(), ")");
}

// ---------------------------------------------------------------------------- identity

IdentityContactMapper::IdentityContactMapper(const CollisionModel& model) : model_(&model) {
    if (const auto* p = dynamic_cast<const PointModel*>(&model)) {
        state_ = &p->state();
    } else if (const auto* s = dynamic_cast<const SphereModel*>(&model)) {
        state_ = &s->state();
        sphere_ = s;
    } else {
        throw_invalid_argument("IdentityContactMapper: model '", model.name(), "' (", model_type_name(model.type()),
                               ") is neither a Point nor a Sphere model");
    }
}

DofIndex IdentityContactMapper::add_point(const Vec3& /*P: the element's own point*/, ElementIndex element_index,
                                          double& r) {
    const Index element = element_index.value();
    // check_element's test, with the model's size read from its state (a Point or Sphere model
    // has one element per point of its state): no virtual call per contact
    if (element < 0 || static_cast<std::size_t>(element) >= state_->size()) [[unlikely]]
        throw_bad_element(*model_, "IdentityContactMapper::add_point", element, Vec3::Zero());
    if (sphere_) r = sphere_->radius(element);
    return DofIndex(element);  // the element's own DOF
}

ConstVec3Span IdentityContactMapper::velocities() const {
    if (state_->velocity.size() == state_->size()) return state_->velocity;
    zero_velocity_.assign(state_->size(), Vec3::Zero());
    return zero_velocity_;
}

void IdentityContactMapper::apply_j(std::span<const double> dq, Vec3Span out) const {
    check_sizes("IdentityContactMapper::apply_j", out.size(), dq.size());
    const std::span<const Vec3> in = as_derivs<Vec3>(dq);
    std::copy(in.begin(), in.end(), out.begin());
}

void IdentityContactMapper::apply_jt(ConstVec3Span f, std::span<double> parent_f) const {
    check_sizes("IdentityContactMapper::apply_jt", f.size(), parent_f.size());
    const std::span<Vec3> out = as_derivs<Vec3>(parent_f);
    for (std::size_t i = 0; i < f.size(); ++i) out[i] += f[i];
}

void IdentityContactMapper::add_jacobian_triplets(TripletList& t, Index ro, Index co) const {
    for (std::size_t i = 0; i < size(); ++i)
        for (int a = 0; a < 3; ++a) t.emplace_back(ro + 3 * Index(i) + a, co + 3 * Index(i) + a, 1.0);
}

// ---------------------------------------------------------------------------- barycentric

std::array<double, 2> line_contact_weights(const Vec3& a, const Vec3& b, const Vec3& P) {
    const Vec3 ab = b - a;
    const double l2 = ab.squaredNorm();
    const double f = l2 < kEps ? 0.0 : (P - a).dot(ab) / l2;
    return {1.0 - f, f};
}

std::array<double, 2> triangle_contact_coordinates(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& P) {
    const Vec3 ab = p1 - p0, ac = p2 - p0, aq = P - p0;
    const double g00 = ab.dot(ab), g01 = ab.dot(ac), g11 = ac.dot(ac);
    const double b0 = aq.dot(ab), b1 = aq.dot(ac);
    const double det = g00 * g11 - g01 * g01;
    double a = (b0 * g11 - b1 * g01) / det;
    double b = (b1 * g00 - b0 * g01) / det;
    if (a < 0 || b < 0 || a + b > 1) {
        // outside: closest edge or vertex, thresholds 0 and 1
        const double p_ab = b0 / g00, p_ac = b1 / g11;
        if (p_ab < 0 && p_ac < 0) {
            a = 0;
            b = 0;
        } else if (p_ab < 1 && b < 0) {
            a = p_ab;
            b = 0;
        } else if (p_ac < 1 && a < 0) {
            a = 0;
            b = p_ac;
        } else {
            const double p_bc = (b1 - b0 + g00 - g01) / (g00 + g11 - 2 * g01);
            if (p_bc < 0) {
                a = 1;
                b = 0;
            } else if (p_bc > 1) {
                a = 0;
                b = 1;
            } else {
                a = 1 - p_bc;
                b = p_bc;
            }
        }
    }
    return {a, b};
}

std::array<double, 2> quad_contact_coordinates(const Vec3& q0, const Vec3& q1, const Vec3& q3, const Vec3& P) {
    // BarycentricMapperMeshTopology::createPointInQuad, SOFA's operations: B = (a b a×b)⁻¹ with
    // a = q1 − q0, b = q3 − q0 as columns, inverted by type::invertMatrix (cofactors / det);
    // fx = B's row 0 · (P − q0), fy = row 1 · (P − q0). Eigen's inverse() (cofactors · (1/det))
    // rounds fx, fy otherwise.
    const Vec3 a = q1 - q0;
    const Vec3 b = q3 - q0;
    Mat3 m;
    m.col(0) = a;
    m.col(1) = b;
    m.col(2) = sofa_vec::cross(a, b);
    const Mat3 base = sofa_vec::inverse(m);
    const Vec3 pos = P - q0;
    return {sofa_vec::dot3(base.row(0).transpose(), pos), sofa_vec::dot3(base.row(1).transpose(), pos)};
}

BarycentricContactMapper::BarycentricContactMapper(const CollisionModel& model) : model_(&model) {
    // compute_row goes by model.type(): each type is its class (no class derives from these)
    if (model.type() == ModelType::Line) state_ = &dynamic_cast<const LineModel&>(model).state();
    else if (model.type() == ModelType::Triangle) state_ = &dynamic_cast<const TriangleModel&>(model).state();
    else if (model.type() == ModelType::Tetrahedron) state_ = &dynamic_cast<const TetrahedronModel&>(model).state();
    else
        throw_invalid_argument("BarycentricContactMapper: model '", model.name(), "' (", model_type_name(model.type()),
                               ") is not a Line, Triangle or Tetrahedron model");
}

void BarycentricContactMapper::resize(std::size_t n) {
    rows_.clear();
    rows_.reserve(n);
    positions_.clear();
    velocities_.clear();
}

ContactBarycentricRow BarycentricContactMapper::compute_row(const Vec3& P, Index e) const {
    ContactBarycentricRow row;
    const auto& x = state_->position;
    // the model's kind, checked by the constructor (its type, not a dynamic_cast a point: a
    // pile of bodies maps hundreds of thousands of contact points a step)
    if (model_->type() == ModelType::Line) {
        const auto* l = static_cast<const LineModel*>(model_);
        const Edge& ed = l->edge(e);
        const auto w = line_contact_weights(x[std::size_t(ed[0])], x[std::size_t(ed[1])], P);
        row.push(ed[0], w[0]);
        row.push(ed[1], w[1]);
    } else if (model_->type() == ModelType::Triangle) {
        const auto* t = static_cast<const TriangleModel*>(model_);
        const std::size_t nt = t->num_topology_triangles();
        if (std::size_t(e) < nt) {
            const Triangle& tr = t->triangle(e);
            const auto ab =
                triangle_contact_coordinates(x[std::size_t(tr[0])], x[std::size_t(tr[1])], x[std::size_t(tr[2])], P);
            row.push(tr[0], 1.0 - ab[0] - ab[1]);
            row.push(tr[1], ab[0]);
            row.push(tr[2], ab[1]);
        } else {
            const std::size_t k = (std::size_t(e) - nt) / 2;
            const Quad& q = t->topology().quads()[k];
            const auto f =
                quad_contact_coordinates(x[std::size_t(q[0])], x[std::size_t(q[1])], x[std::size_t(q[3])], P);
            // SOFA's BarycentricMapperMeshTopology::apply sums a quad's vertices in the order
            // q0, q1, q3, q2; so do we (the rounding of the mapped point depends on it).
            row.push(q[0], (1 - f[0]) * (1 - f[1]));
            row.push(q[1], f[0] * (1 - f[1]));
            row.push(q[3], (1 - f[0]) * f[1]);
            row.push(q[2], f[0] * f[1]);
        }
    } else {
        const auto* h = static_cast<const TetrahedronModel*>(model_);
        const Tetrahedron& te = h->tetrahedron(e);
        const auto w = h->barycentric(e, P);
        for (std::size_t k = 0; k < 4; ++k) row.push(te[k], w[k]);
    }
    return row;
}

DofIndex BarycentricContactMapper::add_point(const Vec3& P, ElementIndex element_index, double& /*r*/) {
    const Index element = element_index.value();
    check_element(*model_, "BarycentricContactMapper::add_point", element, P);
    rows_.push_back(compute_row(P, element));
    positions_.emplace_back(Vec3::Zero());
    velocities_.emplace_back(Vec3::Zero());
    return DofIndex(Index(rows_.size()) - 1);
}

void BarycentricContactMapper::update() {
    const bool has_v = state_->velocity.size() == state_->size();
    for (std::size_t i = 0; i < rows_.size(); ++i) {
        positions_[i] = rows_[i].combine(state_->position);
        velocities_[i] = has_v ? rows_[i].combine(state_->velocity) : Vec3(Vec3::Zero());
    }
}

void BarycentricContactMapper::apply_j(std::span<const double> dq, Vec3Span out) const {
    check_sizes("BarycentricContactMapper::apply_j", out.size(), dq.size());
    const std::span<const Vec3> in = as_derivs<Vec3>(dq);
    for (std::size_t i = 0; i < rows_.size(); ++i) out[i] = rows_[i].combine(in);
}

void BarycentricContactMapper::apply_jt(ConstVec3Span f, std::span<double> parent_f) const {
    check_sizes("BarycentricContactMapper::apply_jt", f.size(), parent_f.size());
    const std::span<Vec3> out = as_derivs<Vec3>(parent_f);
    for (std::size_t i = 0; i < rows_.size(); ++i) rows_[i].spread(out, f[i]);
}

void BarycentricContactMapper::add_jacobian_triplets(TripletList& t, Index ro, Index co) const {
    for (std::size_t i = 0; i < rows_.size(); ++i) rows_[i].add_triplets(t, ro + 3 * Index(i), co);
}

// ---------------------------------------------------------------------------- rigid

RigidContactMapper::RigidContactMapper(const CollisionModel& model, RigidSphereRadius radius_rule)
    : model_(&model), radius_rule_(radius_rule) {
    if (const auto* s = dynamic_cast<const RigidSphereModel*>(&model)) {
        state_ = &s->state();
        sphere_ = s;
    } else if (const auto* c = dynamic_cast<const CylinderModel*>(&model)) {
        state_ = &c->state();
    } else {
        throw_invalid_argument("RigidContactMapper: model '", model.name(), "' (", model_type_name(model.type()),
                               ") is neither a RigidSphere nor a Cylinder model");
    }
}

void RigidContactMapper::resize(std::size_t n) {
    rows_.clear();
    positions_.clear();
    velocities_.clear();
    rows_.reserve(n);
}

DofIndex RigidContactMapper::add_point(const Vec3& P, ElementIndex element_index, double& r) {
    const Index element = element_index.value();
    check_element(*model_, "RigidContactMapper::add_point", element, P);
    const RigidFrame& fr = state_->position[std::size_t(element)];
    RigidPointRow& row = rows_.emplace_back();
    row.frame = element;
    row.local = fr.orientation.conjugate() * (P - fr.center);
    positions_.emplace_back(Vec3::Zero());
    velocities_.emplace_back(Vec3::Zero());
    if (sphere_ && radius_rule_ == RigidSphereRadius::sofa_head) r = sphere_->radius(element);
    return DofIndex(Index(rows_.size()) - 1);
}

void RigidContactMapper::update() {
    const bool has_v = state_->velocity.size() == state_->size();
    for (std::size_t i = 0; i < rows_.size(); ++i) {
        const auto body = std::size_t(rows_[i].frame);
        positions_[i] = rows_[i].place(state_->position[body]);
        velocities_[i] = has_v ? rows_[i].velocity(state_->velocity[body]) : Vec3(Vec3::Zero());
    }
}

void RigidContactMapper::apply_j(std::span<const double> dq, Vec3Span out) const {
    check_sizes("RigidContactMapper::apply_j", out.size(), dq.size());
    const std::span<const RigidDeriv> in = as_derivs<RigidDeriv>(dq);
    for (std::size_t i = 0; i < rows_.size(); ++i) out[i] = rows_[i].velocity(in[std::size_t(rows_[i].frame)]);
}

void RigidContactMapper::apply_jt(ConstVec3Span f, std::span<double> parent_f) const {
    check_sizes("RigidContactMapper::apply_jt", f.size(), parent_f.size());
    const std::span<RigidDeriv> out = as_derivs<RigidDeriv>(parent_f);
    for (std::size_t i = 0; i < rows_.size(); ++i) rows_[i].spread(out[std::size_t(rows_[i].frame)], f[i]);
}

void RigidContactMapper::add_jacobian_triplets(TripletList& t, Index ro, Index co) const {
    for (std::size_t i = 0; i < rows_.size(); ++i) rows_[i].add_triplets(t, ro + 3 * Index(i), co);
}

std::unique_ptr<ContactMapper> make_contact_mapper(const CollisionModel& model, RigidSphereRadius radius_rule) {
    switch (model.type()) {
        case ModelType::Point:
        case ModelType::Sphere:
            return std::make_unique<IdentityContactMapper>(model);
        case ModelType::Line:
        case ModelType::Triangle:
        case ModelType::Tetrahedron:
            return std::make_unique<BarycentricContactMapper>(model);
        case ModelType::RigidSphere:
        case ModelType::Cylinder:
            return std::make_unique<RigidContactMapper>(model, radius_rule);
    }
    throw_invalid_argument("make_contact_mapper: model '", model.name(), "': unknown model type");
}

}  // namespace penalty
