#pragma once
// A beam of twelve tetrahedra under TetrahedronFEMForceField, its x = 0 end fixed, sagging under
// gravity: the scene of the tests that compare the field's methods with SOFA HEAD's states
// (tests/scene/test_fem.cpp, test_corotational_fem.cpp, test_tetrahedron_plasticity.cpp).
#include "penalty/core/types.hpp"

#include <string>
#include <vector>

namespace penalty::test {

/// The beam [0,1]×[0,0.5]×[0,0.5]: 3×2×2 points, two cubes of six tetrahedra; `fem` the extra
/// attributes of its force field `component` (E = 2000 Pa, ν = 0.3).
inline std::string twelve_tetrahedra_beam(const std::string& fem,
                                          const std::string& component = "TetrahedronFEMForceField") {
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <Node name="Beam">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="100" tolerance="1e-12" threshold="1e-12"/>
    <MeshTopology name="topo" position="0 0 0 0.5 0 0 1 0 0 0 0.5 0 0.5 0.5 0 1 0.5 0 0 0 0.5 0.5 0 0.5 1 0 0.5 0 0.5 0.5 0.5 0.5 0.5 1 0.5 0.5" tetrahedra="0 1 4 10 0 1 7 10 0 3 4 10 0 3 9 10 0 6 7 10 0 6 9 10 1 2 5 11 1 2 8 11 1 4 5 11 1 4 10 11 1 7 8 11 1 7 10 11"/>
    <MechanicalObject name="dofs"/>
    <UniformMass totalMass="2"/>
    <)" + component +
           R"( youngModulus="2000" poissonRatio="0.3" )" + fem + R"(/>
    <FixedProjectiveConstraint indices="0 3 6 9"/>
  </Node>
</Node>)";
}

/// SOFA HEAD's positions of the beam (2a278d8, `sofa-head SCENE 100 OUT --every 50`, %.17g)
/// after 50 and 100 steps under method polar: TetrahedronFEMForceField's and
/// TetrahedralCorotationalFEMForceField's are the same.
inline const std::vector<Vec3> kSofaHeadPolarBeam50 = {
    Vec3(0, 0, 0),
    Vec3(0.48297019809461, -0.060729191307034316, 0.0097158718428789967),
    Vec3(0.97587195330520604, -0.12335211229967505, 0.024937528816984991),
    Vec3(0, 0.5, 0),
    Vec3(0.52331664429513369, 0.44107605106030995, 0.0073581585869252654),
    Vec3(1.0238169665407055, 0.37659679877609054, 0.021045540114927808),
    Vec3(0, 0, 0.5),
    Vec3(0.47007115821655238, -0.057807141073933505, 0.50807066160704073),
    Vec3(0.95880694102799524, -0.11921175827801488, 0.52268082174430475),
    Vec3(0, 0.5, 0.5),
    Vec3(0.51167896670278135, 0.44755426169061291, 0.50458857159587511),
    Vec3(1.0100544681881598, 0.3832724693822126, 0.51925774903057453)};
inline const std::vector<Vec3> kSofaHeadPolarBeam100 = {
    Vec3(0, 0, 0),
    Vec3(0.48422183050026796, -0.056017255859617844, 0.0071862186326625685),
    Vec3(0.97812207042451693, -0.11254733664732108, 0.018866753130246779),
    Vec3(0, 0.5, 0),
    Vec3(0.52064002301689849, 0.44578742019741463, 0.0051013874687962464),
    Vec3(1.0210320262050623, 0.38751294077556808, 0.015447566766778716),
    Vec3(0, 0, 0.5),
    Vec3(0.47364322705342554, -0.053668032720560192, 0.50582723264444851),
    Vec3(0.96416973512196502, -0.1092622810060357, 0.51701532417618901),
    Vec3(0, 0.5, 0.5),
    Vec3(0.51128081854104024, 0.45140179224892812, 0.50282606970905386),
    Vec3(1.0102104173722608, 0.39314917530165738, 0.5141139731416049)};

/// SOFA HEAD's positions of the beam after 100 steps under method small (the same for both
/// fields).
inline const std::vector<Vec3> kSofaHeadSmallBeam100 = {
    Vec3(0, 0, 0),
    Vec3(0.48635881993514429, -0.05590999153962424, 0.0070228248685422247),
    Vec3(0.98299023978026956, -0.11209727961967879, 0.018546035390200864),
    Vec3(0, 0.5, 0),
    Vec3(0.52173296262498559, 0.44760234400387372, 0.0043182600537491822),
    Vec3(1.0247328987147111, 0.39001962413250812, 0.014356779954546312),
    Vec3(0, 0, 0.5),
    Vec3(0.47582716283267185, -0.053762933962119772, 0.50596490097027236),
    Vec3(0.96881353075971632, -0.10930947952996005, 0.51703828920492989),
    Vec3(0, 0.5, 0.5),
    Vec3(0.51227120130816417, 0.45305719485749207, 0.50231347898594236),
    Vec3(1.0138418631403046, 0.39545919192024998, 0.51329879773856668)};

}  // namespace penalty::test
