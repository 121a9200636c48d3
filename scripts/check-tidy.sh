#!/usr/bin/env bash
# Runs clang-tidy 14 with .clang-tidy's rules over the library's and the command line's sources,
# from a clang build's compile_commands.json (default build/asan; the presets export it). With
# PENALTY_UNITY_LIBRARY (the default) each layer's unity batches are checked, so that the headers
# are parsed once a batch; the rules' HeaderFilterRegex reports the findings in the sources they
# include. Exit 0: no finding; 1: findings (printed); 77: clang-tidy-14 missing (CTest: skipped).
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
mapfile -t files < <(/usr/bin/python3 - "$build/compile_commands.json" "$root" <<'PY'
import json, sys
commands, root = sys.argv[1], sys.argv[2]
for entry in json.load(open(commands)):
    f = entry["file"]
    # cmake/PenaltyLayer.cmake's batches of the library's layers (<build>/unity/penalty_<layer>/),
    # not the test suites' (<build>/unity/penalty_tests_<suite>/)
    library_batch = "/unity/penalty_" in f and "/unity/penalty_tests" not in f
    own_source = f.startswith(root + "/src/") or f.startswith(root + "/apps/")
    if (library_batch or own_source) and "/generated/" not in f:
        print(f)
PY
)
[ ${#files[@]} -gt 0 ] || { echo "check-tidy: no library source in $build/compile_commands.json"; exit 1; }
jobs="$(nproc)"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
status=0
printf '%s\n' "${files[@]}" | xargs -P "$jobs" -n 1 "$tool" -p "$build" --config-file="$root/.clang-tidy" --quiet >"$log" 2>&1 || status=$?
findings="$(grep -E '(warning|error): ' "$log" | grep -v '^error: too many errors' | sort -u || true)"
if [ "$status" != 0 ] || [ -n "$findings" ]; then
  grep -v -E '^[0-9]+ warnings? generated\.$' "$log" || true
  echo "check-tidy: $(printf '%s' "$findings" | grep -c . || true) findings in ${#files[@]} translation units (rules: .clang-tidy)"
  exit 1
fi
echo "check-tidy: ${#files[@]} translation units, no finding (rules: .clang-tidy)"
