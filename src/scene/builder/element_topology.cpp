// Topologies from element lists: MeshTopology (states_and_topologies.cpp) and SOFA's static
// ...SetTopologyContainer classes (topology_containers.cpp) share this build.
#include "scene/builder/element_topology.hpp"

#include <algorithm>

namespace penalty::scene::builder {

using io::SceneComponent;

namespace {

/// What `src` links: a loader's mesh, a MechanicalObject's points, or a topology built before (SOFA's `src` link copies
/// the container's same-named Data: its points and its element lists, derived ones included).
io::MeshData linked_source(SceneBuilder& b, const Attributes& a) {
    const io::LinkTarget t = a.link("src");
    if (const ComponentSpec* spec = t.component != nullptr ? find_component(t.component->type) : nullptr;
        spec != nullptr && spec->family == ComponentFamily::state) {
        // a MechanicalObject's `position` (SOFA's src copies it; the state is initialised before
        // the topology reads it): its points only
        io::MeshData m;
        m.positions = state_initial_points(b, *t.component, b.node_build(*t.component->node));
        return m;
    }
    if (t.component != nullptr && component_category(t.component->type) != ComponentCategory::loader) {
        const SceneBuilder::BuiltTopology* built = b.built_topology(*t.component);
        if (built == nullptr || built->topology == nullptr)
            a.fail("src", "must link to a mesh loader or a topology built before this one");
        io::MeshData m;
        m.positions = built->positions;
        // a grid's Data as SOFA's GridTopology::GridUpdate computes them when read: its triangles
        // (two per quad) and the edges derived from them
        const MeshTopology grid_mesh = built->grid ? built->grid->mesh(true) : MeshTopology();
        const MeshTopology& topology = built->grid ? grid_mesh : *built->topology;
        m.edges = topology.edges();
        m.triangles = topology.triangles();
        m.quads = topology.quads();
        m.tetrahedra = topology.tetrahedra();
        m.hexahedra = topology.hexahedra();
        return m;
    }
    return b.linked_mesh(a, "src");
}

}  // namespace

void build_element_topology(SceneBuilder& b, const SceneComponent& c, NodeBuild& info, const ElementLists& lists) {
    const Attributes a(c);
    info.topology_component = &c;
    b.guarded(c, [&] {
        auto t = std::make_unique<MeshTopology>();
        io::MeshData mesh;
        // BaseMeshTopology::init loads `filename` after the Data links were read, and its load
        // clears them: the file's lists win over src's (their missing lists are then derived)
        if (a.has("filename")) mesh = b.mesh_of(c);
        else if (a.has("src")) mesh = linked_source(b, a);
        // SOFA's `src` links only the Data the class declares.
        if (!lists.edges) mesh.edges.clear();
        if (!lists.triangles) mesh.triangles.clear();
        if (!lists.quads) mesh.quads.clear();
        if (!lists.tetrahedra) mesh.tetrahedra.clear();
        if (!lists.hexahedra) mesh.hexahedra.clear();
        for (const char* name : {"position", "points"}) {
            if (!lists.nb_points && std::string_view(name) == "points") continue;
            if (a.has(name)) mesh.positions = b.point_data(a, name);
        }
        if (lists.edges) read_element_list(b, a, "edges", mesh.edges, &io::MeshData::edges, &MeshTopology::edges);
        if (lists.triangles)
            read_element_list(b, a, "triangles", mesh.triangles, &io::MeshData::triangles, &MeshTopology::triangles);
        if (lists.quads) read_element_list(b, a, "quads", mesh.quads, &io::MeshData::quads, &MeshTopology::quads);
        if (lists.tetrahedra)
            for (const char* name : {"tetrahedra", "tetras"})
                read_element_list(b, a, name, mesh.tetrahedra, &io::MeshData::tetrahedra, &MeshTopology::tetrahedra);
        if (lists.hexahedra)
            for (const char* name : {"hexahedra", "hexas"})
                read_element_list(b, a, name, mesh.hexahedra, &io::MeshData::hexahedra, &MeshTopology::hexahedra);
        if (!mesh.positions.empty()) {
            t->set_num_points(mesh.positions.size());
        } else if (lists.nb_points && a.has("nbPoints")) {
            // PointSetTopologyContainer::init: nbPoints, raised to cover every element's indices.
            const std::int64_t n = a.integer("nbPoints");
            if (n < 0 || std::uint64_t(n) > b.options().max_dofs)
                a.fail("nbPoints", "must be between 0 and " + std::to_string(b.options().max_dofs));
            MeshTopology counted_topology;
            counted_topology.set_edges(mesh.edges);
            counted_topology.set_triangles(mesh.triangles);
            counted_topology.set_quads(mesh.quads);
            counted_topology.set_tetrahedra(mesh.tetrahedra);
            counted_topology.set_hexahedra(mesh.hexahedra);
            t->set_num_points(std::max(std::size_t(n), counted_topology.num_points()));
        }
        t->set_edges(mesh.edges);
        t->set_triangles(mesh.triangles);
        t->set_quads(mesh.quads);
        t->set_tetrahedra(mesh.tetrahedra);
        t->set_hexahedra(mesh.hexahedra);
        (void)t->edges();  // checks indices against the point count now
        info.topology_positions = mesh.positions;
        info.topology = b.add_topology(std::move(t));
    });
    // By reference: a topological mapping may refill this topology later (NodeBuild addresses
    // are stable while the builder runs, and roles are described before it ends).
    b.role(c, [&info] { return element_counts(info.topology->num_points(), *info.topology); });
    b.note_unread_attributes(c);
}

}  // namespace penalty::scene::builder
