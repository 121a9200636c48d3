// The two point operations an incision needs beyond addPoints(n, ancestors): SOFA's
// PointSetTopologyModifier::addPoints(n, srcElems) (points placed in edges and triangles) and
// TriangleSetTopologyModifier::movePointsProcess (points snapped onto a path).
#include "penalty/core/error.hpp"
#include "penalty/mechanics/topology_container.hpp"

namespace penalty {

// PointSetTopologyModifier::addPoints(n, srcElems): addPointsProcess, addPointsWarning (each
// point's ancestors: the element's vertices, coefficients (1 - l0, l0) on an edge,
// (1 - l0 - l1, l0, l1) in a triangle; the states place its coordinates in the element), propagate.
void TopologyContainer::add_points(const std::vector<PointAncestorElement>& elements) {
    std::vector<std::vector<ElementId>> ancestors(elements.size());
    std::vector<std::vector<double>> coefficients(elements.size());
    for (std::size_t k = 0; k < elements.size(); ++k) {
        const PointAncestorElement& e = elements[k];
        const auto& l = e.local;
        const int count = e.type == ElementType::edge ? 2 : e.type == ElementType::triangle ? 3 : 0;
        if (count == 0)
            throw_invalid_argument("TopologyContainer '", name_, "': new point ", k,
                                   " must lie in an edge or a triangle");
        for (int j = 0; j < count; ++j) {
            const PointId v = e.vertices[std::size_t(j)];
            if (v < 0 || std::size_t(v) >= num_points())
                throw_invalid_argument("TopologyContainer '", name_, "': new point ", k, " has ancestor ", v,
                                       ": the container has ", num_points(), " points");
            ancestors[k].push_back(v);
        }
        coefficients[k] =
            count == 2 ? std::vector<double>{1 - l[0], l[0]} : std::vector<double>{1 - l[0] - l[1], l[0], l[1]};
    }
    begin();
    add_points_process(elements.size());
    add_points_warning(elements.size(), ancestors, coefficients, true, elements);
    propagate();
    done();
}

// TriangleSetTopologyModifier::movePointsProcess: the states move the points (POINTSMOVED,
// computeWeightedValue); the TrianglesMoved events it sends reach only topology data, which
// ignore them (SOFA's TopologyDataHandler warns "MOVED topology event not handled").
void TopologyContainer::move_points(const std::vector<PointId>& ids,
                                    const std::vector<std::vector<ElementId>>& ancestors,
                                    const std::vector<std::vector<double>>& coefficients) {
    if (ids.empty()) return;
    if (ancestors.size() != ids.size())
        throw_invalid_argument("TopologyContainer '", name_, "': ", ids.size(), " moved points with ", ancestors.size(),
                               " ancestor lists");
    for (std::size_t k = 0; k < ids.size(); ++k) {
        if (ids[k] < 0 || std::size_t(ids[k]) >= num_points())
            throw_invalid_argument("TopologyContainer '", name_, "': cannot move point ", ids[k], " of ", num_points());
        for (const ElementId a : ancestors[k])
            if (a < 0 || std::size_t(a) >= num_points())
                throw_invalid_argument("TopologyContainer '", name_, "': moved point ", ids[k], " has ancestor ", a,
                                       ": the container has ", num_points(), " points");
    }
    begin();
    TopologyChange c;
    c.kind = TopologyChangeKind::moved;
    c.element = ElementType::point;
    c.indices.assign(ids.begin(), ids.end());
    c.ancestors = ancestors;
    c.coefficients = coefficients;
    state_changes_.push_back(std::move(c));
    propagate_state_changes();
    done();
}

}  // namespace penalty
