// Contact mappers: J against finite differences of the mapped positions (including rigid
// rotations), Jᵀ consistency (virtual work), velocities = J·v, partition of unity; contact-level
// forces = −∇E by finite differences (rigid torques included); momentum balance of two free bodies.
#include "penalty/response/barycentric_penalty_contact.hpp"

#include "../collision/fixtures.hpp"

#include <gtest/gtest.h>

#include <concepts>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

namespace penalty {
namespace {

using test::named;
using test::rand_quat;
using test::rand_unit;
using test::rand_vec;

// The response's index boundaries (core/index_types.hpp): a mapper takes an element and gives a
// DOF, and a penalty contact is made of two DOFs and two elements, in that order; an integer, or
// one kind where the other is expected, does not compile.
template <class Element>
concept MapsElement = requires(ContactMapper& mapper, const Vec3& P, Element e, double& r) {
    { mapper.add_point(P, e, r) } -> std::same_as<DofIndex>;
};
static_assert(MapsElement<ElementIndex>);
static_assert(!MapsElement<DofIndex> && !MapsElement<Index> && !MapsElement<int>);
template <class Dof, class Element>
concept MakesContact = requires(PenaltyForceField& field, Dof m, Element e, const Vec3& n) {
    field.add_contact(m, m, e, e, n, 1.0, 1.0);
};
static_assert(MakesContact<DofIndex, ElementIndex>);
static_assert(!MakesContact<ElementIndex, DofIndex> && !MakesContact<ElementIndex, ElementIndex>);
static_assert(!MakesContact<DofIndex, DofIndex> && !MakesContact<Index, Index>);
static_assert(std::is_same_v<decltype(DetectionOutput::elem1), ElementIndex>);
static_assert(std::is_same_v<decltype(DetectionOutput::elem2), ElementIndex>);

/// A Vec3 object with a triangle, a quad and a tetrahedron, and a Rigid3 object with 3 bodies.
struct Scene {
    Vec3State soft;
    MeshTopology topo;
    Rigid3State rigid;
    std::unique_ptr<PointModel> points;
    std::unique_ptr<SphereModel> spheres;
    std::unique_ptr<LineModel> lines;
    std::unique_ptr<TriangleModel> triangles;
    std::unique_ptr<TetrahedronModel> tetras;
    std::unique_ptr<RigidSphereModel> rigid_spheres;
    std::unique_ptr<CylinderModel> cylinders;

    explicit Scene(std::mt19937& g) {
        soft.resize(8);
        for (auto& p : soft.position) p = rand_vec(g, 1.0);
        // a non-degenerate tetrahedron 0..3 and a near-planar quad 4..7
        soft.position[0] = Vec3(0, 0, 0) + rand_vec(g, 0.1);
        soft.position[1] = Vec3(1, 0, 0) + rand_vec(g, 0.1);
        soft.position[2] = Vec3(0, 1, 0) + rand_vec(g, 0.1);
        soft.position[3] = Vec3(0, 0, 1) + rand_vec(g, 0.1);
        soft.position[4] = Vec3(2, 0, 0) + rand_vec(g, 0.05);
        soft.position[5] = Vec3(3, 0, 0) + rand_vec(g, 0.05);
        soft.position[6] = Vec3(3, 1, 0) + rand_vec(g, 0.05);
        soft.position[7] = Vec3(2, 1, 0) + rand_vec(g, 0.05);
        for (auto& v : soft.velocity) v = rand_vec(g, 1.0);
        topo.set_num_points(8);
        topo.set_triangles({{0, 1, 2}, {1, 3, 2}});
        topo.set_quads({{4, 5, 6, 7}});
        topo.set_tetrahedra({{0, 1, 2, 3}});
        rigid.resize(3);
        for (auto& f : rigid.position) f = RigidFrame{rand_vec(g, 2.0), rand_quat(g)};
        for (auto& v : rigid.velocity) v = RigidDeriv{rand_vec(g, 1.0), rand_vec(g, 1.0)};
        points = std::make_unique<PointModel>(soft, &topo, named("points"));
        spheres = std::make_unique<SphereModel>(soft, 0.3, std::vector<double>{}, named("spheres"));
        lines = std::make_unique<LineModel>(soft, topo, named("lines"));
        triangles = std::make_unique<TriangleModel>(soft, topo, named("triangles"));
        tetras = std::make_unique<TetrahedronModel>(soft, topo, named("tetras"));
        rigid_spheres = std::make_unique<RigidSphereModel>(rigid, 0.4, std::vector<double>{}, named("rigid spheres"));
        cylinders = std::make_unique<CylinderModel>(rigid, 0.3, 1.0, Vec3::UnitY(), named("cylinders"));
        for (CollisionModel* m : models()) m->update();
    }
    std::vector<CollisionModel*> models() {
        return {points.get(), spheres.get(),       lines.get(),    triangles.get(),
                tetras.get(), rigid_spheres.get(), cylinders.get()};
    }
    bool is_rigid(const CollisionModel* m) const { return m == rigid_spheres.get() || m == cylinders.get(); }

