#!/usr/bin/env python3
"""The bad-input catalogue: `penalty` run as a user would on hostile input.

Usage: bad_inputs.py PENALTY_EXECUTABLE WORK_DIR

One row per case: the files it writes (a scene made from a valid template with one change, a
mesh, ...), the command line, the exit code expected and the fragments the message must hold
(file, line, component and attribute where one is at fault). Exit codes: 0 success, 1 invalid
scene or input, 2 command-line error, 3 diverged, 4 reference mismatch, 5 other error.
Every row also requires: no signal (a crash), no hang (a timeout fails the row), and a message
prefixed `penalty: error:` on every failure. Prints one line per row, then `N passed, M failed`.
"""
import os
import shutil
import subprocess
import sys

penalty, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)

# A ball above a static floor; line numbers below are part of the expected messages.
BALL = """<?xml version="1.0"?>
<Node name="root" dt="0.01" gravity="0 -9.81 0">
    <DefaultAnimationLoop/>
    <CollisionPipeline/>
    <BruteForceBroadPhase/>
    <BVHNarrowPhase/>
    <MinProximityIntersection name="proximity" alarmDistance="0.2" contactDistance="0.05"/>
    <CollisionResponse name="response" response="PenalityContactForceField"/>
    <Node name="Ball">
        <EulerImplicitSolver name="odesolver" rayleighStiffness="0.1" rayleighMass="0.1"/>
        <CGLinearSolver name="linear" iterations="25" tolerance="1e-9" threshold="1e-9"/>
        <MechanicalObject name="dofs" position="0.3 0.5 0.2" translation="0 0 0"/>
        <UniformMass name="mass" totalMass="1"/>
        <SphereCollisionModel name="ball" radius="0.1" contactStiffness="100"/>
    </Node>
    <Node name="Floor">
        <MechanicalObject name="floor" position="-5 0 -5  5 0 -5  5 0 5  -5 0 5"/>
        <MeshTopology name="topo" triangles="0 2 1  0 3 2"/>
        <TriangleCollisionModel name="floor_triangles" simulated="0" moving="0"/>
    </Node>
</Node>
"""

# A soft grid cube (FEM + springs) on its own, for the material attributes.
SOFT = """<?xml version="1.0"?>
<Node name="root" dt="0.01" gravity="0 -9.81 0">
    <Node name="Cube">
        <EulerImplicitSolver name="odesolver"/>
        <CGLinearSolver name="linear" iterations="25" tolerance="1e-9" threshold="1e-9"/>
        <RegularGridTopology name="grid" n="3 3 3" min="0 0 0" max="1 1 1"/>
        <MechanicalObject name="dofs"/>
        <UniformMass name="mass" totalMass="1"/>
        <TetrahedronFEMForceField name="fem" youngModulus="3000" poissonRatio="0.3"/>
        <MeshSpringForceField name="springs" stiffness="100" damping="1"/>
        <FixedConstraint name="fixed" indices="0 1 2"/>
    </Node>
</Node>
"""

# A ball on a floor loaded from a mesh file (the row supplies the file).
MESH_FLOOR = """<?xml version="1.0"?>
<Node name="root" dt="0.01">
    <CollisionPipeline/>
    <BruteForceBroadPhase/>
    <BVHNarrowPhase/>
    <MinProximityIntersection alarmDistance="0.2" contactDistance="0.05"/>
    <CollisionResponse response="PenalityContactForceField"/>
    <Node name="Floor">
        <MeshOBJLoader name="loader" filename="FILE"/>
        <MeshTopology name="topo" src="@loader"/>
        <MechanicalObject name="floor" src="@loader"/>
        <TriangleCollisionModel name="floor_triangles" simulated="0" moving="0"/>
    </Node>
    <Node name="Ball">
        <EulerImplicitSolver/>
        <CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
        <MechanicalObject name="dofs" position="0.2 0.5 0.2"/>
        <UniformMass totalMass="1"/>
        <SphereCollisionModel name="ball" radius="0.1"/>
    </Node>
</Node>
"""

