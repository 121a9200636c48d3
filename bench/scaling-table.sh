#!/usr/bin/env bash
# Issue 54's scaling table: wall time of whole `penalty run`s at several thread counts, and whether
# the states are the same bits at every thread count. Made to be carried to a many-core machine
# in one call (the device tool: the pack is an ignored folder named in `carry`).
#
#   bench/scaling-table.sh pack PACK [BUILD [LABEL]]
#       on the development machine: copies BUILD/bin/penalty (default build/release) and the shared
#       libraries it loads (ldd, without the C library and the loader) into PACK/builds/LABEL
#       (default: the short commit), and, once per pack, writes the scenes into PACK/scenes: the
#       k = 8 bowl (penalty_bench_scaling), the soft body of 114 075 DOFs on the organ
#       (penalty_bench_large_scenes n = 64) and SOFA's MeshSpringForceField and collisionMultiple
#       (../shared/sofa/scenes, with their meshes). Pack a second build (before/after) into the
#       same PACK: both run on the same machine in one call.
#   bench/scaling-table.sh run PACK [THREADS...]        (default threads: 1 2 4 8 16)
#       on the machine measured: each build × scene × thread count, one `penalty run` each, its
#       states exported at the last step; prints one markdown row per build and scene: the steps'
#       wall seconds at each thread count (the whole run's, loading included, in parentheses), the
#       best speed-up of the steps over one thread, and "same bits" when every thread
#       count's state files equal one thread's (DIFFERENT, naming the thread counts, otherwise).
#
# Steps (the issue's): bowl 200, MeshSpringForceField 300, collisionMultiple 300, soft body 40
# (SCALING_SOFT_BODY_STEPS overrides; ~0.3 s a step on one core of the development machine), the soft
# body again with --reduction blocked (soft_body_100k_blocked).
# SCALING_SCENES="bowl_k8 mesh_spring ..." runs a subset; SCALING_KEEP_LOGS=DIR keeps each run's
# summary (its phases' times a step) as DIR/LABEL_SCENE_THREADS.log. Exit 0, 1 when states differ, 2 usage.
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
mode="${1:-}"
pack="${2:-}"
usage() {
    echo "usage: $0 pack PACK [BUILD [LABEL]] | run PACK [THREADS...]" >&2
    exit 2
}
[[ -n "$pack" && ("$mode" == pack || "$mode" == run) ]] || usage

scene_names=(bowl_k8 mesh_spring collision_multiple soft_body_100k soft_body_100k_blocked)
declare -A scene_file=([bowl_k8]=cubes_in_bowl_k8.scn [mesh_spring]=MeshSpringForceField.scn
    [collision_multiple]=collisionMultiple.scn [soft_body_100k]=soft_body_on_organ_n64.scn
    [soft_body_100k_blocked]=soft_body_on_organ_n64.scn)
declare -A scene_steps=([bowl_k8]=200 [mesh_spring]=300 [collision_multiple]=300
    [soft_body_100k]="${SCALING_SOFT_BODY_STEPS:-40}"
    [soft_body_100k_blocked]="${SCALING_SOFT_BODY_STEPS:-40}")
# options beyond the scene's: the soft body's one state again with the CG's dot products in blocks
# (--reduction blocked; a build without the option prints "no --reduction" for that row)
declare -A scene_options=([soft_body_100k_blocked]="--reduction blocked")

copy_libraries() {  # binary, destination folder: what ldd resolves, less glibc and the loader
    local binary="$1" dest="$2" lib
    mkdir -p "$dest"
    ldd "$binary" | awk '/=> \// { print $3 }' | while read -r lib; do
        case "$(basename "$lib")" in
            libc.so* | libm.so* | libpthread.so* | libdl.so* | librt.so* | ld-linux*) ;;
            *) cp -L "$lib" "$dest/" ;;
        esac
    done
}

write_scenes() {  # build folder, destination folder
    local build="$1" dest="$2" shared="$root/../shared/sofa"
    mkdir -p "$dest/mesh"
    # the benchmarks write the scene they would run and stop (bench/scene_probe.hpp)
    PENALTY_SCALING_SCENES="$dest" PENALTY_SCALING_SCENES_ONLY=1 \
        "$build/bench/penalty_bench_scaling" --benchmark_filter='k:8/' >/dev/null
    PENALTY_SCALING_SCENES="$dest" PENALTY_SCALING_SCENES_ONLY=1 \
        "$build/bench/penalty_bench_large_scenes" --benchmark_filter='n:64/' >/dev/null
    local scene mesh
    for scene in MeshSpringForceField collisionMultiple; do
        [[ -f "$shared/scenes/$scene.scn" ]] || { echo "$0: no $shared/scenes/$scene.scn" >&2; exit 1; }
        cp "$shared/scenes/$scene.scn" "$dest/"
        for mesh in $(grep -o 'filename="mesh/[^"]*"' "$shared/scenes/$scene.scn" | sed 's/filename="//; s/"$//'); do
            cp "$shared/$mesh" "$dest/mesh/"
        done
    done
}

