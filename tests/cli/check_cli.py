#!/usr/bin/env python3
"""End-to-end checks of the `penalty` command line: exit codes, messages and output files.

Usage: check_cli.py PENALTY_EXECUTABLE TESTS_CLI_DIR WORK_DIR
Every check prints one line; the script exits 1 at the first failure (with the command's output).
"""
import csv
import json
import os
import re
import struct
import shutil
import socket
import subprocess
import sys
import xml.etree.ElementTree as ET

penalty, data, work = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def run(*args, expect):
    p = subprocess.run([penalty, *args], capture_output=True, text=True, timeout=300)
    if p.returncode != expect:
        print(f"FAIL: penalty {' '.join(args)}: exit {p.returncode}, expected {expect}\n--- stdout\n{p.stdout}--- stderr\n{p.stderr}")
        sys.exit(1)
    print(f"ok: penalty {' '.join(args)} -> exit {expect}")
    return p


def check(condition, what):
    if not condition:
        print(f"FAIL: {what}")
        sys.exit(1)
    print(f"ok: {what}")


scene = os.path.join(data, "cube_on_floor.scn")

# Exit codes and one-line reasons.
p = run("run", os.path.join(data, "malformed.scn"), expect=1)
check(p.stderr.strip().endswith("malformed.scn:3: UniformMass 'mass': attribute 'totalMass': expected a number, found 'abc'"),
      "malformed attribute: file, line, component and attribute named")
p = run("run", os.path.join(data, "unknown_component.scn"), expect=1)
check("unknown_component.scn:3: unknown component 'FancyForceField' (not supported by penalty)" in p.stderr,
      "unknown component named with file and line")
p = run("run", os.path.join(data, "diverges.scn"), "--steps", "1000", "--quiet", expect=3)
check(re.search(r"simulation diverged at step \d+ .*state '/A/p' DOF \d", p.stderr) is not None, "divergence names the state")
run("run", scene, "--steps", "-3", expect=2)
run("run", os.path.join(data, "no_such_scene.scn"), expect=2)
run("bogus", expect=2)
run("run", scene, "--reference", work, expect=2)  # --reference needs --export-states

# info
p = run("info", scene, expect=0)
check("Node /Cube" in p.stdout and "PointCollisionModel 'cube_points'" in p.stdout and
      re.search(r"VisualStyle +ignored \(display flags\)", p.stdout) is not None,
      "info shows the tree and the ignored components")
check("floor_triangles (Triangle, /Floor) - cube_points (Point, /Cube): penalty contact in /Cube, implicit (solver of /Cube)"
      in p.stdout, "info shows where the contacts of each model pair go")
p = run("info", os.path.join(data, "malformed.scn"), expect=1)
check("malformed.scn:3: UniformMass 'mass': attribute 'totalMass'" in p.stderr, "info builds the scene and reports its errors")

# run with every output
states, vtk, stats = (os.path.join(work, d) for d in ("states", "vtk", "stats.csv"))
steps = 30
p = run("run", scene, "--steps", str(steps), "--quiet", "--export-states", states, "--export-every", "7",
        "--vtk", vtk, "--vtk-every", "10", "--stats", stats, "--export-mapped", expect=0)
check(re.search(r"steps: 30 +\(dt 0.01 s, simulated 0.3 s\)", p.stdout) is not None, "summary line of steps")
check(re.search(r"contacts per step: mean [0-9.]+, max [1-9]", p.stdout) is not None, "contacts happened")
check("time per step: detection" in p.stdout and "solve" in p.stdout, "per-phase timings printed")

# SOFA regression state files: the cube (solver subtree, unmapped) then the mapped surface.
names = sorted(os.listdir(states))
check(names == ["0_cube_mstate.txt", "1_surface_mstate.txt"], f"state files {names}")
lines = open(os.path.join(states, "0_cube_mstate.txt")).read().splitlines()
times = [float(l[3:]) for l in lines[0::2]]
check(all(l.startswith("T= ") for l in lines[0::2]) and all(l.startswith("  X= ") for l in lines[1::2]),
      "state file layout: 'T= t' then '  X= x0 y0 z0 ...'")
