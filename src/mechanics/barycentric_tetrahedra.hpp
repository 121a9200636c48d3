#pragma once
// What SOFA's two tetrahedron mappers share (BarycentricMapperMeshTopology::init and
// BarycentricMapperTopologyContainer::init for TetrahedronSetTopology), in SOFA's operations and
// order (private to the mechanics stage): each tetrahedron's inverse edge matrix and centre, a
// point's score against it, and its weights.
#include "penalty/core/error.hpp"
#include "penalty/mechanics/mapping.hpp"
#include "sofa_vector_ops.hpp"

#include <cmath>
#include <span>
#include <vector>

namespace penalty::detail {

/// B = (x1 − x0, x2 − x0, x3 − x0)⁻¹ (type::Mat::invert) and c = (x0 + x1 + x2 + x3)·¼ of each
/// tetrahedron; std::invalid_argument for a vertex out of range or a degenerate tetrahedron.
struct TetrahedronFrames {
    std::vector<Mat3> bases;
    std::vector<Vec3> centres;

    TetrahedronFrames(const std::vector<Tetrahedron>& tetras, std::span<const Vec3> x)
        : bases(tetras.size()), centres(tetras.size()) {
        for (std::size_t t = 0; t < tetras.size(); ++t) {
            for (const PointId p : tetras[t])
                if (std::size_t(p) >= x.size())
                    throw_invalid_argument("BarycentricMapping: tetrahedron ", t, " vertex out of range");
            const Vec3& x0 = x[std::size_t(tetras[t][0])];
            const Vec3& x1 = x[std::size_t(tetras[t][1])];
            const Vec3& x2 = x[std::size_t(tetras[t][2])];
            const Vec3& x3 = x[std::size_t(tetras[t][3])];
            Mat3 edges;  // columns x1 − x0, x2 − x0, x3 − x0 (SOFA: the transpose of the rows)
            edges.col(0) = x1 - x0;
            edges.col(1) = x2 - x0;
            edges.col(2) = x3 - x0;
            if (std::abs(sofa_vec::determinant(edges)) < 1e-300)
                throw_invalid_argument("BarycentricMapping: tetrahedron ", t, " is degenerate");
            bases[t] = sofa_vec::inverse(edges);
            centres[t] = sofa_vec::scaled(((x0 + x1) + x2) + x3, 0.25);
        }
    }

    /// The score of `p` against tetrahedron t whose vertex 0 is at `x0`: b = B·(p − x0) (into
    /// `coefs`); max(−b0, −b1, −b2, b0 + b1 + b2 − 1), replaced, when positive (outside), by |p − c|².
    [[nodiscard]] double score(std::size_t t, const Vec3& x0, const Vec3& p, Vec3& coefs) const {
        coefs = sofa_vec::times(bases[t], p - x0);
        const double d =
            std::max(std::max(-coefs[0], -coefs[1]), std::max(-coefs[2], coefs[0] + coefs[1] + coefs[2] - 1));
        if (d <= 0) return d;
        const Vec3 r = p - centres[t];
        return sofa_vec::dot3(r, r);
    }
};

/// The weights of a point with coordinates b in `tet`: ((1 − b0) − b1) − b2, b0, b1, b2, as SOFA.
inline void push_tetrahedron_weights(BarycentricRow& row, const Tetrahedron& tet, const Vec3& b) {
    row.push(tet[0], 1 - b[0] - b[1] - b[2]);
    row.push(tet[1], b[0]);
    row.push(tet[2], b[1]);
    row.push(tet[3], b[2]);
}

}  // namespace penalty::detail
