// Mappings and constraints: IdentityMapping, BarycentricMapping, SubsetMapping, RigidMapping,
// FixedProjectiveConstraint (and its older name FixedConstraint).
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/rigid_frame_mapping.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using io::SceneNode;
using K = AttributeKind;
using F = ComponentFamily;

// ---- mappings -------------------------------------------------------------------------------
constexpr AttributeSpec kMappingEnds[] = {
    {"input", K::link, "(the parent node's state)", "", ValueCheck::none, "node or MechanicalObject mapped from"},
    {"output", K::link, "(this node's state)", "", ValueCheck::none, "must be this node's MechanicalObject"},
};
constexpr AttributeSpec kSubsetMapping[] = {
    {"indices", K::indices, "(matched by position)", "", ValueCheck::none, "input point of each output point"},
    {"radius", K::real, "1e-5", "m", ValueCheck::nonnegative,
     "without indices: largest distance of a matched input point"},
};
constexpr AttributeSpec kRigidMapping[] = {
    {"points", K::points, "(the output's positions)", "m", ValueCheck::none, "points in the frames"},
    {"index", K::indices, "0", "", ValueCheck::none, "frame of every point (one index)"},
    {"rigidIndexPerPoint", K::indices, "", "", ValueCheck::none, "frame of each point"},
    {"globalToLocalCoords", K::boolean, "0", "", ValueCheck::none, "points given in world coordinates"},
    {"initialPoints", K::numbers, "(the output's positions)", "m", ValueCheck::none,
     "SOFA's local points (3 numbers each) or frames (7, Rigid3d output)"},
};

struct MappingEnds {
    BaseState* in = nullptr;
    Vec3Object* out = nullptr;           ///< the output when it is a Vec3d state
    BaseState* out_state = nullptr;      ///< the output (Vec3d, or Rigid3d where the mapping allows it)
    const NodeBuild* in_info = nullptr;  ///< the input's node (its topology)
};

/// The state a mapping's `input` / `output` link names (default: parent's / own node's).
BaseState* mapping_end(SceneBuilder& b, const Attributes& a, std::string_view attr, const SceneNode* fallback) {
    const SceneNode* target_node = fallback;
    if (a.has(attr)) {
        const io::LinkTarget t = a.link(attr);
        if (t.node != nullptr) {
            target_node = t.node;
        } else if (t.component != nullptr && find_component(t.component->type)->family == F::state) {
            target_node = t.component->node;
            if (b.node_build(*target_node).state_component != t.component)
                a.fail(attr, "links to a MechanicalObject that was not built");
        } else {
            a.fail(attr, "must link to a node or a MechanicalObject");
        }
    }
    if (target_node == nullptr || b.node_builds().count(target_node) == 0 ||
        b.node_build(*target_node).node == nullptr || b.node_build(*target_node).node->state() == nullptr)
        a.fail(attr, "no MechanicalObject to map " + std::string(attr == "input" ? "from" : "to"));
    return b.node_build(*target_node).node->state();
}

/// Resolves input and output; the output is the node's own Vec3d state (or Rigid3d state with
/// `rigid_output_allowed`).
MappingEnds mapping_ends(SceneBuilder& b, const Attributes& a, const NodeBuild& info,
                         bool rigid_output_allowed = false) {
    const SceneComponent& c = a.component();
    if (info.state_component == nullptr)
        io::throw_element_error(c, "needs a MechanicalObject in its node (its output)");
    MappingEnds ends;
    ends.in = mapping_end(b, a, "input", info.scene_node->parent);
    BaseState* out = mapping_end(b, a, "output", info.scene_node);
    if (out != info.node->state()) a.fail("output", "must be the MechanicalObject of the mapping's own node");
    for (const auto& [n, i] : b.node_builds())
        if (i.node && i.node->state() == ends.in) ends.in_info = &i;
    ends.out = dynamic_cast<Vec3Object*>(out);
    ends.out_state = out;
    if (ends.out == nullptr && !(rigid_output_allowed && dynamic_cast<Rigid3Object*>(out) != nullptr))
        a.fail("output", rigid_output_allowed ? "must be a Vec3d or Rigid3d MechanicalObject"
                                              : "must be a Vec3d MechanicalObject");
    return ends;
}

