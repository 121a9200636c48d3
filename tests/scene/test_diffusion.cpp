// Diffusion of a scalar over tetrahedra (builder/diffusion.cpp): TetrahedronDiffusionFEMForceField
// on a Vec1d temperature measured on the tagged Vec3d geometry, with MeshMatrixMass<Vec1d,Vec3d>
// under a first-order implicit Euler: a bar of 3×1×1 cubes (Hexa2TetraTopologicalMapping), one end
// point held at 1. Its temperatures are SOFA HEAD's (2a278d8, SofaPython3's diffusion_bar.py,
// tests/python/scripts/diffusion_bar_sofa_head.json), bit for bit at steps 1 and 10; a zero
// coefficient diffuses nothing; the refusals name file, line, component and attribute.
#include "penalty/scene/live_data.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

using namespace penalty;

/// The bar with `diffusion` (the TetrahedronDiffusionFEMForceField's attributes) and `tags` on
/// its geometry.
std::string diffusion_bar(const std::string& diffusion, const std::string& tags = "3dgeometry") {
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <RegularGridTopology name="grid" nx="4" ny="2" nz="2" xmin="0" xmax="1" ymin="0" ymax="0.2" zmin="0" zmax="0.2"/>
  <Node name="Bar">
    <TetrahedronSetTopologyContainer name="tets"/>
    <TetrahedronSetTopologyModifier/>
    <Hexa2TetraTopologicalMapping input="@../grid" output="@tets"/>
    <MechanicalObject name="geometry" position="@../grid.position" tags=")" +
           tags + R"("/>
    <Node name="Heat">
      <EulerImplicitSolver firstOrder="1"/>
      <CGLinearSolver iterations="200" tolerance="1e-12" threshold="1e-30"/>
      <MechanicalObject name="T" template="Vec1d" size="16" position="1 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0"/>
      <MeshMatrixMass template="Vec1d,Vec3d" massDensity="1" topology="@../tets" geometryState="@../geometry"/>
      <FixedProjectiveConstraint indices="0"/>
      <TetrahedronDiffusionFEMForceField template="Vec1d" topology="@../tets" )" +
           diffusion + R"(/>
    </Node>
  </Node>
</Node>)";
}

const std::string kSofaBar = R"(constantDiffusionCoefficient="0.05" tagMechanics="3dgeometry")";

std::vector<double> bar_temperatures(scene::Scene& s) {
    return dynamic_cast<const Vec1Object&>(*s.data({"/Bar/Heat/T", false}, "position").state).position;
}

TEST(Diffusion, ABarsTemperaturesAreSofaHeadsBitForBit) {
    auto s = test::build(diffusion_bar(kSofaBar));
    s->step();
    EXPECT_EQ(bar_temperatures(*s),
              (std::vector<double>{1.0, 0.024328103431548495, -0.0017637234116910858, -8.419407335895364e-05,
                                   0.11864523982221287, -0.007093651736579427, 0.0009744261016493777,
                                   -0.0004709998276023962, 0.0833917419536961, 0.020709999493878636,
                                   0.004517914123168634, 8.023321340742758e-05, 0.020225709922476742,
                                   -0.05623529483212058, -0.00018990339459508483, 0.0005284097942407192}));
    for (int k = 1; k < 10; ++k) s->step();
    EXPECT_EQ(
        bar_temperatures(*s),
        (std::vector<double>{1.0, 0.07788589070108351, 0.011473126225013, 0.0020620125266712667, 0.5416982683755757,
                             -0.002169155627664271, -0.0012232411816418222, -2.1934084955544373e-05,
                             0.43110747285879425, 0.02735167951794296, 0.02308314343933745, 0.006236352225280977,
                             0.2538308728982052, -0.15461845902486623, -0.02934314347015224, -0.0052159893401536985}));
}

TEST(Diffusion, AZeroCoefficientDiffusesNothing) {
    auto s = test::build(diffusion_bar(R"(constantDiffusionCoefficient="0" tagMechanics="3dgeometry")"));
    for (int k = 0; k < 5; ++k) s->step();
    std::vector<double> expected(16, 0.0);
    expected[0] = 1.0;
    EXPECT_EQ(bar_temperatures(*s), expected);
}

TEST(Diffusion, TheGeometryIsFoundByItsTag) {
    EXPECT_EQ(test::error_of(diffusion_bar(kSofaBar, "other")),
              "test.scn:15: TetrahedronDiffusionFEMForceField: attribute 'tagMechanics': no Vec3d MechanicalObject "
              "tagged '3dgeometry' in this node or above (its positions measure the tetrahedra)");
    // the default tag is "meca"
    EXPECT_EQ(test::error_of(diffusion_bar(R"(constantDiffusionCoefficient="0.05")")),
              "test.scn:15: TetrahedronDiffusionFEMForceField: attribute 'tagMechanics': no Vec3d MechanicalObject "
              "tagged 'meca' in this node or above (its positions measure the tetrahedra)");
    auto meca = test::build(diffusion_bar(R"(constantDiffusionCoefficient="0.05")", "meca"));
    meca->step();
    EXPECT_EQ(bar_temperatures(*meca),
              (std::vector<double>{1.0, 0.024328103431548495, -0.0017637234116910858, -8.419407335895364e-05,
                                   0.11864523982221287, -0.007093651736579427, 0.0009744261016493777,
                                   -0.0004709998276023962, 0.0833917419536961, 0.020709999493878636,
                                   0.004517914123168634, 8.023321340742758e-05, 0.020225709922476742,
                                   -0.05623529483212058, -0.00018990339459508483, 0.0005284097942407192}));
}

}  // namespace
