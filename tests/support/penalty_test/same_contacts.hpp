#pragma once
/// @file
/// Two contact pipelines hold the same contacts, to the last bit: the same live pairs in the same
/// order, and in each the same springs (DOFs, elements, age, normal, rest distance, stiffness).

#include "penalty/simulation/contact_pipeline.hpp"
#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace penalty::test {

inline void expect_same_contacts(const ContactPipeline& a, const ContactPipeline& b, int step) {
    const auto& ea = a.graph_entries();
    const auto& eb = b.graph_entries();
    EXPECT_EQ(ea.size(), eb.size()) << "step " << step;
    for (std::size_t k = 0; k < std::min(ea.size(), eb.size()); ++k) {
        const auto ca = ea[k].contact->force_field().contacts();
        const auto cb = eb[k].contact->force_field().contacts();
        EXPECT_EQ(ca.size(), cb.size()) << "step " << step << " entry " << k;
        if (ca.size() != cb.size()) continue;
        for (std::size_t i = 0; i < ca.size(); ++i) {
            EXPECT_TRUE(ca[i].m1 == cb[i].m1 && ca[i].m2 == cb[i].m2 && ca[i].index1 == cb[i].index1 &&
                        ca[i].index2 == cb[i].index2 && ca[i].age == cb[i].age)
                << "step " << step << " entry " << k << " contact " << i;
            EXPECT_TRUE(same_bits(ca[i].normal, cb[i].normal) && same_bits(ca[i].dist, cb[i].dist) &&
                        same_bits(ca[i].ks, cb[i].ks))
                << "step " << step << " entry " << k << " contact " << i;
        }
    }
}

}  // namespace penalty::test