GOOD_OBJ = "v -5 0 -5\nv 5 0 -5\nv 5 0 5\nv -5 0 5\nf 1 3 2\nf 1 4 3\n"


def edit(template, old, new, count=1):
    assert old in template, f"template has no {old!r}"
    return template.replace(old, new, count)


def ball(old, new):
    return edit(BALL, old, new)


def soft(old, new):
    return edit(SOFT, old, new)


def mesh_floor(path):
    return edit(MESH_FLOOR, 'filename="FILE"', f'filename="{path}"')


CASES = []


def case(name, expect, fragments, scene=None, args=None, files=None, setup=None):
    CASES.append(dict(name=name, expect=expect, fragments=fragments, scene=scene, args=args or [],
                      files=files or {}, setup=setup))


def attr(line, component, attribute):
    """The fragment that names file, line, component and attribute."""
    return f"bad.scn:{line}: {component}: attribute '{attribute}'"


# ---- XML structure --------------------------------------------------------------------------------
case("empty file", 1, ["bad.scn"], scene="")
case("not XML", 1, ["bad.scn"], scene="this is not a scene\n")
case("binary garbage", 1, ["bad.scn"], scene="\x00\x01\x02<Node>\xff\xfe")
case("unclosed root", 1, ["bad.scn"], scene=BALL.replace("</Node>\n", "", 1)[: BALL.rfind("</Node>")])
case("mismatched tag", 1, ["bad.scn:9", "mismatched"], scene=ball("    </Node>\n    <Node name=\"Floor\">", "    </Nod>\n    <Node name=\"Floor\">"))
case("root is not a Node", 1, ["bad.scn", "Node"], scene="<Scene><Node name='a'/></Scene>\n")
case("unknown component", 1, ["bad.scn:13: unknown component 'FancyMass'"], scene=ball("<UniformMass", "<FancyMass"))
case("second mass in a node", 1, ["bad.scn:14", "UniformMass", "line 13"],
     scene=ball('<UniformMass name="mass" totalMass="1"/>', '<UniformMass name="mass" totalMass="1"/>\n        <UniformMass totalMass="1"/>'))
case("second linear solver", 1, ["bad.scn:12", "CGLinearSolver", "line 11"],
     scene=ball('<CGLinearSolver name="linear"', '<CGLinearSolver/>\n        <CGLinearSolver name="linear"'))
case("second ODE solver", 1, ["bad.scn:11", "EulerExplicitSolver", "line 10"],
     scene=ball('<CGLinearSolver name="linear"', '<EulerExplicitSolver/>\n        <CGLinearSolver name="linear"'))
case("second state", 1, ["bad.scn:13", "MechanicalObject", "line 12"],
     scene=ball('<UniformMass name="mass"', '<MechanicalObject position="1 1 1"/>\n        <UniformMass name="mass"'))
case("second topology (SOFA keeps the last)", 0, ["bad.scn:19", "MeshTopology", "replaces", "line 18"],
     scene=ball('<TriangleCollisionModel name="floor_triangles"', '<MeshTopology triangles="0 1 2"/>\n        <TriangleCollisionModel name="floor_triangles"'))
case("second DefaultAnimationLoop (the same loop; SOFA keeps the last)", 0, [],
     scene=ball("<CollisionPipeline/>", "<DefaultAnimationLoop/>\n    <CollisionPipeline/>"))

