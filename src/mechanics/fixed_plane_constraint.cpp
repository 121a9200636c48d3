#include "penalty/mechanics/fixed_plane_constraint.hpp"

namespace penalty {

void FixedPlaneProjectiveConstraint::init() {
    for (Index i : indices_)
        if (i < 0 || static_cast<std::size_t>(i) >= state_->num_dofs())
            throw_invalid_argument("FixedPlaneProjectiveConstraint: index ", i, " out of range (", state_->num_dofs(),
                                   " DOFs)");
}

// FixedPlaneProjectiveConstraint::projectResponse: u ← u − d (u·d) on the linear part.
void FixedPlaneProjectiveConstraint::project_response(Eigen::Ref<Eigen::VectorXd> v) const {
    const Eigen::Index stride = state_->deriv_size();
    for (Index i : follow(indices_)) {
        auto u = v.segment<3>(stride * static_cast<Eigen::Index>(i));
        const Vec3 value = u;
        u = value - direction_ * value.dot(direction_);
    }
}

bool FixedPlaneProjectiveConstraint::list_discarded_rows(std::vector<Index>& rows) const {
    const Index stride = state_->deriv_size();
    for (Index i : follow(indices_))
        for (Index c = 0; c < 3; ++c)
            if (direction_[c] != 0.0) rows.push_back(stride * i + c);
    return true;
}

std::vector<Index> points_between_planes(std::span<const Vec3> points, const Vec3& direction, double dmin,
                                         double dmax) {
    std::vector<Index> inside;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double d = points[i].dot(direction);
        if (d > dmin && d < dmax) inside.push_back(static_cast<Index>(i));
    }
    return inside;
}

}  // namespace penalty
