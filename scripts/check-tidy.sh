#!/usr/bin/env bash
# Runs clang-tidy 14 with .clang-tidy's rules over the library's and the command line's sources,
# from a clang build's compile_commands.json (default build/asan; the presets export it). With
# PENALTY_UNITY_LIBRARY (the default) a layer's unity batches are checked a few at a time, as one
# translation unit with its batch's command (each layer compiles as one unit:
# scripts/check-test-unity.sh), so that the standard library's and Eigen's headers are parsed and
# walked once a group rather than once a batch (about 11 CPU-s a unit: the mechanics layer's 80
# files took 104 s as 10 units, 76 s as 5, on two cores); the rules' HeaderFilterRegex reports the
# findings in the sources they include.
# Exit 0: no finding; 1: findings (printed); 77: clang-tidy-14 missing (CTest: skipped).
#   scripts/check-tidy.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build/asan}"
tool="$(command -v clang-tidy-14 || true)"
if [ -z "$tool" ]; then
  echo "check-tidy: clang-tidy-14 is missing (scripts/install-deps.sh installs it)"
  exit 77
fi
if [ ! -f "$build/compile_commands.json" ]; then
  echo "check-tidy: $build/compile_commands.json is missing: configure a preset first (cmake --preset asan)"
  exit 1
fi
root="$PWD"
work="$(mktemp -d)"
log="$work/tidy.log"
trap 'rm -rf "$work"' EXIT
# Batches grouped by layer, kBatchesPerUnit to a unit (balance on two cores against the parse saved);
# the units and the command line's sources, largest first, with their commands in $work.
mapfile -t files < <(/usr/bin/python3 - "$build/compile_commands.json" "$root" "$work" <<'PY'
import json, os, sys
commands, root, work = sys.argv[1], sys.argv[2], sys.argv[3]
kBatchesPerUnit = 3
entries, units, by_layer = [], [], {}
for entry in json.load(open(commands)):
    f = entry["file"]
    # cmake/PenaltyLayer.cmake's batches of the library's layers (<build>/unity/penalty_<layer>/),
    # not the test suites' (<build>/unity/penalty_tests_<suite>/)
    library_batch = "/unity/penalty_" in f and "/unity/penalty_tests" not in f
    own_source = f.startswith(root + "/src/") or f.startswith(root + "/apps/")
    if "/generated/" in f or not (library_batch or own_source):
        continue
    if library_batch:
        by_layer.setdefault(os.path.dirname(f), []).append(entry)
    elif all(e["file"] != f for e in entries):  # (a source built by two targets: checked once)
        entries.append(entry)
        units.append((os.path.getsize(f), f))
for layer, batches in sorted(by_layer.items()):
    batches.sort(key=lambda e: e["file"])
    for g in range(0, len(batches), kBatchesPerUnit):
        group = batches[g:g + kBatchesPerUnit]
        unit = os.path.join(work, f"{os.path.basename(layer)}_{g // kBatchesPerUnit}.cpp")
        with open(unit, "w") as out:
            out.writelines(f'#include "{e["file"]}"\n' for e in group)
        first = group[0]
        command = first["command"].replace(first["file"], unit)
        entries.append({"directory": first["directory"], "command": command, "file": unit})
        units.append((len(group) * 10**6, unit))  # a group before any single source
json.dump(entries, open(os.path.join(work, "compile_commands.json"), "w"))
for _, f in sorted(units, reverse=True):
    print(f)
PY
)
[ ${#files[@]} -gt 0 ] || { echo "check-tidy: no library source in $build/compile_commands.json"; exit 1; }
jobs="$(nproc)"
status=0
printf '%s\n' "${files[@]}" | xargs -P "$jobs" -n 1 "$tool" -p "$work" --config-file="$root/.clang-tidy" --quiet >"$log" 2>&1 || status=$?
findings="$(grep -E '(warning|error): ' "$log" | grep -v '^error: too many errors' | sort -u || true)"
if [ "$status" != 0 ] || [ -n "$findings" ]; then
  grep -v -E '^[0-9]+ warnings? generated\.$' "$log" || true
  echo "check-tidy: $(printf '%s' "$findings" | grep -c . || true) findings in ${#files[@]} translation units (rules: .clang-tidy)"
  exit 1
fi
echo "check-tidy: ${#files[@]} translation units, no finding (rules: .clang-tidy)"
