#!/usr/bin/env bash
# Rewrites tests/scene/expected/<scene>/ (the stored states of the project scenes' regression
# test, tests/scene/test_project_scenes.cpp) with `penalty run --export-states`, for the runs
# listed in tests/scene/expected/manifest.txt. Builds penalty (Release) first.
#
#   scripts/regenerate-expected.sh [BUILD_DIR]     (default: build/regenerate-expected)
#
# Only run it after a deliberate change of the numbers, and review `git diff --stat
# tests/scene/expected` (then the diff itself) before committing: see scenes/README.md.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build/regenerate-expected}"
jobs="${PENALTY_JOBS:-2}"

cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPENALTY_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target penalty_cli
penalty="$build/bin/penalty"

expected="$root/tests/scene/expected"
while read -r scene steps every; do
    case "$scene" in ''|'#'*) continue ;; esac
    out="$expected/$scene"
    rm -rf "$out"
    mkdir -p "$out"
    "$penalty" run "$root/scenes/$scene.scn" --steps "$steps" --export-every "$every" \
        --export-states "$out" --quiet
    echo "$scene: $steps steps, every $every -> $(ls "$out" | wc -l) state files"
done < "$expected/manifest.txt"
