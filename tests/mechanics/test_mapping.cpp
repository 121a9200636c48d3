#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "penalty_test/finite_difference.hpp"
#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <span>

namespace penalty {
namespace {

using test::same_bits;

/// Every vector of `a` the bits of `b`'s, the signs of zeros included.
bool all_same_bits(std::span<const Vec3> a, const std::vector<Vec3>& b) {
    return a.size() == b.size() &&
           std::equal(a.begin(), a.end(), b.begin(), [](const Vec3& x, const Vec3& y) { return same_bits(x, y); });
}

std::mt19937 mapping_rng(7);
double uni() { return std::uniform_real_distribution<double>(-1, 1)(mapping_rng); }
Vec3 rand_vec() { return Vec3(uni(), uni(), uni()); }

/// Generic checks of a mapping whose input has `in_size` scalars per DOF:
///  ⟨J dx, y⟩ = ⟨dx, Jᵀ y⟩, J (apply_j) = FD of apply, triplets = apply_j.
/// `perturb(h, i)` moves input scalar i by h (and restores with −h); `read_out()` returns the
/// output positions flattened.
template <class In>
void check_mapping(Mapping<In, Vec3Types>& map, MechanicalObject<In>& in, Vec3Object& out,
                   const std::function<void(double, Eigen::Index)>& perturb) {
    map.init();
    const auto nin = static_cast<Eigen::Index>(in.scalar_size());
    const auto nout = static_cast<Eigen::Index>(out.scalar_size());
    ASSERT_GT(nout, 0);
    // Adjoint identity on random vectors.
    for (int trial = 0; trial < 5; ++trial) {
        Eigen::VectorXd dx = Eigen::VectorXd::NullaryExpr(nin, [] { return uni(); });
        Eigen::VectorXd y = Eigen::VectorXd::NullaryExpr(nout, [] { return uni(); });
        in.dx_flat() = dx;
        map.apply_dx();
        const double lhs = out.dx_flat().dot(y);
        out.df_flat() = y;
        in.df_flat().setZero();
        map.apply_jt_df();
        const double rhs = dx.dot(in.df_flat());
        EXPECT_NEAR(lhs, rhs, 1e-12 * std::max(1.0, std::abs(lhs)));
        EXPECT_GT(std::abs(lhs), 1e-6);
    }
    // J column by column vs central finite differences of apply.
    map.apply_position();
    Eigen::MatrixXd j(nout, nin), j_fd(nout, nin);
    const double h = 1e-6;
    for (Eigen::Index c = 0; c < nin; ++c) {
        in.dx_flat().setZero();
        in.dx_flat()[c] = 1.0;
        map.apply_dx();
        j.col(c) = out.dx_flat();
        perturb(h, c);
        map.apply_position();
        const Eigen::VectorXd xp = ConstFlatVector(reinterpret_cast<const double*>(out.position.data()), nout);
        perturb(-2 * h, c);
        map.apply_position();
        const Eigen::VectorXd xm = ConstFlatVector(reinterpret_cast<const double*>(out.position.data()), nout);
        perturb(h, c);
        map.apply_position();
        j_fd.col(c) = (xp - xm) / (2 * h);
    }
    EXPECT_TRUE(test::near_relative(j, j_fd, 1e-7)) << j << "\n--\n" << j_fd;
    EXPECT_GT(j.cwiseAbs().maxCoeff(), 0.1);
    TripletList t;
    map.add_jacobian_triplets(t, 0, 0);
    SparseMatrix js(nout, nin);
    js.setFromTriplets(t.begin(), t.end());
    EXPECT_TRUE(test::near_relative(Eigen::MatrixXd(js), j, 1e-14));
}

void perturb_vec3(Vec3Object& in, double h, Eigen::Index c) {
    in.position[static_cast<std::size_t>(c / 3)][c % 3] += h;
}

void perturb_rigid(Rigid3Object& in, double h, Eigen::Index c) {
    RigidFrame& f = in.position[static_cast<std::size_t>(c / 6)];
    const auto k = c % 6;
    if (k < 3) {
        f.center[k] += h;
    } else {
        // World-frame small rotation about axis k−3 (matches the angular velocity convention).
        f.orientation = Quat(Eigen::AngleAxisd(h, Vec3::Unit(k - 3))) * f.orientation;
    }
}

TEST(Mapping, IdentityVec3) {
    Vec3Object in, out;
    for (int i = 0; i < 4; ++i) in.position.push_back(rand_vec());
    in.init();
    IdentityMapping map(in, out);
    check_mapping<Vec3Types>(map, in, out, [&](double h, Eigen::Index c) { perturb_vec3(in, h, c); });
    EXPECT_EQ(out.position[2], in.position[2]);
}

// SOFA's MechanicalObject::init stores a state's own positions as its rest positions before the
// mapping's init maps the positions (applyRestPosition off): a force field on the mapped state
// reads the state's own (SubsetMapping.scn: a grid of float bounds on a finer parent's points).
TEST(Mapping, OwnPositionsStayTheRestPositionsOfTheMappedState) {
    Vec3Object in;
    in.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 1, 0)};
    in.init();
    Vec3Object own;
    own.position = {Vec3(1.0 + 1e-9, 0, 0), Vec3(2, 1, 1e-9)};  // near input points 1 and 2
    BarycentricMapping subset(in, own);
    subset.set_weights({{{1, 1.0}}, {{2, 1.0}}});
    subset.init();
    EXPECT_EQ(own.position[0], in.position[1]);
    EXPECT_EQ(own.position[1], in.position[2]);
    EXPECT_EQ(own.rest_position[0], Vec3(1.0 + 1e-9, 0, 0));
    EXPECT_EQ(own.rest_position[1], Vec3(2, 1, 1e-9));
    ASSERT_EQ(own.velocity.size(), 2u);
    // without positions of its own (or with another count) the rest positions are the mapped ones
    for (const std::size_t count : {std::size_t{0}, std::size_t{1}}) {
        Vec3Object out;
        out.position.assign(count, Vec3(5, 5, 5));
        BarycentricMapping map(in, out);
        map.set_weights({{{1, 1.0}}, {{2, 1.0}}});
        map.init();
        ASSERT_EQ(out.rest_position.size(), 2u);
        EXPECT_EQ(out.rest_position[0], in.position[1]);
        EXPECT_EQ(out.rest_position[1], in.position[2]);
        EXPECT_EQ(out.position[1], in.position[2]);
    }
}