# ---- types ----------------------------------------------------------------------------------------
case("mass not a number", 1, [attr(13, "UniformMass 'mass'", "totalMass"), "abc"], scene=ball('totalMass="1"', 'totalMass="abc"'))
case("node dt not a number", 1, ["bad.scn:2: Node 'root': attribute 'dt'"], scene=ball('dt="0.01"', 'dt="fast"'))
case("gravity with 2 numbers", 1, ["bad.scn:2: Node 'root': attribute 'gravity'", "3 numbers"], scene=ball('gravity="0 -9.81 0"', 'gravity="0 -9.81"'))
case("iterations not an integer", 1, [attr(11, "CGLinearSolver 'linear'", "iterations")], scene=ball('iterations="25"', 'iterations="2.5"'))
case("position not a multiple of 3", 1, [attr(12, "MechanicalObject 'dofs'", "position"), "multiple of 3"], scene=ball('position="0.3 0.5 0.2"', 'position="0.3 0.5"'))
case("boolean not a boolean", 1, [attr(19, "TriangleCollisionModel 'floor_triangles'", "simulated")], scene=ball('simulated="0"', 'simulated="maybe"'))
case("negative triangle index", 1, [attr(18, "MeshTopology 'topo'", "triangles")], scene=ball('triangles="0 2 1  0 3 2"', 'triangles="0 2 -1  0 3 2"'))
case("triangle index out of range", 1, ["bad.scn:19", "vertex index 7 out of range"], scene=ball('triangles="0 2 1  0 3 2"', 'triangles="0 2 7  0 3 2"'))
case("huge inline position list", 1, [attr(12, "MechanicalObject 'dofs'", "position"), "more than penalty's limit"],
     scene=ball('position="0.3 0.5 0.2"', 'position="' + "0 0 0 " * 400_000 + '"'))

# ---- numeric extremes, every physical attribute ---------------------------------------------------
for value, what in [("nan", "expected a number"), ("inf", "expected a number"), ("-inf", "expected a number"),
                    ("1e300", "magnitude above 1e100"), ("1e-300", "magnitude below 1e-100")]:
    case(f"dt = {value}", 1, ["bad.scn:2: Node 'root': attribute 'dt'", what], scene=ball('dt="0.01"', f'dt="{value}"'))
    case(f"totalMass = {value}", 1, [attr(13, "UniformMass 'mass'", "totalMass"), what], scene=ball('totalMass="1"', f'totalMass="{value}"'))
    case(f"contactStiffness = {value}", 1, [attr(14, "SphereCollisionModel 'ball'", "contactStiffness"), what],
         scene=ball('contactStiffness="100"', f'contactStiffness="{value}"'))
