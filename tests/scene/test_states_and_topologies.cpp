// States and topologies of the scene builder (scene/builder/states_and_topologies.cpp):
// MechanicalObject (long and short transform forms, the short ones read as floats, positions
// from a topology, one velocity for all), RegularGridTopology (n, nx ny nz, the six float bounds)
// and MeshTopology: the states at init are SOFA HEAD's (2a278d8, `sofa-head SCENE 1 OUT`, T = 0,
// %.17g), bit for bit, and after one step the one velocity moved every point. Vec1d and Rigid3d
// states, the `penalty info` lines, the notes, and the refusals naming the file, line,
// component and attribute.
#include "builder_scenes.hpp"

#include "penalty/mechanics/state.hpp"

namespace {

using namespace penalty::test_builder_scenes;
using ::testing::ElementsAre;

/// `body` in a node A with a solver (line 5 onwards: the state's line when it comes first).
std::string solved_node(const std::string& body) {
    return "<Node name=\"root\" dt=\"0.01\" gravity=\"0 0 0\">\n<Node name=\"A\">\n<EulerImplicitSolver/>\n"
           "<CGLinearSolver iterations=\"10\" tolerance=\"1e-12\" threshold=\"1e-12\"/>\n" +
           body + "\n</Node>\n</Node>\n";
}

const std::vector<Vec3>& state_points(const scene::Scene& s, std::size_t index = 0) {
    return dynamic_cast<const Vec3Object&>(*s.states().at(index).state).position;
}

TEST(StatesAndTopologies, InitialStatesAreSofaHeads) {
    // long forms in double: scale, then rotation (z by 90°), then translation
    const auto a = build(solved_node(
        R"(<MechanicalObject name="a" position="1 0 0  0 1 0" rotation="0 0 90" translation="1 2 3" scale3d="2 2 2"/>)"));
    EXPECT_THAT(state_points(*a), ElementsAre(Vec3(1.0000000000000004, 4, 3), Vec3(-1, 2.0000000000000004, 3)));
    // short forms read as floats (0.7 is 0.69999998807907104)
    const auto b =
        build(solved_node(R"(<MechanicalObject name="b" position="1 0 0  0 1 0" dx="0.7" ry="30" scale="1.5"/>)"));
    EXPECT_THAT(state_points(*b), ElementsAre(Vec3(1.9990380937557291, 0, -0.75), Vec3(0.69999998807907104, 1.5, 0)));
    // a grid's points, x fastest
    const auto c = build(solved_node(R"(<RegularGridTopology n="3 2 2" min="0 0 0" max="1 1 1"/>
<MechanicalObject name="c"/>)"));
    EXPECT_THAT(state_points(*c), ElementsAre(Vec3(0, 0, 0), Vec3(0.5, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0),
                                              Vec3(0.5, 1, 0), Vec3(1, 1, 0), Vec3(0, 0, 1), Vec3(0.5, 0, 1),
                                              Vec3(1, 0, 1), Vec3(0, 1, 1), Vec3(0.5, 1, 1), Vec3(1, 1, 1)));
    // nx ny nz and the six bounds, read as floats
    const auto d = build(solved_node(
        R"(<RegularGridTopology nx="2" ny="2" nz="2" xmin="0" ymin="0" zmin="0" xmax="0.7" ymax="1" zmax="1.3"/>
<MechanicalObject name="d"/>)"));
    const double x7 = 0.69999998807907104, z13 = 1.2999999523162842;
    EXPECT_THAT(state_points(*d), ElementsAre(Vec3(0, 0, 0), Vec3(x7, 0, 0), Vec3(0, 1, 0), Vec3(x7, 1, 0),
                                              Vec3(0, 0, z13), Vec3(x7, 0, z13), Vec3(0, 1, z13), Vec3(x7, 1, z13)));
    // one position gives way to the topology's points; the one velocity is every point's
    const auto e = build(solved_node(R"(<MeshTopology position="0 0 0  1 0 0  0 1 0" triangles="0 1 2"/>
<MechanicalObject name="e" position="5 5 5" velocity="1 0 0"/>
<UniformMass totalMass="3"/>)"));
    EXPECT_THAT(state_points(*e), ElementsAre(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)));
    e->step();
    EXPECT_THAT(state_points(*e), ElementsAre(Vec3(0.01, 0, 0), Vec3(1.01, 0, 0), Vec3(0.01, 1, 0)));
}

TEST(StatesAndTopologies, ShortFormsInDoubleWithTheQuirkFix) {
    scene::BuildOptions o;
    ASSERT_TRUE(enable_sofa_quirk_fix(o.sofa_quirk_fixes, "mechanical_object_float_short_forms"));
    const auto b = build(solved_node(R"(<MechanicalObject position="1 0 0" dx="0.7"/>)"), o);
    EXPECT_THAT(state_points(*b), ElementsAre(Vec3(1.7, 0, 0)));
    const auto big = build(solved_node(R"(<MechanicalObject position="0 0 0" dx="1e40"/>)"), o);
    EXPECT_THAT(state_points(*big), ElementsAre(Vec3(1e40, 0, 0)));
    EXPECT_EQ(error_of(solved_node(R"(<MechanicalObject position="0 0 0" dx="1e40"/>)")),
              "test.scn:5: MechanicalObject: attribute 'dx': '1e40' is beyond float range, and SOFA reads this "
              "attribute as a float (--fix-sofa-quirk mechanical_object_float_short_forms reads it in double)");
    ASSERT_TRUE(enable_sofa_quirk_fix(o.sofa_quirk_fixes, "regular_grid_float_bounds"));
    const auto d = build(
        solved_node(
            R"(<RegularGridTopology nx="2" ny="1" nz="1" xmin="0" ymin="0" zmin="0" xmax="0.7" ymax="0" zmax="0" scale="2"/>
<MechanicalObject/>)"),
        o);
    EXPECT_THAT(state_points(*d), ElementsAre(Vec3(0, 0, 0), Vec3(1.4, 0, 0)));
}

// SOFA HEAD (sofa-head on scenes/sphere_pairs.scn, which had src="@loader" under a SphereLoader
// with translation="-1 0 0": its bed at x = -2.2, not -1.2): BaseComponent::setSrc links the
// loader's auto-linked Data into the state's of the same name or alias it does not set, and a
// SphereLoader's translation, rotation and scale (scale3d) are auto-linked, so the state moves
// the loaded points again. A state's own transform stays; the fix keeps the loader's alone.
TEST(StatesAndTopologies, SrcOnASphereLoaderTakesItsTransformAsSofaHead) {
    const std::filesystem::path dir = temp_dir("sphere_loader_src");
    std::filesystem::create_directories(dir);
    {
        std::ofstream out(dir / "two.sph");
        out << "sph 1.0\nnums 2\nsphe 1 0.5 0 0 0.1\nsphe 2 1 0 0 0.1\n";
    }
    const std::string loader = "<SphereLoader name=\"loader\" filename=\"" + (dir / "two.sph").string() +
                               "\" translation=\"-1 0 0\" scale=\"2 2 2\"/>\n";
    // the loader: 2x − 1; the state again: 2(2x − 1) − 1
    const auto twice = build(solved_node(loader + R"(<MechanicalObject src="@loader"/>)"));
    EXPECT_THAT(state_points(*twice), ElementsAre(Vec3(-1, 0, 0), Vec3(1, 0, 0)));
    const auto own = build(solved_node(loader + R"(<MechanicalObject src="@loader" translation="0 1 0"/>)"));
    EXPECT_THAT(state_points(*own), ElementsAre(Vec3(0, 1, 0), Vec3(2, 1, 0)));  // scale 2, its own translation
    const auto linked = build(solved_node(loader + R"(<MechanicalObject position="@loader.position"/>)"));
    EXPECT_THAT(state_points(*linked), ElementsAre(Vec3(0, 0, 0), Vec3(1, 0, 0)));
    scene::BuildOptions o;
    ASSERT_TRUE(enable_sofa_quirk_fix(o.sofa_quirk_fixes, "sphere_loader_src_transform"));
    const auto fixed = build(solved_node(loader + R"(<MechanicalObject src="@loader"/>)"), o);
    EXPECT_THAT(state_points(*fixed), ElementsAre(Vec3(0, 0, 0), Vec3(1, 0, 0)));
    std::filesystem::remove_all(dir);
}

TEST(StatesAndTopologies, AShortFormThatIsNotOneNumberIsItsDefaultWithANote) {
    const auto s = build(solved_node(R"(<MechanicalObject position="1 0 0  2 0 0" dx="0.1 0.2" dy="3"/>)"));
    EXPECT_THAT(state_points(*s), ElementsAre(Vec3(1, 3, 0), Vec3(2, 3, 0)));
    EXPECT_THAT(s->warnings(), testing::Contains("test.scn:5: MechanicalObject: dx '0.1 0.2' is not one number: 0 "
                                                 "used (SOFA's MechanicalObject::parse reads it so, with an error "
                                                 "message)"));
}

TEST(StatesAndTopologies, SizeGivesZerosAndIsBounded) {
    const auto s = build(solved_node(R"(<MechanicalObject size="4"/>)"));
    EXPECT_EQ(state_points(*s), std::vector<Vec3>(4, Vec3::Zero()));
    const auto one = build(solved_node(R"(<MechanicalObject/>)"));
    EXPECT_EQ(state_points(*one).size(), 1u);  // SOFA's default size
    EXPECT_EQ(error_of(solved_node(R"(<MechanicalObject size="-1"/>)")),
              "test.scn:5: MechanicalObject: attribute 'size': must be between 0 and 10000000");
    scene::BuildOptions small;
    small.max_dofs = 10;
    try {
        (void)build(solved_node(R"(<RegularGridTopology n="3 3 3"/><MechanicalObject/>)"), small);
        ADD_FAILURE() << "no error";
    } catch (const io::SceneError& e) {
        EXPECT_STREQ(e.what(), "test.scn:5: RegularGridTopology: 27 grid points (more than 10)");
    }
}

TEST(StatesAndTopologies, Vec1AndRigidStates) {
    const auto v = build(solved_node(R"(<MechanicalObject template="Vec1d" name="lengths" position="1 2 3"/>)"));
    const auto& lengths = dynamic_cast<const Vec1Object&>(*v->simulation().root().children()[0]->state());
    EXPECT_THAT(lengths.position, ElementsAre(1.0, 2.0, 3.0));
    EXPECT_EQ(v->role(*v->file().root->children[0]->components[2]), "Vec1d state, 3 DOFs");
    const auto sized = build(solved_node(R"(<MechanicalObject template="Vec1d" size="2"/>)"));
    EXPECT_EQ(sized->simulation().root().children()[0]->state()->num_dofs(), 2u);
    EXPECT_EQ(error_of(solved_node(R"(<MechanicalObject name="m" position="1 2 3"/>
<Node name="B"><MechanicalObject template="Vec1d" position="@../m.position"/></Node>)")),
              "test.scn:6: MechanicalObject: attribute 'position': a Vec1d state takes numbers, not a link");
    // a Rigid3d state without positions: its topology's points as the frames' centres
    const auto r = build(solved_node(R"(<MeshTopology position="0 0 0  1 2 3"/>
<MechanicalObject template="Rigid3d" velocity="1 0 0 0 0 1"/>)"));
    const auto& frames = dynamic_cast<const Rigid3Object&>(*r->simulation().root().children()[0]->state());
    ASSERT_EQ(frames.position.size(), 2u);
    EXPECT_EQ(frames.position[1].center, Vec3(1, 2, 3));
    EXPECT_TRUE(frames.position[1].orientation.coeffs().isApprox(Quat::Identity().coeffs(), 0.0));
    ASSERT_EQ(frames.velocity.size(), 2u);
    EXPECT_EQ(frames.velocity[1].angular, Vec3(0, 0, 1));
    EXPECT_EQ(error_of(solved_node(R"(<MechanicalObject template="Rigid3d" velocity="1 0 0 0"/>)")),
              "test.scn:5: MechanicalObject: attribute 'velocity': expected a multiple of 6 numbers");
}

TEST(StatesAndTopologies, EachSaysWhatItIsInPenaltyInfo) {
    const auto s = build(R"(<Node name="root">
  <Node name="A">
    <EulerImplicitSolver/><CGLinearSolver/>
    <RegularGridTopology n="3 2 2" min="0 0 0" max="1 1 1"/>
    <MechanicalObject scale3d="2 2 2" rotation="0 0 90" translation="1 2 3"/>
    <Node name="M"><MechanicalObject position="0 0 0"/><IdentityMapping/></Node>
  </Node>
  <Node name="Static"><MechanicalObject template="Rigid3d" position="0 0 0 0 0 0 1"/></Node>
</Node>
)");
    const io::SceneNode& a = *s->file().root->children[0];
    EXPECT_EQ(s->role(*a.components[2]),
              "grid 3 x 2 x 2 from (0, 0, 0) to (1, 1, 1): 12 points, 31 edges, 22 triangles, 11 quads, 2 hexahedra");
    EXPECT_EQ(s->role(*a.components[3]),
              "Vec3d state, 12 DOFs, scaled (2, 2, 2), rotated (0, 0, 90) deg, translated (1, 2, 3); integrated by "
              "the ODE solver of /A");
    // (one position gives way to the 12 the identity maps)
    EXPECT_EQ(s->role(*a.children[0]->components[0]),
              "Vec3d state, 12 DOFs; mapped: positions and velocities from its mapping");
    EXPECT_EQ(s->role(*s->file().root->children[1]->components[0]),
              "Rigid3d state, 1 DOF; static: in no solver's subtree, never moves");
}

TEST(StatesAndTopologies, GridDataAreCheckedAndPartialFormsIgnoredWithANote) {
    const auto grid = [](const std::string& attributes) {
        return solved_node("<RegularGridTopology " + attributes + "/>\n<MechanicalObject/>");
    };
    EXPECT_EQ(error_of(grid(R"(n="2 2")")), "test.scn:5: RegularGridTopology: attribute 'n': expected 3 integers");
    EXPECT_EQ(error_of(grid(R"(n="0 2 2")")),
              "test.scn:5: RegularGridTopology: attribute 'n': each count must be between 1 and 100000");
    EXPECT_EQ(error_of(grid(R"(nx="2" ny="0" nz="2")")),
              "test.scn:5: RegularGridTopology: attribute 'ny': must be between 1 and 100000");
    EXPECT_EQ(error_of(grid(R"(computeQuadList="0")")),
              "test.scn:5: RegularGridTopology: attribute 'computeQuadList': only 1 is supported");
    EXPECT_EQ(error_of(solved_node(R"(<MeshTopology name="m" position="0 0 0"/>
<RegularGridTopology src="@m"/>
<MechanicalObject/>)")),
              "test.scn:6: RegularGridTopology: attribute 'src': must link to a RegularGridTopology built before this "
              "one");
    EXPECT_EQ(error_of(grid(R"(xmin="0" ymin="0" zmin="0" xmax="1e39" ymax="1" zmax="1")")),
              "test.scn:5: RegularGridTopology: attribute 'xmax': '1e39' is beyond float range, and SOFA reads this "
              "attribute as a float (--fix-sofa-quirk regular_grid_float_bounds reads it in double)");
    // five of the six bounds: ignored as one alone is
    const auto five = build(grid(R"(n="2 1 1" xmin="3" ymin="0" zmin="0" xmax="4" ymax="0" max="2 0 0")"));
    EXPECT_THAT(state_points(*five), ElementsAre(Vec3(0, 0, 0), Vec3(2, 0, 0)));
    // nx alone, xmin alone: ignored (n and min/max used), each with a note
    const auto partial = build(grid(R"(n="2 1 1" nx="5" xmin="3" max="2 0 0")"));
    EXPECT_THAT(state_points(*partial), ElementsAre(Vec3(0, 0, 0), Vec3(2, 0, 0)));
    EXPECT_THAT(partial->warnings(),
                testing::IsSupersetOf({std::string("RegularGridTopology: nx, ny, nz ignored (SOFA reads "
                                                   "them only when the three are given)"),
                                       std::string("RegularGridTopology: xmin..zmax ignored (SOFA reads "
                                                   "them only when the six are given); min and max used")}));
    // src: the linked grid's n, min, max and first point, unless given here
    const auto linked = build(solved_node(R"(<RegularGridTopology name="g" n="2 1 1" min="1 0 0" max="3 0 0"/>
<MechanicalObject name="first"/>
<Node name="B"><RegularGridTopology src="@../g"/><MechanicalObject/>
<Node name="C"><RegularGridTopology src="@../../g" max="5 0 0"/><MechanicalObject/></Node></Node>)"));
    EXPECT_THAT(state_points(*linked, 1), ElementsAre(Vec3(1, 0, 0), Vec3(3, 0, 0)));
    EXPECT_THAT(state_points(*linked, 2), ElementsAre(Vec3(1, 0, 0), Vec3(5, 0, 0)));
}

}  // namespace
