#pragma once
/// @file
/// TetrahedronFEMForceField's element kernel of method large (TetrahedronFEMForceField::computeForce),
/// in SOFA's operation order: F = J·(factor·(M·(Jᵀ·δ))) over J's and M's non-zero entries, and the
/// element energy ½ δᵀF. Templated on the value type: T = double is the scalar reference (one
/// element), a vector of lanes (tetrahedron_large_lanes.cpp) does one element per lane with the
/// same operations in the same order, hence the same bits. J, M and R are read from the one lane
/// layout, detail::TetrahedronLargeLanes (LaneStrainDisplacement, LaneMaterial, LaneRotation):
/// one lane for the scalar loops, four or eight for the vector kernels. Internal (namespace detail).
#include "penalty/mechanics/ordered_scatter.hpp"

#include <array>
#include <cstddef>

namespace penalty::detail {
/// Elements first … end − 1 of an element loop.
struct ElementRange {
    std::size_t first = 0;
    std::size_t end = 0;
};

/// Rows of J non-zero in Voigt column c (xx, yy, zz, xy, yz, zx), vertex by vertex and, within a
/// vertex, component by component: a row 3k + comp is non-zero only in the columns coupling comp.
constexpr std::array<int, 6> kColumnRowCount{4, 4, 4, 8, 8, 8};
constexpr std::array<std::array<int, 8>, 6> kColumnRows{{{0, 3, 6, 9, 0, 0, 0, 0},
                                                         {1, 4, 7, 10, 0, 0, 0, 0},
                                                         {2, 5, 8, 11, 0, 0, 0, 0},
                                                         {0, 1, 3, 4, 6, 7, 9, 10},
                                                         {1, 2, 4, 5, 7, 8, 10, 11},
                                                         {0, 2, 3, 5, 6, 8, 9, 11}}};
/// Voigt columns of J non-zero on a vertex's x, y and z rows, in increasing order.
constexpr std::array<std::array<int, 3>, 3> kRowColumns{{{0, 3, 5}, {1, 3, 4}, {2, 4, 5}}};

/// Vertex r/3's entry of J(r, c): 0 its g_yz, 1 its g_xz, 2 its g_xy (as strain_displacement
/// places them), by row component r % 3 and Voigt column c; −1 where J is 0.
constexpr std::array<std::array<int, 6>, 3> kCofactorOfEntry{
    {{0, -1, -1, 1, -1, 2}, {-1, 1, -1, 0, 2, -1}, {-1, -1, 2, -1, 1, 0}}};

/// The value type of one lane read alone (the scalar loops); the vector kernels name theirs the
/// same way (a member typedef: a vector type given as a template argument loses its may_alias).
struct OneLane {
    using type = double;
};

/// The lanes first, first + 1, … of a block's entry (an array of lanes) as one Vector::type.
template <class Vector, class Entry>
[[gnu::always_inline]] inline const typename Vector::type& lanes_at(const Entry& entry, std::size_t first) {
    return *reinterpret_cast<const typename Vector::type*>(entry.data() + first);
}

/// J(r, c) of a block's lanes from `first` on (kCofactorOfEntry; never asked where J is 0).
template <class Vector, class Block>
struct LaneStrainDisplacement {
    const Block& block;
    std::size_t first;
    [[gnu::always_inline]] const typename Vector::type& operator()(int r, int c) const {
        return lanes_at<Vector>(block.cofactor[static_cast<std::size_t>(r / 3)][static_cast<std::size_t>(
                                    kCofactorOfEntry[static_cast<std::size_t>(r % 3)][static_cast<std::size_t>(c)])],
                                first);
    }
};

/// D/(36V)(i, k) of a block's lanes from `first` on: the normal block (i, k < 3) and the shear
/// diagonal (i = k ≥ 3).
template <class Vector, class Block>
struct LaneMaterial {
    const Block& block;
    std::size_t first;
    [[gnu::always_inline]] const typename Vector::type& operator()(int i, int k) const {
        return lanes_at<Vector>(i < 3 ? block.material[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(k)]
                                      : block.shear[static_cast<std::size_t>(i) - 3],
                                first);
    }
};

/// R(i, k) of lane `lane` of a block, read in place (sofa_vec::times and transpose_times).
template <class Block>
struct LaneRotation {
    const Block& block;
    std::size_t lane;
    double operator()(int i, int k) const {
        return block.rotation[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(k)][lane];
    }
};

/// r(i, k) into lane `lane` of a block's R.
template <class Block, class Matrix>
void store_lane_rotation(Block& block, std::size_t lane, const Matrix& r) {
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            block.rotation[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(k)][lane] = r(i, k);
}

/// f(to, from) for each entry (array of lanes) of two blocks of any widths, the same entry of each.
template <class To, class From, class F>
void for_each_entry(To& to, const From& from, const F& f) {
    for (std::size_t i = 0; i < 9; ++i) f(to.rotation[i], from.rotation[i]);
    for (std::size_t k = 0; k < 4; ++k)
        for (std::size_t c = 0; c < 3; ++c) f(to.cofactor[k][c], from.cofactor[k][c]);
    for (std::size_t i = 0; i < 9; ++i) f(to.material[i], from.material[i]);
    for (std::size_t i = 0; i < 3; ++i) f(to.shear[i], from.shear[i]);
}

/// Σ over the non-zero rows r of column c, in kColumnRows order: j(r, c)·δ_r, the first term
/// alone then each next one added (no leading 0 +). T is double (one element) or a vector of
/// lanes (one element each, see large_dforce_avx).
template <int C, class T, class Entries>
[[gnu::always_inline]] inline void strain_entry(const Entries& j, const T (&delta)[12], T& sum) {
    constexpr auto& rows = kColumnRows[C];
    sum = j(rows[0], C) * delta[rows[0]];
    for (int n = 1; n < kColumnRowCount[C]; ++n)
        sum += j(rows[static_cast<std::size_t>(n)], C) * delta[rows[static_cast<std::size_t>(n)]];
}

/// An element's stored energy ½ δᵀF (method large), over the entries of δ that can be non-zero
/// (3, 6, 7, 9, 10, 11: the others are 0 by construction), summed left to right; one element
/// (Displacement, into a double) or one per vector lane (arrays of lanes, into lanes).
template <class Entries, class Energy>
[[gnu::always_inline]] inline void large_element_energy(const Entries& delta, const Entries& force, Energy& energy) {
    energy = 0.5 * (delta[3] * force[3] + delta[6] * force[6] + delta[7] * force[7] + delta[9] * force[9] +
                    delta[10] * force[10] + delta[11] * force[11]);
}

/// F = J·(factor·(M·(Jᵀ·δ))) with SOFA's sums (TetrahedronFEMForceField::computeForce): each
/// entry of Jᵀδ sums J's non-zero terms of its column vertex by vertex, left to right; M·(Jᵀδ)
/// uses M's normal 3×3 block and shear diagonal only; the scaling by `factor` (addDForce's
/// kFactor; null in addForce) comes before the last product, which again sums the non-zero
/// terms of each row in column order. j(r, c) and m(i, k) give J's and M's entries. Inlined,
/// loops of constant counts, the last one unrolled by pragma (without it SphereModel's step costs
/// 43 % more instructions): the solve's inner kernel, for one element (T = double) or for one
/// element per vector lane.
template <class T, class StrainDisplacementEntries, class MaterialEntries>
[[gnu::always_inline]] inline void element_force_of(const StrainDisplacementEntries& j, const MaterialEntries& m,
                                                    const T (&delta)[12], const T* factor, T (&force)[12]) {
    T strain[6];
    strain_entry<0>(j, delta, strain[0]);
    strain_entry<1>(j, delta, strain[1]);
    strain_entry<2>(j, delta, strain[2]);
    strain_entry<3>(j, delta, strain[3]);
    strain_entry<4>(j, delta, strain[4]);
    strain_entry<5>(j, delta, strain[5]);
    T stress[6];
    for (int i = 0; i < 3; ++i) stress[i] = m(i, 0) * strain[0] + m(i, 1) * strain[1] + m(i, 2) * strain[2];
    for (int i = 3; i < 6; ++i) stress[i] = m(i, i) * strain[i];
    if (factor)
        for (T& s : stress) s *= *factor;
#pragma GCC unroll 12
    for (int r = 0; r < 12; ++r) {
        const auto& columns = kRowColumns[static_cast<std::size_t>(r % 3)];
        force[r] = j(r, columns[0]) * stress[columns[0]] + j(r, columns[1]) * stress[columns[1]] +
                   j(r, columns[2]) * stress[columns[2]];
    }
}

}  // namespace penalty::detail