TEST(Mapping, IdentityRigidToVec3TakesCentres) {
    Rigid3Object in;
    Vec3Object out;
    for (int i = 0; i < 3; ++i)
        in.position.push_back({rand_vec(), Quat(Eigen::AngleAxisd(uni(), rand_vec().normalized()))});
    in.init();
    RigidCenterIdentityMapping map(in, out);
    check_mapping<Rigid3Types>(map, in, out, [&](double h, Eigen::Index c) { perturb_rigid(in, h, c); });
    EXPECT_EQ(out.position[1], in.position[1].center);
}

TEST(Mapping, RigidMappingAdjointAndFiniteDifferences) {
    Rigid3Object in;
    Vec3Object out;
    for (int i = 0; i < 2; ++i)
        in.position.push_back({rand_vec(), Quat(Eigen::AngleAxisd(2 * uni(), rand_vec().normalized()))});
    in.velocity = {RigidDeriv{rand_vec(), rand_vec()}, RigidDeriv{rand_vec(), rand_vec()}};
    in.init();
    RigidMapping map(in, out);
    std::vector<Vec3> local;
    for (int i = 0; i < 5; ++i) local.push_back(rand_vec());
    map.set_points(local, {0, 1, 1, 0, 1});
    check_mapping<Rigid3Types>(map, in, out, [&](double h, Eigen::Index c) { perturb_rigid(in, h, c); });
    map.apply_position();
    EXPECT_TRUE(out.position[1].isApprox(in.position[1].center + in.position[1].orientation * local[1], 1e-14));
    // Velocity of a material point: v + ω × r.
    map.apply_velocity();
    const Vec3 r = in.position[0].orientation * local[3];
    EXPECT_TRUE(out.velocity[3].isApprox(in.velocity[0].linear + in.velocity[0].angular.cross(r), 1e-14));
    RigidMapping bad_frames(in, out);
    bad_frames.set_points(local, {0, 2, 0, 0, 0});
    EXPECT_THROW(bad_frames.init(), std::invalid_argument);
    EXPECT_THROW(bad_frames.set_points(local, {0, -1, 0, 0, 0}), std::invalid_argument);
    // set_points_from_world inverts apply.
    RigidMapping map2(in, out);
    std::vector<Vec3> world(out.position.begin(), out.position.end());
    map2.set_points_from_world(world, {0, 1, 1, 0, 1});
    for (std::size_t i = 0; i < local.size(); ++i) EXPECT_TRUE(map2.points()[i].local.isApprox(local[i], 1e-12));
}

