#include "penalty/simulation/node.hpp"

#include "penalty/core/pointer_index.hpp"
#include "penalty/simulation/solver.hpp"

#include <algorithm>
#include <cmath>

namespace penalty {

namespace {
/// Erases (and destroys) the element of `owners` that owns `p`; false if there is none.
template <class T>
bool erase_owned(std::vector<std::unique_ptr<T>>& owners, const T* p) {
    const auto it = std::find_if(owners.begin(), owners.end(), [&](const auto& o) { return o.get() == p; });
    if (it == owners.end()) return false;
    owners.erase(it);
    return true;
}

/// Erases (and destroys) the elements of `owners` that own one of `removed`, keeping the
/// others' order; returns how many were erased. Sorted pointers and a binary search each: one
/// pass, where an erase per pointer moved the tail each time.
template <class T>
std::size_t erase_owned(std::vector<std::unique_ptr<T>>& owners, std::span<const T* const> removed) {
    if (removed.empty()) return 0;
    thread_local std::vector<std::uintptr_t> sorted;
    sorted.clear();
    for (const T* p : removed) sorted.push_back(reinterpret_cast<std::uintptr_t>(p));
    std::sort(sorted.begin(), sorted.end());
    const auto listed = [](const auto& owner) {
        return std::binary_search(sorted.begin(), sorted.end(), reinterpret_cast<std::uintptr_t>(owner.get()));
    };
    const auto kept_end = std::remove_if(owners.begin(), owners.end(), listed);
    const auto erased = static_cast<std::size_t>(owners.end() - kept_end);
    owners.erase(kept_end, owners.end());
    return erased;
}
}  // namespace

Node::Node(std::string name, Node* parent) : name_(std::move(name)), parent_(parent) {
    if (parent_ == nullptr) return;
    Node* root = parent_;
    while (root->parent_ != nullptr) root = root->parent_;
    id_ = ++root->ids_issued_;
}

Node::~Node() = default;

std::uint64_t Node::structure_version() const {
    const Node* root = this;
    while (root->parent_ != nullptr) root = root->parent_;
    return root->structure_version_;
}

void Node::structure_changed() {
    Node* root = this;
    while (root->parent_ != nullptr) root = root->parent_;
    ++root->structure_version_;
}

Node& Node::add_child(std::string child_name) {
    children_.push_back(std::make_unique<Node>(std::move(child_name), this));
    structure_changed();
    return *children_.back();
}

bool Node::remove_child(const Node* child) {
    if (!erase_owned(children_, child)) return false;
    structure_changed();
    return true;
}

std::size_t Node::remove_children(std::span<const Node* const> removed) {
    const std::size_t erased = erase_owned(children_, removed);
    if (erased > 0) structure_changed();
    return erased;
}

void Node::set_gravity(const Vec3& g) {
    if (!g.allFinite()) throw_invalid_argument("Node '", name_, "': gravity is not finite");
    gravity_ = g;
    structure_changed();
}

void Node::set_dt(double dt) {
    if (!std::isfinite(dt) || dt <= 0.0)
        throw_invalid_argument("Node '", name_, "': dt must be finite and > 0, got ", dt);
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
    structure_changed();
    return *force_fields_.back();
}

bool Node::remove_force_field(const BaseForceField* ff) {
    const BaseForceField* const removed[] = {ff};
    return remove_force_fields(removed) > 0;
}

std::size_t Node::remove_force_fields(std::span<const BaseForceField* const> removed) {
    mass_place_ -= listed_before_mass(removed);
    const std::size_t erased = erase_owned(force_fields_, removed);
    if (erased > 0) structure_changed();
    return erased;
}

std::size_t Node::listed_before_mass(std::span<const BaseForceField* const> listed) const {
    std::size_t before = 0;
    for (std::size_t k = 0; k < std::min(mass_place_, force_fields_.size()); ++k)
        if (std::find(listed.begin(), listed.end(), force_fields_[k].get()) != listed.end()) ++before;
    return before;
}

void Node::move_force_fields_to_end(std::span<BaseForceField* const> moved) {
    const std::size_t n = moved.size();
    const std::size_t total = force_fields_.size();
    if (n <= total && std::equal(moved.begin(), moved.end(), force_fields_.end() - std::ptrdiff_t(n),
                                 [](const BaseForceField* a, const auto& b) { return a == b.get(); }))
        return;
    // Places by a hash lookup, not searches (quadratic in the fields: a pile's root node holds
    // thousands of contact fields, moved whenever contact pairs come or go); the tables are kept
    // by the thread from one call to the next, so a steady pile allocates nothing here.
    struct Scratch {
        PointerIndex<BaseForceField> place;
        std::vector<std::size_t> moved_places;
        std::vector<std::uint8_t> is_moved;
        std::vector<std::unique_ptr<BaseForceField>> reordered;
    };
    thread_local Scratch scratch;
    Scratch& t = scratch;
    t.place.clear();
    for (std::size_t k = 0; k < total; ++k) t.place.emplace(force_fields_[k].get(), k);
    t.moved_places.resize(n);
    t.is_moved.assign(total, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t at = t.place.find(moved[i]);
        const bool here = at != PointerIndex<BaseForceField>::npos;
        if (!here || t.is_moved[at] != 0)
            throw_invalid_argument("Node '", name_, "': move_force_fields_to_end: entry ", i,
                                   here ? " is listed twice" : " is not a force field of this node");
        t.is_moved[at] = 1;
        t.moved_places[i] = at;
    }
    t.reordered.clear();
    mass_place_ -= listed_before_mass(moved);
    for (std::size_t k = 0; k < total; ++k)
        if (t.is_moved[k] == 0) t.reordered.push_back(std::move(force_fields_[k]));
    for (const std::size_t k : t.moved_places) t.reordered.push_back(std::move(force_fields_[k]));
    force_fields_.swap(t.reordered);  // the old vector, all moved from, is kept as scratch
    t.reordered.clear();
    structure_changed();
}

}  // namespace penalty
