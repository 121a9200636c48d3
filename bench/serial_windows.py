#!/usr/bin/python3
"""Where a multi-threaded run leaves cores idle: the main thread's work while no other thread runs.

    perf record -F 2000 -o run.data build/release/bin/penalty run SCENE --threads 2 --steps 200
    /usr/bin/python3 bench/serial_windows.py run.data [--window-ms 1] [--top 30] [--group NAME=REGEX ...]

Reads `perf script` (cpu-clock samples, one a thread every 1/F s while it runs). The run's
threads are the sampled ones; the main thread is the one with the lowest id. The run is cut into
windows (--window-ms); a window in which only the main thread has samples is serial: the others
sleep (TBB's workers block after a short spin) while the main thread works alone. Prints the
samples of each thread, the core time the run had (wall × threads, from the first to the last
sample) against the time sampled (the samples' periods; idle = the difference), the main thread's
samples in serial windows, and those samples by symbol and by group (a --group is a name and a
regular expression on the symbol; a symbol goes to the first group it matches). Needs perf.
"""
import argparse
import collections
import re
import statistics
import subprocess
import sys


def samples(data):
    out = subprocess.run(["perf", "script", "-i", data, "-F", "tid,time,period,ip,sym"], capture_output=True,
                         text=True)
    if out.returncode != 0:
        sys.exit(f"serial_windows: perf script failed on {data}: {out.stderr.strip()}")
    rows = []
    for line in out.stdout.splitlines():
        m = re.match(r"\s*(\d+)\s+([\d.]+):\s+(\d+)\s+[0-9a-f]+\s*(.*)", line)
        if m:  # (tid, time s, symbol, period s: cpu-clock's period is in ns)
            symbol = m.group(4).strip() or "[unknown]"
            rows.append((int(m.group(1)), float(m.group(2)), symbol, int(m.group(3)) * 1e-9))
    if not rows:
        sys.exit(f"serial_windows: no sample in {data}")
    return rows


def serial_samples(rows, width):
    """The main thread (lowest id) and its samples, by symbol, in the windows of `width` seconds
    (from the first sample) where no other thread has a sample. rows: (tid, time s, symbol, ...)."""
    main_tid = min(r[0] for r in rows)
    start = min(r[1] for r in rows)
    others_in = collections.Counter()
    for tid, t, *_ in rows:
        if tid != main_tid:
            others_in[int((t - start) / width)] += 1
    serial = collections.Counter()
    for tid, t, sym, *_ in rows:
        if tid == main_tid and others_in[int((t - start) / width)] == 0:
            serial[sym] += 1
    return main_tid, serial


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("data", help="perf.data of the run")
    ap.add_argument("--window-ms", type=float, default=1.0, help="window length (ms); default 1")
    ap.add_argument("--top", type=int, default=30, help="symbols listed; default 30")
    ap.add_argument("--group", action="append", default=[], metavar="NAME=REGEX",
                    help="a group of symbols (repeatable; first match wins)")
    args = ap.parse_args()
    if not args.window_ms > 0:
        sys.exit("serial_windows: --window-ms must be > 0")
    groups = []
    for g in args.group:
        name, sep, pattern = g.partition("=")
        if not sep or not name:
            sys.exit(f"serial_windows: --group '{g}' is not NAME=REGEX")
        try:
            groups.append((name, re.compile(pattern)))
        except re.error as e:
            sys.exit(f"serial_windows: --group '{g}': {e}")

    rows = samples(args.data)
    per_thread = collections.Counter(r[0] for r in rows)
    main_tid, serial = serial_samples(rows, args.window_ms / 1000.0)
    start = min(r[1] for r in rows)
    end = max(r[1] for r in rows)

    total = len(rows)
    period = statistics.median(r[3] for r in rows)  # seconds of a thread's work a sample stands for
    threads = len(per_thread)
    wall = end - start
    print(f"threads {threads}, samples {total}, wall {wall:.3f} s (first to last sample)")
    for tid, n in sorted(per_thread.items()):
        print(f"  thread {tid}{' (main)' if tid == main_tid else ''}: {n} samples ({100.0 * n / total:.1f} %)")
    busy = sum(r[3] for r in rows)
    print(f"core time {threads * wall:.3f} s, sampled {busy:.3f} s, idle {threads * wall - busy:.3f} s "
          f"(a sample = {1000 * period:.3f} ms of a thread's work)")
    n_serial = sum(serial.values())
    print(f"main thread alone (windows of {args.window_ms:g} ms without another thread's sample): "
          f"{n_serial} samples, {100.0 * n_serial / per_thread[main_tid]:.1f} % of the main thread's, "
          f"{n_serial * period:.3f} s")
    if groups:
        by_group = collections.Counter()
        for sym, n in serial.items():
            name = next((g for g, rx in groups if rx.search(sym)), "other")
            by_group[name] += n
        print("by group:")
        for name, n in by_group.most_common():
            print(f"  {n:6d}  {100.0 * n / max(1, n_serial):5.1f} %  {name}")
    print(f"top {args.top} symbols:")
    for sym, n in serial.most_common(args.top):
        print(f"  {n:6d}  {sym[:120]}")


if __name__ == "__main__":
    main()