TEST(Mapping, RigidMappingOfManyPointsOnThreadsIsTheRowOperations) {
    // 20 000 points on three frames (above OrderedScatter::kMinElements): apply and apply_j in
    // ranges on TBB's threads; at 1, 2 and 8 threads each gives the bits of RigidPointRow::place
    // and ::velocity, and apply_jt the frames' sums in point order.
    constexpr std::size_t kPoints = 20'000;
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const auto random = [&] { return Vec3(u(rng), u(rng), u(rng)); };
    Rigid3Object in;
    Vec3Object out;
    for (int f = 0; f < 3; ++f)
        in.position.push_back({random(), Quat(Eigen::AngleAxisd(u(rng), random().normalized()))});
    in.init();
    for (RigidDeriv& v : in.velocity) v = {random(), random()};
    std::vector<Vec3> local(kPoints);
    std::vector<Index> frames(kPoints);
    for (std::size_t i = 0; i < kPoints; ++i) {
        local[i] = random();
        frames[i] = Index(i * 7 % 3);
    }
    RigidMapping map(in, out);
    map.set_points(local, frames);
    map.init();
    std::vector<RigidPointRow> rows = map.points();
    std::vector<Vec3> positions(kPoints), velocities(kPoints), forces(kPoints);
    std::vector<RigidDeriv> spread(3);
    for (std::size_t i = 0; i < kPoints; ++i) {
        positions[i] = rows[i].place(in.position[std::size_t(frames[i])]);
        velocities[i] = rows[i].velocity(in.velocity[std::size_t(frames[i])]);
        forces[i] = random();
        rows[i].spread(spread[std::size_t(frames[i])], forces[i]);
    }
    for (const int threads : {1, 2, 8}) {
        std::fill(out.position.begin(), out.position.end(), Vec3::Zero());
        std::fill(out.velocity.begin(), out.velocity.end(), Vec3::Zero());
        std::copy(forces.begin(), forces.end(), out.df.begin());
        std::fill(in.df.begin(), in.df.end(), RigidDeriv{});
        tbb::task_arena(threads).execute([&] {
            map.apply_position();
            map.apply_velocity();
            map.apply_jt_df();
        });
        EXPECT_TRUE(all_same_bits(out.position, positions)) << threads;
        EXPECT_TRUE(all_same_bits(out.velocity, velocities)) << threads;
        for (std::size_t f = 0; f < 3; ++f) {
            EXPECT_TRUE(same_bits(in.df[f].linear, spread[f].linear)) << threads << ' ' << f;
            EXPECT_TRUE(same_bits(in.df[f].angular, spread[f].angular)) << threads << ' ' << f;
        }
    }
}

TEST(Mapping, BarycentricOnTetrahedra) {
    Vec3Object in, out;
    in.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(1, 1, 1)};
    in.init();
    MeshTopology topo;
    topo.set_tetrahedra({{0, 1, 2, 3}, {1, 2, 3, 4}});
    BarycentricMapping map(in, out);
    const std::vector<Vec3> pts = {Vec3(0.1, 0.2, 0.3), Vec3(0.6, 0.6, 0.6), Vec3(-0.5, 0.1, 0.1)};
    map.map_on_tetrahedra(topo, in.position, pts);
    check_mapping<Vec3Types>(map, in, out, [&](double h, Eigen::Index c) { perturb_vec3(in, h, c); });
    map.apply_position();
    for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_TRUE(out.position[i].isApprox(pts[i], 1e-14)) << i;
    EXPECT_EQ(map.weights()[0][0].index, 0);  // inside tetra 0
    EXPECT_EQ(map.weights()[1][3].index, 4);  // inside tetra 1
    EXPECT_NEAR(map.weights()[0][0].weight, 0.4, 1e-15);
}

