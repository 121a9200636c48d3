#!/usr/bin/env python3
"""The command line as a newcomer meets it: a misspelt option is named (not taken for the scene),
`--version`, one thread limit in `--help`, the docs and the library, one line for a run of ignored
components in `penalty info`, and `--summary-json`.

Usage: check_cli_options.py PENALTY_EXECUTABLE SOURCE_DIR WORK_DIR
Every check prints one line; the script exits 1 at the first failure (with the command's output).
"""
import json
import os
import re
import shutil
import subprocess
import sys

penalty, source, work = (os.path.abspath(a) for a in sys.argv[1:4])
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
scene = os.path.join(source, "tests", "cli", "cube_on_floor.scn")


def run(*args, expect):
    p = subprocess.run([penalty, *args], capture_output=True, text=True, timeout=300, cwd=work)
    if p.returncode != expect:
        print(f"FAIL: penalty {' '.join(args)}: exit {p.returncode}, expected {expect}\n--- stdout\n{p.stdout}--- stderr\n{p.stderr}")
        sys.exit(1)
    print(f"ok: penalty {' '.join(args)} -> exit {expect}")
    return p


def check(condition, what, output=""):
    if not condition:
        print(f"FAIL: {what}\n{output}")
        sys.exit(1)
    print(f"ok: {what}")


# A misspelt option before the scene: named, with the nearest option; never "scene: File does not exist".
for args, name, nearest in [(["run", "--stpes", "10"], "--stpes", "--steps"),
                            (["run", "--stpes=10", scene], "--stpes", "--steps"),
                            (["run", scene, "--thread", "2"], "--thread", "--threads"),
                            (["info", "--data-dri", "x", scene], "--data-dri", "--data-dir"),
                            (["run", "--frobnicate", scene], "--frobnicate", None)]:
    p = run(*args, expect=2)
    check(f"unknown option '{name}'" in p.stderr and "does not exist" not in p.stderr
          and (nearest is None or f"did you mean '{nearest}'" in p.stderr)
          and (nearest is not None or "did you mean" not in p.stderr),
          f"{' '.join(args)}: names {name}" + (f" and suggests {nearest}" if nearest else ""), p.stderr)
p = run("run", scene, "--steps", "-3", expect=2)
check("out of range" in p.stderr and "unknown option" not in p.stderr, "a negative value is a value, not an option", p.stderr)

# --version: the CMake project's version
with open(os.path.join(source, "CMakeLists.txt")) as f:
    version = re.search(r"project\(penalty VERSION ([0-9.]+)", f.read()).group(1)
p = run("--version", expect=0)
check(p.stdout.strip() == f"penalty {version}", f"--version prints 'penalty {version}'", p.stdout)

# The thread limit: one number, penalty::kMaxThreads, in --help, in docs/reliability.md and enforced.
with open(os.path.join(source, "include", "penalty", "simulation", "simulation.hpp")) as f:
    max_threads = int(re.search(r"inline constexpr int kMaxThreads = (\d+);", f.read()).group(1))
p = run("run", "--help", expect=0)
check(re.search(rf"--threads \S*INT in \[1, {max_threads}\]", p.stdout) is not None, f"run --help: --threads 1 to {max_threads}",
      p.stdout)
with open(os.path.join(source, "docs", "reliability.md")) as f:
    row = next(line for line in f if line.startswith("| `--threads`"))
check(f"1 … {max_threads} " in row and "hardware" not in row, "docs/reliability.md states the same thread limit", row)
run("run", scene, "--steps", "1", "--quiet", "--threads", str(max_threads), expect=0)
p = run("run", scene, "--threads", str(max_threads + 1), expect=2)
check(f"out of range (1 to {max_threads})" in p.stderr, "one thread more is refused with the range", p.stderr)

# penalty info: a run of ignored components of one type is one line
plugins = "\n".join(f'    <RequiredPlugin pluginName="Sofa.Component.Part{i}"/>' for i in range(14))
with open(scene) as f:
    text = f.read()
with_plugins = os.path.join(work, "plugins.scn")
with open(with_plugins, "w") as f:
    f.write(re.sub(r"(<Node name=\"root\"[^>]*>\n)", lambda m: m.group(1) + plugins + "\n", text, count=1))
p = run("info", with_plugins, expect=0)
lines = [line for line in p.stdout.splitlines() if "RequiredPlugin" in line]
check(len(lines) == 1 and re.search(r"RequiredPlugin \u00d714 +ignored \(plugin loading\)", lines[0]) is not None,
      "penalty info: 14 RequiredPlugins are one line", "\n".join(lines))

# --summary-json: the summary penalty prints, as JSON (the keys of Python's Scene.run())
summary = os.path.join(work, "summary.json")
p = run("run", scene, "--steps", "40", "--quiet", "--summary-json", summary, expect=0)
with open(summary) as f:
    data = json.load(f)
expected_keys = {"steps", "dt", "simulated_time", "wall_seconds", "detection_seconds", "response_seconds",
                 "solve_seconds", "output_seconds", "mean_contacts", "max_contacts", "max_penetration", "kinetic_energy",
                 "contact_energy", "dissipated_energy", "cg", "mean_cg_iterations", "max_cg_iterations", "cg_limit_steps",
                 "newton", "mean_newton_iterations", "max_newton_iterations", "newton_unconverged_steps", "state_files",
                 "tunnelling", "text"}
check(set(data) == expected_keys, "summary JSON has every field of the summary", sorted(data))
check(data["tunnelling"] is None, "summary JSON: no tunnelling guard, tunnelling is null", data["tunnelling"])
check(data["steps"] == 40 and data["text"] in p.stdout and f"maximum penetration {data['max_penetration']:.6g} m" in p.stdout
      and f"max {data['max_contacts']};" in p.stdout, "summary JSON holds the printed numbers", json.dumps(data, indent=1))
p = run("run", scene, "--steps", "5", "--quiet", "--no-tunnelling", "warn", "--summary-json", summary, expect=0)
with open(summary) as f:
    guard = json.load(f)["tunnelling"]
check(isinstance(guard, dict) and guard["mode"] == "warn" and guard["crossings"] == 0,
      "summary JSON: the guard's totals under tunnelling", guard)
p = run("run", scene, "--steps", "2", "--quiet", "--summary-json", os.path.join(scene, "x.json"), expect=5)
check(("cannot write" in p.stderr or "cannot open" in p.stderr) and "x.json" in p.stderr,
      "an unwritable --summary-json is exit 5 naming the file", p.stderr)

# Every option the component list names (e.g. "penalty run writes VTK with --vtk DIR") is one of
# `penalty run` or `penalty info`: a summary never sends a user to an option that does not exist.
p = run("info", "--components", expect=0)
named = set(re.findall(r"(?<![\w-])--[a-z][a-z0-9-]*", p.stdout))
helps = run("run", "--help", expect=0).stdout + run("info", "--help", expect=0).stdout
offered = set(re.findall(r"(?<![\w-])--[a-z][a-z0-9-]*", helps))
check(named and named <= offered, f"the component list names only real options ({sorted(named)})",
      f"not options: {sorted(named - offered)}")

print("CLI option checks passed")
