// Lumped masses, regions of interest and the projective constraints that read them:
// DiagonalMass, BoxROI, FixedPlaneProjectiveConstraint.
#include "penalty/mechanics/diagonal_mass.hpp"
#include "penalty/mechanics/fixed_plane_constraint.hpp"
#include "penalty/mechanics/oriented_box.hpp"
#include "penalty/mechanics/regions.hpp"
#include "penalty/mechanics/rigid_diagonal_mass.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/regions_of_interest.hpp"
#include "scene/builder/scene_builder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <sstream>

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

// ---- DiagonalMass ---------------------------------------------------------------------------
// SOFA's DiagonalMass data: massDensity and totalMass default to 1, the default being used as
// totalMass = 1 when none of the three is set (DiagonalMass::massInitialization).
constexpr AttributeSpec kDiagonalMass[] = {
    {"massDensity", K::real, "1", "kg/m^3", ValueCheck::nonnegative,
     "per volume, area or length of the lumped elements"},
    {"totalMass", K::real, "1", "kg", ValueCheck::nonnegative, "shared in proportion to the lumped elements; wins"},
    {"vertexMass", K::text, "", "kg", ValueCheck::none,
     "mass of each vertex (a short list is padded with its last value); Rigid3d: mass volume [inertia] per frame"},
    {"computeMassOnRest", K::boolean, "1", "", ValueCheck::none, "penalty lumps on rest positions only"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "the elements to lump"},
    {"geometryState", K::link, "(the node's state)", "", ValueCheck::none, "penalty: the mass's own state only"},
    {"showGravityCenter", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"showAxisSizeFactor", K::real, "1", "", ValueCheck::none, "drawing only"},
};

/// DiagonalMass<Rigid3> (SOFA's initRigidImpl): `vertexMass` is a list of SOFA's RigidMass, each
/// "mass volume [inertia 3x3]" (11 numbers; brackets and commas are separators), taken as given.
void build_rigid_diagonal_mass(SceneBuilder& b, const Attributes& a, NodeBuild& info, Rigid3Object& s) {
    const SceneComponent& c = a.component();
    std::vector<RigidDiagonalMass::FrameMass> masses;
    b.guarded(c, [&] {
        std::string text = a.text("vertexMass");
        for (char& ch : text)
            if (ch == '[' || ch == ']' || ch == ',') ch = ' ';
        std::vector<double> v;
        std::istringstream in(text);
        for (std::string word; in >> word;) {
            char* end = nullptr;
            const double x = std::strtod(word.c_str(), &end);
            if (end == word.c_str() || *end != '\0' || !std::isfinite(x))
                a.fail("vertexMass", "expected numbers (mass volume [inertia]) per frame, found '" + word + "'");
            v.push_back(x);
        }
        if (v.size() % 11 != 0)
            a.fail("vertexMass",
                   "a Rigid3d DiagonalMass takes 11 numbers per frame (mass volume [3x3 inertia]), found " +
                       std::to_string(v.size()));
        for (std::size_t i = 0; i < v.size(); i += 11)
            masses.push_back({v[i], Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(v.data() + i + 2)});
        if (masses.size() > s.num_dofs() && s.num_dofs() > 0)
            b.warn(c.describe() + ": " + std::to_string(masses.size()) + " masses for " + std::to_string(s.num_dofs()) +
                   " frames: the extra ones are not used");
        info.node->set_mass<RigidDiagonalMass>(s, std::move(masses));
    });
    auto* mass = static_cast<RigidDiagonalMass*>(info.node->mass());
    b.record_mass(*mass, *info.node, c);
    b.role(c, [mass] {
        return std::to_string(mass->masses().size()) + " rigid masses as given, " + num(mass->total_mass()) +
               " kg in all";
    });
    b.note_unread_attributes(c);
}

