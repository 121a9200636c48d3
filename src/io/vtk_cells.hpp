#pragma once
// What the two VTK readers share (legacy: mesh.cpp; XML: mesh_vtu.cpp): a cell of a VTK type
// added to the mesh as SOFA's MeshVTKLoader::doLoad adds it.
#include "penalty/io/mesh.hpp"

#include <cstdint>
#include <filesystem>
#include <vector>

namespace penalty::io {

/// Adds the cell of VTK type `type` with points `p`: 1 vertex (nothing), 3 line, 4 polyline
/// (consecutive edges), 5 triangle, 7 polygon (a fan), 8 pixel (quad p0 p1 p3 p2), 9 quad,
/// 10 tetrahedron, 11 voxel (hexahedron p0 p1 p3 p2 p4 p5 p7 p6), 12 hexahedron. A wrong point
/// count is an error at `cell_line`, another type at `type_line`.
void add_vtk_cell(MeshData& mesh, std::int64_t type, const std::vector<PointId>& p, const std::filesystem::path& path,
                  int cell_line, int type_line);

}  // namespace penalty::io