expected_times = [k * 0.01 for k in range(0, steps, 7)] + [(steps - 1) * 0.01]
check(len(times) == len(expected_times) and all(abs(a - b) < 1e-12 for a, b in zip(times, expected_times)),
      f"exported times {times} (every 7 steps plus the last)")
first = [float(v) for v in lines[1][5:].split()]
as_float = lambda v: struct.unpack("f", struct.pack("f", v))[0]  # SOFA reads dx dy dz as floats
check(len(first) == 24 and first[0:3] == [as_float(0.3), as_float(0.5), as_float(0.1)], "8 Vec3 DOFs, transformed by dx dy dz")

# VTK series: .pvd collections list every written step; pieces parse and have the right sizes.
pvds = sorted(f for f in os.listdir(vtk) if f.endswith(".pvd"))
check(pvds == ["0_cube.pvd", "1_surface.pvd", "2_floor.pvd", "contacts.pvd"], f"pvd files {pvds}")
collection = ET.parse(os.path.join(vtk, "0_cube.pvd")).getroot().find("Collection")
datasets = collection.findall("DataSet")
check(len(datasets) == 4, "pvd lists steps 0, 10, 20 and the final state")  # 30 steps, every 10, plus the end
check(abs(float(datasets[-1].get("timestep")) - 0.3) < 1e-12, "last VTK step is the final state at t = 0.3")
piece = ET.parse(os.path.join(vtk, datasets[0].get("file"))).getroot().find("UnstructuredGrid/Piece")
check(piece.get("NumberOfPoints") == "8" and piece.get("NumberOfCells") == "1", "cube piece: 8 points, 1 hexahedron")
types = piece.find("Cells/DataArray[@Name='types']").text.split()
check(types == ["12"], "cell type VTK_HEXAHEDRON")
contacts = ET.parse(os.path.join(vtk, ET.parse(os.path.join(vtk, "contacts.pvd")).getroot()
                                 .find("Collection").findall("DataSet")[-1].get("file"))).getroot()
cpiece = contacts.find("PolyData/Piece")
check(int(cpiece.get("NumberOfLines")) > 0, f"contact springs at the end: {cpiece.get('NumberOfLines')}")
check(cpiece.find("CellData/DataArray[@Name='force']") is not None, "contact force array")

# CSV statistics: header and one row per step.
with open(stats) as f:
    rows = list(csv.DictReader(f))
check(len(rows) == steps, f"{len(rows)} CSV rows")
check(list(rows[0].keys())[:5] == ["step", "time", "contacts", "active_contacts", "max_penetration"], "CSV header")
check(int(rows[-1]["step"]) == steps - 1 and abs(float(rows[-1]["time"]) - 0.3) < 1e-12, "last CSV row is step 29 at t = 0.3")
check(max(int(r["contacts"]) for r in rows) > 0, "CSV records contacts")

# --compare-trajectory: a run against its own every-step export passes (plain and gzip files);
# one value moved by 1e-6 at step 5 is found (step, state, DOF) and gives exit code 4.
import gzip
traj = os.path.join(work, "trajectory")
run("run", scene, "--steps", "20", "--quiet", "--export-states", traj, expect=0)
p = run("run", scene, "--steps", "20", "--quiet", "--compare-trajectory", traj, expect=0)
check("every state within 1e-12 at every step: PASS" in p.stdout, "self comparison passes")
cube = os.path.join(traj, "0_cube_mstate.txt")
lines = open(cube).read().splitlines()
x = lines[11].split()  # step 5: lines 10 (T=) and 11 (X=)
x[2] = repr(float(x[2]) + 1e-6)  # DOF 0, y
lines[11] = "  " + " ".join(x)
with gzip.open(cube + ".gz", "wt") as f:
    f.write("\n".join(lines) + "\n")
