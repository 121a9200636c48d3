// SpringForceField and MeshSpringForceField (mechanics/spring_force_field.cpp): force and sign, derivatives
// against finite differences, SOFA's per-spring dforce to the bit, springs per element, the force
// and product on threads (the bits of one thread, every kernel path, both arithmetics).
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"
#include "penalty/mechanics/spring_force_field.hpp"

#include "penalty_test/force_field_derivatives.hpp"
#include "penalty_test/grid_meshes.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <string>

namespace penalty {
namespace {

TEST(SpringForceField, ForceMatchesFormulaAndSign) {
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(2, 0, 0)};
    s.velocity = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
    s.init();
    SpringForceField ff(s);
    ff.add_spring({0, 1, 10.0, 3.0, 1.5});
    ff.init();
    ff.accumulate_force();
    // F = 10 (2 − 1.5) + 3 (1) = 8 along +x on a, −x on b.
    EXPECT_NEAR(s.force[0].x(), 8.0, 1e-14);
    EXPECT_NEAR(s.force[1].x(), -8.0, 1e-14);
    EXPECT_NEAR(ff.potential_energy(), 0.5 * 10 * 0.25, 1e-14);
    EXPECT_THROW(ff.add_spring({0, 1, -1.0, 0, 1}), std::invalid_argument);
    EXPECT_THROW(ff.add_spring({0, 1, 1.0, std::numeric_limits<double>::quiet_NaN(), 1}), std::invalid_argument);
    // an index no state can have (its byte offset would overflow) is refused at once
    EXPECT_THROW(ff.add_spring({0, std::numeric_limits<Index>::max(), 1.0, 0, 1}), std::invalid_argument);
    EXPECT_EQ(ff.springs().size(), 1u);
    ff.add_spring({0, 5, 1.0, 0, 1});
    EXPECT_THROW(ff.init(), std::invalid_argument);
}

TEST(SpringForceField, DerivativesMatchFiniteDifferencesOnRandomSprings) {
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> u(-1, 1);
    int checked = 0;
    for (int trial = 0; trial < 20; ++trial) {
        Vec3Object s;
        for (int i = 0; i < 5; ++i) s.position.emplace_back(u(rng), u(rng), u(rng));
        s.init();
        SpringForceField ff(s);
        for (int k = 0; k < 6; ++k) {
            const Index a = static_cast<Index>(rng() % 5);
            const Index b = (a + 1 + static_cast<Index>(rng() % 4)) % 5;
            ff.add_spring({a, b, 10 + 90 * std::abs(u(rng)), 0.5, std::abs(u(rng))});
        }
        ff.init();
        const auto d = test::check_force_field_derivatives(
            ff, s, {.dforce_vs_fd = 1e-5, .assembled_vs_dforce = 1e-12, .force_vs_energy = 1e-5});
        EXPECT_GT(d.k_fd.cwiseAbs().maxCoeff(), 1.0);
        ++checked;
    }
    EXPECT_EQ(checked, 20);
}

TEST(SpringForceField, DforceIsBitwiseSofasPerSpringProduct) {
    // add_dforce runs a hoisted loop (speed); it must give the bits of SOFA's per-spring product in
    // spring order: d = (m·(dx_b − dx_a))·k (SpringForceField) or m·((dx_b − dx_a)·k)
    // (QuadularBendingSprings), df_a += d, df_b −= d; m read back from the stiffness triplets.
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    for (const SpringArithmetic arithmetic :
         {SpringArithmetic::spring_force_field, SpringArithmetic::quadular_bending_springs}) {
        Vec3Object s;
        for (int i = 0; i < 7; ++i) s.position.emplace_back(u(rng), u(rng), u(rng));
        for (int i = 0; i < 7; ++i) s.velocity.emplace_back(u(rng), u(rng), u(rng));
        s.init();
        SpringForceField ff(s);
        ff.set_arithmetic(arithmetic);
        for (int k = 0; k < 15; ++k) {
            const Index a = static_cast<Index>(rng() % 7);
            const Index b = (a + 1 + static_cast<Index>(rng() % 6)) % 7;
            ff.add_spring({a, b, 10 + 90 * std::abs(u(rng)), 0.5, 0.3 + std::abs(u(rng))});
        }
        ff.init();
        ff.accumulate_force();
        TripletList t;
        ff.add_stiffness_triplets(t, 0, 0, 1.0);
        ASSERT_EQ(t.size(), 36 * ff.springs().size());
        for (auto& d : s.dx) d = Vec3(u(rng), u(rng), u(rng));
        for (auto& d : s.df) d = Vec3(u(rng), u(rng), u(rng));
        std::vector<Vec3> expected(s.df.begin(), s.df.end());
        const double k = -0.0123;
        for (std::size_t i = 0; i < ff.springs().size(); ++i) {
            Mat3 m;  // the (a, b) block of spring i: triplet 4·(3r + c) + 1 holds +m(r, c)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) m(r, c) = t[36 * i + 4 * static_cast<std::size_t>(3 * r + c) + 1].value();
            const auto a = static_cast<std::size_t>(ff.springs()[i].a);
            const auto b = static_cast<std::size_t>(ff.springs()[i].b);
            const Vec3 dx = s.dx[b] - s.dx[a];
            Vec3 d;
            for (int r = 0; r < 3; ++r) {
                if (arithmetic == SpringArithmetic::spring_force_field)
                    d[r] = (m(r, 0) * dx[0] + m(r, 1) * dx[1] + m(r, 2) * dx[2]) * k;
                else d[r] = m(r, 0) * (dx[0] * k) + m(r, 1) * (dx[1] * k) + m(r, 2) * (dx[2] * k);
            }
            expected[a] += d;
            expected[b] -= d;
        }
        ff.accumulate_dforce(k, 0.0);
        for (std::size_t j = 0; j < expected.size(); ++j)
            for (int c = 0; c < 3; ++c) EXPECT_EQ(s.df[j][c], expected[j][c]) << j;  // bitwise
    }
}

TEST(MeshSpringForceField, SpringsPerElementAndStiffnessOverLength) {
    MeshTopology topo;
    topo.set_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}});
    std::vector<Vec3> x0 = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 2, 0), Vec3(0, 2, 0),
                            Vec3(0, 0, 2), Vec3(2, 0, 2), Vec3(2, 2, 2), Vec3(0, 2, 2)};
    const auto springs = mesh_springs(topo, x0, MeshSpringParameters::uniform(10.0, 4.0));
    ASSERT_EQ(springs.size(), 28u);  // 12 edges, then 12 face diagonals (quads), then 4 body diagonals
    EXPECT_EQ(springs[0].a, 0);
    EXPECT_EQ(springs[0].b, 1);
    EXPECT_NEAR(springs[0].ks, 5.0, 1e-15);
    EXPECT_NEAR(springs[0].kd, 2.0, 1e-15);
    EXPECT_NEAR(springs[12].rest_length, std::sqrt(8.0), 1e-15);
    EXPECT_NEAR(springs[27].rest_length, std::sqrt(12.0), 1e-15);
    EXPECT_NEAR(springs[27].ks, 10.0 / std::sqrt(12.0), 1e-15);
    // Only lines: 12 springs.
    MeshSpringParameters lines;
    lines.lines_stiffness = 1.0;
    EXPECT_EQ(mesh_springs(topo, x0, lines).size(), 12u);
    // Tetra: 6 pairs. Zero rest length rejected.
    MeshTopology tet;
    tet.set_tetrahedra({{0, 1, 2, 3}});
    EXPECT_EQ(mesh_springs(tet, x0, MeshSpringParameters::uniform(1, 0)).size(), 6u);
    std::vector<Vec3> bad = {Vec3::Zero(), Vec3::Zero(), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    EXPECT_THROW(mesh_springs(tet, bad, MeshSpringParameters::uniform(1, 0)), std::invalid_argument);
    EXPECT_THROW(mesh_springs(tet, x0, MeshSpringParameters::uniform(-1, 0)), std::invalid_argument);
}

