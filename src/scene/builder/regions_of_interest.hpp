#pragma once
// What the region-of-interest engines share (BoxROI in masses_and_regions.cpp, PlaneROI and
// SphereROI in regions_of_interest.cpp): their inputs (points and element lists, SOFA's
// BaseROI::init and PlaneROI::init defaults) and their outputs (index lists read through links
// such as `@roi.triangleIndices`).
#include "penalty/mechanics/regions_of_interest.hpp"
#include "scene/builder/scene_builder.hpp"

#include <optional>

namespace penalty::scene::builder {

/// Where an ROI looks for its points and elements when the scene gives none.
enum class RoiContext {
    /// BaseROI::init (BoxROI, SphereROI): points = the rest positions of the node's own state,
    /// else of the node's first loader, else of the nearest ancestor's state; elements = the
    /// node's own topology.
    base_roi,
    /// PlaneROI::init: points = the rest positions of the nearest state (the node's or an
    /// ancestor's), else of the node's first loader; elements = the nearest topology.
    plane_roi,
};

/// Which element lists an ROI class has: BaseROI's five, or PlaneROI's edges, triangles and
/// tetrahedra.
struct RoiListNames {
    bool quads_and_hexahedra = true;  ///< false for PlaneROI (edges, triangles, tetrahedra only)
    bool quad_alias = false;          ///< BoxROI: `quad` is an alias of `quads` (BoxROI::BoxROI)
};

/// The ROI's points: `position` or its alias `rest_position` (inline or a link), else the
/// context's default (see RoiContext).
[[nodiscard]] std::vector<Vec3> roi_points(SceneBuilder& b, const Attributes& a, const NodeBuild& info,
                                           RoiContext context);
/// The points of a data `name` (inline or a link), when the scene sets it (SphereROI's `centers`).
[[nodiscard]] std::optional<std::vector<Vec3>> given_points(SceneBuilder& b, const Attributes& a,
                                                            std::string_view name);
/// True when every link of `attr` resolves. A region's `position` whose link finds nothing is
/// SOFA's empty Data (a warning, no point tested), not a scene error (validate() lets it pass).
[[nodiscard]] bool roi_link_resolves(const io::SceneComponent& c, std::string_view attr);
/// The ROI's element lists: each given (inline or a link to a loader's or a topology's list), else
/// the context's topology's; empty when its `compute...` flag is 0. The spec declares each list
/// of `names` and its flag.
[[nodiscard]] RoiElements roi_elements(SceneBuilder& b, const Attributes& a, const NodeBuild& info, RoiContext context,
                                       RoiListNames names = {});
/// The index outputs of a selection by Data name: `indices` (and `aliases` of it), `edgeIndices`,
/// `triangleIndices`, `quadIndices`, `tetrahedronIndices`, `hexahedronIndices`.
[[nodiscard]] std::vector<std::pair<std::string, std::vector<PointId>>> roi_index_outputs(
    RoiSelection selection, std::initializer_list<const char*> aliases_of_indices = {});
/// The element outputs of a selection by Data name (BaseROI's edgesInROI, trianglesInROI,
/// quadsInROI, tetrahedraInROI, hexahedraInROI: the selected elements of `elements`, in order).
[[nodiscard]] std::vector<std::pair<std::string, io::MeshData>> roi_element_outputs(const RoiSelection& selection,
                                                                                    const RoiElements& elements);
/// Records the outputs `indices`, `edgeIndices`, `triangleIndices`, `quadIndices`,
/// `tetrahedronIndices`, `hexahedronIndices` of engine `c` (and `aliases` of `indices`).
void record_roi_selection(SceneBuilder& b, const io::SceneComponent& c, RoiSelection selection,
                          std::initializer_list<const char*> aliases_of_indices = {});
/// Records the elements of the selection as BaseROI's outputs edgesInROI, trianglesInROI,
/// quadsInROI, tetrahedraInROI, hexahedraInROI (the selected elements of `elements`, in order).
void record_roi_elements_in(SceneBuilder& b, const io::SceneComponent& c, const RoiSelection& selection,
                            const RoiElements& elements);
/// `penalty info`: "selects 3 of 40 points, 2 of 60 triangles (inside 1 box)".
[[nodiscard]] std::string describe_roi_selection(const RoiSelection& s, std::size_t num_points,
                                                 const RoiElements& elements, const std::string& shapes);

}  // namespace penalty::scene::builder