case("dt = 0", 1, ["bad.scn:2: Node 'root': attribute 'dt'", "> 0"], scene=ball('dt="0.01"', 'dt="0"'))
case("dt = -0", 1, ["bad.scn:2: Node 'root': attribute 'dt'", "> 0"], scene=ball('dt="0.01"', 'dt="-0"'))
case("dt negative", 1, ["bad.scn:2: Node 'root': attribute 'dt'", "> 0"], scene=ball('dt="0.01"', 'dt="-0.01"'))
case("totalMass = 0", 1, [attr(13, "UniformMass 'mass'", "totalMass")], scene=ball('totalMass="1"', 'totalMass="0"'))
case("totalMass negative", 1, [attr(13, "UniformMass 'mass'", "totalMass")], scene=ball('totalMass="1"', 'totalMass="-2"'))
case("gravity = 1e308", 1, ["bad.scn:2: Node 'root': attribute 'gravity'", "magnitude above 1e100"], scene=ball('gravity="0 -9.81 0"', 'gravity="0 -1e308 0"'))
case("gravity nan", 1, ["bad.scn:2: Node 'root': attribute 'gravity'"], scene=ball('gravity="0 -9.81 0"', 'gravity="0 nan 0"'))
case("contactStiffness negative", 1, [attr(14, "SphereCollisionModel 'ball'", "contactStiffness")], scene=ball('contactStiffness="100"', 'contactStiffness="-5"'))
case("radius negative", 1, [attr(14, "SphereCollisionModel 'ball'", "radius")], scene=ball('radius="0.1"', 'radius="-0.1"'))
case("radius nan", 1, [attr(14, "SphereCollisionModel 'ball'", "radius")], scene=ball('radius="0.1"', 'radius="nan"'))
case("radius 1e300", 1, [attr(14, "SphereCollisionModel 'ball'", "radius"), "magnitude"], scene=ball('radius="0.1"', 'radius="1e300"'))
case("alarmDistance negative", 1, [attr(7, "MinProximityIntersection 'proximity'", "alarmDistance")], scene=ball('alarmDistance="0.2"', 'alarmDistance="-1"'))
case("alarmDistance nan", 1, [attr(7, "MinProximityIntersection 'proximity'", "alarmDistance")], scene=ball('alarmDistance="0.2"', 'alarmDistance="nan"'))
case("contactDistance 1e300", 1, [attr(7, "MinProximityIntersection 'proximity'", "contactDistance"), "magnitude"], scene=ball('contactDistance="0.05"', 'contactDistance="1e300"'))
case("iterations = 0", 1, ["bad.scn:11", "CGLinearSolver 'linear'", "iterations"], scene=ball('iterations="25"', 'iterations="0"'))
case("iterations huge", 1, ["bad.scn:11", "CGLinearSolver 'linear'", "iterations"], scene=ball('iterations="25"', 'iterations="1000000000000"'))
case("tolerance negative", 1, ["bad.scn:11", "CGLinearSolver 'linear'", "tolerance"], scene=ball('tolerance="1e-9"', 'tolerance="-1"'))
case("rayleighStiffness negative", 1, ["bad.scn:10", "EulerImplicitSolver 'odesolver'", "rayleighStiffness"], scene=ball('rayleighStiffness="0.1"', 'rayleighStiffness="-0.1"'))
case("rayleighMass inf", 1, [attr(10, "EulerImplicitSolver 'odesolver'", "rayleighMass")], scene=ball('rayleighMass="0.1"', 'rayleighMass="inf"'))
case("translation nan", 1, [attr(12, "MechanicalObject 'dofs'", "translation")], scene=ball('translation="0 0 0"', 'translation="0 nan 0"'))
case("translation 1e300", 1, [attr(12, "MechanicalObject 'dofs'", "translation"), "magnitude"], scene=ball('translation="0 0 0"', 'translation="1e300 0 0"'))
case("position 1e300", 1, [attr(12, "MechanicalObject 'dofs'", "position"), "magnitude"], scene=ball('position="0.3 0.5 0.2"', 'position="0.3 1e300 0.2"'))
case("youngModulus 0", 1, [attr(9, "TetrahedronFEMForceField 'fem'", "youngModulus")], scene=soft('youngModulus="3000"', 'youngModulus="0"'))
case("youngModulus negative", 1, [attr(9, "TetrahedronFEMForceField 'fem'", "youngModulus")], scene=soft('youngModulus="3000"', 'youngModulus="-3000"'))
case("youngModulus 1e300", 1, [attr(9, "TetrahedronFEMForceField 'fem'", "youngModulus"), "magnitude"], scene=soft('youngModulus="3000"', 'youngModulus="1e300"'))
case("poissonRatio 0.5", 1, [attr(9, "TetrahedronFEMForceField 'fem'", "poissonRatio")], scene=soft('poissonRatio="0.3"', 'poissonRatio="0.5"'))
case("poissonRatio nan", 1, [attr(9, "TetrahedronFEMForceField 'fem'", "poissonRatio")], scene=soft('poissonRatio="0.3"', 'poissonRatio="nan"'))
case("spring stiffness negative", 1, [attr(10, "MeshSpringForceField 'springs'", "stiffness")], scene=soft('stiffness="100"', 'stiffness="-100"'))
case("spring stiffness 1e300", 1, [attr(10, "MeshSpringForceField 'springs'", "stiffness"), "magnitude"], scene=soft('stiffness="100"', 'stiffness="1e300"'))
case("grid n = 0", 1, ["bad.scn:6: RegularGridTopology 'grid': attribute 'n"], scene=soft('n="3 3 3"', 'n="0 3 3"'))
case("grid too many points", 1, ["bad.scn:6", "RegularGridTopology 'grid'", "grid points"], scene=soft('n="3 3 3"', 'n="100000 100000 3"'))
case("fixed index out of range", 1, [attr(11, "FixedConstraint 'fixed'", "indices"), "index 99 out of range"], scene=soft('indices="0 1 2"', 'indices="0 1 99"'))
case("totalMass on a state with no DOF (no doubled prefix)", 1, ["bad.scn:13: UniformMass 'mass': totalMass given for a state with no DOF"],
     scene=ball('position="0.3 0.5 0.2"', 'size="0"'))