void build_diagonal_mass(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    if (auto* r = dynamic_cast<Rigid3Object*>(&s)) {
        build_rigid_diagonal_mass(b, a, info, *r);
        return;
    }
    DiagonalMass* mass = nullptr;
    b.guarded(c, [&] {
        auto* v = dynamic_cast<Vec3Object*>(&s);
        if (v == nullptr) io::throw_element_error(c, "penalty's DiagonalMass supports Vec3d and Rigid3d states only");
        if (!a.boolean("computeMassOnRest")) a.fail("computeMassOnRest", "penalty lumps on the rest positions only");
        if (a.has("geometryState")) {
            const io::LinkTarget g = a.link("geometryState");
            if (g.component != info.state_component) a.fail("geometryState", "must be the mass's own state");
        }
        const MeshTopology& topology = b.topology_of(a, info);
        mass = &info.node->set_mass<DiagonalMass>(*v, topology);
        if (a.has("totalMass")) mass->set_total_mass(a.real("totalMass"));
        if (a.has("massDensity")) mass->set_mass_density(a.real("massDensity"));
        if (a.has("vertexMass")) mass->set_vertex_masses(a.numbers("vertexMass"));
    });
    b.record_mass(*mass, *info.node, c);
    b.role(c, [mass] {
        return "lumped mass from the " + std::string(lumped_element_name(mass->element_kind())) + ", density " +
               num(mass->mass_density()) + ", " + num(mass->total_mass()) + " kg in all";
    });
    b.add_init(1, c, [mass] { mass->init(); });
    b.note_unread_attributes(c);
}

// ---- BoxROI ---------------------------------------------------------------------------------
// SOFA's BoxROI (BaseROI::init, BaseROI::doUpdate, BoxROI::roiInit): the points of `position`
// (default: the rest positions of the node's state) inside any box, with no box the box
// 0 0 0 1 1 1; and the elements (given, or the node's topology's) inside: all of their points in
// some box (`strict`, the default), else their centre (regions_of_interest.hpp).
constexpr AttributeSpec kBoxRoi[] = {
    {"box", K::numbers, "0 0 0 1 1 1", "m", ValueCheck::none, "boxes: xmin ymin zmin xmax ymax zmax each"},
    {"orientedBox", K::numbers, "", "m", ValueCheck::none,
     "boxes: p0 p1 p2 (corners) and depth, each (oriented_box.hpp)"},
    {"position", K::points, "(rest positions of the node's state)", "m", ValueCheck::none, "points tested"},
    {"rest_position", K::points, "", "m", ValueCheck::none, "alias of position"},
    {"edges", K::elements, "(the node's topology)", "", ValueCheck::none, "edges tested (inline or a link)"},
    {"triangles", K::elements, "(the node's topology)", "", ValueCheck::none, "triangles tested (inline or a link)"},
    {"quads", K::elements, "(the node's topology)", "", ValueCheck::none, "quads tested (inline or a link)"},
    {"quad", K::elements, "", "", ValueCheck::none, "alias of quads"},
    {"tetrahedra", K::elements, "(the node's topology)", "", ValueCheck::none, "tetrahedra tested (inline or a link)"},
    {"hexahedra", K::elements, "(the node's topology)", "", ValueCheck::none, "hexahedra tested (inline or a link)"},
    {"computeEdges", K::boolean, "1", "", ValueCheck::none, "0: that list is not tested"},
    {"computeTriangles", K::boolean, "1", "", ValueCheck::none, "0: that list is not tested"},
    {"computeQuads", K::boolean, "1", "", ValueCheck::none, "0: that list is not tested"},
    {"computeTetrahedra", K::boolean, "1", "", ValueCheck::none, "0: that list is not tested"},
    {"computeHexahedra", K::boolean, "1", "", ValueCheck::none, "0: that list is not tested"},
    {"strict", K::boolean, "1", "", ValueCheck::none, "1: all points of an element inside; 0: its centre"},
    {"doUpdate", K::boolean, "1", "", ValueCheck::none,
     "1: selects again when `position` links a state's moving positions; 0: the selection of init stays"},
    {"indices", K::indices, "", "", ValueCheck::none, "output (a written value is replaced)"},
    {"edgeIndices", K::indices, "", "", ValueCheck::none, "output"},
    {"triangleIndices", K::indices, "", "", ValueCheck::none, "output"},
    {"quadIndices", K::indices, "", "", ValueCheck::none, "output"},
    {"tetrahedronIndices", K::indices, "", "", ValueCheck::none, "output"},
    {"hexahedronIndices", K::indices, "", "", ValueCheck::none, "output"},
    {"drawBoxes", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"drawROI", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"drawPoints", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"drawEdges", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"drawTriangles", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"drawQuads", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"drawTetrahedra", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"drawHexahedra", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"drawSize", K::real, "0", "", ValueCheck::none, "drawing only"},
};

/// BoxROI's selection (BaseROI::doUpdate): the points inside a box, the elements by `test`.
RoiSelection select_in_box_roi(const std::vector<Vec3>& points, const RoiElements& elements,
                               const std::vector<AlignedBox>& boxes, const std::vector<OrientedBox>& oriented,
                               ElementTest test) {
    const auto inside = [&boxes, &oriented](const Vec3& p) {
        return std::any_of(boxes.begin(), boxes.end(), [&p](const AlignedBox& box) { return box.contains(p); }) ||
               std::any_of(oriented.begin(), oriented.end(), [&p](const OrientedBox& box) { return box.contains(p); });
    };
    return select_in_region(points, elements, inside, test);
}