TEST(Mapping, BarycentricOnTetrahedraTakesSofasNearestCentreAndWeights) {
    // SOFA's BarycentricMapperMeshTopology::init: a point outside every tetrahedron goes to the
    // one whose centre is nearest (|p − centre|²), not to the one it is barycentrically nearest;
    // the first weight is ((1 − b0) − b1) − b2, not 1 − (b0 + b1 + b2).
    Vec3Object in, out;
    // tetra 0: the unit tetrahedron (its edge matrix is the identity: b = p exactly); tetra 1: a
    // sliver 0.01 thick at x ≈ −0.4, its centre (−0.4025, 0.325, 0.325)
    in.position = {Vec3(0, 0, 0),    Vec3(1, 0, 0),    Vec3(0, 1, 0),    Vec3(0, 0, 1),
                   Vec3(-0.4, 0, 0), Vec3(-0.4, 1, 0), Vec3(-0.4, 0, 1), Vec3(-0.41, 0.3, 0.3)};
    in.init();
    MeshTopology topo;
    topo.set_tetrahedra({{0, 1, 2, 3}, {4, 5, 6, 7}});
    BarycentricMapping map(in, out);
    // p0: outside both, 0.3 outside tetra 0 barycentrically (|p − c0|² = 0.3025) and about 10
    // outside the sliver (|p − c1|² ≈ 0.0218): SOFA takes the sliver. p1: inside tetra 0.
    const std::vector<Vec3> pts = {Vec3(-0.3, 0.25, 0.25), Vec3(0.1, 0.2, 0.3)};
    map.map_on_tetrahedra(topo, in.position, pts);
    ASSERT_EQ(map.weights()[0].size(), 4u);
    EXPECT_EQ(map.weights()[0][0].index, 4);
    EXPECT_EQ(map.weights()[0][3].index, 7);
    ASSERT_EQ(map.weights()[1][0].index, 0);
    const double w0 = map.weights()[1][0].weight;
    EXPECT_EQ(w0, ((1.0 - 0.1) - 0.2) - 0.3);  // 0.39999999999999997
    EXPECT_NE(w0, 1.0 - (0.1 + 0.2 + 0.3));    // 0.3999999999999999
    EXPECT_EQ(map.weights()[1][1].weight, 0.1);
    EXPECT_EQ(map.weights()[1][2].weight, 0.2);
    EXPECT_EQ(map.weights()[1][3].weight, 0.3);
}

TEST(Mapping, BarycentricProductsAreBitwiseTheRowOperations) {
    // apply_j and apply_jt run on a flattened copy of the rows (speed); they must give the bits
    // of BarycentricRow::combine and ::spread, rows of every count, entries in row order.
    Vec3Object in, out;
    in.position.resize(9);
    for (auto& p : in.position) p = rand_vec();
    in.init();
    std::vector<BarycentricRow> rows(7);
    for (std::size_t i = 0; i < rows.size(); ++i)
        for (std::size_t k = 0; k <= i; ++k) rows[i].push(static_cast<Index>((3 * i + 5 * k) % 9), uni());
    BarycentricMapping map(in, out);
    map.set_rows(rows);
    map.init();
    for (auto& d : in.dx) d = rand_vec();
    map.apply_dx();
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const Vec3 expected = rows[i].combine(in.dx);
        for (int c = 0; c < 3; ++c) EXPECT_EQ(out.dx[i][c], expected[c]) << i;  // bitwise
    }
    for (auto& f : out.df) f = rand_vec();
    for (auto& f : in.df) f = rand_vec();
    std::vector<Vec3> expected(in.df.begin(), in.df.end());
    for (std::size_t i = 0; i < rows.size(); ++i) rows[i].spread(expected, out.df[i]);
    map.apply_jt_df();
    for (std::size_t j = 0; j < expected.size(); ++j)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(in.df[j][c], expected[j][c]) << j;  // bitwise
}