case("state size huge", 1, [attr(12, "MechanicalObject 'dofs'", "size")], scene=ball('position="0.3 0.5 0.2"', 'size="100000000000"'))

# ---- links ----------------------------------------------------------------------------------------
case("broken link", 1, [attr(10, "MeshTopology 'topo'", "src"), "broken link '@nothing'"], scene=edit(MESH_FLOOR, 'src="@loader"', 'src="@nothing"').replace("FILE", "floor.obj"), files={"floor.obj": GOOD_OBJ})
case("link index too far", 1, [attr(10, "MeshTopology 'topo'", "src"), "broken link"], scene=edit(MESH_FLOOR, 'src="@loader"', 'src="@[-5]"').replace("FILE", "floor.obj"), files={"floor.obj": GOOD_OBJ})
case("link to a component of the wrong kind", 1, [attr(11, "MechanicalObject 'floor'", "src")], scene=edit(MESH_FLOOR, '<MechanicalObject name="floor" src="@loader"/>', '<MechanicalObject name="floor" src="@floor_triangles"/>').replace("FILE", "floor.obj"), files={"floor.obj": GOOD_OBJ})

# ---- meshes ---------------------------------------------------------------------------------------
case("missing mesh", 1, [attr(9, "MeshOBJLoader 'loader'", "filename"), "cannot find data file 'no/such.obj'"], scene=mesh_floor("no/such.obj"))
case("empty mesh", 1, ["empty.obj: no vertices"], scene=mesh_floor("empty.obj"), files={"empty.obj": ""})
case("garbage mesh", 1, ["garbage.obj: no vertices"], scene=mesh_floor("garbage.obj"), files={"garbage.obj": "hello world\nthis is not a mesh\n"})
case("mesh index out of range", 1, ["range.obj:3", "vertex index 9 out of range"], scene=mesh_floor("range.obj"), files={"range.obj": "v 0 0 0\nv 1 0 0\nf 1 2 9\n"})
case("mesh coordinate 1e300", 1, ["big.obj:2", "magnitude above 1e100"], scene=mesh_floor("big.obj"), files={"big.obj": "v 0 0 0\nv 1e300 0 0\nv 0 0 1\nf 1 2 3\n"})
case("mesh coordinate nan", 1, ["nan.obj:1", "vertex coordinate"], scene=mesh_floor("nan.obj"), files={"nan.obj": "v nan 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n"})
case("mesh file is a directory", 1, ["'adir.obj'", "is a directory"], scene=mesh_floor("adir.obj"), setup=lambda d: os.makedirs(os.path.join(d, "adir.obj")))
case("mesh file is /dev/zero", 1, ["'/dev/zero'", "character device"], scene=mesh_floor("/dev/zero"))
case("mesh file is a symlink loop", 1, ["'loop.obj'", "symbolic link loop"], scene=mesh_floor("loop.obj"),
     setup=lambda d: (os.symlink("loop2.obj", os.path.join(d, "loop.obj")), os.symlink("loop.obj", os.path.join(d, "loop2.obj"))))
case("gmsh node count huge", 1, ["huge.msh:5", "node"], scene=edit(mesh_floor("huge.msh"), "MeshOBJLoader", "MeshGmshLoader", 1),
     files={"huge.msh": "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n99999999999\n1 0 0 0\n$EndNodes\n"})
case("degenerate floor triangles warned", 0, ["note:", "floor_triangles", "1 of 2 triangles have zero area (first: triangle 1)"],
     scene=mesh_floor("flat.obj"), files={"flat.obj": "v -5 0 -5\nv 5 0 -5\nv 5 0 5\nv -5 0 -5\nf 1 3 2\nf 1 4 2\n"}, args=["--steps", "5"])

