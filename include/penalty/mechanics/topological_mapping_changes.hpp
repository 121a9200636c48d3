#pragma once
/// @file
/// The topological mappings while their input changes: SOFA's ...TopologicalMapping::
/// updateTopologicalMappingTopDown, run by the input's propagation (as a listener: after the
/// input's data handlers), which edits the output container through its own operations (so the
/// output's followers see SOFA's events). Each keeps SOFA's Loc2GlobVec / Glob2LocMap between the
/// output's elements and the input's.

#include "penalty/mechanics/topology_container.hpp"

#include <array>
#include <map>
#include <vector>

namespace penalty {

/// A topological mapping between two containers (input → output).
class TopologicalMappingFollower : public TopologyHandler {
public:
    TopologicalMappingFollower(TopologyContainer& input, TopologyContainer& output)
        : input_(&input), output_(&output) {}
    [[nodiscard]] TopologyContainer& input() const { return *input_; }
    [[nodiscard]] TopologyContainer& output() const { return *output_; }
    /// The input element of each output element (SOFA's Loc2GlobVec).
    [[nodiscard]] const std::vector<ElementId>& output_to_input() const { return loc2glob_; }
    /// SOFA's getFromIndex(getGlobIndex(output element)): the input cell an output element comes
    /// from (a face's only cell, else 0, as SOFA); -1 when the mapping has no such rule.
    [[nodiscard]] virtual ElementId input_cell_of(ElementId /*output_element*/) const { return -1; }

protected:
    /// ENDING_EVENT, POINTSADDED, POINTSREMOVED: what every mapping forwards to its output.
    bool forward_common(const TopologyChange& change);
    TopologyContainer* input_;
    TopologyContainer* output_;
    std::vector<ElementId> loc2glob_;
    std::map<ElementId, ElementId> glob2loc_;
};

/// Tetra2TriangleTopologicalMapping: the output holds the input's border triangles.
class Tetra2TriangleMappingFollower final : public TopologicalMappingFollower {
public:
    /// Builds the maps from the output as init() made it (the input's triangles on one
    /// tetrahedron, in the input's order; none with `no_initial_triangles`).
    Tetra2TriangleMappingFollower(TopologyContainer& input, TopologyContainer& output, bool flip_normals,
                                  bool no_new_triangles, bool no_initial_triangles);
    void handle_topology_changes(std::span<const TopologyChange> changes) override;
    [[nodiscard]] ElementId input_cell_of(ElementId output_element) const override;

private:
    void triangles_removed(const TopologyChange& c);
    void tetrahedra_added(const TopologyChange& c);
    void tetrahedra_removed(const TopologyChange& c);
    bool flip_normals_, no_new_triangles_;
};

/// Hexa2QuadTopologicalMapping: the output holds the input's quads on one hexahedron.
class Hexa2QuadMappingFollower final : public TopologicalMappingFollower {
public:
    Hexa2QuadMappingFollower(TopologyContainer& input, TopologyContainer& output, bool flip_normals);
    void handle_topology_changes(std::span<const TopologyChange> changes) override;
    [[nodiscard]] ElementId input_cell_of(ElementId output_element) const override;

private:
    void hexahedra_removed(const TopologyChange& c);
    bool flip_normals_;
};

/// Quad2TriangleTopologicalMapping: two output triangles per input quad (SOFA's In2OutMap).
class Quad2TriangleMappingFollower final : public TopologicalMappingFollower {
public:
    Quad2TriangleMappingFollower(TopologyContainer& input, TopologyContainer& output);
    void handle_topology_changes(std::span<const TopologyChange> changes) override;

private:
    void quads_removed(const TopologyChange& c);
    std::map<ElementId, std::array<ElementId, 2>> in2out_;
};

/// Triangle2EdgeTopologicalMapping: the output holds the input's edges on one triangle.
class Triangle2EdgeMappingFollower final : public TopologicalMappingFollower {
public:
    Triangle2EdgeMappingFollower(TopologyContainer& input, TopologyContainer& output);
    void handle_topology_changes(std::span<const TopologyChange> changes) override;

private:
    void triangles_removed(const TopologyChange& c);
    void triangles_added(const TopologyChange& c);
};

}  // namespace penalty
