// Sparse grids: SparseGridTopology (the voxelisation of a closed surface mesh file).
#include "penalty/io/data_path.hpp"
#include "penalty/io/mesh.hpp"
#include "penalty/mechanics/fem.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

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

/// SparseGridRamificationTopology's own Data (nbVirtualFinerLevels is SparseGridTopology's).
constexpr AttributeSpec kSparseGridRamification[] = {
    {"finestConnectivity", K::boolean, "1", "", ValueCheck::none,
     "two BOUNDARY cells are connected only when a surface edge crosses their common face "
     "(SparseGridRamificationTopology::sharingTriangle); 0: all face neighbours are"},
};

/// SparseGridMultipleTopology's own Data, with SparseGridRamificationTopology's.
constexpr AttributeSpec kSparseGridMultiple[] = {
    {"fileTopologies", K::text, "", "", ValueCheck::none,
     "the closed surfaces (.obj), blank-separated, most specific last"},
    {"stiffnessCoefs", K::numbers, "", "", ValueCheck::none, "a stiffness coefficient per surface (missing ones: 1)"},
    {"massCoefs", K::numbers, "", "", ValueCheck::none, "a mass coefficient per surface (missing ones: 1)"},
    {"computeRamifications", K::boolean, "1", "", ValueCheck::none, "build the grid as SparseGridRamificationTopology"},
    {"erasePreviousCoef", K::boolean, "0", "", ValueCheck::none,
     "a BOUNDARY cell takes the last surface's coefficients (0: the mean of the previous ones and its)"},
    {"finestConnectivity", K::boolean, "1", "", ValueCheck::none, "as SparseGridRamificationTopology's"},
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
        surface.positions = b.point_data(a, "position");
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

/// The grid's point counts `n` (each between 1 and 100000, raised to 2 as SparseGridTopology::init),
/// within the builder's point budget.
std::array<int, 3> grid_counts(SceneBuilder& b, const Attributes& a) {
    std::array<int, 3> n{2, 2, 2};
    if (a.has("n")) {
        const std::vector<double> v = a.numbers("n");
        if (v.size() != 3) a.fail("n", "expected 3 integers");
        for (const double x : v)
            if (!(x >= 1 && x <= 100000)) a.fail("n", "each count must be between 1 and 100000");
        n = {std::max(int(v[0]), 2), std::max(int(v[1]), 2), std::max(int(v[2]), 2)};
    }
    const auto points = std::uint64_t(n[0]) * std::uint64_t(n[1]) * std::uint64_t(n[2]);
    if (points > b.options().max_dofs)
        io::throw_element_error(a.component(), std::to_string(points) + " grid points (more than " +
                                                   std::to_string(b.options().max_dofs) + ")");
    return n;
}

/// SparseGridTopology::buildVirtualFinerLevels: the finest level has (n − 1)·2^levels + 1 points
/// per axis.
std::array<int, 3> finest_counts(SceneBuilder& b, const Attributes& a, std::array<int, 3> n, std::int64_t levels) {
    if (levels > 6) a.fail("nbVirtualFinerLevels", "at most 6 levels (each multiplies the cells by 8)");
    std::uint64_t fine_points = 1;
    for (int& v : n) {
        v = (v - 1) * (1 << levels) + 1;
        fine_points *= std::uint64_t(v);
    }
    if (fine_points > b.options().max_dofs)
        a.fail("nbVirtualFinerLevels", "the finest level has " + std::to_string(fine_points) +
                                           " grid points (more than " + std::to_string(b.options().max_dofs) + ")");
    return n;
}

/// The surface as polygons for SparseGridRamificationTopology::sharingTriangle.
SparseGridFacets facets_of(const io::MeshData& surface) {
    SparseGridFacets f;
    f.positions = surface.positions;
    for (const Triangle& t : surface.triangles) f.facets.push_back({t[0], t[1], t[2]});
    return f;
}

/// The coarser levels over `finest` (levels − 1 virtual ones, then this grid): ramified
/// (SparseGridRamificationTopology::buildFromFiner) or not (SparseGridTopology::buildFromFiner).
SparseGridTopology coarser_levels(SparseGridTopology finest, std::int64_t levels, bool ramified, bool top_ramified,
                                  bool fill) {
    auto level = std::make_shared<const SparseGridTopology>(std::move(finest));
    for (std::int64_t l = 1; l < levels; ++l)
        level =
            std::make_shared<const SparseGridTopology>(ramified ? SparseGridTopology::from_finer_ramified(level, fill)
                                                                : SparseGridTopology::from_finer(level, fill));
    return top_ramified ? SparseGridTopology::from_finer_ramified(level, fill)
                        : SparseGridTopology::from_finer(level, fill);
}

/// SparseGridTopology and SparseGridRamificationTopology.
SparseGridTopology single_surface_grid(SceneBuilder& b, const Attributes& a) {
    const bool ramification = a.component().type == "SparseGridRamificationTopology";
    const bool finest_connectivity = ramification && a.boolean("finestConnectivity");
    const io::MeshData surface = sparse_grid_surface(b, a);
    const std::array<int, 3> n = grid_counts(b, a);
    Vec3 lo = a.vector3("min"), hi = a.vector3("max");
    if (lo.isZero(0) && hi.isZero(0)) std::tie(lo, hi) = SparseGridTopology::default_box(surface.positions);
    const std::int64_t levels = a.integer("nbVirtualFinerLevels");
    const bool fill = a.boolean("fillWeighted");
    const SparseGridFacets facets = finest_connectivity ? facets_of(surface) : SparseGridFacets{};
    const SparseGridFacets* crossing = finest_connectivity ? &facets : nullptr;
    if (levels == 0) {
        SparseGridTopology grid = SparseGridTopology::from_surface(n, lo, hi, surface.positions, surface.triangles,
                                                                   a.boolean("onlyInsideCells"));
        // SparseGridRamificationTopology::buildAsFinest: without virtual levels the connexions
        // only matter to finestConnectivity's point numbering
        return finest_connectivity ? SparseGridTopology::ramified_finest(std::move(grid), crossing, true) : grid;
    }
    // the virtual finest level never reads onlyInsideCells (SOFA does not pass it on)
    SparseGridTopology finest = SparseGridTopology::from_surface(finest_counts(b, a, n, levels), lo, hi,
                                                                 surface.positions, surface.triangles, false);
    if (ramification) finest = SparseGridTopology::ramified_finest(std::move(finest), crossing, finest_connectivity);
    return coarser_levels(std::move(finest), levels, ramification, ramification, fill);
}

/// SparseGridMultipleTopology: SparseGridMultipleTopology::buildAsFinest on the finest level, as
/// a SparseGridRamificationTopology unless computeRamifications is 0 (the virtual levels always
/// are: SOFA does not pass computeRamifications on).
SparseGridTopology multiple_surface_grid(SceneBuilder& b, const Attributes& a) {
    std::vector<std::string> files;
    {
        std::istringstream words(a.text("fileTopologies"));
        for (std::string w; words >> w;) files.push_back(w);
    }
    if (files.empty()) a.fail("fileTopologies", "no surface file given (SOFA: 'No file topology provided')");
    std::vector<io::MeshData> surfaces;
    for (const std::string& file : files) {
        try {
            const std::filesystem::path path = io::resolve_data_file(file, b.scene_dir(), b.options().data_dirs);
            if (path.extension() != ".obj")
                a.fail("fileTopologies", "only .obj surfaces are supported, got '" + file + "'");
            surfaces.push_back(io::load_obj(path, /*triangulate=*/true));
        } catch (const io::SceneError&) {
            throw;
        } catch (const io::LoadError& e) {
            io::throw_attribute_error(a.component(), "fileTopologies", e.what());
        }
    }
    // missing coefficients are 1 (SOFA warns "not enough stiffnessCoefs"); single precision
    const auto coefficients = [&](std::string_view name) {
        std::vector<float> v;
        if (a.has(name))
            for (const double x : a.numbers(name)) {
                if (!std::isfinite(x) || x < 0)
                    a.fail(name, "each coefficient must be finite and >= 0, found " + num(x));
                v.push_back(float(x));
            }
        v.resize(std::max(v.size(), files.size()), 1.0f);
        return v;
    };
    const std::vector<float> stiffness = coefficients("stiffnessCoefs"), mass = coefficients("massCoefs");
    Vec3 lo = a.vector3("min"), hi = a.vector3("max");
    if (lo.isZero(0) && hi.isZero(0)) {
        std::vector<Vec3> all;  // the box of every surface, grown by 1/100 of its size each side
        for (const io::MeshData& m : surfaces) all.insert(all.end(), m.positions.begin(), m.positions.end());
        std::tie(lo, hi) = SparseGridTopology::default_box(all);
    }
    std::vector<SparseGridTopology::WeightedSurface> weighted;
    for (std::size_t i = 0; i < surfaces.size(); ++i)
        weighted.push_back({surfaces[i].positions, surfaces[i].triangles, stiffness[i], mass[i]});
    const std::array<int, 3> n = grid_counts(b, a);
    const std::int64_t levels = a.integer("nbVirtualFinerLevels");
    const bool fill = a.boolean("fillWeighted"), erase = a.boolean("erasePreviousCoef");
    const bool ramify = a.boolean("computeRamifications"), finest_connectivity = a.boolean("finestConnectivity");
    // findConnexionsAtFinestLevel tests the faces against fileTopology's surface
    std::optional<SparseGridFacets> facets;
    if (finest_connectivity && (ramify || levels > 0)) {
        if (!a.has("fileTopology") && !a.has("filename"))
            a.fail("finestConnectivity",
                   "1 tests the cells' faces against fileTopology's surface: give fileTopology, or 0");
        facets = facets_of(sparse_grid_surface(b, a));
    }
    const SparseGridFacets* crossing = facets ? &*facets : nullptr;
    if (levels == 0) {
        SparseGridTopology grid =
            SparseGridTopology::from_surfaces(n, lo, hi, weighted, fill, erase, a.boolean("onlyInsideCells"));
        return ramify && finest_connectivity ? SparseGridTopology::ramified_finest(std::move(grid), crossing, true)
                                             : grid;
    }
    SparseGridTopology finest =
        SparseGridTopology::from_surfaces(finest_counts(b, a, n, levels), lo, hi, weighted, fill, erase);
    finest = SparseGridTopology::ramified_finest(std::move(finest), crossing, finest_connectivity);
    return coarser_levels(std::move(finest), levels, true, ramify, fill);
}

void build_sparse_grid(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    info.topology_component = &c;
    b.guarded(c, [&] {
        info.sparse_grid.emplace(c.type == "SparseGridMultipleTopology" ? multiple_surface_grid(b, a)
                                                                        : single_surface_grid(b, a));
        info.topology_positions = info.sparse_grid->points();
        info.topology = b.add_topology(std::make_unique<MeshTopology>(info.sparse_grid->mesh()));
    });
    b.role(c, [g = &*info.sparse_grid, t = info.topology] {
        const auto& n = g->grid().n();
        std::size_t boundary = 0;
        for (const SparseCellType type : g->cell_types()) boundary += type == SparseCellType::boundary ? 1 : 0;
        return "sparse grid " + std::to_string(n[0]) + " x " + std::to_string(n[1]) + " x " + std::to_string(n[2]) +
               (g->finer_levels() > 0 ? " (from " + std::to_string(g->finer_levels()) + " virtual finer levels)"
                                      : std::string()) +
               " from " + vec(g->grid().min()) + " to " + vec(g->grid().max()) + ", " + std::to_string(boundary) +
               " boundary cells: " + element_counts(g->points().size(), *t);
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kSparseGridComponents[] = {
    {.type = "SparseGridTopology",
     .family = F::topology,
     .summary = "sparse grid: the cells of a regular grid that meet or lie inside a closed surface",
     .attributes = kSparseGrid,
     .build = build_sparse_grid},
    {.type = "SparseGridRamificationTopology",
     .family = F::topology,
     .summary = "SparseGridTopology whose cells split by the connected parts of the material inside them",
     .attributes = kSparseGridRamification,
     .shared_attributes = kSparseGrid,
     .build = build_sparse_grid},
    {.type = "SparseGridMultipleTopology",
     .family = F::topology,
     .summary = "sparse grid of several closed surfaces, each with its stiffness and mass coefficients",
     .attributes = kSparseGridMultiple,
     .shared_attributes = kSparseGrid,
     .build = build_sparse_grid},
};

}  // namespace

void sparse_grid_stiffness_factors(HexahedronFEMForceField& ff, const NodeBuild& info) {
    // SparseGridTopology::getStiffnessCoef: 0.5 on boundary cells when fillWeighted
    // (buildAsFinest), averaged from the finer cells on a grid with virtual finer levels
    const bool fill = Attributes(*info.topology_component).boolean("fillWeighted");
    const bool own_coefficients = info.topology_component->type == "SparseGridMultipleTopology";
    if (!fill && info.sparse_grid->finer() == nullptr && !own_coefficients) return;
    ff.set_stiffness_factors(info.sparse_grid->stiffness_coefficients(fill));
}

std::vector<double> sparse_grid_mass_factors(const NodeBuild& info) {
    // SparseGridTopology::getMassCoef: as the stiffness's, but SparseGridMultipleTopology's massCoefs
    return info.sparse_grid->mass_coefficients(Attributes(*info.topology_component).boolean("fillWeighted"));
}

std::span<const ComponentSpec> sparse_grid_components() { return kSparseGridComponents; }

}  // namespace penalty::scene::builder