TEST(Mapping, BarycentricProductsOfALargeMappingOnThreadsAreTheRowOperations) {
    // 20 000 rows of four entries over 10 000 inputs (both above OrderedScatter::kMinElements):
    // apply, apply_j and apply_jt's full gather run in ranges on TBB's threads; at 1, 2 and 8
    // threads each gives the bits of BarycentricRow::combine and ::spread in row order.
    constexpr std::size_t kInputs = 10'000, kRows = 20'000;
    std::mt19937 rng(5);
    std::uniform_int_distribution<Index> input(0, Index(kInputs) - 1);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Vec3Object in, out;
    in.position.resize(kInputs);
    for (auto& p : in.position) p = Vec3(u(rng), u(rng), u(rng));
    in.init();
    std::vector<BarycentricRow> rows(kRows);
    for (BarycentricRow& row : rows)
        for (int k = 0; k < 4; ++k) row.push(input(rng), u(rng));
    BarycentricMapping map(in, out);
    map.set_rows(rows);
    map.init();
    for (auto& d : in.dx) d = Vec3(u(rng), u(rng), u(rng));
    std::vector<Vec3> forces(kRows), start_df(kInputs);
    for (auto& f : forces) f = Vec3(u(rng), u(rng), u(rng));  // every row forced: the full gather
    for (auto& f : start_df) f = Vec3(u(rng), u(rng), u(rng));
    std::vector<Vec3> positions(kRows), products(kRows), spread = start_df;
    for (std::size_t i = 0; i < kRows; ++i) {
        positions[i] = rows[i].combine(in.position);
        products[i] = rows[i].combine(in.dx);
        rows[i].spread(spread, forces[i]);
    }
    for (const int threads : {1, 2, 8}) {
        std::fill(out.position.begin(), out.position.end(), Vec3::Zero());
        std::fill(out.dx.begin(), out.dx.end(), Vec3::Zero());
        std::copy(forces.begin(), forces.end(), out.df.begin());
        std::copy(start_df.begin(), start_df.end(), in.df.begin());
        bool on_threads = false;
        tbb::task_arena(threads).execute([&] {
            on_threads = detail::ranges_on_threads(kRows) && detail::ranges_on_threads(kInputs);
            map.apply_position();
            map.apply_dx();
            map.apply_jt_df();
        });
        EXPECT_EQ(on_threads, threads > 1) << threads;
        EXPECT_TRUE(all_same_bits(out.position, positions)) << threads;
        EXPECT_TRUE(all_same_bits(out.dx, products)) << threads;
        EXPECT_TRUE(all_same_bits(in.df, spread)) << threads;
    }
}

TEST(Mapping, BarycentricSparseJtOfALargeMappingOnThreadsIsTheFullSpread) {
    // a collision surface's Jᵀ: 20 000 rows over 10 000 inputs, 150 rows forced (the scatter of
    // the forced rows), the inputs' search for a −0 start in ranges on TBB's threads; with no
    // input at −0 and with 40 of them, at 1, 2 and 8 threads each input gets the bits of
    // BarycentricRow::spread over every row in order (the unforced rows' +0 terms included)
    constexpr std::size_t kInputs = 10'000, kRows = 20'000;
    std::mt19937 rng(9);
    std::uniform_int_distribution<Index> input(0, Index(kInputs) - 1);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Vec3Object in, out;
    in.position.resize(kInputs, Vec3::Zero());
    in.init();
    std::vector<BarycentricRow> rows(kRows);
    for (BarycentricRow& row : rows)
        for (int k = 0; k < 3; ++k) row.push(input(rng), u(rng));
    BarycentricMapping map(in, out);
    map.set_rows(rows);
    map.init();
    std::vector<Vec3> forces(kRows, Vec3::Zero());
    for (std::size_t i = 0; i < kRows; i += kRows / 150) forces[i] = Vec3(u(rng), 0.0, u(rng));
    for (const std::size_t negative_zeros : {0, 40}) {
        std::vector<Vec3> start_df(kInputs);
        for (auto& f : start_df) f = Vec3(u(rng), u(rng), u(rng));
        for (std::size_t n = 0; n < negative_zeros; ++n) start_df[(n * 7919) % kInputs] = Vec3(-0.0, 0.25, -0.0);
        std::vector<Vec3> spread = start_df;
        for (std::size_t i = 0; i < kRows; ++i) rows[i].spread(spread, forces[i]);
        for (const int threads : {1, 2, 8}) {
            std::copy(forces.begin(), forces.end(), out.df.begin());
            std::copy(start_df.begin(), start_df.end(), in.df.begin());
            tbb::task_arena(threads).execute([&] { map.apply_jt_df(); });
            EXPECT_TRUE(all_same_bits(in.df, spread)) << negative_zeros << " inputs at -0, " << threads << " threads";
        }
    }
}

/// Bitwise equality of two doubles, the sign of a zero included.

