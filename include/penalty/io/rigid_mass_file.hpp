#pragma once
/// @file
/// SOFA's `.rigid` mass files (UniformMass `filename`, read by UniformMass<Rigid3>::loadRigidMass):
/// the first line is skipped; then keywords, each followed by its numbers: `vertexMass m`,
/// `inrt` (9 numbers, row by row: the inertia per unit mass, m²), `volm v`, `center`/`cntr`
/// (3), `frme` (4), `grav` (3), `visc`, `stck`, `step`, `prec` (1 each); `#` starts a comment
/// to the end of the line; an unknown keyword skips its line (SOFA reports it and goes on).
/// Only vertexMass and inrt change the mass SOFA builds; the others are read and ignored.
#include "penalty/core/types.hpp"
#include "penalty/io/error.hpp"

#include <filesystem>
#include <optional>
#include <string_view>

namespace penalty::io {

struct RigidMassFile {
    std::optional<double> vertex_mass;  ///< kg
    std::optional<Mat3> inertia;        ///< per unit mass, m²
};

/// @throws LoadError `path:line: what` for a keyword whose numbers are missing or not numbers.
[[nodiscard]] RigidMassFile load_rigid_mass_file(const std::filesystem::path& path);
[[nodiscard]] RigidMassFile parse_rigid_mass_file(std::string_view text, const std::filesystem::path& path);

}  // namespace penalty::io
