#include "penalty/simulation/node.hpp"

#include "penalty/simulation/solver.hpp"

#include <algorithm>
#include <cmath>

namespace penalty {

Node::Node(std::string name, Node* parent) : name_(std::move(name)), parent_(parent) {
    if (parent_ == nullptr) return;
    Node* root = parent_;
    while (root->parent_ != nullptr) root = root->parent_;
    id_ = ++root->ids_issued_;
}

Node::~Node() = default;

Node& Node::add_child(std::string child_name) {
    children_.push_back(std::make_unique<Node>(std::move(child_name), this));
    return *children_.back();
}

bool Node::remove_child(const Node* child) {
    const auto it = std::find_if(children_.begin(), children_.end(), [&](const auto& c) { return c.get() == child; });
    if (it == children_.end()) return false;
    children_.erase(it);
    return true;
}

void Node::set_gravity(const Vec3& g) {
    if (!g.allFinite()) throw_invalid_argument("Node '", name_, "': gravity is not finite");
    gravity_ = g;
}

void Node::set_dt(double dt) {
    if (!std::isfinite(dt) || dt <= 0.0) throw_invalid_argument("Node '", name_, "': dt must be finite and > 0, got ", dt);
    dt_ = dt;
}

Vec3 Node::gravity() const {
    if (gravity_) return *gravity_;
    return parent_ ? parent_->gravity() : Vec3(0.0, -9.81, 0.0);
}

double Node::dt() const {
    if (dt_) return *dt_;
    return parent_ ? parent_->dt() : 0.01;
}

BaseForceField& Node::add_force_field_ptr(std::unique_ptr<BaseForceField> ff) {
    if (!ff) throw_invalid_argument("Node '", name_, "': null force field");
    force_fields_.push_back(std::move(ff));
    return *force_fields_.back();
}

bool Node::remove_force_field(const BaseForceField* ff) {
    const auto it = std::find_if(force_fields_.begin(), force_fields_.end(), [&](const auto& p) { return p.get() == ff; });
    if (it == force_fields_.end()) return false;
    force_fields_.erase(it);
    return true;
}

}  // namespace penalty
