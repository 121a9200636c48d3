// SubtreeSystem::assemble: the assembled m·M + k·K of a subtree, mapped stiffness through Jᵀ K J.
#include "penalty/simulation/subtree_system.hpp"

#include "subtree_layout.hpp"

#include <Eigen/SparseCore>

#include <algorithm>
#include <unordered_map>

namespace penalty {

SparseMatrix SubtreeSystem::assemble(double m, double k) const {
    // Extended index space: independent scalars, then mapped scalars; P maps system DOFs to it.
    std::unordered_map<const BaseState*, Index> ext_offset;
    for (std::size_t i = 0; i < layout_->independent.size(); ++i)
        ext_offset[layout_->independent[i]] = layout_->offsets[i];
    Index total = layout_->size;
    for (BaseState* s : layout_->mapped) {
        ext_offset[s] = total;
        total += static_cast<Index>(s->scalar_size());
    }
    using ColMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, Eigen::Index>;
    std::unordered_map<const BaseState*, ColMatrix> p_rows;  // (state scalars) x layout_->size
    for (std::size_t i = 0; i < layout_->independent.size(); ++i) {
        const auto n = layout_->sizes[i];
        ColMatrix id(n, layout_->size);
        TripletList t;
        for (Eigen::Index j = 0; j < n; ++j) t.emplace_back(j, layout_->offsets[i] + j, 1.0);
        id.setFromTriplets(t.begin(), t.end());
        p_rows[layout_->independent[i]] = id;
    }
    for (BaseMapping* map : layout_->mappings) {
        const auto nin = static_cast<Eigen::Index>(map->from()->scalar_size());
        const auto nout = static_cast<Eigen::Index>(map->to()->scalar_size());
        ColMatrix j(nout, nin);
        TripletList t;
        map->add_jacobian_triplets(t, 0, 0);
        j.setFromTriplets(t.begin(), t.end());
        const auto it = p_rows.find(map->from());
        ColMatrix rows = it == p_rows.end() ? ColMatrix(nout, layout_->size) : ColMatrix(j * it->second);
        if (BaseState* second = map->second_from()) {  // J₂·P₂ of a second input
            ColMatrix j2(nout, static_cast<Eigen::Index>(second->scalar_size()));
            TripletList t2;
            map->add_second_input_jacobian_triplets(t2, 0, 0);
            j2.setFromTriplets(t2.begin(), t2.end());
            if (const auto it2 = p_rows.find(second); it2 != p_rows.end()) rows = ColMatrix(rows + j2 * it2->second);
        }
        p_rows[map->to()] = rows;
    }
    ColMatrix p(total, layout_->size);
    {
        TripletList t;
        for (const auto& [s, rows] : p_rows) {
            const Index o = ext_offset.at(s);
            for (Eigen::Index c = 0; c < rows.outerSize(); ++c)
                for (ColMatrix::InnerIterator itr(rows, c); itr; ++itr)
                    t.emplace_back(o + itr.row(), itr.col(), itr.value());
        }
        p.setFromTriplets(t.begin(), t.end());
    }
    TripletList kt;
    const StateOffsets offs = [&](const BaseState* s) {
        const auto it = ext_offset.find(s);
        return it == ext_offset.end() ? total : it->second;
    };
    for (BaseForceField* ff : layout_->force_fields) ff->add_stiffness(kt, offs, k);
    for (const auto& entry : layout_->masses)  // masses on mapped states: Pᵀ·(m·M)·P with the stiffness
        if (!layout_->is_independent(entry.first->state()))
            entry.first->add_mass_triplets(kt, offs(entry.first->state()), m);
    kt.erase(
        std::remove_if(kt.begin(), kt.end(), [&](const Triplet& t) { return t.row() >= total || t.col() >= total; }),
        kt.end());
    ColMatrix kext(total, total);
    kext.setFromTriplets(kt.begin(), kt.end());
    TripletList mt;
    for (const auto& entry : layout_->masses)
        if (layout_->is_independent(entry.first->state()))
            entry.first->add_mass_triplets(mt, offset(entry.first->state()), m);
    ColMatrix mm(layout_->size, layout_->size);
    mm.setFromTriplets(mt.begin(), mt.end());
    ColMatrix a = ColMatrix(ColMatrix(p.transpose()) * kext * p) + mm;
    return SparseMatrix(a);
}

}  // namespace penalty