/// BoxROI's `box` linked to points (a Vec3d state's `position`, a point output of an engine):
/// SOFA's conversion of a list of Vec3 to a list of Vec6 (BaseData::genericCopyValueFrom: per
/// point, its three numbers then three zeros), tested as copied (the copy comes after
/// BoxROI::roiInit, which ordered nothing: each box goes from the point to the origin, a box with
/// a positive coordinate holding nothing on that axis).
std::vector<AlignedBox> boxes_of_points(const std::vector<Vec3>& points) {
    std::vector<AlignedBox> boxes;
    boxes.reserve(points.size());
    for (const Vec3& p : points) boxes.push_back(AlignedBox{p, Vec3::Zero()});
    return boxes;
}

/// BoxROI's boxes (BoxROI::roiInit): each `box`'s corners ordered, the default box only when
/// neither `box` nor `orientedBox` is given, the oriented boxes from their three corners and depth.
/// After a write (`written`, SofaQuirkFixes::fix_box_roi_write off), SOFA's roiInit does not run
/// again: the written `box` is tested as written, the oriented boxes stay those of init. A `box`
/// linked to moving points (`linked`): boxes_of_points.
void read_box_roi_boxes(const Attributes& a, const BoxRoiWrite* written, const LivePoints* linked,
                        std::vector<AlignedBox>& boxes, std::vector<OrientedBox>& oriented) {
    const bool defaults = !a.has("box") && !a.has("orientedBox");
    const std::vector<double> v = defaults ? std::vector<double>{0, 0, 0, 1, 1, 1}
                                  : linked ? std::vector<double>{}
                                           : a.numbers("box");
    if (linked != nullptr) boxes = boxes_of_points(linked->current());
    else if (v.size() % 6 != 0 || (a.has("box") && v.empty()))
        a.fail("box", "expected 6 numbers per box, found " + std::to_string(v.size()));
    for (std::size_t i = 0; i < v.size(); i += 6) {
        const Vec3 lo(v[i], v[i + 1], v[i + 2]), hi(v[i + 3], v[i + 4], v[i + 5]);
        boxes.push_back(written != nullptr && written->box_as_written ? AlignedBox{lo, hi}
                                                                      : AlignedBox::from_corners(lo, hi));
    }
    std::vector<double> o = a.numbers("orientedBox");
    if (o.size() % 10 != 0 || (a.has("orientedBox") && o.empty()))
        a.fail("orientedBox", "expected 10 numbers per box (p0, p1, p2, depth), found " + std::to_string(o.size()));
    if (written != nullptr && written->oriented_of_init) {
        SceneComponent init = a.component();  // the same file and line in an error
        std::erase_if(init.attributes, [](const io::SceneAttribute& x) { return x.name == "orientedBox"; });
        if (!written->oriented_of_init->empty())
            init.attributes.push_back({"orientedBox", *written->oriented_of_init, 0});
        o = Attributes(init).numbers("orientedBox");
    }
    for (std::size_t i = 0; i < o.size(); i += 10) {
        const Vec3 p0(o[i], o[i + 1], o[i + 2]), p1(o[i + 3], o[i + 4], o[i + 5]), p2(o[i + 6], o[i + 7], o[i + 8]);
        if ((p1 - p0).cross(p2 - p0).norm() == 0)
            a.fail("orientedBox", "box " + std::to_string(i / 10) + ": p0, p1 and p2 are aligned (no plane)");
        oriented.emplace_back(p0, p1, p2, o[i + 9]);
    }
}

