#!/usr/bin/env bash
# Builds the libFuzzer targets (preset `asan`: clang++, ASan + UBSan; the same build as the
# sanitizer test suite) and runs each one, one a core.
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET ...]     (default: 40 s each, every target)
# Targets: scene_info scene_step mesh_obj mesh_gmsh mesh_sph mesh_vtk http_request.
# Corpora grow in build/fuzz-corpus/<target> (kept between runs, so a long run by hand resumes
# where the last one stopped); seeds come from scenes/, tests/ and fuzz/seeds/. A crash, leak,
# sanitizer report or time-out leaves its input in build/fuzz-artifacts/<target>/ and makes this
# script fail; copy such an input into fuzz/regressions/ (tests/scene/test_fuzz_regressions.cpp
# runs every file there in the normal test suite). See docs/reliability.md.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-40}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scene_info scene_step mesh_obj mesh_gmsh mesh_sph mesh_vtk http_request)

command -v clang++ >/dev/null || { echo "fuzz: clang++ is missing (scripts/install-deps.sh installs it)"; exit 1; }
cmake --preset asan >/dev/null
cmake --build --preset asan --target "${targets[@]/#/penalty_fuzz_}"  # only the targets asked for

root="$PWD"
seeds_of() {
  case "$1" in
    scene_*) ls "$root"/scenes/*.scn "$root"/tests/cli/*.scn "$root"/tests/io/data/scenes/*.scn "$root"/fuzz/seeds/scene/* ;;
    mesh_obj) ls "$root"/scenes/mesh/*.obj "$root"/tests/io/data/mesh/*.obj "$root"/fuzz/seeds/obj/* ;;
    mesh_gmsh) ls "$root"/scenes/mesh/*.msh "$root"/tests/io/data/mesh/*.msh "$root"/fuzz/seeds/gmsh/* ;;
    mesh_sph) ls "$root"/scenes/mesh/*.sph "$root"/tests/io/data/mesh/*.sph "$root"/fuzz/seeds/sph/* ;;
    mesh_vtk) ls "$root"/tests/io/data/mesh/*.vtk "$root"/fuzz/seeds/vtk/* ;;
    http_request) ls "$root"/fuzz/seeds/http/* ;;
  esac
}

# One target: its corpus, seeds and dictionary; exit status 0 when it found nothing.
run_target() {
  local t="$1"
  local corpus="$root/build/fuzz-corpus/$t"
  local artifacts="$root/build/fuzz-artifacts/$t/"
  mkdir -p "$corpus" "$artifacts"
  local seed_dir
  seed_dir="$(mktemp -d)"
  for f in $(seeds_of "$t" 2>/dev/null); do cp "$f" "$seed_dir/"; done
  echo "=== fuzz $t: ${seconds} s, seed 1, corpus $(ls "$corpus" | wc -l) inputs + $(ls "$seed_dir" | wc -l) seeds" \
    > "$root/build/fuzz-$t.head"
  local dict=()
  case "$t" in
    scene_*) dict=(-dict="$root/fuzz/scene.dict") ;;
    http_request) dict=(-dict="$root/fuzz/http.dict") ;;
  esac
  # Scene inputs resolve mesh names against scenes/ (the seeds' own meshes).
  local rc=0
  ( cd "$root/scenes" && "$root/build/asan/fuzz/penalty_fuzz_$t" -seed=1 -max_total_time="$seconds" \
      -timeout=20 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
      "${dict[@]}" -artifact_prefix="$artifacts" "$corpus" "$seed_dir" ) \
    > "$root/build/fuzz-$t.log" 2>&1 || rc=$?
  rm -rf "$seed_dir"
  return "$rc"
}

# The targets run side by side, one a core (each libFuzzer process is one thread); their reports
# are printed in target order once all have finished.
jobs_at_once="$(nproc 2>/dev/null || echo 1)"
declare -A pid_of
failed=()
report() {
  local t="$1" rc="$2"
  cat "$root/build/fuzz-$t.head"
  if [ "$rc" -eq 0 ]; then
    grep -E "stat::number_of_executed_units|cov:" "$root/build/fuzz-$t.log" | tail -2
  else
    echo "fuzz $t FAILED: see build/fuzz-$t.log and $root/build/fuzz-artifacts/$t/"; tail -40 "$root/build/fuzz-$t.log"
    failed+=("$t")
  fi
}
declare -A rc_of
running=()
for t in "${targets[@]}"; do
  run_target "$t" &
  pid_of[$t]=$!
  running+=("$t")
  if [ ${#running[@]} -ge "$jobs_at_once" ]; then
    first="${running[0]}"
    rc=0; wait "${pid_of[$first]}" || rc=$?
    rc_of[$first]=$rc
    running=("${running[@]:1}")
  fi
done
for t in "${running[@]}"; do
  rc=0; wait "${pid_of[$t]}" || rc=$?
  rc_of[$t]=$rc
done
for t in "${targets[@]}"; do report "$t" "${rc_of[$t]}"; done
if [ ${#failed[@]} -gt 0 ]; then echo "fuzz: findings in ${failed[*]}"; exit 1; fi
echo "fuzz: ${#targets[@]} targets, no finding"