TEST(Mapping, BarycentricJtOfFewForcedRowsIsBitwiseTheFullSpread) {
    // apply_jt skips the rows whose force is ±0 when they are most rows; every input must get
    // the bits of BarycentricRow::spread over all rows, the sign of zeros included: inputs
    // starting at −0 or +0, negative and positive weights, forced rows with zero components.
    Vec3Object in, out;
    in.position.resize(12);
    for (auto& p : in.position) p = rand_vec();
    in.init();
    std::vector<BarycentricRow> rows(40);
    for (std::size_t i = 0; i < rows.size(); ++i)
        for (std::size_t k = 0; k < 1 + i % 8; ++k) rows[i].push(static_cast<Index>((7 * i + 5 * k) % 12), uni());
    rows[3] = BarycentricRow{};
    rows[3].push(11, -0.5);  // input 11: only negative weights (−0 terms)
    rows[3].push(11, -0.25);
    rows[7] = BarycentricRow{};
    rows[7].push(9, 0.5);  // input 9: row 7 alone (unforced), a positive weight (+0 terms in z)
    for (BarycentricRow& r : rows)
        for (auto& e : r.entries) {
            if (e.index == 11 && &r != &rows[3]) e.index = 10;
            if (e.index == 9 && &r != &rows[7]) e.index = 8;
        }
    BarycentricMapping map(in, out);
    map.set_rows(rows);
    map.init();
    for (int trial = 0; trial < 4; ++trial) {
        for (auto& f : out.df) f = Vec3(trial % 2 == 0 ? 0.0 : -0.0, -0.0, 0.0);  // unforced rows: ±0
        out.df[5] = rand_vec();
        out.df[17] = Vec3(uni(), -0.0, 0.0);  // forced, with zero components
        if (trial >= 2) out.df[33] = rand_vec();
        for (auto& v : in.df) v = rand_vec();
        in.df[0] = Vec3(-0.0, 0.0, -0.0);   // starts at −0: the skipped +0 terms decide its sign
        in.df[11] = Vec3(-0.0, -0.0, 0.0);  // only −0 terms from row 3 (unforced): stays −0
        in.df[4] = Vec3(0.0, -0.0, 1.0);
        in.df[9] = Vec3(1.0, 0.5, -0.0);  // −0 in its last component only
        if (trial == 3) in.df[11] = Vec3(-0.0, 2.0, -0.0);
        std::vector<Vec3> expected(in.df.begin(), in.df.end());
        for (std::size_t i = 0; i < rows.size(); ++i) rows[i].spread(expected, out.df[i]);
        map.apply_jt_df();
        for (std::size_t j = 0; j < expected.size(); ++j)
            for (int c = 0; c < 3; ++c)
                EXPECT_TRUE(same_bits(in.df[j][c], expected[j][c])) << "trial " << trial << " input " << j << "." << c
                                                                    << ": " << in.df[j][c] << " vs " << expected[j][c];
        if (trial == 0) {
            EXPECT_TRUE(std::signbit(in.df[11][0]));  // the −0 case was exercised
            EXPECT_FALSE(std::signbit(in.df[9][2]));  // row 7's +0 term turned input 9's −0 into +0
        }
    }
}

TEST(Mapping, BarycentricProductsOfSelectedRowsAreBitwiseTheFullOnesWithZerosElsewhere) {
    Vec3Object in, out;
    in.position.resize(9);
    for (auto& p : in.position) p = rand_vec();
    in.init();
    std::vector<BarycentricRow> rows(10);
    for (std::size_t i = 0; i < rows.size(); ++i)
        for (std::size_t k = 0; k < 1 + i % 8; ++k) rows[i].push(static_cast<Index>((3 * i + 5 * k) % 9), uni());
    BarycentricMapping map(in, out);
    map.set_rows(rows);
    map.init();
    for (auto& d : in.dx) d = rand_vec();
    const Vec3 untouched(0.125, -7.0, 3.0);
    for (auto& d : out.dx) d = untouched;
    const std::vector<std::uint32_t> selected = {1, 4, 5, 9};
    ASSERT_TRUE(map.maps_selected_rows());
    map.apply_dx_rows(selected);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const bool is_selected = std::find(selected.begin(), selected.end(), i) != selected.end();
        const Vec3 expected = is_selected ? rows[i].combine(in.dx) : untouched;
        for (int c = 0; c < 3; ++c) EXPECT_TRUE(same_bits(out.dx[i][c], expected[c])) << i;
    }
    // Jᵀ over the selected rows: the others hold garbage, taken as +0 and not read; the bits of
    // the full spread with +0 in them, inputs starting at −0 included.
    for (int trial = 0; trial < 2; ++trial) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        for (auto& f : out.df) f = Vec3(nan, nan, nan);
        for (const std::uint32_t i : selected) out.df[i] = Vec3(0.0, -0.0, 0.0);
        out.df[4] = rand_vec();
        if (trial == 1) out.df[9] = Vec3(uni(), 0.0, -0.0);
        for (auto& v : in.df) v = rand_vec();
        in.df[0] = Vec3(-0.0, -0.0, 0.0);
        in.df[3] = Vec3(1.0, -0.0, -0.0);
        std::vector<Vec3> expected(in.df.begin(), in.df.end());
        for (std::size_t i = 0; i < rows.size(); ++i) {
            const bool is_selected = std::find(selected.begin(), selected.end(), i) != selected.end();
            rows[i].spread(expected, is_selected ? out.df[i] : Vec3(0.0, 0.0, 0.0));
        }
        map.apply_jt_df_rows(selected);
        for (std::size_t j = 0; j < expected.size(); ++j)
            for (int c = 0; c < 3; ++c)
                EXPECT_TRUE(same_bits(in.df[j][c], expected[j][c])) << "trial " << trial << " input " << j << "." << c;
    }
    // It reads the inputs of its entries, and only those.
    std::vector<std::uint32_t> listed;
    ASSERT_TRUE(map.list_inputs_read(listed));
    std::vector<std::uint8_t> read(in.num_dofs(), 0);
    for (const std::uint32_t j : listed) {
        ASSERT_LT(j, read.size());
        read[j] = 1;
    }
    for (std::size_t j = 0; j < read.size(); ++j) {
        bool used = false;
        for (const BarycentricRow& r : rows)
            for (const auto& e : r) used = used || static_cast<std::size_t>(e.index) == j;
        EXPECT_EQ(read[j] != 0, used) << j;
    }
}