# ---- tiny magnitudes: the other end of the 1e100 cap (a subnormal overflows a quotient) ----------
case("contactDistance subnormal", 1, [attr(7, "MinProximityIntersection 'proximity'", "contactDistance"), "magnitude below 1e-100"],
     scene=ball('contactDistance="0.05"', 'contactDistance="1e-308"'))
case("alarmDistance 1e-300", 1, [attr(7, "MinProximityIntersection 'proximity'", "alarmDistance"), "magnitude below 1e-100"],
     scene=ball('alarmDistance="0.2"', 'alarmDistance="1e-300"'))
case("radius 1e-300", 1, [attr(14, "SphereCollisionModel 'ball'", "radius"), "magnitude below 1e-100"], scene=ball('radius="0.1"', 'radius="1e-300"'))
case("spring stiffness 1e-300", 1, [attr(10, "MeshSpringForceField 'springs'", "stiffness"), "magnitude below 1e-100"],
     scene=soft('stiffness="100"', 'stiffness="1e-300"'))
case("youngModulus 4.9e-324", 1, [attr(9, "TetrahedronFEMForceField 'fem'", "youngModulus"), "magnitude below 1e-100"],
     scene=soft('youngModulus="3000"', 'youngModulus="4.9e-324"'))
case("mesh coordinate 1e-300", 1, ["tiny.obj:2", "magnitude below 1e-100"], scene=mesh_floor("tiny.obj"),
     files={"tiny.obj": "v 0 0 0\nv 1e-300 0 0\nv 0 0 1\nf 1 2 3\n"})
case("zero stays zero (not a tiny magnitude)", 0, ["steps: 3"], scene=ball('translation="0 0 0"', 'translation="0 -0 0.0e0"'),
     args=["--steps", "3"])
case("--dt 1e-300", 2, ["penalty: error:", "--dt", "out of range [1e-100, 86400]"], scene=BALL, args=["--dt", "1e-300"])

# ---- byte-order marks and CRLF (Windows editors) ---------------------------------------------------
case("OBJ with a byte-order mark and CRLF keeps its first vertex", 0, ["bom.obj: 4 points, 2 triangles"],
     scene=mesh_floor("bom.obj"), files={"bom.obj": "\ufeff" + GOOD_OBJ.replace("\n", "\r\n")}, args=["info"])
case("scene with a byte-order mark and CRLF", 0, ["steps: 3"], scene="\ufeff" + BALL.replace("\n", "\r\n"), args=["--steps", "3"])

# ---- outputs that cannot be written: exit 5 naming the path ----------------------------------------
for option, value in [("--export-states", "afile/states"), ("--stats", "afile/stats.csv"), ("--vtk", "afile/vtk"),
                      ("--summary-json", "afile/summary.json"), ("--debug-file", "afile/debug.txt")]:
    extra = ["--debug-step", "0"] if option == "--debug-file" else []
    case(f"{option} under a regular file", 5, ["penalty: error:", "afile"], scene=BALL,
         args=[option, value, *extra, "--steps", "2"], files={"afile": "x"})
case("--view under a regular file", 5, ["penalty: error:", "afile"], scene=BALL,
     args=["--view", "afile/view", "--no-serve", "--steps", "2"], files={"afile": "x"})

# ---- command line ---------------------------------------------------------------------------------
for value, fragment in [("-3", "out of range"), ("99999999999999999999", "out of range"), ("9223372036854775808", "out of range"),
                        ("18446744073709551617", "out of range"), ("1000000001", "out of range"), ("2e3", "not a whole number"),
                        ("abc", "not a whole number")]:
    case(f"--steps {value}", 2, ["penalty: error:", "--steps", fragment], scene=BALL, args=["--steps", value])
for value, fragment in [("nan", "not a finite number"), ("inf", "not a finite number"), ("0", "out of range"), ("-1", "out of range"),
                        ("1e300", "out of range")]:
    case(f"--dt {value}", 2, ["penalty: error:", "--dt", fragment], scene=BALL, args=["--dt", value])
for value in ["0", "100000", "2147483647", "-1"]:
    case(f"--threads {value}", 2, ["penalty: error:", "--threads", "out of range"], scene=BALL, args=["--threads", value])
