#pragma once
/// @file
/// Incision of a triangle surface along a path (SOFA's TriangleSetGeometryAlgorithms:
/// computeIntersectedObjectsList, SplitAlongPath with SnapAlongPath / SnapBorderPath,
/// InciseAlongEdgeList), over a dynamic triangle container and the positions of its state.
///
/// A cut from a to b: the triangles, edges and points the segment crosses (the path), each crossing
/// a new point (on an edge: its barycentric point; inside a triangle: the triangle's), the crossed
/// triangles split along the path (new triangles replace them), then the path's edges duplicated so
/// that the two sides separate. Every change goes through the container's modifier (points with
/// their ancestors, edges, triangles added then removed), so everything that follows the container
/// follows the cut. See docs/topological-changes.md#incision.

#include "penalty/core/types.hpp"
#include "penalty/mechanics/topology_container.hpp"

#include <array>
#include <utility>
#include <vector>

namespace penalty {

/// One element of a cut's path (SOFA's intersected_topoElements / indices / barycoefs).
struct IncisionPathElement {
    ElementType type = ElementType::point;
    ElementId index = -1;
    /// point: its position (only the first path element after a previous cut); edge: [0] the
    /// coordinate along the edge from its vertex 0; triangle: the barycentric coordinates.
    std::array<double, 3> coefs{};
};

class TriangleIncision {
public:
    /// `positions`: the container's state positions (read as the cut goes: new points appear).
    TriangleIncision(TopologyContainer& container, const std::vector<Vec3>& positions);

    /// TopologicalChangeProcessor::findElementIndex: the triangle holding `p` (its bounding box
    /// and inside test; else the triangle holding p's projection on its plane), `previous` when it
    /// is one of several; -1 when none.
    [[nodiscard]] ElementId find_triangle(const Vec3& p, ElementId previous = -1) const;
    /// computeTriangleBarycoefs: p's barycentric coordinates in triangle t (1/3 each when flat).
    [[nodiscard]] std::array<double, 3> barycentric(ElementId t, const Vec3& p) const;
    /// compute3PointsBarycoefs: p's barycentric coordinates in the triangle (a, b, c).
    [[nodiscard]] static std::array<double, 3> barycentric_of(const Vec3& p, const Vec3& a, const Vec3& b,
                                                              const Vec3& c);

    /// computeIntersectedObjectsList: the path from a (in triangle ta, or the point last_point of
    /// a previous cut when >= 0) to b (in triangle tb). False when the segment does not reach b
    /// across the mesh (leaves it, or a and b lie in one triangle). ta may change (SOFA's).
    bool intersected_objects(PointId last_point, const Vec3& a, const Vec3& b, ElementId& ta, ElementId& tb,
                             std::vector<IncisionPathElement>& path) const;

    /// SplitAlongPath: creates the path's points and splits the triangles it crosses; `new_edges`
    /// receives the edges along the path. Snaps path points closer than `epsilon_path` to a vertex
    /// onto it, and a path end closer than `epsilon_border` to a border edge onto that edge (0:
    /// off). Returns the number of points created; -1 for a path SOFA cannot split.
    int split_along_path(PointId a_point, Vec3& a, PointId b_point, Vec3& b, std::vector<IncisionPathElement>& path,
                         std::vector<ElementId>& new_edges, double epsilon_path, double epsilon_border);