/// Registers the mapping's init (phase 0, top-down) and its `penalty info` line.
void finish_mapping(SceneBuilder& b, const SceneComponent& c, const NodeBuild& info, const MappingEnds& ends,
                    const std::string& how) {
    BaseMapping* mapping = info.node->mapping();
    b.record_origin(mapping, c);
    b.add_init(0, c, [mapping] { mapping->init(); });
    const std::string from = ends.in_info != nullptr ? node_path(*ends.in_info->scene_node) : "?";
    b.role(c, [out = ends.out_state, from, how] {
        return "maps " + from + " onto this node's " + counted(out->num_dofs(), "point", "points") + " (" + how + ")";
    });
    b.note_unread_attributes(c);
}

void build_identity_mapping(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    const MappingEnds ends = mapping_ends(b, a, info);
    auto* in3 = dynamic_cast<Vec3Object*>(ends.in);
    b.guarded(c, [&] {
        if (in3) info.node->set_mapping<IdentityMapping>(*in3, *ends.out);
        else info.node->set_mapping<RigidCenterIdentityMapping>(dynamic_cast<Rigid3Object&>(*ends.in), *ends.out);
    });
    finish_mapping(b, c, info, ends, in3 ? "identity" : "identity: the frames' centres");
}

/// RigidMapping<Rigid3d, Rigid3d> (rigid_frame_mapping.hpp): the output frames' local frames are
/// `initialPoints`, else the output's frames (in world coordinates with globalToLocalCoords: only
/// their centres are brought into the input frame, as SOFA's getGlobalToLocalCoords).
void build_rigid_frame_mapping(const Attributes& a, const MappingEnds& ends, NodeBuild& info) {
    auto* inr = dynamic_cast<Rigid3Object*>(ends.in);
    if (!inr) a.fail("input", "RigidMapping needs a Rigid3d input");
    auto& out = dynamic_cast<Rigid3Object&>(*ends.out_state);
    std::vector<RigidFrame> local = out.position;
    if (a.has("initialPoints")) {
        const std::vector<double> v = a.numbers("initialPoints");
        if (v.size() % 7 != 0)
            a.fail("initialPoints",
                   "expected 7 numbers (x y z qx qy qz qw) per frame, found " + std::to_string(v.size()));
        local.resize(v.size() / 7);
        for (std::size_t i = 0; i < local.size(); ++i)
            local[i] = RigidFrame{Vec3(v[7 * i], v[7 * i + 1], v[7 * i + 2]),
                                  Quat(v[7 * i + 6], v[7 * i + 3], v[7 * i + 4], v[7 * i + 5])};
    }
    // RigidMapping::getRigidIndex: rigidIndexPerPoint when it has one entry per frame, else `index`.
    std::vector<Index> frames;
    if (a.has("rigidIndexPerPoint"))
        for (PointId i : a.indices("rigidIndexPerPoint")) frames.push_back(i);
    if (frames.size() != local.size()) {
        const std::vector<PointId> index = a.has("index") ? a.indices("index") : std::vector<PointId>{0};
        if (index.size() != 1) a.fail("index", "expected one frame index");
        frames.assign(local.size(), Index(index.front()));
    }
    if (!a.has("initialPoints") && a.boolean("globalToLocalCoords"))
        for (std::size_t i = 0; i < local.size(); ++i) {
            const auto r = static_cast<std::size_t>(frames[i]);
            if (r >= inr->position.size()) a.fail("rigidIndexPerPoint", "frame index out of range");
            const RigidFrame& f = inr->position[r];
            local[i] = RigidFrame{f.orientation.conjugate() * (out.position[i].center - f.center), Quat::Identity()};
        }
    info.node->set_mapping<RigidFrameMapping>(*inr, out).set_frames(std::move(local), std::move(frames));
}