case("--export-every 0", 2, ["penalty: error:", "--export-every"], scene=BALL, args=["--export-every", "0"])
case("--vtk-every -1", 2, ["penalty: error:", "--vtk-every"], scene=BALL, args=["--vtk-every", "-1"])
case("--divergence-factor -1", 2, ["penalty: error:", "--divergence-factor"], scene=BALL, args=["--divergence-factor", "-1"])
case("unknown option", 2, ["penalty: error:", "--frobnicate"], scene=BALL, args=["--frobnicate"])
case("missing scene file", 2, ["penalty: error:", "no_such.scn"], args=["no_such.scn"])
case("scene is a directory", 2, ["penalty: error:", "directory"], args=["."])
case("scene is /dev/zero", 1, ["penalty: error:", "/dev/zero", "character device"], args=["/dev/zero"])
case("--reference without --export-states", 2, ["penalty: error:", "--reference needs --export-states"], scene=BALL, args=["--reference", "."])
case("--data-dir missing", 2, ["penalty: error:", "--data-dir"], scene=BALL, args=["--data-dir", "no_such_dir"])
# --set (docs/sweeps.md): malformed is a usage error (2); a path or attribute the scene lacks, or a
# value the builder refuses, is an invalid input (1) naming it.
case("--set without '='", 2, ["penalty: error:", "--set '/Ball/ball.radius'", "no '='"], scene=BALL,
     args=["--set", "/Ball/ball.radius"])
case("--set without attribute", 2, ["penalty: error:", "--set '/Ball/ball=1'", "no '.attribute'"], scene=BALL,
     args=["--set", "/Ball/ball=1"])
case("--set unknown node", 1, ["penalty: error:", "bad.scn: --set '/Bal/ball.radius=1'", "no node 'Bal' in '/'"],
     scene=BALL, args=["--set", "/Bal/ball.radius=1"])
case("--set unknown attribute", 1, ["penalty: error:", "bad.scn:14: SphereCollisionModel 'ball'",
                                    "no attribute 'radios'", "penalty does not read it"],
     scene=BALL, args=["--set", "/Ball/ball.radios=1"])
case("--set refused value", 1, [attr(14, "SphereCollisionModel 'ball'", "radius")], scene=BALL,
     args=["--set", "/Ball/ball.radius=abc"])
case("--set root dt refused", 1, [attr(2, "Node 'root'", "dt")], scene=BALL, args=["--set", "/root.dt=-1"])
case("--vtk onto a file", 5, ["penalty: error:"], scene=BALL, args=["--vtk", "afile", "--steps", "2"], files={"afile": "x"})

# ---- runs that diverge, and the edge of normal ----------------------------------------------------
case("explicit solver, stiff contact: ejected", 3,
     ["penalty: error: simulation diverged at step", "the energy grew by", "times the scene's energy scale"],
     scene=ball('<EulerImplicitSolver name="odesolver" rayleighStiffness="0.1" rayleighMass="0.1"/>', '<EulerExplicitSolver name="odesolver"/>')
     .replace('contactStiffness="100"', 'contactStiffness="1e6"').replace('dt="0.01"', 'dt="0.02"'), args=["--steps", "2000"])
# A 0.1 kg ball on a 10 kg static floor (its mass cannot fall: it is not part of the energy scale),
# ejected by an unstable explicit contact at 1340 m/s; before, the floor's mass made the scale 1.4 MJ
# and the ball reached 13 km with exit 0.
EJECTED = (ball('<EulerImplicitSolver name="odesolver" rayleighStiffness="0.1" rayleighMass="0.1"/>', '<EulerExplicitSolver name="odesolver"/>')
           .replace('totalMass="1"', 'totalMass="0.1"').replace('contactStiffness="100"', 'contactStiffness="1e4"')
           .replace('<MeshTopology name="topo"', '<UniformMass name="floor_mass" totalMass="10"/>\n        <MeshTopology name="topo"'))
