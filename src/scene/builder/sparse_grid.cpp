// Sparse grids: SparseGridTopology (the voxelisation of a closed surface mesh file).
#include "penalty/io/data_path.hpp"
#include "penalty/io/mesh.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"
#include "penalty/mechanics/fem.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

constexpr AttributeSpec kSparseGrid[] = {
    {"n", K::indices, "2 2 2", "", ValueCheck::none, "grid points along x, y, z (raised to 2)"},
    {"min", K::vector3, "0 0 0", "m", ValueCheck::none, "lower corner (min = max = 0: the surface's box grown by 1%)"},
    {"max", K::vector3, "0 0 0", "m", ValueCheck::none, "upper corner"},
    {"fileTopology", K::text, "", "", ValueCheck::none, "closed surface mesh (.obj) to voxelise"},
    {"filename", K::text, "", "", ValueCheck::none, "alias of fileTopology"},
    {"position", K::points, "", "m", ValueCheck::none,
     "without a file: the surface's points (inline or a link), with `triangles` and `quads` as its facets"},
    {"triangles", K::elements, "", "", ValueCheck::none, "facets of the surface given by `position`"},
    {"quads", K::elements, "", "", ValueCheck::none, "facets of the surface given by `position` (fans)"},
    {"onlyInsideCells", K::boolean, "0", "", ValueCheck::none, "keep only the cells inside the surface"},
    {"fillWeighted", K::boolean, "1", "", ValueCheck::none,
     "boundary cells have half the stiffness in a HexahedronFEMForceField"},
    {"nbVirtualFinerLevels", K::integer, "0", "", ValueCheck::nonnegative,
     "build the grid from a voxelisation 2^levels times finer (SparseGridTopology::buildVirtualFinerLevels)"},
};

/// SparseGridRamificationTopology's own Data (nbVirtualFinerLevels is SparseGridTopology's): with
/// finestConnectivity 0 and no virtual finer level it builds exactly SparseGridTopology's grid (SparseGridRamificationTopology::buildAsFinest adds
/// nothing then); the ramified grids are refused.
constexpr AttributeSpec kSparseGridRamification[] = {
    {"finestConnectivity", K::boolean, "1", "", ValueCheck::none,
     "split cells by the surface's connected parts (only 0: ramified grids are not supported)"},
};

/// The surface to voxelise: `fileTopology` (an .obj), else `position` with `triangles` and `quads`
/// (SparseGridTopology::buildAsFinest: the given points and facets, quads as fans).
io::MeshData sparse_grid_surface(SceneBuilder& b, const Attributes& a) {
    const SceneComponent& c = a.component();
    std::optional<std::string> file = a.optional_text("fileTopology");
    if (!file) file = a.optional_text("filename");
    if (!file) {
        if (!a.has("position"))
            io::throw_element_error(c, "needs fileTopology (a closed surface mesh) or position (the surface's points)");
        io::MeshData surface;
        surface.positions = a.is_link("position") ? b.linked_positions(a, "position") : a.points("position");
        if (a.has("triangles")) surface.triangles = a.elements<3>("triangles");
        if (a.has("quads"))
            for (const auto& q : a.elements<4>("quads")) {
                surface.triangles.push_back({q[0], q[1], q[2]});
                surface.triangles.push_back({q[0], q[2], q[3]});
            }
        for (const Triangle& t : surface.triangles)
            for (const PointId i : t)
                if (i < 0 || std::size_t(i) >= surface.positions.size())
                    a.fail(a.has("quads") ? "quads" : "triangles",
                           "uses point " + std::to_string(i) + " of " + std::to_string(surface.positions.size()));
        return surface;
    }
    const char* attr = a.has("fileTopology") ? "fileTopology" : "filename";
    try {
        const std::filesystem::path path = io::resolve_data_file(*file, b.scene_dir(), b.options().data_dirs);
        if (path.extension() != ".obj") a.fail(attr, "only .obj surfaces are supported, got '" + *file + "'");
        return io::load_obj(path, /*triangulate=*/true);  // polygons as fans (v0, v[j-1], v[j]), as SOFA
    } catch (const io::SceneError&) {
        throw;
    } catch (const io::LoadError& e) {
        io::throw_attribute_error(c, attr, e.what());
    }
}