void build_rigid_mapping(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    const MappingEnds ends = mapping_ends(b, a, info, true);
    if (ends.out == nullptr) {
        b.guarded(c, [&] { build_rigid_frame_mapping(a, ends, info); });
        finish_mapping(b, c, info, ends, "rigid: frames fixed in the frames");
        return;
    }
    b.guarded(c, [&] {
        auto* inr = dynamic_cast<Rigid3Object*>(ends.in);
        if (!inr) a.fail("input", "RigidMapping needs a Rigid3d input");
        auto& m = info.node->set_mapping<RigidMapping>(*inr, *ends.out);
        std::vector<Index> frames;
        for (const char* name : {"rigidIndexPerPoint", "index"})
            if (a.has(name))
                for (PointId i : a.indices(name)) frames.push_back(i);
        if (frames.size() == 1) frames.assign(ends.out->position.size(), frames.front());
        std::vector<Vec3> pts = a.has("points") ? a.points("points") : ends.out->position;
        if (!a.has("points") && a.has("initialPoints")) {
            const std::vector<double> v = a.numbers("initialPoints");
            if (v.size() % 3 != 0)
                a.fail("initialPoints", "expected 3 numbers per point, found " + std::to_string(v.size()));
            pts.clear();
            for (std::size_t i = 0; i < v.size(); i += 3) pts.emplace_back(v[i], v[i + 1], v[i + 2]);
        }
        if (a.boolean("globalToLocalCoords")) m.set_points_from_world(pts, frames);
        else m.set_points(pts, frames);
    });
    finish_mapping(b, c, info, ends, "rigid: points fixed in the frames");
}

void build_subset_mapping(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    const MappingEnds ends = mapping_ends(b, a, info);
    b.guarded(c, [&] {
        auto* in3 = dynamic_cast<Vec3Object*>(ends.in);
        if (!in3) a.fail("input", "SubsetMapping needs a Vec3d input");
        auto& m = info.node->set_mapping<BarycentricMapping>(*in3, *ends.out);
        std::vector<std::vector<BarycentricMapping::Entry>> rows;
        if (a.has("indices")) {
            for (PointId i : a.indices("indices")) rows.push_back({{Index(i), 1.0}});
        } else {
            // SubsetMapping::init without indices: each output point takes the nearest input point
            // closer than `radius` (strictly; the last one on ties)
            const double radius = a.real("radius");
            for (std::size_t i = 0; i < ends.out->position.size(); ++i) {
                double best = radius;
                Index found = -1;
                for (std::size_t j = 0; j < in3->position.size(); ++j) {
                    const double r = (ends.out->position[i] - in3->position[j]).norm();
                    if (r < best) {
                        best = r;
                        found = Index(j);
                    }
                }
                if (found < 0)
                    io::throw_element_error(c, "output point " + std::to_string(i) +
                                                   " matches no input point within radius " + num(radius) +
                                                   " (SOFA would leave it fixed)");
                rows.push_back({{found, 1.0}});
            }
        }
        m.set_weights(std::move(rows));
    });
    finish_mapping(b, c, info, ends, "subset: one input point per output point");
}

/// Weights of the output's points (after its own transform) in the input's volume elements. A
/// RegularGridTopology is searched as SOFA's regular-grid mapper does (RegularGridTopology::
/// findCube, then findNearestCube): in the grid's written coordinates (min, max, n), whatever
/// translation, rotation or scale the input state applied to its positions; a point outside the
/// grid takes the nearest cell with unclamped (extrapolated) trilinear coordinates. Mesh
/// topologies use the input's rest positions.
void build_barycentric_mapping(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    const MappingEnds ends = mapping_ends(b, a, info);
    const NodeBuild* in = ends.in_info;
    b.guarded(c, [&] {
        auto* in3 = dynamic_cast<Vec3Object*>(ends.in);
        if (!in3) a.fail("input", "BarycentricMapping needs a Vec3d input");
        if (in == nullptr || in->topology == nullptr) a.fail("input", "the input's node has no topology to map onto");
        auto& m = info.node->set_mapping<BarycentricMapping>(*in3, *ends.out);
        const std::span<const Vec3> points = ends.out->position;
        if (in->grid) map_on_regular_grid(m, *in->grid, points);
        else if (in->sparse_grid) map_on_sparse_grid(m, *in->sparse_grid, points);
        else if (!in->topology->tetrahedra().empty() && in->topology->hexahedra().empty() &&
                 in->topology_component != nullptr && in->topology_component->type.ends_with("SetTopologyContainer"))
            m.map_on_set_tetrahedra(*in->topology, in3->rest_position, points);  // SOFA's TetrahedronSetMapper
        else if (!in->topology->tetrahedra().empty()) m.map_on_tetrahedra(*in->topology, in3->rest_position, points);
        else if (!in->topology->hexahedra().empty() && in->topology_component != nullptr &&
                 in->topology_component->type == "HexahedronSetTopologyContainer")
            m.map_on_set_hexahedra(*in->topology, in3->rest_position, points);  // SOFA's HexahedronSetMapper
        else if (!in->topology->hexahedra().empty()) m.map_on_hexahedra(*in->topology, in3->rest_position, points);
        else
            io::throw_element_error(
                c, "the input topology has no tetrahedra or hexahedra (penalty maps onto volumes only)");
    });
    std::string how = "barycentric: trilinear in the input's hexahedra";
    if (in && in->grid) how = "barycentric: trilinear in the grid's cells";
    else if (in && in->sparse_grid) how = "barycentric: trilinear in the sparse grid's cells";
    else if (in && !in->topology->tetrahedra().empty()) how = "barycentric: in the input's tetrahedra";
    finish_mapping(b, c, info, ends, how);
}