case("explicit, 0.1 kg ball on a heavy static floor: ejected", 3,
     ["penalty: error: simulation diverged at step", "the energy grew by", "times the scene's energy scale"],
     scene=EJECTED, args=["--steps", "1000"])
case("the same with the check off", 0, ["steps: 1000"], scene=EJECTED, args=["--steps", "1000", "--divergence-factor", "0"])
case("implicit, dt = 1000: tunnels away", 3, ["simulation diverged at step 0", "state '/Ball/dofs' DOF 0", "in one step, more than 100 times the initial scene size"],
     scene=BALL, args=["--dt", "1000", "--steps", "3"])
case("the same with the check off", 0, ["steps: 3"], scene=BALL, args=["--dt", "1000", "--steps", "3", "--divergence-factor", "0"])
case("--steps 0 writes the initial state", 0, ["states: 1 files", "the initial state only"], scene=BALL, args=["--steps", "0", "--export-states", "out"])
case("demo --stiffness -1", 2, ["penalty: error:", "--stiffness", "out of range"], args=["demo", "--stiffness", "-1"])
case("demo --friction nan", 2, ["penalty: error:", "--friction", "not a finite number"], args=["demo", "--friction", "nan"])
case("info on a second mass", 1, ["bad.scn:14", "line 13"],
     scene=ball('<UniformMass name="mass" totalMass="1"/>', '<UniformMass name="mass" totalMass="1"/>\n        <UniformMass totalMass="1"/>'),
     args=["info"])

# ---- bad input met during the run: still exit 1, naming the step, file, line and component -------
SHEET = open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scene", "data", "incision_sheet.scn"),
             encoding="utf-8").read()
case("incision point in no triangle (at the step)", 1, ["step ", "cut.txt:3", "TopologicalChangeProcessor", "no triangle"],
     scene=edit(SHEET, 'filename="incision_sheet.txt"', 'filename="cut.txt"'),
     files={"cut.txt": "T= 0.02\n  INCISE= 2\n1.15 0.05 0 9 9 0\n"}, args=["--steps", "5"])


def run_case(index, c):
    d = os.path.join(work, f"case{index:03d}")
    os.makedirs(d)
    for name, text in c["files"].items():
        with open(os.path.join(d, name), "w", encoding="utf-8") as f:
            f.write(text)
    if c["setup"]:
        c["setup"](d)
    args = list(c["args"])
    command = "run"
    if args and args[0] in ("info", "demo"):
        command = args.pop(0)
    if c["scene"] is not None:
        with open(os.path.join(d, "bad.scn"), "w", encoding="utf-8", errors="surrogateescape") as f:
            f.write(c["scene"])
        argv = [penalty, command, "bad.scn", *args]
    else:
        argv = [penalty, command, *args]
    if command == "run":
        argv.append("--quiet")
    try:
        p = subprocess.run(argv, cwd=d, capture_output=True, text=True, errors="replace", timeout=120)
    except subprocess.TimeoutExpired:
        return "hung (more than 120 s)"
    out = p.stdout + p.stderr
    if p.returncode < 0:
        return f"killed by signal {-p.returncode}\n{out}"
    problems = []
    if p.returncode != c["expect"]:
        problems.append(f"exit {p.returncode}, expected {c['expect']}")
    if p.returncode != 0 and "penalty: error:" not in p.stderr:
        problems.append("no 'penalty: error:' line on stderr")
    if "UniformMass: UniformMass" in out or "': UniformMass:" in out:
        problems.append("doubled component prefix in the message")
    for fragment in c["fragments"]:
        if fragment not in out:
            problems.append(f"missing {fragment!r}")
    if problems:
        return "; ".join(problems) + "\n--- output\n" + out[-2000:]
    return None


passed = failed = 0
for i, c in enumerate(CASES):
    problem = run_case(i, c)
    if problem is None:
        passed += 1
        print(f"ok   {i:3d} {c['name']}")
    else:
        failed += 1
        print(f"FAIL {i:3d} {c['name']}: {problem}")
print(f"{passed} passed, {failed} failed")
sys.exit(1 if failed or passed < 60 else 0)
