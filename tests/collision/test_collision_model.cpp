// The collision models' common part (collision/collision_model.cpp): element and model boxes with skins
// and radii, SOFA's canCollideWith rule, the validation of a model's input and of each step.
#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>

namespace penalty {
namespace {

using test::make_state;

TEST(Boxes, ElementAndModelBoxesIncludeSkinsAndRadii) {
    Vec3State s = make_state({{0, 0, 0}, {2, 1, 0}});
    CollisionModelParams p;
    p.contact_distance = 0.1;
    SphereModel sph(s, 0.5, {0.25}, p);
    const Aabb b0 = sph.element_box(0);
    EXPECT_NEAR((b0.min - Vec3::Constant(-0.35)).norm(), 0.0, 1e-15);
    const Aabb m = sph.model_box();
    EXPECT_NEAR((m.max - Vec3(2.6, 1.6, 0.6)).norm(), 0.0, 1e-15);
    Rigid3State rs = test::make_rigid_state({RigidFrame{Vec3(0, 0, 0), Quat::Identity()}});
    CylinderModel cyl(rs);  // r 0.5, h 2, axis y: box [-0.5,0.5]x[-1.5,1.5]x[-0.5,0.5], no skin
    const Aabb cb = cyl.element_box(0);
    EXPECT_NEAR((cb.min - Vec3(-0.5, -1.5, -0.5)).norm(), 0.0, 1e-15);
    EXPECT_NEAR((cb.max - Vec3(0.5, 1.5, 0.5)).norm(), 0.0, 1e-15);
    EXPECT_TRUE(b0.overlaps(cb));
    Aabb far;
    far.extend(Vec3(1.0, 0, 0));
    EXPECT_FALSE(b0.overlaps(far, 0.5));
    EXPECT_TRUE(b0.overlaps(far, 0.65));
}

// CollisionModel::element_row, the prefetch hint of evaluate_candidates: for the models with one
// element per DOF it is the row of the state's positions (base + i·stride is element i's
// centre); the others have none.
TEST(Boxes, ElementRowOfAModelWithOneElementPerDofIsItsPositions) {
    Vec3State s = make_state({{0, 0, 0}, {2, 1, 0}, {3, 0, 1}});
    const auto at = [](const CollisionModel::ElementRow& row, std::size_t i) {
        return static_cast<const void*>(row.base + i * row.stride);
    };
    const PointModel points(s);
    const SphereModel spheres(s, 0.5);
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(at(points.element_row(), i), static_cast<const void*>(&points.point(Index(i))));
        EXPECT_EQ(at(spheres.element_row(), i), static_cast<const void*>(&spheres.center(Index(i))));
    }
    Rigid3State rs = test::make_rigid_state(
        {RigidFrame{Vec3(0, 0, 0), Quat::Identity()}, RigidFrame{Vec3(1, 2, 3), Quat::Identity()}});
    const RigidSphereModel rigid(rs, 0.5);
    EXPECT_EQ(at(rigid.element_row(), 1), static_cast<const void*>(&rigid.center(Index(1))));
    EXPECT_EQ(rigid.element_row().stride, sizeof(RigidFrame));
    const CylinderModel cylinder(rs);
    EXPECT_EQ(cylinder.element_row().base, nullptr);
}

TEST(CanCollideWith, SofaRule) {
    Vec3State s = make_state({{0, 0, 0}});
    PointModel a(s), b(s);
    EXPECT_TRUE(can_collide_with(a, b));
    EXPECT_FALSE(can_collide_with(a, a));  // same node, selfCollision false
    a.params().self_collision = true;
    EXPECT_TRUE(can_collide_with(a, a));
    a.params().node = 3;
    b.params().node = 3;
    EXPECT_TRUE(can_collide_with(a, b));
    EXPECT_FALSE(can_collide_with(b, a));
    EXPECT_FALSE(keep_model_pair(a, b));  // needs both directions
    b.params().node = 4;
    a.params().group = {1, 2};
    b.params().group = {3};
    EXPECT_TRUE(keep_model_pair(a, b));
    b.params().group = {2, 5};
    EXPECT_FALSE(keep_model_pair(a, b));
    b.params().group = {};
    EXPECT_TRUE(keep_model_pair(a, b));
    a.params().simulated = false;
    b.params().simulated = false;
    EXPECT_FALSE(keep_model_pair(a, b));
    b.params().simulated = true;
    b.params().active = false;
    EXPECT_FALSE(keep_model_pair(a, b));
}

TEST(Validation, BadInputThrowsNamingModelElementAndParameter) {
    Vec3State s = make_state({{0, 0, 0}, {std::nan(""), 0, 0}});
    SphereModel sph(s, 1.0, {}, test::named("balls"));
    try {
        sph.validate();
        FAIL();
    } catch (const std::invalid_argument& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("balls"), std::string::npos) << m;
        EXPECT_NE(m.find("element 1"), std::string::npos) << m;
        EXPECT_NE(m.find("centre"), std::string::npos) << m;
    }
    Vec3State ok = make_state({{0, 0, 0}});
    SphereModel neg(ok, 1.0, {-0.5}, test::named("neg"));
    try {
        neg.validate();
        FAIL();
    } catch (const std::invalid_argument& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("neg"), std::string::npos) << m;
        EXPECT_NE(m.find("radius"), std::string::npos) << m;
        EXPECT_NE(m.find("element 0"), std::string::npos) << m;
    }
    CollisionModelParams p;
    p.contact_distance = -1;
    PointModel pm(ok, nullptr, p);
    EXPECT_THROW(pm.validate(), std::invalid_argument);
    auto ip = IntersectionParams::new_proximity();
    ip.alarm_distance = std::nan("");
    EXPECT_THROW(ip.validate(), std::invalid_argument);
    PointModel pm2(ok);
    EXPECT_THROW((void)detect_model_pair(ip, pm2, pm2), std::invalid_argument);
    // detection validates positions
    SphereModel other(ok, 1.0);
    EXPECT_THROW((void)detect_model_pair(IntersectionParams::new_proximity(), sph, other), std::invalid_argument);
    // bad topology index
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    Vec3State small = make_state({{0, 0, 0}});
    TriangleModel bad(small, mesh->topo, test::named("surf"));
    EXPECT_THROW(bad.validate(), std::invalid_argument);
}