    /// Parent state as a flat vector (positions are not flat for Rigid3, so perturb instead).
    void perturb(const CollisionModel* m, std::span<const double> dq, double eps) {
        if (is_rigid(m)) {
            for (std::size_t i = 0; i < rigid.size(); ++i) {
                const Vec3 dc(dq[6 * i], dq[6 * i + 1], dq[6 * i + 2]);
                const Vec3 dw(dq[6 * i + 3], dq[6 * i + 4], dq[6 * i + 5]);
                rigid.position[i].center += eps * dc;
                const double a = eps * dw.norm();
                if (a != 0.0)
                    rigid.position[i].orientation =
                        Quat(Eigen::AngleAxisd(a, dw.normalized())) * rigid.position[i].orientation;
            }
        } else {
            for (std::size_t i = 0; i < soft.size(); ++i)
                soft.position[i] += eps * Vec3(dq[3 * i], dq[3 * i + 1], dq[3 * i + 2]);
        }
    }
};

std::vector<double> random_flat(std::mt19937& g, std::size_t n) {
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<double> v(n);
    for (auto& x : v) x = u(g);
    return v;
}

/// A point near element e of model m (inside or slightly outside).
Vec3 point_near(Scene& s, const CollisionModel& m, Index e, std::mt19937& g) {
    switch (m.type()) {
        case ModelType::Line: {
            const auto& l = static_cast<const LineModel&>(m);
            std::uniform_real_distribution<double> t(-0.2, 1.2);
            return l.p1(e) + t(g) * (l.p2(e) - l.p1(e)) + rand_vec(g, 0.2);
        }
        case ModelType::Triangle: {
            const auto& t = static_cast<const TriangleModel&>(m);
            return (t.p(e, 0) + t.p(e, 1) + t.p(e, 2)) / 3.0 + rand_vec(g, 0.8);
        }
        case ModelType::Tetrahedron: {
            const auto& t = static_cast<const TetrahedronModel&>(m);
            return (t.p(e, 0) + t.p(e, 1) + t.p(e, 2) + t.p(e, 3)) / 4.0 + rand_vec(g, 0.5);
        }
        case ModelType::RigidSphere:
        case ModelType::Cylinder:
            return s.rigid.position[std::size_t(e)].center + rand_vec(g, 0.6);
        default:
            return s.soft.position[std::size_t(e)] + rand_vec(g, 0.3);
    }
}

TEST(ContactMapper, JacobianMatchesFiniteDifferencesAndAdjoint) {
    std::mt19937 g(20260806);
    int checked = 0, rigid_checked = 0;
    for (int trial = 0; trial < 40; ++trial) {
        Scene s(g);
        for (CollisionModel* m : s.models()) {
            auto mapper = make_contact_mapper(*m);
            const std::size_t n = 6;
            mapper->resize(n);
            std::uniform_int_distribution<Index> pick(0, Index(m->size()) - 1);
            for (std::size_t k = 0; k < n; ++k) {
                double r = 0.0;
                const Index e = pick(g);
                (void)mapper->add_point(point_near(s, *m, e, g), ElementIndex(e), r);
            }
            mapper->update();
            const auto dq = random_flat(g, mapper->parent_scalar_size());
            std::vector<Vec3> jdq(mapper->size());
            mapper->apply_j(dq, jdq);

            // velocities = J·v
            std::vector<double> v(mapper->parent_scalar_size());
            if (s.is_rigid(m)) {
                auto f = flat_span(std::as_const(s.rigid.velocity));
                v.assign(f.begin(), f.end());
            } else {
                auto f = flat_span(std::as_const(s.soft.velocity));
                v.assign(f.begin(), f.end());
            }
            std::vector<Vec3> jv(mapper->size());
            mapper->apply_j(v, jv);
            for (std::size_t i = 0; i < jv.size(); ++i)
                ASSERT_LT((jv[i] - mapper->velocities()[i]).norm(), 1e-12 * (1 + jv[i].norm()));

            // J = d(positions)/dq by central differences (weights / local points frozen)
            const double h = 1e-6;
            const auto x0_soft = s.soft.position;
            const auto x0_rigid = s.rigid.position;
            s.perturb(m, dq, h);
            mapper->update();
            const std::vector<Vec3> xp(mapper->positions().begin(), mapper->positions().end());
            s.soft.position = x0_soft;
            s.rigid.position = x0_rigid;
            s.perturb(m, dq, -h);
            mapper->update();
            const std::vector<Vec3> xm(mapper->positions().begin(), mapper->positions().end());
            s.soft.position = x0_soft;
            s.rigid.position = x0_rigid;
            mapper->update();
            for (std::size_t i = 0; i < jdq.size(); ++i) {
                const Vec3 fd = (xp[i] - xm[i]) / (2 * h);
                ASSERT_LT((fd - jdq[i]).norm(), 1e-6 * (1 + jdq[i].norm()))
                    << model_type_name(m->type()) << " point " << i;
            }

            // virtual work: F·(J dq) = (Jᵀ F)·dq
            std::vector<Vec3> F(mapper->size());
            for (auto& f : F) f = rand_vec(g, 10.0);
            std::vector<double> jtf(mapper->parent_scalar_size(), 0.0);
            mapper->apply_jt(F, jtf);
            double w_contact = 0, w_dofs = 0, scale = 0;
            for (std::size_t i = 0; i < F.size(); ++i) {
                w_contact += F[i].dot(jdq[i]);
                scale += F[i].norm() * jdq[i].norm();
            }
            for (std::size_t j = 0; j < dq.size(); ++j) w_dofs += jtf[j] * dq[j];
            ASSERT_GT(scale, 0.0);
            ASSERT_NEAR(w_contact, w_dofs, 1e-12 * scale) << model_type_name(m->type());

            // triplets = apply_j
            TripletList t;
            mapper->add_jacobian_triplets(t, 0, 0);
            SparseMatrix J(Eigen::Index(3 * mapper->size()), Eigen::Index(mapper->parent_scalar_size()));
            J.setFromTriplets(t.begin(), t.end());
            const Eigen::VectorXd jd = J * Eigen::Map<const Eigen::VectorXd>(dq.data(), Eigen::Index(dq.size()));
            for (std::size_t i = 0; i < jdq.size(); ++i)
                ASSERT_LT((jd.segment<3>(Eigen::Index(3 * i)) - jdq[i]).norm(), 1e-12 * (1 + jdq[i].norm()));

            // barycentric weights: partition of unity
            if (const auto* bm = dynamic_cast<const BarycentricContactMapper*>(mapper.get()))
                for (const auto& row : bm->rows()) {
                    double sum = 0;
                    for (const auto& entry : row) sum += entry.weight;
                    ASSERT_NEAR(sum, 1.0, 1e-12);
                }
            ++checked;
            if (s.is_rigid(m)) ++rigid_checked;
        }
    }
    EXPECT_EQ(checked, 40 * 7);
    EXPECT_EQ(rigid_checked, 40 * 2);
}

// A contact point must name an element of its model, and (except for Point and Sphere models,
// whose contact point is the element itself) be finite: the error names the mapper, the model,
// the element and, for a non-finite point, the point; a failed call adds no row.
TEST(ContactMapper, BadElementOrNonFinitePointNamesTheModelAndTheElement) {
    std::mt19937 g(20261127);
    Scene s(g);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    int identity = 0, barycentric = 0, rigid = 0;
    for (CollisionModel* m : s.models()) {
        auto mapper = make_contact_mapper(*m);
        mapper->resize(2);
        const std::string name = "'" + m->name() + "'";
        const auto message_of = [&](const Vec3& P, Index e) -> std::string {
            try {
                double r = 0.0;
                (void)mapper->add_point(P, ElementIndex(e), r);
            } catch (const std::invalid_argument& error) {
                return error.what();
            }
            return "no exception";
        };
        const Index size = Index(m->size());
        for (const Index e : {Index(-1), size, size + 7}) {
            const std::string message = message_of(point_near(s, *m, 0, g), e);
            EXPECT_NE(message.find(name), std::string::npos) << message;
            EXPECT_NE(message.find("element " + std::to_string(e) + " out of range [0, " + std::to_string(size) + ")"),
                      std::string::npos)
                << message;
        }
        const std::string nan_message = message_of(Vec3(0.5, nan, 0.0), 0);
        const bool point_is_the_element = m == s.points.get() || m == s.spheres.get();
        if (point_is_the_element) {
            EXPECT_EQ(nan_message, "no exception") << m->name();  // P is not read
            ++identity;
        } else {
            EXPECT_NE(nan_message.find(name + ", element 0: non-finite contact point P (0.5"), std::string::npos)
                << nan_message;
            EXPECT_EQ(mapper->size(), 0u) << m->name();  // nothing added by the failed calls
            ++(s.is_rigid(m) ? rigid : barycentric);
        }
    }
    EXPECT_EQ(identity, 2);
    EXPECT_EQ(barycentric, 3);
    EXPECT_EQ(rigid, 2);
}

TEST(ContactMapper, TriangleProjectionAndQuadBilinear) {
    const Vec3 p0(0, 0, 0), p1(1, 0, 0), p2(0, 1, 0);
    auto ab = triangle_contact_coordinates(p0, p1, p2, Vec3(0.25, 0.25, 3));
    EXPECT_DOUBLE_EQ(ab[0], 0.25);
    EXPECT_DOUBLE_EQ(ab[1], 0.25);
    ab = triangle_contact_coordinates(p0, p1, p2, Vec3(-1, -1, 0));  // vertex 0
    EXPECT_EQ(ab[0], 0.0);
    EXPECT_EQ(ab[1], 0.0);
    ab = triangle_contact_coordinates(p0, p1, p2, Vec3(0.5, -1, 0));  // edge 01
    EXPECT_DOUBLE_EQ(ab[0], 0.5);
    EXPECT_EQ(ab[1], 0.0);
    ab = triangle_contact_coordinates(p0, p1, p2, Vec3(1, 1, 0));  // edge 12 midpoint
    EXPECT_DOUBLE_EQ(ab[0], 0.5);
    EXPECT_DOUBLE_EQ(ab[1], 0.5);
    ab = triangle_contact_coordinates(p0, p1, p2, Vec3(3, -0.5, 0));  // beyond vertex 1
    EXPECT_EQ(ab[0], 1.0);
    EXPECT_EQ(ab[1], 0.0);
    const auto f = quad_contact_coordinates(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 4, 0), Vec3(0.5, 1, 7));
    EXPECT_DOUBLE_EQ(f[0], 0.25);
    EXPECT_DOUBLE_EQ(f[1], 0.25);
    const auto w = line_contact_weights(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(3, 1, 0));
    EXPECT_DOUBLE_EQ(w[0], -0.5);  // not clamped (SOFA)
    EXPECT_DOUBLE_EQ(w[1], 1.5);
}

// SOFA's BarycentricMapperMeshTopology::createPointInQuad inverts (a b a×b) by type::invertMatrix
// (cofactors divided by det) and takes fx, fy as rows 0, 1 of the inverse · (P − q0). With this
// quad, Eigen's inverse() (cofactors · (1/det)) gives fx and fy one and two ulps lower
// (0x1.a08b56bfbe9c6p-3, -0x1.c0836e2470ef5p-2): the values below pin SOFA's operations.
TEST(ContactMapper, QuadCoordinatesInSofasOperationOrder) {
    const Vec3 q0(0.69999999999999996, 0.59999999999999998, 0.29999999999999999);
    const Vec3 q1(1.7, 0.81000000000000005, 0.29999999999999999);
    const Vec3 q3(0.70999999999999996, 1.6000000000000001, 0.33999999999999997);
    const Vec3 P(0.90000000000000002, 0.20000000000000001, 0.40000000000000002);
    const auto f = quad_contact_coordinates(q0, q1, q3, P);
    EXPECT_EQ(f[0], 0x1.a08b56bfbe9c7p-3);
    EXPECT_EQ(f[1], -0x1.c0836e2470ef7p-2);
}

/// Energy of the contact's springs at the current parent state (frozen contact geometry).
double contact_energy(BarycentricPenaltyContact& c, std::size_t n1, std::size_t n2) {
    std::vector<double> f1(n1, 0.0), f2(n2, 0.0);
    c.add_force(f1, f2);
    return c.force_field().potential_energy();
}

TEST(BarycentricPenaltyContact, ParentForcesAreMinusEnergyGradientIncludingTorques) {
    std::mt19937 g(7);
    int active_total = 0, pairs = 0;
    for (int trial = 0; trial < 30; ++trial) {
        Scene s(g);
        const std::vector<std::pair<CollisionModel*, CollisionModel*>> combos = {
            {s.triangles.get(), s.rigid_spheres.get()},
            {s.cylinders.get(), s.triangles.get()},
            {s.tetras.get(), s.spheres.get()},
            {s.lines.get(), s.points.get()},
            {s.rigid_spheres.get(), s.rigid_spheres.get()},
            {s.cylinders.get(), s.spheres.get()}};
        for (const auto& combo : combos) {
            CollisionModel* const m1 = combo.first;  // (named variables: lambdas below capture them)
            CollisionModel* const m2 = combo.second;
            BarycentricPenaltyContact c(*m1, *m2, 0.5);
            DetectionOutputList out;
            std::uniform_int_distribution<Index> e1(0, Index(m1->size()) - 1), e2(0, Index(m2->size()) - 1);
            for (int k = 0; k < 5; ++k) {
                DetectionOutput o;
                o.elem1 = ElementIndex(e1(g));
                o.elem2 = ElementIndex(e2(g));
                o.id = k;
                o.point = {point_near(s, *m1, o.elem1.value(), g), point_near(s, *m2, o.elem2.value(), g)};
                o.normal = rand_unit(g);
                out.push_back(o);
            }
            c.set_detection_outputs(out);
            const std::size_t n1 = c.mapper1().parent_scalar_size(), n2 = c.mapper2().parent_scalar_size();
            const bool same = s.is_rigid(m1) == s.is_rigid(m2);  // one parent state for both sides
            std::vector<double> f1(n1, 0.0), f2(n2, 0.0);
            c.add_force(f1, f2);
            const std::size_t active = c.force_field().active_count();
            active_total += int(active);
            ++pairs;
            // combined generalized force per parent (same state: both sides add to one vector)
            const auto dq1 = random_flat(g, n1);
            const auto dq2 = same ? dq1 : random_flat(g, n2);
            double w_dofs = 0;
            for (std::size_t j = 0; j < n1; ++j) w_dofs += f1[j] * dq1[j];
            for (std::size_t j = 0; j < n2; ++j) w_dofs += f2[j] * dq2[j];
            // virtual work at the contact points
            std::vector<Vec3> j1(c.mapper1().size()), j2(c.mapper2().size());
            c.mapper1().apply_j(dq1, j1);
            c.mapper2().apply_j(dq2, j2);
            double w_contact = 0;
            for (std::size_t i = 0; i < j1.size(); ++i) w_contact += c.contact_forces1()[i].dot(j1[i]);
            for (std::size_t i = 0; i < j2.size(); ++i) w_contact += c.contact_forces2()[i].dot(j2[i]);
            ASSERT_NEAR(w_dofs, w_contact, 1e-10 * (1 + std::abs(w_dofs)));
            // −dE/dε along (dq1, dq2) by central differences
            const double h = 1e-6;
            const auto xs = s.soft.position;
            const auto xr = s.rigid.position;
            auto move = [&](double eps) {
                s.soft.position = xs;
                s.rigid.position = xr;
                s.perturb(m1, dq1, eps);
                if (!same) s.perturb(m2, dq2, eps);
            };
            move(h);
            const double ep = contact_energy(c, n1, n2);
            move(-h);
            const double em = contact_energy(c, n1, n2);
            move(0.0);
            (void)contact_energy(c, n1, n2);
            if (active == 0) continue;
            const double fd = -(ep - em) / (2 * h);
            ASSERT_NEAR(w_dofs, fd, 1e-5 * (1 + std::abs(fd)))
                << model_type_name(m1->type()) << "-" << model_type_name(m2->type());
        }
    }
    // hit-rate gate: random normals make about half of the springs active
    EXPECT_GT(active_total, pairs);  // > 1 active spring per pair on average (5 springs each)
}

TEST(BarycentricPenaltyContact, TwoFreeBodiesExchangeOppositeForces) {
    std::mt19937 g(42);
    auto mesh = test::octahedron(Vec3::Zero(), 1.0);
    mesh->state.velocity.assign(mesh->state.size(), Vec3::Zero());
    CollisionModelParams pt = named("octahedron");
    TriangleModel tri(mesh->state, mesh->topo, pt);
    int hits = 0;
    const int trials = 200;
    for (int trial = 0; trial < trials; ++trial) {
        Rigid3State body = test::make_rigid_state({RigidFrame{rand_unit(g) * 1.3, rand_quat(g)}});
        body.velocity.assign(1, RigidDeriv{});
        RigidSphereModel sph(body, 0.5, {}, named("ball"));
        const auto params = IntersectionParams::new_proximity();
        auto det = detect_model_pair(params, tri, sph);
        if (det.outputs.empty()) continue;
        ++hits;
        BarycentricPenaltyContact c(tri, sph, params.contact_distance);
        c.set_detection_outputs(det.outputs);
        std::vector<Vec3> f_mesh(mesh->state.size(), Vec3::Zero());
        std::vector<RigidDeriv> f_body(1);
        c.add_force(flat_span(f_mesh), flat_span(f_body));
        ASSERT_GT(c.force_field().active_count(), 0u);
        Vec3 total = f_body[0].linear;
        double scale = f_body[0].linear.norm();
        for (const auto& f : f_mesh) total += f;
        ASSERT_GT(scale, 0.0);
        ASSERT_LT(total.norm(), 1e-12 * scale);
    }
    EXPECT_GT(hits, trials / 2);  // the ball at distance 1.3 always reaches a face within A = 1
}

}  // namespace
}  // namespace penalty
