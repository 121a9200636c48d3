// StateTopologyFollower: SOFA's MechanicalObject::handleStateChange (replaceValue, resize,
// computeWeightedValue, renumberValues) over every vector of a state.
#include "penalty/mechanics/state_topology.hpp"

#include "penalty/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace penalty {

namespace {

template <class Value>
void replace_and_shrink(std::vector<Value>& v, const std::vector<ElementId>& removed, std::size_t old_size) {
    if (v.size() != old_size) return;  // SOFA: a vector of another size (unset) is left alone
    auto last = std::size_t(old_size) - 1;
    for (const ElementId i : removed) {
        v[std::size_t(i)] = v[last];
        --last;
    }
    v.resize(old_size - removed.size());
}

// DataTypes::interpolate: Σ c_k x_k, in the ancestors' order.
Vec3 interpolate(const std::vector<Vec3>& v, const std::vector<ElementId>& ancestors, const std::vector<double>& c) {
    Vec3 sum = Vec3::Zero();
    for (std::size_t k = 0; k < ancestors.size(); ++k) sum += v[std::size_t(ancestors[k])] * c[k];
    return sum;
}
RigidFrame interpolate(const std::vector<RigidFrame>& v, const std::vector<ElementId>& ancestors,
                       const std::vector<double>& c) {
    RigidFrame out;
    out.center = Vec3::Zero();
    Eigen::Vector4d q = Eigen::Vector4d::Zero();
    for (std::size_t k = 0; k < ancestors.size(); ++k) {
        out.center += v[std::size_t(ancestors[k])].center * c[k];
        q += v[std::size_t(ancestors[k])].orientation.coeffs() * c[k];
    }
    out.orientation.coeffs() = q;
    out.orientation.normalize();
    return out;
}
RigidDeriv interpolate(const std::vector<RigidDeriv>& v, const std::vector<ElementId>& ancestors,
                       const std::vector<double>& c) {
    RigidDeriv out;
    for (std::size_t k = 0; k < ancestors.size(); ++k) {
        out.linear += v[std::size_t(ancestors[k])].linear * c[k];
        out.angular += v[std::size_t(ancestors[k])].angular * c[k];
    }
    return out;
}

/// The value of a new point before its ancestors weigh in: SOFA's Coord() / Deriv(), zero (an
/// Eigen vector's default constructor leaves it uninitialized).
template <class Value>
Value zero_value() {
    if constexpr (std::is_same_v<Value, Vec3>) return Vec3::Zero();
    else return Value{};
}

/// Grows `v` by the added points (zero, or weighted from their ancestors); a buffer too small is
/// kept in `retired` (views of it stay valid).
template <class Value>
void grow_weighted(std::vector<Value>& v, std::size_t old_size, const TopologyChange& change,
                   std::vector<std::vector<Value>>& retired) {
    const std::size_t n = old_size + change.indices.size();
    if (n > v.capacity()) {
        std::vector<Value> bigger;
        bigger.reserve(std::max(n, 2 * v.capacity()));
        bigger.assign(v.begin(), v.end());
        retired.push_back(std::move(v));
        v = std::move(bigger);
    }
    v.resize(n, zero_value<Value>());
    for (std::size_t k = 0; k < change.ancestors.size(); ++k) {
        const auto& a = change.ancestors[k];
        if (a.empty()) continue;
        std::vector<double> c = change.coefficients.size() > k && !change.coefficients[k].empty()
                                    ? change.coefficients[k]
                                    : std::vector<double>(a.size(), 1.0 / double(a.size()));
        v[old_size + k] = interpolate(v, a, c);
    }
}

/// ...SetGeometryAlgorithms::initPointAdded for the coordinates of the added points: on an
/// edge c0 + (c1 - c0) l0; in a triangle p0 + (p1 - p0) l0 + (p2 - p0) l1 + n l2 (n the unit
/// normal (p1 - p0) x (p2 - p0)).
void place_in_elements(std::vector<Vec3>& v, std::size_t old_size, const TopologyChange& change) {
    for (std::size_t k = 0; k < change.ancestor_elements.size(); ++k) {
        const PointAncestorElement& e = change.ancestor_elements[k];
        const auto& l = e.local;
        const Vec3 p0 = v[std::size_t(e.vertices[0])];
        const Vec3 p1 = v[std::size_t(e.vertices[1])];
        if (e.type == ElementType::edge) {
            v[old_size + k] = p0 + (p1 - p0) * l[0];
        } else if (e.type == ElementType::triangle) {
            const Vec3 p2 = v[std::size_t(e.vertices[2])];
            const Vec3 a = p1 - p0, b = p2 - p0;
            Vec3 n(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]);
            const double norm = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            if (norm > 2.220446049250313e-16) n = Vec3(n[0] / norm, n[1] / norm, n[2] / norm);
            v[old_size + k] = p0 + a * l[0] + b * l[1] + n * l[2];
        }
    }
}
template <class Value>
void place_in_elements(std::vector<Value>&, std::size_t, const TopologyChange&) {}