// ---- constraints ----------------------------------------------------------------------------
constexpr AttributeSpec kFixed[] = {
    {"indices", K::indices, "", "", ValueCheck::none, "fixed DOFs"},
    {"fixAll", K::boolean, "0", "", ValueCheck::none, "fix every DOF"},
    {"activate_projectVelocity", K::boolean, "0", "", ValueCheck::none,
     "also set the fixed DOFs' velocity to 0 after each step (0: they keep their velocity)"},
};

void build_fixed(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    b.guarded(c, [&] {
        auto& f = info.node->add_constraint<FixedProjectiveConstraint>(s);
        b.record_origin(&f, c);
        std::vector<Index> idx;
        for (PointId i : b.indices(a, "indices")) idx.push_back(i);
        for (Index i : idx)
            if (std::size_t(i) >= s.num_dofs())
                a.fail("indices",
                       "index " + std::to_string(i) + " out of range (" + std::to_string(s.num_dofs()) + " DOFs)");
        f.set_indices(std::move(idx));
        const bool all = a.boolean("fixAll");
        f.set_fix_all(all);
        f.set_project_velocity(a.boolean("activate_projectVelocity"));
        b.add_init(1, c, [p = &f] { p->init(); });
        b.role(c, [p = &f, st = &s, all] {
            return all ? "fixes all " + counted(st->num_dofs(), "DOF", "DOFs")
                       : "fixes " + std::to_string(p->indices().size()) + " of " +
                             counted(st->num_dofs(), "DOF", "DOFs");
        });
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kMappingAndConstraintComponents[] = {
    {.type = "IdentityMapping",
     .family = F::mapping,
     .summary = "identity mapping",
     .attributes = kMappingEnds,
     .build = build_identity_mapping},
    {.type = "BarycentricMapping",
     .family = F::mapping,
     .summary = "barycentric mapping",
     .attributes = kMappingEnds,
     .build = build_barycentric_mapping},
    {.type = "SubsetMapping",
     .family = F::mapping,
     .summary = "subset mapping",
     .attributes = kSubsetMapping,
     .shared_attributes = kMappingEnds,
     .build = build_subset_mapping},
    {.type = "RigidMapping",
     .family = F::mapping,
     .summary = "rigid mapping",
     .attributes = kRigidMapping,
     .shared_attributes = kMappingEnds,
     .build = build_rigid_mapping},
    {.type = "FixedProjectiveConstraint",
     .family = F::constraint,
     .summary = "fixed points",
     .attributes = kFixed,
     .build = build_fixed},
    {.type = "FixedConstraint",
     .family = F::constraint,
     .summary = "fixed points (older name)",
     .attributes = kFixed,
     .build = build_fixed,
     .sofa_class = "FixedProjectiveConstraint"},
};

}  // namespace

std::span<const ComponentSpec> mapping_and_constraint_components() { return kMappingAndConstraintComponents; }

}  // namespace penalty::scene::builder