TEST(SpringForceField, ForceAndProductOnThreadsAreTheBitsOfOneThread) {
    // the springs of a 14 × 13 × 10-point Kuhn grid's tetrahedra (more than
    // OrderedScatter::kMinElements), in mesh order and shuffled, inside one state and between two
    // (the second a copy of the grid moved by 1.5 m: the same springs, 1.5 m longer)
    const RegularGridTopology grid({14, 13, 10}, Vec3::Zero(), Vec3(1.3, 1.2, 0.9));
    const MeshTopology mesh = test::kuhn_tetrahedra(grid);
    const std::vector<Spring> in_order = mesh_springs(mesh, grid.points(), MeshSpringParameters::uniform(100.0, 0.5));
    ASSERT_GE(in_order.size(), detail::OrderedScatter::kMinElements);
    std::vector<Spring> shuffled = in_order;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(3));
    const auto same_bits = [](const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
        return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
    };
    struct Products {
        std::vector<Vec3> force, product;  ///< the first state's, then the second's
        double energy = 0.0;
        std::size_t chunks = 0, deferred = 0;
    };
    std::vector<KernelPath> paths{KernelPath::scalar};
    if (kernel_path_supported(KernelPath::avx)) paths.push_back(KernelPath::avx);
    for (const bool two_states : {false, true})
        for (const std::vector<Spring>* springs : {&in_order, static_cast<const std::vector<Spring>*>(&shuffled)})
            for (const SpringArithmetic arithmetic :
                 {SpringArithmetic::spring_force_field, SpringArithmetic::quadular_bending_springs})
                for (const KernelPath path : paths) {
                    std::mt19937 rng(11);
                    std::uniform_real_distribution<double> u(-1.0, 1.0);
                    Vec3Object s1, s2;
                    for (Vec3Object* s : {&s1, &s2}) {
                        s->position = grid.points();
                        if (s == &s2)
                            for (Vec3& p : s->position) p += Vec3(1.5, 0.0, 0.0);
                        s->init();
                        for (Vec3& p : s->position) p += 0.03 * Vec3(u(rng), u(rng), u(rng));
                        for (Vec3& v : s->velocity) v = Vec3(u(rng), u(rng), u(rng));
                        for (Vec3& d : s->dx) d = Vec3(u(rng), u(rng), u(rng));
                    }
                    std::optional<SpringForceField> ff;
                    if (two_states) ff.emplace(s1, s2);
                    else ff.emplace(s1);
                    ff->set_arithmetic(arithmetic);
                    ff->set_kernel_path(path);
                    for (const Spring& spring : *springs) ff->add_spring(spring);
                    ff->init();
                    const auto run = [&](int threads) {
                        Products out;
                        for (Vec3Object* s : {&s1, &s2}) {
                            std::fill(s->force.begin(), s->force.end(), Vec3::Zero());
                            std::fill(s->df.begin(), s->df.end(), Vec3(0.25, -0.5, 1.0));
                        }
                        tbb::task_arena(threads).execute([&] {
                            ff->accumulate_force();
                            ff->accumulate_dforce(-0.37, 0.0);
                        });
                        for (const Vec3Object* s : {&s1, &s2}) {
                            out.force.insert(out.force.end(), s->force.begin(), s->force.end());
                            out.product.insert(out.product.end(), s->df.begin(), s->df.end());
                        }
                        out.energy = ff->potential_energy();
                        out.chunks = ff->product_scatter().chunk_count();
                        out.deferred = ff->product_scatter().deferred_terms();
                        return out;
                    };
                    const Products one = run(1);
                    EXPECT_EQ(one.chunks, 0U);
                    EXPECT_GT(one.energy, 0.0);
                    if (two_states) {
                        // both states take forces and products
                        const std::size_t n = s1.num_dofs();
                        const auto nonzero = [](auto begin, auto end) {
                            return std::any_of(begin, end, [](const Vec3& f) { return f.norm() > 0.0; });
                        };
                        EXPECT_TRUE(nonzero(one.force.begin(), one.force.begin() + std::ptrdiff_t(n)));
                        EXPECT_TRUE(nonzero(one.force.begin() + std::ptrdiff_t(n), one.force.end()));
                    }
                    for (const int threads : {2, 3, 8}) {
                        const Products many = run(threads);
                        const std::string where =
                            std::string(to_string(path)) + ", arithmetic " +
                            std::to_string(static_cast<int>(arithmetic)) + ", " + std::to_string(threads) + " threads" +
                            (springs == &in_order ? "" : ", shuffled") + (two_states ? ", two states" : ", one state");
                        EXPECT_GT(many.chunks, 1U) << where;
                        EXPECT_GT(many.deferred, 0U) << where;
                        EXPECT_TRUE(same_bits(many.force, one.force)) << where;
                        EXPECT_TRUE(same_bits(many.product, one.product)) << where;
                        EXPECT_EQ(std::memcmp(&many.energy, &one.energy, sizeof(double)), 0) << where;
                    }
                }
}

