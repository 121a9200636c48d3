#include "penalty/collision/collision_model.hpp"

#include "penalty/core/error.hpp"

#include <algorithm>

namespace penalty {

const char* model_type_name(ModelType t) {
    switch (t) {
        case ModelType::Point:
            return "Point";
        case ModelType::Line:
            return "Line";
        case ModelType::Triangle:
            return "Triangle";
        case ModelType::Sphere:
            return "Sphere";
        case ModelType::RigidSphere:
            return "RigidSphere";
        case ModelType::Cylinder:
            return "Cylinder";
        case ModelType::Tetrahedron:
            return "Tetrahedron";
    }
    return "?";
}

CollisionModel::CollisionModel(ModelType type, CollisionModelParams params) : type_(type), params_(std::move(params)) {}

Aabb CollisionModel::model_box() const {
    Aabb box;
    for (std::size_t i = 0; i < size(); ++i) box.extend(element_box(Index(i)));
    return box;
}

void CollisionModel::element_boxes(std::size_t begin, std::size_t end, Aabb* out) const {
    for (std::size_t i = begin; i < end; ++i) *out++ = element_box(Index(i));
}

void CollisionModel::validate_for_step() const {
    if (elements_unchanged_and_finite()) CollisionModel::validate();  // the parameters only
    else validate();
}

void CollisionModel::update() {
    if (!params_.moving && updated_once_) return;
    do_update();
    updated_once_ = true;
}

void CollisionModel::validate() const {
    const auto& p = params_;
    auto bad = [&](const char* what, double v) {
        throw_invalid_argument(model_type_name(type_), "Model '", p.name, "': parameter ", what, " is ", v,
                               " (must be finite and >= 0)");
    };
    if (!(p.contact_distance >= 0.0) || !is_finite(p.contact_distance)) bad("contactDistance", p.contact_distance);
    if (!(p.contact_stiffness >= 0.0) || !is_finite(p.contact_stiffness)) bad("contactStiffness", p.contact_stiffness);
    if (!(p.contact_friction >= 0.0) || !is_finite(p.contact_friction)) bad("contactFriction", p.contact_friction);
}

void CollisionModel::check_point(const Vec3& x, Index elem, const char* what) const {
    if (!x.allFinite()) {
        throw_invalid_argument(model_type_name(type_), "Model '", params_.name, "': element ", elem, ": ", what,
                               " is not finite (", x.x(), ", ", x.y(), ", ", x.z(), ")");
    }
}

bool same_node(const CollisionModel& a, const CollisionModel& b) {
    return &a == &b || (a.params().node >= 0 && a.params().node == b.params().node);
}

bool can_collide_with(const CollisionModel& a, const CollisionModel& b) {
    if (same_node(a, b)) return a.params().self_collision;
    const auto& ga = a.params().group;
    const auto& gb = b.params().group;
    if (ga.empty() || gb.empty()) return true;
    for (int x : ga)
        if (std::find(gb.begin(), gb.end(), x) != gb.end()) return false;
    return true;
}

bool keep_model_pair(const CollisionModel& a, const CollisionModel& b) {
    if (!a.params().active || !b.params().active) return false;
    if (!a.params().simulated && !b.params().simulated) return false;
    return can_collide_with(a, b) && can_collide_with(b, a);
}

}  // namespace penalty