void build_box_roi(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    std::vector<AlignedBox> boxes;
    std::vector<OrientedBox> oriented;
    std::size_t num_points = 0;
    RoiElements elements;
    RoiSelection selection;
    b.guarded(c, [&] {
        // `box` linked to moving points (BoxROI's constructor: addInput(&d_alignedBoxes)): followed
        const std::optional<LivePoints> linked = a.has("box") ? b.moving_input(a, "box") : std::nullopt;
        read_box_roi_boxes(a, b.box_roi_write(c), linked ? &*linked : nullptr, boxes, oriented);
        const std::vector<Vec3> points = roi_points(b, a, info, RoiContext::base_roi);
        num_points = points.size();
        elements = roi_elements(b, a, info, RoiContext::base_roi, {.quad_alias = true});
        const ElementTest test = a.boolean("strict") ? ElementTest::all_points : ElementTest::center;
        selection = select_in_box_roi(points, elements, boxes, oriented, test);
        // over moving positions (a state's, which the solve writes) or a moving `box`: run again
        // on read (live_engines.cpp)
        b.add_live_engine(a, points, [boxes, oriented, elements, test](const std::vector<Vec3>& x, LiveEngine& engine) {
            const std::vector<Vec3>* box_points = engine.followed("box");
            const RoiSelection s =
                select_in_box_roi(x, elements, box_points ? boxes_of_points(*box_points) : boxes, oriented, test);
            for (auto& [name, mesh] : roi_element_outputs(s, elements)) engine.meshes[name] = std::move(mesh);
            engine.meshes["quadInROI"] = engine.meshes["quadsInROI"];  // alias
            for (auto& [name, indices] : roi_index_outputs(s)) engine.indices[name] = indices;
        });
    });
    b.role(c, [n = boxes.size() + oriented.size(), num_points, selection, elements] {
        return describe_roi_selection(selection, num_points, elements, counted(n, "box", "boxes"));
    });
    record_roi_elements_in(b, c, selection, elements);
    if (const io::MeshData* quads = b.engine_mesh(c, "quadsInROI"))
        b.record_engine_mesh(c, "quadInROI", *quads);  // alias
    record_roi_selection(b, c, std::move(selection));
    b.note_unread_attributes(c);
}

// ---- FixedPlaneProjectiveConstraint ------------------------------------------------------------
// SOFA's defaults: direction unset (0 0 0), dmin = dmax = 0; the points between the planes are
// selected (appended to `indices`) only when dmin != dmax (FixedPlaneProjectiveConstraint::init).
constexpr AttributeSpec kFixedPlane[] = {
    {"direction", K::vector3, "0 0 0", "", ValueCheck::none, "the constrained direction (not normalised, as SOFA)"},
    {"dmin", K::real, "0", "m", ValueCheck::none, "points with dmin < x.direction < dmax are selected"},
    {"dmax", K::real, "0", "m", ValueCheck::none, ""},
    {"indices", K::indices, "", "", ValueCheck::none, "DOFs constrained besides the selected ones"},
};

void build_fixed_plane(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    b.guarded(c, [&] {
        const Vec3 direction = a.vector3("direction");
        const double dmin = a.real("dmin");
        const double dmax = a.real("dmax");
        std::vector<Index> indices;
        for (PointId i : b.indices(a, "indices")) indices.push_back(i);
        if (dmin != dmax) {
            std::vector<Vec3> points;
            if (auto* v = dynamic_cast<Vec3Object*>(&s)) points = v->position;
            else
                for (const RigidFrame& f : dynamic_cast<Rigid3Object&>(s).position) points.push_back(f.center);
            for (Index i : points_between_planes(points, direction, dmin, dmax)) indices.push_back(i);
        }
        auto& f = info.node->add_constraint<FixedPlaneProjectiveConstraint>(s, direction);
        b.record_origin(&f, c);
        f.set_indices(std::move(indices));
        b.add_init(1, c, [p = &f] { p->init(); });
        b.role(c, [p = &f, st = &s] {
            return "removes the response along " + vec(p->direction()) + " of " + std::to_string(p->indices().size()) +
                   " of " + counted(st->num_dofs(), "DOF", "DOFs");
        });
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kMassAndRegionComponents[] = {
    {.type = "DiagonalMass",
     .family = F::mass,
     .summary = "lumped mass from the topology's elements",
     .attributes = kDiagonalMass,
     .build = build_diagonal_mass},
    {.type = "BoxROI",
     .family = F::engine,
     .summary = "indices of the points inside boxes",
     .attributes = kBoxRoi,
     .build = build_box_roi},
    {.type = "FixedPlaneProjectiveConstraint",
     .family = F::constraint,
     .summary = "no response along a direction for the points between two planes",
     .attributes = kFixedPlane,
     .build = build_fixed_plane},
    {.type = "FixedPlaneConstraint",
     .family = F::constraint,
     .summary = "FixedPlaneProjectiveConstraint (older name)",
     .attributes = kFixedPlane,
     .build = build_fixed_plane,
     .sofa_class = "FixedPlaneProjectiveConstraint"},
};

}  // namespace

std::span<const ComponentSpec> mass_and_region_components() { return kMassAndRegionComponents; }

}  // namespace penalty::scene::builder
