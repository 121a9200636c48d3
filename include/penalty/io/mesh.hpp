#pragma once
/// @file
/// Mesh files as SOFA's mesh loaders read them: Wavefront OBJ (MeshOBJLoader), Gmsh v1/v2 ASCII
/// (MeshGmshLoader), sphere lists `.sph` (SphereLoader) and legacy ASCII VTK (MeshVTKLoader),
/// plus the loaders' common post-processing (transform, sub-elements, triangulation).
///
/// Element indices are 0-based point indices into `positions`. Every index is checked against
/// the number of points; a bad file raises penalty::io::LoadError naming the file and the line.
/// Nothing is reserved from a count read in a file before it has been checked against what is
/// left of the file, so a corrupt count cannot exhaust memory.

#include "penalty/core/types.hpp"
#include "penalty/io/error.hpp"
#include "penalty/mechanics/loader_placement.hpp"
#include "penalty/mechanics/topology.hpp"

#include <filesystem>
#include <string_view>
#include <vector>

namespace penalty::io {

/// A loaded mesh: positions and element lists, in file order.
struct MeshData {
    std::vector<Vec3> positions;          ///< point coordinates
    std::vector<Edge> edges;              ///< 2 point indices each
    std::vector<Triangle> triangles;      ///< 3 point indices each (file orientation)
    std::vector<Quad> quads;              ///< 4 point indices each
    std::vector<Tetrahedron> tetrahedra;  ///< 4 point indices each
    std::vector<Hexahedron> hexahedra;    ///< 8 point indices each (SOFA/VTK order)
    std::vector<double> radii;            ///< one radius per point (`.sph` files only; else empty)
};

/// Reads a Wavefront OBJ file as SOFA's MeshOBJLoader does:
///  - `v x y z` adds a point (extra coordinates are ignored); `vn`, `vt`, `g`, `o`, `s`,
///    `usemtl`, `mtllib` and unknown keywords are ignored;
///  - `f` and `l` records take the first number of each `v/vt/vn` token; negative indices
///    count back from the points defined so far; 2 vertices give an edge (stored sorted),
///    4 vertices a quad (or two fan triangles when `triangulate`), 3 or more than 4 vertices
///    the fan triangles (v0, v[j-1], v[j]);
///  - index 0, a record with fewer than 2 vertices, or an index outside [0, number of points)
///    is an error.
/// @throws LoadError `path:line: what`
///  - `handle_seams` (MeshOBJLoader's handleSeams): each point becomes one point per distinct
///    (texture coordinate, normal) index pair its face corners use (pairs in increasing order,
///    absent indices −1), and points no `f`/`l` record uses are dropped; without `vt`/`vn`
///    indices this only drops the unused points.
[[nodiscard]] MeshData load_obj(const std::filesystem::path& path, bool triangulate = false, bool handle_seams = false);

/// Reads a Gmsh mesh in the legacy v1 (`$NOD`/`$ELM`) or v2 ASCII (`$MeshFormat 2.x`) format,
/// as SOFA's MeshGmshLoader does: node numbers are mapped to their position in the node list;
/// element types 1 (edge), 2 (triangle), 3 (quad), 4 (tetrahedron), 5 (hexahedron),
/// 8/9/11 (second-order edge/triangle/tetrahedron: only the corner nodes are kept) are stored,
/// type 15 (point) and other types are skipped. Sub-elements are NOT created here: SOFA's
/// MeshGmshLoader does it by default, call create_subelements() (load_scene_mesh() does).
/// Format 4 ASCII files are read as SOFA's MeshGmsh::readGmsh reads them (nodes in block
/// order, element node n = n-th node read). Binary files and format 3 are rejected.
/// @throws LoadError `path:line: what`
[[nodiscard]] MeshData load_gmsh(const std::filesystem::path& path);

/// Reads an OFF file as SOFA's MeshOffLoader: the `OFF` keyword, then (blank and `#` lines
/// skipped) a line `vertices faces edges`, one vertex per line, one face per line `n i j k [l]`:
/// n = 3 gives a triangle, n = 4 a quad, other n skip the line (not counted as a face).
/// @throws LoadError `path:line: what`
[[nodiscard]] MeshData load_off(const std::filesystem::path& path);

/// Reads a `.trian` file as SOFA's MeshTrianLoader (trian2 = false): the vertex count, the
/// vertices (x y z), the triangle count, then per triangle its 3 points and its 3 neighbours
/// (the neighbours are read and not used).
/// @throws LoadError `path:line: what`
[[nodiscard]] MeshData load_trian(const std::filesystem::path& path);

/// Reads a SOFA sphere file (`.sph`): first line `sph 1.0`, then `nums N`,
/// `sphe index x y z radius` records and `#` comments; unknown keywords skip their line.
/// Fills `positions` and `radii`. A negative radius is an error.
/// @throws LoadError `path:line: what`
[[nodiscard]] MeshData load_sph(const std::filesystem::path& path);

/// Reads a legacy ASCII VTK file (`# vtk DataFile Version 2.x/3.x/4.x`, `ASCII`) with a
/// `DATASET POLYDATA` (POINTS, LINES -> consecutive edges, POLYGONS -> triangle/quad/fan,
/// VERTICES ignored) or `DATASET UNSTRUCTURED_GRID` (POINTS, CELLS, CELL_TYPES with types
/// 1 vertex (ignored), 3 line, 4 polyline, 5 triangle, 7 polygon (fan), 8 pixel, 9 quad,
/// 10 tetrahedron, 11 voxel, 12 hexahedron). POINT_DATA / CELL_DATA end the geometry.
/// BINARY files, other datasets and other cell types are errors.
/// @throws LoadError `path:line: what`
[[nodiscard]] MeshData load_vtk_legacy(const std::filesystem::path& path);

/// Reads an XML VTK file (`<VTKFile type="UnstructuredGrid">`, .vtu) as SOFA's MeshVTKLoader
/// (XMLVTKReader): one Piece, its Points (read as doubles whatever their DataArray type), its
/// Cells (connectivity, offsets, types; the cell types of load_vtk_legacy). ASCII DataArrays only.
/// @throws LoadError `path:line: what`
[[nodiscard]] MeshData load_vtk_xml(const std::filesystem::path& path);

/// load_vtk_xml or load_vtk_legacy by the file's first line, as MeshVTKLoader::detectFileType:
/// `<?xml` or `<VTKFile` → XML, `# vtk` → legacy.
[[nodiscard]] MeshData load_vtk(const std::filesystem::path& path);

/// Dispatches on the extension (case-insensitive): .obj, .msh, .sph, .vtk, .vtu, .off, .trian.
/// @throws LoadError for another extension or a bad file
[[nodiscard]] MeshData load_mesh_file(const std::filesystem::path& path);

/// The parsers behind the loaders, on a file's text already in memory; `path` only names the
/// file in errors. Same results and errors as load_obj, load_gmsh, load_sph, load_vtk_legacy
/// (which read the file, refusing what is not a regular file, then call these).
[[nodiscard]] MeshData parse_obj(std::string_view text, const std::filesystem::path& path, bool triangulate = false,
                                 bool handle_seams = false);
[[nodiscard]] MeshData parse_gmsh(std::string_view text, const std::filesystem::path& path);
[[nodiscard]] MeshData parse_sph(std::string_view text, const std::filesystem::path& path);
[[nodiscard]] MeshData parse_vtk_legacy(std::string_view text, const std::filesystem::path& path);
[[nodiscard]] MeshData parse_vtk_xml(std::string_view text, const std::filesystem::path& path);
[[nodiscard]] MeshData parse_off(std::string_view text, const std::filesystem::path& path);
[[nodiscard]] MeshData parse_trian(std::string_view text, const std::filesystem::path& path);

/// SOFA's placement of a loader's points (place_loaded_points, loader_placement.hpp): scale
/// first, then the rotation (Euler degrees, R = Rz·Ry·Rx), then the translation, in SOFA's
/// operations (a MeshLoader's reinit run twice). Sphere radii are not changed (SOFA's
/// SphereLoader does not scale them either).
void apply_transform(MeshData& mesh, const Vec3& translation, const Vec3& rotation_degrees, const Vec3& scale3d,
                     LoaderKind kind = LoaderKind::mesh_loader);

/// Same transform on a plain list of points.
void apply_transform(std::vector<Vec3>& points, const Vec3& translation, const Vec3& rotation_degrees,
                     const Vec3& scale3d, LoaderKind kind = LoaderKind::mesh_loader);

/// SOFA MeshLoader `createSubelements`: in this order, appends the missing boundary quads of
/// the hexahedra (faces (0,3,2,1), (4,5,6,7), (0,1,5,4), (1,2,6,5), (2,3,7,6), (3,0,4,7)), the
/// missing triangles of the tetrahedra ((0,2,1), (0,1,3), (0,3,2), (1,2,3)), the missing edges
/// of the quads, then of the triangles (edge j = (e[j+1], e[j+2]) in element order). An
/// element is missing when no element with the same vertex set exists yet.
void create_subelements(MeshData& mesh);

/// SOFA MeshLoader `triangulate` post-pass: every quad (q0,q1,q2,q3) becomes (q0,q1,q2) and
/// (q0,q2,q3), appended after the existing triangles; the quad list is emptied.
void triangulate_quads(MeshData& mesh);

/// SOFA MeshLoader `flipNormals`: reverses the vertex order of every triangle and quad.
void flip_normals(MeshData& mesh);

}  // namespace penalty::io