/// MechanicalObject::handleStateChange(POINTSMOVED): computeWeightedValue, point after point.
template <class Value>
void move_weighted(std::vector<Value>& v, const TopologyChange& change) {
    if (v.empty()) return;
    for (std::size_t k = 0; k < change.indices.size() && k < change.ancestors.size(); ++k) {
        const auto& a = change.ancestors[k];
        std::vector<double> c = change.coefficients.size() > k && !change.coefficients[k].empty()
                                    ? change.coefficients[k]
                                    : std::vector<double>(a.size(), 1.0 / double(a.size()));
        v[std::size_t(change.indices[k])] = interpolate(v, a, c);
    }
}

template <class Value>
void renumber(std::vector<Value>& v, const std::vector<ElementId>& index) {
    if (v.size() < index.size()) return;
    const std::vector<Value> copy = v;
    for (std::size_t i = 0; i < index.size(); ++i) v[i] = copy[std::size_t(index[i])];
}

}  // namespace

template <class DataTypes>
void StateTopologyFollower<DataTypes>::handle_state_change(const TopologyChange& change) {
    if (change.element != ElementType::point) return;
    MechanicalObject<DataTypes>& s = *state_;
    const std::size_t n = s.position.size();
    auto each = [&](auto&& f) {
        f(s.position);
        f(s.rest_position);
        f(s.velocity);
        f(s.force);
        f(s.external_force);
        f(s.dx);
        f(s.df);
    };
    switch (change.kind) {
        case TopologyChangeKind::removed:
            for (const ElementId i : change.indices)
                if (i < 0 || std::size_t(i) >= n)
                    throw_invalid_argument("state '", s.name, "': cannot remove point ", i, " of ", n);
            each([&](auto& v) { replace_and_shrink(v, change.indices, n); });
            break;
        case TopologyChangeKind::added:
            for (auto* v : {&s.position, &s.rest_position})
                if (v->size() == n) {
                    grow_weighted(*v, n, change, retired_coords_);
                    place_in_elements(*v, n, change);
                }
            for (auto* v : {&s.velocity, &s.force, &s.external_force, &s.dx, &s.df})
                if (v->size() == n) grow_weighted(*v, n, change, retired_derivs_);
            break;
        case TopologyChangeKind::renumbered:
            each([&](auto& v) { renumber(v, change.indices); });
            break;
        case TopologyChangeKind::moved:
            for (const ElementId i : change.indices)
                if (i < 0 || std::size_t(i) >= n)
                    throw_invalid_argument("state '", s.name, "': cannot move point ", i, " of ", n);
            each([&](auto& v) { move_weighted(v, change); });
            break;
        case TopologyChangeKind::ending:
            break;
    }
}

template class StateTopologyFollower<Vec3Types>;
template class StateTopologyFollower<Rigid3Types>;

}  // namespace penalty