void build_sparse_grid(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    info.topology_component = &c;
    b.guarded(c, [&] {
        if (c.type == "SparseGridRamificationTopology") {
            if (a.boolean("finestConnectivity"))
                a.fail("finestConnectivity", "1 (SOFA's default) ramifies the grid, which penalty does not support: give 0");
            if (a.integer("nbVirtualFinerLevels") != 0)
                a.fail("nbVirtualFinerLevels", "virtual finer levels are not supported (only 0)");
        }
        const io::MeshData surface = sparse_grid_surface(b, a);
        std::array<int, 3> n{2, 2, 2};
        if (a.has("n")) {
            const std::vector<double> v = a.numbers("n");
            if (v.size() != 3) a.fail("n", "expected 3 integers");
            for (const double x : v)
                if (!(x >= 1 && x <= 100000)) a.fail("n", "each count must be between 1 and 100000");
            n = {int(v[0]), int(v[1]), int(v[2])};
        }
        const auto points = std::uint64_t(std::max(n[0], 2)) * std::uint64_t(std::max(n[1], 2)) * std::uint64_t(std::max(n[2], 2));
        if (points > b.options().max_dofs)
            io::throw_element_error(c, std::to_string(points) + " grid points (more than " +
                                           std::to_string(b.options().max_dofs) + ")");
        Vec3 lo = a.vector3("min"), hi = a.vector3("max");
        if (lo.isZero(0) && hi.isZero(0)) std::tie(lo, hi) = SparseGridTopology::default_box(surface.positions);
        const std::int64_t levels = a.integer("nbVirtualFinerLevels");
        if (levels == 0) {
            info.sparse_grid.emplace(
                SparseGridTopology::from_surface(n, lo, hi, surface.positions, surface.triangles, a.boolean("onlyInsideCells")));
        } else {
            // SparseGridTopology::buildVirtualFinerLevels: the finest level voxelises the surface with
            // (n − 1)·2^levels + 1 points per axis (n raised to 2 first), each coarser one is built
            // from the finer one (buildFromFiner), this grid last
            if (levels > 6) a.fail("nbVirtualFinerLevels", "at most 6 levels (each multiplies the cells by 8)");
            std::array<int, 3> fine = n;
            std::uint64_t fine_points = 1;
            for (int& v : fine) {
                v = (std::max(v, 2) - 1) * (1 << levels) + 1;
                fine_points *= std::uint64_t(v);
            }
            if (fine_points > b.options().max_dofs)
                a.fail("nbVirtualFinerLevels", "the finest level has " + std::to_string(fine_points) + " grid points (more than " +
                                                   std::to_string(b.options().max_dofs) + ")");
            auto level = std::make_shared<const SparseGridTopology>(
                SparseGridTopology::from_surface(fine, lo, hi, surface.positions, surface.triangles, false));
            const bool fill = a.boolean("fillWeighted");
            for (std::int64_t l = 1; l < levels; ++l)
                level = std::make_shared<const SparseGridTopology>(SparseGridTopology::from_finer(level, fill));
            info.sparse_grid.emplace(SparseGridTopology::from_finer(level, fill));
        }
        info.topology_positions = info.sparse_grid->points();
        info.topology = b.add_topology(std::make_unique<MeshTopology>(info.sparse_grid->mesh()));
    });
    b.role(c, [g = &*info.sparse_grid, t = info.topology] {
        const auto& n = g->grid().n();
        std::size_t boundary = 0;
        for (const SparseCellType type : g->cell_types()) boundary += type == SparseCellType::boundary ? 1 : 0;
        return "sparse grid " + std::to_string(n[0]) + " x " + std::to_string(n[1]) + " x " + std::to_string(n[2]) +
               (g->finer_levels() > 0 ? " (from " + std::to_string(g->finer_levels()) + " virtual finer levels)" : std::string()) +
               " from " +
               vec(g->grid().min()) + " to " + vec(g->grid().max()) + ", " + std::to_string(boundary) + " boundary cells: " +
               element_counts(g->points().size(), *t);
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kComponents[] = {
    {.type = "SparseGridTopology",
     .family = F::topology,
     .summary = "sparse grid: the cells of a regular grid that meet or lie inside a closed surface",
     .attributes = kSparseGrid,
     .build = build_sparse_grid},
    {.type = "SparseGridRamificationTopology",
     .family = F::topology,
     .summary = "SparseGridTopology with cells split by the surface's connected parts (unsplit grids only)",
     .attributes = kSparseGridRamification,
     .shared_attributes = kSparseGrid,
     .build = build_sparse_grid},
};

}  // namespace

void sparse_grid_stiffness_factors(HexahedronFEMForceField& ff, const NodeBuild& info) {
    // SparseGridTopology::getStiffnessCoef: 0.5 on boundary cells when fillWeighted
    // (buildAsFinest), averaged from the finer cells on a grid with virtual finer levels
    const bool fill = Attributes(*info.topology_component).boolean("fillWeighted");
    if (!fill && info.sparse_grid->finer() == nullptr) return;
    ff.set_stiffness_factors(info.sparse_grid->coefficients(fill));
}

std::span<const ComponentSpec> sparse_grid_components() { return kComponents; }

}  // namespace penalty::scene::builder