TEST(Mapping, BarycentricOnHexahedraIsTrilinear) {
    Vec3Object in, out;
    // A distorted hexahedron (not a parallelepiped).
    in.position = {Vec3(0, 0, 0), Vec3(1, 0, 0),   Vec3(1.2, 1, 0), Vec3(0, 1, 0.1),
                   Vec3(0, 0, 1), Vec3(1, 0.1, 1), Vec3(1, 1, 1.3), Vec3(-0.1, 1, 1)};
    in.init();
    MeshTopology topo;
    topo.set_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}});
    BarycentricMapping map(in, out);
    std::vector<Vec3> pts;
    std::vector<Vec3> uvw = {Vec3(0.3, 0.6, 0.2), Vec3(0.9, 0.1, 0.5)};
    for (const Vec3& u : uvw) {
        const auto w = trilinear_weights(u);
        Vec3 p = Vec3::Zero();
        for (int k = 0; k < 8; ++k) p += w[static_cast<std::size_t>(k)] * in.position[static_cast<std::size_t>(k)];
        pts.push_back(p);
    }
    map.map_on_hexahedra(topo, in.position, pts);
    check_mapping<Vec3Types>(map, in, out, [&](double h, Eigen::Index c) { perturb_vec3(in, h, c); });
    map.apply_position();
    for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_TRUE(out.position[i].isApprox(pts[i], 1e-12));
    const auto w0 = trilinear_weights(uvw[0]);
    for (int k = 0; k < 8; ++k)
        EXPECT_NEAR(map.weights()[0][static_cast<std::size_t>(k)].weight, w0[static_cast<std::size_t>(k)], 1e-12);
}

TEST(Mapping, BarycentricOnRegularGridAdjointAndFiniteDifferences) {
    // Points located in the cells of a 3 x 2 x 3 grid (one outside, clamped to the nearest
    // cell as SOFA does); the grid nodes are then moved off the grid so J is not trivially
    // the trilinear interpolation of a box.
    RegularGridTopology g({3, 2, 3}, Vec3(-1, 0, 0.5), Vec3(1, 0.8, 2.5));
    Vec3Object in, out;
    in.position = g.points();
    in.init();
    const std::vector<Vec3> pts = {Vec3(-0.7, 0.1, 0.6), Vec3(0.4, 0.5, 2.2), Vec3(0.0, 0.4, 1.5), Vec3(1.3, 0.2, 1.0)};
    BarycentricMapping map(in, out);
    map_on_regular_grid(map, g, pts);
    for (auto& x : in.position) x += 0.1 * rand_vec();
    check_mapping<Vec3Types>(map, in, out, [&](double h, Eigen::Index c) { perturb_vec3(in, h, c); });
    ASSERT_EQ(map.weights().size(), pts.size());
    // A point far outside the grid (cell index beyond int) takes the last cell, with
    // extrapolated weights that still reproduce it on the undeformed grid.
    BarycentricMapping far_map(in, out);
    const std::vector<Vec3> far = {Vec3(1e30, 0.4, 1.5)};
    map_on_regular_grid(far_map, g, far);
    EXPECT_EQ(far_map.weights()[0][0].index, g.point_index(1, 0, 1));
    Vec3 reproduced = Vec3::Zero();
    for (const auto& e : far_map.weights()[0]) reproduced += e.weight * g.points()[std::size_t(e.index)];
    EXPECT_TRUE(reproduced.isApprox(far[0], 1e-12)) << reproduced.transpose();
    for (const auto& w : map.weights()) {
        double sum = 0;
        for (const auto& e : w) sum += e.weight;
        EXPECT_NEAR(sum, 1.0, 1e-14);  // partition of unity: a translation of the grid moves every point
    }
}