os.remove(cube)
p = run("run", scene, "--steps", "20", "--quiet", "--compare-trajectory", traj, expect=4)
check(re.search(r"0_cube_mstate.txt vs 0_cube_mstate.txt.gz: .*\n.*first step with \|dx\| > 1e-12: step 5 \(t = 0.05 s\) DOF 0 y", p.stdout)
      is not None, "gzip trajectory read, first step, DOF and component of the difference")
p = run("run", scene, "--steps", "20", "--quiet", "--compare-trajectory", traj, "--trajectory-threshold", "1e-5", expect=0)
check("PASS" in p.stdout, "a looser --trajectory-threshold accepts the difference")

# SOFA-quirk switches and the debug export.
p = run("run", scene, "--steps", "2", "--quiet", "--fix-sofa-quirk", "no_such_quirk", expect=2)
check("unknown SOFA quirk 'no_such_quirk'" in p.stderr, "unknown quirk names itself")
p = run("info", scene, "--fix-sofa-quirks", "all", expect=0)
check("newproximity_triangle_sphere_edge_flags [on for every pipeline]" in p.stdout and
      "SOFA quirk fixes: minproximity_line_sphere_mirror" in p.stdout, "info shows the quirk fixes that are on")
# mechanical_object_float_short_forms: SOFA reads dy="0.1" as a float (0.10000000149011612); the
# fix reads it in double.
short = os.path.join(work, "short_forms.scn")
with open(short, "w") as f:
    f.write('<Node name="root" dt="0.01" gravity="0 0 0"><Node name="A"><EulerImplicitSolver/><CGLinearSolver/>'
            '<MechanicalObject name="mo" position="0 0 0" dy="0.1"/><UniformMass totalMass="1"/></Node></Node>')
def first_y(extra):
    out = os.path.join(work, "short_forms_" + str(len(extra)))
    run("run", short, "--steps", "1", "--quiet", "--export-states", out, *extra, expect=0)
    lines = open(os.path.join(out, "0_mo_mstate.txt")).read().splitlines()
    return float(lines[1].replace("X=", "").split()[1])
check(first_y([]) == 0.10000000149011612, "dy is read as a float by default, as SOFA")
check(first_y(["--fix-sofa-quirk", "mechanical_object_float_short_forms"]) == 0.1, "the quirk fix reads dy in double")
debug = os.path.join(work, "debug.txt")
p = run("run", scene, "--steps", "30", "--quiet", "--debug-step", "25", "--debug-file", debug, expect=0)
text = open(debug).read()
check(text.startswith("# penalty debug export: step 25, t_start 0.25") and "\ncontacts:\n" in text and
      re.search(r"\ncontact 0 elements \d+ \d+ point1 \S+ \S+ \S+ point2 .* normal .* distance .* penetration", text)
      and re.search(r"\nsolve /Cube linear solve 0: iterations \d+ end \w+ residual", text)
      and "\nforce /Cube/cube 7 " in text, "debug export: contacts, linear solves, forces")
run("run", scene, "--steps", "30", "--quiet", "--debug-step", "30", expect=2)

# The built-in scene (the README's main job).
p = run("run", "--steps", "60", "--quiet", expect=0)
check("built-in scene" in p.stdout and re.search(r"contacts per step: mean [0-9.]+, max [1-9]", p.stdout) is not None,
      "built-in scene runs and makes contacts")
# The browser viewer's files (docs/viewer.md): frames 0, 10, 20 and the end; the last frame's
# time and contact count are the CSV's last row.
view = os.path.join(work, "view")
view_stats = os.path.join(work, "view_stats.csv")
run("run", scene, "--steps", "30", "--quiet", "--view", view, "--view-every", "10", "--no-serve", "--stats", view_stats,
    expect=0)
with open(os.path.join(view, "run.json")) as f:
    manifest = json.load(f)
