#!/usr/bin/env bash
# Compiles each test suite (tests/<suite>/test_*.cpp) and each library layer (src/<folder>/**.cpp
# with src/kernels/<folder>/*.cpp) as ONE translation unit, syntax only, and prints every name two
# files of a suite or layer both define in their anonymous namespaces. The builds compile the
# suites in unity batches of 24 files (PENALTY_UNITY_TESTS) and the layers in batches of eight
# (PENALTY_UNITY_LIBRARY): a clash breaks the build only when both files land in one batch, which
# adding any file can cause.
# Usage: scripts/check-test-unity.sh [suite-or-layer...]   exit 1 when one does not compile as one unit
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root/tests"
suites=("$@")
[ ${#suites[@]} -eq 0 ] && mapfile -t suites < <(ls -d */ | tr -d /)
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
status=0
for suite in "${suites[@]}"; do
  mapfile -t files < <(ls "$suite"/test_*.cpp 2>/dev/null | grep -v '_allocation\.cpp$')
  [ ${#files[@]} -eq 0 ] && continue
  unit="$work/$suite.cpp"
  for f in "${files[@]}"; do echo "#include \"$root/tests/$f\""; done > "$unit"
  if ! out=$(g++ -std=c++20 -fsyntax-only -DPENALTY_SHARED_DIR=\"\" -DPENALTY_SOURCE_DIR=\"\" \
        -I"$root/include" -I"$root/src" -I"$root/tests/support" -I"$root/tests/collision" \
        -isystem /usr/include/eigen3 "$unit" 2>&1); then
    echo "== $suite: its files do not compile as one unit"
    grep -E 'error:' <<<"$out" | head -20
    status=1
  else
    echo "== $suite: ok"
  fi
done
# The library's layers (cmake/PenaltyLayer.cmake): every source of src/<folder>/, its sub-folders
# included, and of src/kernels/<folder>/.
cd "$root/src"
layers=("$@")
[ ${#layers[@]} -eq 0 ] && mapfile -t layers < <(ls -d */ | tr -d / | grep -v '^kernels$')
for layer in "${layers[@]}"; do
  [ -d "$layer" ] || continue
  mapfile -t files < <(find "$layer" -name '*.cpp' | sort; [ -d "kernels/$layer" ] && find "kernels/$layer" -maxdepth 1 -name '*.cpp' | sort)
  [ ${#files[@]} -eq 0 ] && continue
  unit="$work/layer_$layer.cpp"
  for f in "${files[@]}"; do echo "#include \"$root/src/$f\""; done > "$unit"
  if ! out=$(g++ -std=c++20 -fsyntax-only -DNDEBUG -I"$root/include" -I"$root/src" -isystem /usr/include/eigen3 \
        "$unit" 2>&1); then
    echo "== src/$layer: its files do not compile as one unit"
    grep -E 'error:' <<<"$out" | head -20
    status=1
  else
    echo "== src/$layer: ok"
  fi
done
exit $status
