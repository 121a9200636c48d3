#!/usr/bin/env bash
# Compiles each test suite (tests/<suite>/test_*.cpp) as ONE translation unit, syntax only, and
# prints every name two files of a suite both define in their anonymous namespaces. The release
# build compiles the suites in unity batches of six files (PENALTY_UNITY_TESTS): a clash breaks the
# build only when both files land in one batch, which adding any file can cause.
# Usage: scripts/check-test-unity.sh [suite...]     exit 1 when a suite does not compile as one unit
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
exit $status