frames = manifest["frames"]
check(frames["count"] == 4 and all(abs(a - b) < 1e-12 for a, b in zip(frames["time"], [0, 0.1, 0.2, 0.3])),
      f"viewer frames at t = 0, 0.1, 0.2, 0.3: {frames['time']}")
with open(view_stats) as f:
    view_rows = list(csv.DictReader(f))
check(frames["contacts"][-1] == int(view_rows[-1]["contacts"]) > 0, "viewer's last contact count is the CSV's")
# frame j (step k = 10·j ≥ 1, then the end) reports what CSV row k − 1 reports
for j, k in enumerate([10, 20, 30], start=1):
    row = view_rows[k - 1]
    check(abs(frames["time"][j] - float(row["time"])) < 1e-12 and frames["contacts"][j] == int(row["contacts"]) and
          all(abs(frames[c][j] - float(row[c])) <= 1e-12 * max(1.0, abs(float(row[c])))
              for c in ["kinetic_energy", "contact_energy", "dissipated_energy", "max_penetration"]),
          f"viewer frame {j} has the statistics of CSV row {k - 1}")
check(os.path.getsize(os.path.join(view, "positions.f32")) == 4 * 4 * manifest["frame_floats"], "positions.f32: 4 frames of float32")
check(os.path.getsize(os.path.join(view, "contacts.f32")) == 4 * 10 * sum(frames["contacts"]), "contacts.f32: 10 floats per contact")
check(os.path.exists(os.path.join(view, "index.html")) and os.path.exists(os.path.join(view, "three.module.min.js")),
      "viewer page files written")
run("view", view, "--no-serve", expect=0)
p = run("view", work, "--no-serve", expect=1)
check("has no run.json: not a viewer directory" in p.stderr, "penalty view names a directory without run.json")
run("run", scene, "--view", view, "--view-every", "0", expect=2)


def oversized_request_answers(port):
    """Sends a request whose header is over the server's limit, all of it, then reads the answer:
    the server must answer 431 and read what is left before it closes (closing with unread input
    resets the connection, and the reset can discard the answer before it is read)."""
    with socket.create_connection(("127.0.0.1", port), timeout=10) as s:
        try:
            s.sendall(b"GET / HTTP/1.1\r\nX: " + b"a" * 40000 + b"\r\n\r\n")
            s.shutdown(socket.SHUT_WR)
            answer = b""
            while chunk := s.recv(4096):
                answer += chunk
        except OSError as e:
            return f"error {e}"
    return answer.split(b"\r\n")[0].decode(errors="replace")


server = subprocess.Popen([penalty, "view", view], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
try:
    address = re.search(r"http://127\.0\.0\.1:(\d+)/", server.stdout.readline())
    check(address is not None, "penalty view prints the address it serves")
    answers = [oversized_request_answers(int(address.group(1))) for _ in range(20)]
    check(all(" 431 " in a for a in answers), f"penalty view answers 431 to 20 oversized headers sent whole: {set(answers)}")
finally:
    server.terminate()
    server.wait(timeout=30)

# SOFA HEAD's orders: on by default, --no-sofa-head-orders turns them off (the visitors' order);
# one contact pair here, so both orders give the same trajectory
on, off = (os.path.join(work, d) for d in ("orders_on", "orders_off"))
run("run", scene, "--steps", "20", "--quiet", "--export-states", on, "--sofa-head-orders", expect=0)
run("run", scene, "--steps", "20", "--quiet", "--export-states", off, "--no-sofa-head-orders", expect=0)
check(open(os.path.join(on, "0_cube_mstate.txt")).read() == open(os.path.join(off, "0_cube_mstate.txt")).read(),
      "--sofa-head-orders and --no-sofa-head-orders accepted; one contact pair: the same states")
p = run("run", "--help", expect=0)
check("--no-sofa-head-orders" in p.stdout, "run --help names --no-sofa-head-orders")

print("all CLI checks passed")