TEST(SpringForceField, SpringsAddedAfterInitOrAResizedFirstStateRunOnOneThread) {
    const RegularGridTopology grid({14, 13, 10}, Vec3::Zero(), Vec3(1.3, 1.2, 0.9));
    const std::vector<Spring> springs =
        mesh_springs(test::kuhn_tetrahedra(grid), grid.points(), MeshSpringParameters::uniform(100.0, 0.5));
    Vec3Object a, b;
    a.position = b.position = grid.points();
    a.init();
    b.init();
    SpringForceField between(a, b), inside(a);
    for (const Spring& s : springs) {
        between.add_spring(s);
        inside.add_spring(s);
    }
    between.init();
    inside.init();
    inside.add_spring(springs.front());  // after init: the ends for the split are made again at init
    tbb::task_arena(4).execute([&] {
        between.accumulate_force();
        inside.accumulate_force();
    });
    EXPECT_GT(between.product_scatter().chunk_count(), 1U);
    EXPECT_EQ(inside.product_scatter().chunk_count(), 0U);
    inside.init();
    tbb::task_arena(4).execute([&] { inside.accumulate_force(); });
    EXPECT_GT(inside.product_scatter().chunk_count(), 1U);
    // the first state grown after init: its points no longer end where the split numbered the
    // second state's, so the field runs on one thread (and its scatter is not rebuilt)
    SpringForceField grown(a, b);
    for (const Spring& s : springs) grown.add_spring(s);
    grown.init();
    a.resize(a.num_dofs() + 1);
    for (Vec3& p : b.position) p += Vec3(0.1, 0.0, 0.0);  // (stretched: a force to compute)
    std::fill(a.force.begin(), a.force.end(), Vec3::Zero());
    std::fill(b.force.begin(), b.force.end(), Vec3::Zero());
    tbb::task_arena(4).execute([&] { grown.accumulate_force(); });
    EXPECT_EQ(grown.product_scatter().chunk_count(), 0U);
    EXPECT_GT(grown.potential_energy(), 0.0);
}

}  // namespace
}  // namespace penalty
