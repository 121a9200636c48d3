#!/usr/bin/python3
"""Plot and fit the whole-scene scaling benchmark (bench/bench_scaling.cpp, issue 17).

    build/release/bench/penalty_bench_scaling --benchmark_out=scaling.json --benchmark_out_format=json
    /usr/bin/python3 bench/plot_scaling.py scaling.json [--out docs/images/scaling.png]

Reads Google Benchmark's JSON, prints the table of docs/performance.md (k, cubes, DOFs,
contacts/step, active, ms/step wall and CPU, CG iterations, phase split) and the least-squares
slopes of log(time per step) against log(contacts per step) and log(DOFs), over the k whose
contacts per step are at least --min-contacts (k = 1 has a handful of contacts: its time is the
fixed cost of a step), and draws both on log-log axes. Needs matplotlib (Debian's python3-matplotlib).
"""
import argparse
import json
import math
import sys
from pathlib import Path


def load(path):
    with open(path) as f:
        data = json.load(f)
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
    rows = []
    for b in data["benchmarks"]:
        if b.get("run_type") == "aggregate" or b.get("error_occurred"):
            continue
        if not b["name"].startswith("BM_CubesInBowl/"):
            continue
        u = scale[b.get("time_unit", "ns")]
        rows.append({
            "k": int(b["k"]), "cubes": int(b["cubes"]), "dofs": int(b["dofs"]),
            "contacts": b["contacts"], "active": b["active"], "cg": b["cg_its"], "kinetic": b.get("kinetic_j", float("nan")),
            "sunk": int(b.get("sunk", -1)),
            "wall_ms": b["real_time"] * u, "cpu_ms": b["cpu_time"] * u,
            "detect_ms": b["detect_ms"], "response_ms": b["response_ms"], "solve_ms": b["solve_ms"],
            "steps": int(b["iterations"]),
        })
    rows.sort(key=lambda r: r["k"])
    return data.get("context", {}), rows


def fit(xs, ys):
    """Least squares of log y = a + s log x; returns (s, a)."""
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((x - mx) ** 2 for x in lx)
    sxy = sum((x - mx) * (y - my) for x, y in zip(lx, ly))
    s = sxy / sxx
    return s, my - s * mx


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("json")
    p.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "docs" / "images" / "scaling.png"))
    p.add_argument("--min-contacts", type=float, default=10.0)
    a = p.parse_args()
    context, rows = load(a.json)
    if not rows:
        sys.exit("no BM_CubesInBowl results in " + a.json)

    print("| k | cubes | DOFs | contacts/step | active | ms/step (wall) | ms/step (CPU) | CG its/step | "
          "detection / response / solve ms (wall) | kinetic energy (J) | sunk nodes |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|")
    for r in rows:
        print(f"| {r['k']} | {r['cubes']} | {r['dofs']} | {r['contacts']:.0f} | {r['active']:.0f} | "
              f"{r['wall_ms']:.3g} | {r['cpu_ms']:.3g} | {r['cg']:.1f} | "
              f"{r['detect_ms']:.3g} / {r['response_ms']:.3g} / {r['solve_ms']:.3g} | {r['kinetic']:.2g} | {r['sunk']} |")

    used = [r for r in rows if r["contacts"] >= a.min_contacts]
    slopes = {}
    if len(used) >= 2:
        for key in ("wall_ms", "cpu_ms"):
            slopes[("contacts", key)] = fit([r["contacts"] for r in used], [r[key] for r in used])
            slopes[("dofs", key)] = fit([r["dofs"] for r in used], [r[key] for r in used])
        ks = ", ".join(str(r["k"]) for r in used)
        for (x, key), (s, _) in slopes.items():
            print(f"slope of log({key}) vs log({x}) over k = {ks}: {s:.2f}")
    else:
        print("fewer than two k with enough contacts: no slope")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, x, label in ((axes[0], "contacts", "contact springs per step"), (axes[1], "dofs", "DOFs")):
        for key, style, name in (("wall_ms", "o-", "wall"), ("cpu_ms", "s--", "CPU (all threads)")):
            ax.loglog([r[x] for r in rows], [r[key] for r in rows], style, label=f"ms/step, {name}")
            if (x, key) in slopes:
                s, c = slopes[(x, key)]
                xs = [used[0][x], used[-1][x]]
                ax.loglog(xs, [math.exp(c) * v ** s for v in xs], ":", color="gray",
                          label=f"least squares ({name}): slope {s:.2f}")
        for r in rows:
            ax.annotate(f"k={r['k']}", (r[x], r["wall_ms"]), textcoords="offset points", xytext=(4, -10), fontsize=7)
        ax.set_xlabel(label)
        ax.set_ylabel("time per step (ms)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="upper left")
    host = context.get("host_name", "")
    cpus = context.get("num_cpus", "")
    load_avg = context.get("load_avg", [])
    fig.suptitle(f"k×k×k FEM cubes in a bowl (penalty_bench_scaling; {cpus} CPUs{', ' + host if host else ''}"
                 f"{', load ' + ' '.join(f'{v:.1f}' for v in load_avg) if load_avg else ''})", fontsize=10)
    fig.tight_layout()
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(a.out, dpi=110)
    print("wrote", a.out)


if __name__ == "__main__":
    main()