// The per-step check (CollisionModel::validate_for_step) has validate()'s outcome: the same
// error for a position that became NaN/inf after a passing validate(), a full validate() again
// when the state changed size, and nothing when all is well. element_boxes() over a range gives
// element_box()'s doubles.
TEST(ModelValidation, StepCheckHasValidatesOutcomeAndRangeBoxesAreElementBoxes) {
    auto mesh = test::octahedron(Vec3(0.3, -0.2, 0.1), 1.5);
    CollisionModelParams params = test::named("surf");
    params.contact_distance = 0.125;
    TriangleModel tri(mesh->state, mesh->topo, params);
    LineModel lines(mesh->state, mesh->topo, params);
    PointModel points(mesh->state, &mesh->topo, params);
    const std::vector<const CollisionModel*> models{&tri, &lines, &points};
    auto message = [](auto&& f) {
        try {
            f();
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    int errors = 0;
    for (const CollisionModel* m : models) {
        EXPECT_EQ(message([&] { m->validate_for_step(); }), "");  // first call: the full validate()
        EXPECT_EQ(message([&] { m->validate_for_step(); }), "");  // then the quick one
        std::vector<Aabb> boxes(m->size());
        m->element_boxes(0, m->size(), boxes.data());
        for (std::size_t i = 0; i < m->size(); ++i) {
            const Aabb one = m->element_box(Index(i));
            EXPECT_EQ(boxes[i].min, one.min);
            EXPECT_EQ(boxes[i].max, one.max);
        }
        for (const double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
            for (std::size_t v = 0; v < mesh->state.size(); ++v) {
                for (int c = 0; c < 3; ++c) {
                    const double keep = mesh->state.position[v][c];
                    mesh->state.position[v][c] = bad;
                    const std::string full = message([&] { m->validate(); });
                    const std::string quick = message([&] { m->validate_for_step(); });
                    mesh->state.position[v][c] = keep;
                    EXPECT_FALSE(full.empty());
                    EXPECT_EQ(quick, full);
                    errors += !quick.empty();
                    EXPECT_EQ(message([&] { m->validate_for_step(); }), "");
                }
            }
        }
        // a parameter made invalid between steps is still caught
        const_cast<CollisionModel*>(m)->params().contact_distance = -1.0;
        EXPECT_NE(message([&] { m->validate_for_step(); }).find("contactDistance"), std::string::npos);
        const_cast<CollisionModel*>(m)->params().contact_distance = 0.125;
    }
    EXPECT_EQ(errors, 3 * 2 * 6 * 3);
    // the state shrinks under the models: validate()'s index error again, not a stale pass
    mesh->state.position.pop_back();
    EXPECT_NE(message([&] { tri.validate_for_step(); }).find("out of range"), std::string::npos);
    EXPECT_NE(message([&] { lines.validate_for_step(); }).find("out of range"), std::string::npos);
}

}  // namespace
}  // namespace penalty