    /// InciseAlongEdgeList: duplicates the points inside the chain of `edges` and moves the
    /// triangles on one side onto the copies. `end_points`: the chain's ends that are not on the
    /// border (where a next cut continues); `reach_border`: its last end is on the border.
    bool incise_along_edge_list(const std::vector<ElementId>& edges, std::vector<PointId>& new_points,
                                std::vector<PointId>& end_points, bool& reach_border);

private:
    [[nodiscard]] const MeshTopology& mesh() const { return container_->mesh(); }
    [[nodiscard]] const Vec3& x(PointId p) const { return (*positions_)[std::size_t(p)]; }
    bool segment_triangle_intersection(bool entered, const Vec3& a, const Vec3& b, ElementId t,
                                       std::vector<PointId>& indices, double& bary, double& kmin) const;
    bool intersected_points(PointId last_point, const Vec3& a, const Vec3& b, ElementId& ta, ElementId& tb,
                            std::vector<ElementId>& edges, std::vector<double>& coords) const;
    bool point_inside(ElementId t, const Vec3& p) const;
    [[nodiscard]] Vec3 edge_point(ElementId e, double coord) const;
    void snap_along_path(std::vector<IncisionPathElement>& path, std::vector<std::vector<double>>& snaps,
                         double epsilon) const;
    void snap_border_path(PointId pa, Vec3& a, PointId pb, Vec3& b, std::vector<IncisionPathElement>& path,
                          const std::vector<std::vector<double>>& snaps, double epsilon) const;
    void snap_border_end(bool last, Vec3& a_written, const Vec3& end, std::vector<IncisionPathElement>& path,
                         double epsilon) const;
    [[nodiscard]] std::vector<double> project_on_edge(ElementId e, const Vec3& c, bool& intersected) const;
    void apply_split(const std::vector<PointAncestorElement>& points, const std::vector<Triangle>& triangles,
                     const std::vector<std::vector<ElementId>>& ancestors, std::vector<ElementId> removed);
    void move_snapped(const std::vector<std::vector<double>>& snaps);

    TopologyContainer* container_;
    const std::vector<Vec3>* positions_;
};

/// One INCISE= line of a TopologicalChangeProcessor file: the cut's points, and their triangles
/// (the index form) or none (the coordinates form: each point's triangle is found).
struct IncisionLine {
    std::vector<Vec3> points;
    std::vector<ElementId> triangles;
};

/// What a line did: the segments cut, and the first one refused (its path leaves the surface or
/// stays in one triangle: SOFA's "Invalid path", which ends the line), or -1.
struct IncisionOutcome {
    std::size_t segments_cut = 0;
    int refused_segment = -1;
};

/// TopologicalChangeProcessor::processTopologicalChanges, an INCISE= line: each segment from the
/// previous point (or from where the previous cut ended inside the surface) to the next, cut
/// (computeIntersectedObjectsList, SplitAlongPath, InciseAlongEdgeList). Throws
/// std::invalid_argument naming the point for a point in no triangle or a triangle index out of
/// range, and for a segment SOFA cannot split.
IncisionOutcome incise_line(TopologyContainer& container, const std::vector<Vec3>& positions, const IncisionLine& line,
                            double epsilon_path, double epsilon_border);

/// TopologicalChangeProcessor's TriangleIncisionInformation (saveIndicesAtInit): the points of
/// the cuts of one time as triangles and barycentric coordinates there, followed through the
/// changes (updateTriangleIncisionInformation).
struct SavedIncision {
    double time = 0;
    std::vector<ElementId> triangles;
    std::vector<std::array<double, 3>> barycentric;
    std::vector<Vec3> coordinates;  ///< computeCoordinates: from the triangles' current positions
};

/// TopologicalChangeProcessor::saveIndices: each (time, line) located on the current mesh (the
/// coordinates form: findElementIndex), the lines of one time (within 1e-10) merged; a cut
/// starting where the previous one ended (within 1e-5) starts 1e-5 of the way along its first
/// segment instead (SOFA's "HACK"). Throws std::invalid_argument for a point in no triangle.
std::vector<SavedIncision> save_incisions(TopologyContainer& container, const std::vector<Vec3>& positions,
                                          const std::vector<std::pair<double, IncisionLine>>& lines);

/// TopologicalChangeProcessor::inciseWithSavedIndices: the saved cut `index`, its points where
/// their triangles now are, each segment cut as incise_line's, every saved cut's triangles and
/// barycentric coordinates found again after each segment.
IncisionOutcome incise_saved(TopologyContainer& container, const std::vector<Vec3>& positions,
                             std::vector<SavedIncision>& saved, std::size_t index, double epsilon_path,
                             double epsilon_border);

/// The number of connected components of a triangle list (triangles sharing a vertex are
/// connected); what a cut across a surface changes.
[[nodiscard]] std::size_t count_connected_components(const std::vector<Triangle>& triangles, std::size_t num_points);

}  // namespace penalty
