#!/usr/bin/env bash
# Byte-identical trajectories across a refactoring (issue 14 "One path for each fact").
#
#   scripts/check-identical-states.sh record HASHFILE [PENALTY]   run every scene, write SHA-256 sums
#   scripts/check-identical-states.sh check  HASHFILE [PENALTY]   run again, compare with HASHFILE
#
# Each scene of scenes/ and ../shared/sofa/scenes (when present), and the built-in scene, runs
# 300 steps with --export-states (SOFA's regression state files, mapped states included); the
# SHA-256 of every exported file is recorded. `check` exits 1 naming each file that differs.
# PENALTY defaults to build/release/bin/penalty. Sums are only comparable on one machine and
# compiler (floating-point results depend on both).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
mode="${1:-}"; hashfile="${2:-}"
penalty="${3:-$root/build/release/bin/penalty}"
if [[ "$mode" != record && "$mode" != check ]] || [[ -z "$hashfile" ]]; then
  echo "usage: $0 record|check HASHFILE [PENALTY]" >&2; exit 2
fi
[[ -x "$penalty" ]] || { echo "$0: no executable at $penalty (build first)" >&2; exit 2; }
shared="$root/../shared/sofa"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT

scenes=("$root"/scenes/*.scn)
if [[ -d "$shared/scenes" ]]; then scenes+=("$shared"/scenes/*.scn); fi

run_one() {  # name, then the arguments after `penalty run`
  local name="$1"; shift
  local out="$work/$name"
  mkdir -p "$out"
  if ! "$penalty" run "$@" --steps 300 --export-states "$out" --export-mapped >"$work/$name.log" 2>&1; then
    echo "$name: penalty run failed:" >&2; tail -5 "$work/$name.log" >&2; exit 1
  fi
}
run_one builtin
for scene in "${scenes[@]}"; do
  dir="$(basename "$(dirname "$scene")")"
  run_one "$dir-$(basename "$scene" .scn)" "$scene" --data-dir "$shared" --data-dir "$root/scenes"
done
(cd "$work" && find . -type f ! -name '*.log' -print0 | sort -z | xargs -0 sha256sum) >"$work/sums"
count="$(wc -l <"$work/sums")"
if [[ "$mode" == record ]]; then
  cp "$work/sums" "$hashfile"
  echo "recorded $count state files of $(( ${#scenes[@]} + 1 )) scenes in $hashfile"
else
  if diff <(cat "$hashfile") "$work/sums" >"$work/diff"; then
    echo "identical: $count state files of $(( ${#scenes[@]} + 1 )) scenes"
  else
    echo "DIFFERENT (< recorded, > now):"; cat "$work/diff"; exit 1
  fi
fi