TEST(Mapping, ChainedMappingsComposeJacobians) {
    // rigid frame -> surface points (RigidMapping) -> contact point (barycentric on a triangle).
    Rigid3Object frame;
    frame.position = {{Vec3(0.5, -0.2, 1.0), Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()))}};
    frame.init();
    Vec3Object surface, contact;
    RigidMapping rigid(frame, surface);
    rigid.set_points({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)});
    rigid.init();
    BarycentricMapping bary(surface, contact);
    bary.set_weights({{{0, 0.5}, {1, 0.25}, {2, 0.25}}});
    bary.init();
    // J_total = J_bary J_rigid via apply_dx; adjoint through the chain.
    Eigen::VectorXd dx = Eigen::VectorXd::NullaryExpr(6, [] { return uni(); });
    frame.dx_flat() = dx;
    rigid.apply_dx();
    bary.apply_dx();
    const Eigen::VectorXd jdx = contact.dx_flat();
    const Eigen::VectorXd y = Eigen::VectorXd::NullaryExpr(3, [] { return uni(); });
    contact.df_flat() = y;
    surface.df_flat().setZero();
    frame.df_flat().setZero();
    bary.apply_jt_df();
    rigid.apply_jt_df();
    EXPECT_NEAR(jdx.dot(y), dx.dot(frame.df_flat()), 1e-12);
    // FD of the composed apply.
    const double h = 1e-6;
    for (int c = 0; c < 6; ++c) {
        Eigen::VectorXd e = Eigen::VectorXd::Zero(6);
        e[c] = 1;
        frame.dx_flat() = e;
        rigid.apply_dx();
        bary.apply_dx();
        const Vec3 col = contact.dx[0];
        perturb_rigid(frame, h, c);
        rigid.apply_position();
        bary.apply_position();
        const Vec3 xp = contact.position[0];
        perturb_rigid(frame, -2 * h, c);
        rigid.apply_position();
        bary.apply_position();
        const Vec3 xm = contact.position[0];
        perturb_rigid(frame, h, c);
        rigid.apply_position();
        bary.apply_position();
        EXPECT_TRUE(test::near_relative(col, Vec3((xp - xm) / (2 * h)), 1e-7)) << c;
    }
}

TEST(Mapping, BadInputThrows) {
    Vec3Object in, out;
    in.position = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitX() + Vec3::UnitY()};
    in.init();
    BarycentricMapping map(in, out);
    map.set_weights({{{7, 1.0}}});
    EXPECT_THROW(map.init(), std::invalid_argument);
    EXPECT_THROW(map.set_weights({{{-1, 1.0}}}), std::invalid_argument);
    EXPECT_THROW(map.set_weights({{{0, std::numeric_limits<double>::quiet_NaN()}}}), std::invalid_argument);
    MeshTopology flat;
    flat.set_tetrahedra({{0, 1, 2, 3}});  // coplanar: degenerate
    EXPECT_THROW(map.map_on_tetrahedra(flat, in.position, std::vector<Vec3>{Vec3::Zero()}), std::invalid_argument);
    // a point SOFA's search cannot place (its starting squared distance is 1e10): NaN, or 1e5 or
    // farther from every centre, is an error, not a row on no tetrahedron
    const std::vector<Vec3> corners = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
    MeshTopology unit;
    unit.set_tetrahedra({{0, 1, 2, 3}});
    EXPECT_THROW(
        map.map_on_tetrahedra(unit, corners, std::vector<Vec3>{Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0)}),
        std::invalid_argument);
    EXPECT_THROW(map.map_on_tetrahedra(unit, corners, std::vector<Vec3>{Vec3(2e5, 0, 0)}), std::invalid_argument);
    map.map_on_tetrahedra(unit, corners, std::vector<Vec3>{Vec3(9e4, 0, 0)});  // within reach: mapped
    EXPECT_EQ(map.weights()[0][1].index, 1);
}

}  // namespace
}  // namespace penalty