if [[ "$mode" == pack ]]; then
    build="${3:-$root/build/release}"
    label="${4:-$(git -C "$root" rev-parse --short HEAD)}"
    [[ -x "$build/bin/penalty" ]] || { echo "$0: no executable at $build/bin/penalty (build first)" >&2; exit 2; }
    dest="$pack/builds/$label"
    rm -rf "$dest"
    mkdir -p "$dest/bin"
    cp "$build/bin/penalty" "$dest/bin/"
    copy_libraries "$build/bin/penalty" "$dest/lib"
    [[ -d "$pack/scenes" ]] || write_scenes "$build" "$pack/scenes"
    echo "packed $label ($(du -sh "$dest" | cut -f1)); scenes $(du -sh "$pack/scenes" | cut -f1)"
    exit 0
fi

shift 2
threads=("$@")
[[ ${#threads[@]} -gt 0 ]] || threads=(1 2 4 8 16)
[[ "${threads[0]}" == 1 ]] || threads=(1 "${threads[@]}")  # one thread: the reference of time and bits
read -r -a selected <<<"${SCALING_SCENES:-${scene_names[*]}}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
status=0

header="| build | scene | steps |"
rule="|---|---|---:|"
for t in "${threads[@]}"; do header+=" $t |"; rule+="---:|"; done
echo "$header best speed-up | states |"
echo "$rule---:|---|"

# One `penalty run` of scene $name at $t threads with build $build (label $label): its cell of the
# table into cell[$label|$t] and its steps' seconds into seconds_of[$label|$t] (empty if it failed).
declare -A cell seconds_of
measure() {
    local out="$work/$label/$name/$t" start whole seconds
    mkdir -p "$out"
    start="$(date +%s.%N)"
    if ! LD_LIBRARY_PATH="$build/lib" "$build/bin/penalty" run "$pack/scenes/${scene_file[$name]}" \
        --data-dir "$pack/scenes" --steps "$steps" --threads "$t" --quiet --export-states "$out" \
        --export-every "$steps" ${options[@]+"${options[@]}"} >"$out.log" 2>&1; then
        cell[$label|$t]="failed"
        seconds_of[$label|$t]=""
        echo "$label $name --threads $t failed:" >&2
        tail -3 "$out.log" >&2
        status=1
        return
    fi
    whole="$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')"
    [[ -z "${SCALING_KEEP_LOGS:-}" ]] ||
        { mkdir -p "$SCALING_KEEP_LOGS" && cp "$out.log" "$SCALING_KEEP_LOGS/${label}_${name}_$t.log"; }
    # the steps' wall time from penalty's summary ("steps: N ... in S s wall"), without the
    # scene's loading, which is serial (~1 s for the soft body's 9 MB scene)
    seconds="$(sed -n 's/^steps: .* in \([0-9.]*\) s wall.*/\1/p' "$out.log")"
    [[ -n "$seconds" ]] || seconds="$whole"
    cell[$label|$t]="$(printf '%.2f' "$seconds") s ($(printf '%.2f' "$whole"))"
    seconds_of[$label|$t]="$seconds"
}

# Scene by scene, thread count by thread count, the builds one after the other: a slow phase of
# the machine falls on every build alike.
builds=("$pack"/builds/*/)
for name in "${selected[@]}"; do
    steps="${scene_steps[$name]}"
    read -r -a options <<<"${scene_options[$name]:-}"
    runnable=()
    for build in "${builds[@]}"; do
        label="$(basename "$build")"
        if [[ ${#options[@]} -gt 0 ]] && ! LD_LIBRARY_PATH="$build/lib" "$build/bin/penalty" run --help |
            grep -q -- "${options[0]}"; then
            continue
        fi
        runnable+=("$build")
    done
    for t in "${threads[@]}"; do
        for build in "${runnable[@]}"; do
            label="$(basename "$build")"
            measure
        done
    done
    for build in "${builds[@]}"; do
        label="$(basename "$build")"
        row="| $label | $name | $steps |"
        if [[ ! " ${runnable[*]} " == *" $build "* ]]; then
            echo "$row no ${options[0]} |"
            continue
        fi
        one="${seconds_of[$label|1]}"
        best=""
        differing=()
        for t in "${threads[@]}"; do
            row+=" ${cell[$label|$t]} |"
            [[ "$t" != 1 && -n "${seconds_of[$label|$t]}" && -n "$one" ]] || continue
            diff -rq "$work/$label/$name/1" "$work/$label/$name/$t" >/dev/null || differing+=("$t")
            best="$(awk -v one="$one" -v s="${seconds_of[$label|$t]}" -v best="${best:-0}" \
                'BEGIN { v = one / s; print (v > best ? v : best) }')"
        done
        row+=" $(printf '%.2f' "${best:-1}")× |"
        if [[ ${#differing[@]} -eq 0 ]]; then
            row+=" same bits |"
        else
            row+=" DIFFERENT at ${differing[*]} |"
            status=1
        fi
        echo "$row"
    done
done
exit "$status"
