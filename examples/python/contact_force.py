"""Contact force and penetration over time for the built-in scene (a soft FEM cube and a rigid
ball dropped on a floor), read from scene.contacts() after every step.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/contact_force.py [OUT_DIR]

The picture goes into OUT_DIR, by default out/ in the current folder.
"""
import numpy as np

import _common
import matplotlib.pyplot as plt

import penalty


def main():
    out = _common.output_dir()
    scene = penalty.builtin_scene()
    steps = 400
    time = np.empty(steps)
    force = {}          # pair name -> total normal force (N) per step
    penetration = np.zeros(steps)
    for k in range(steps):
        scene.step()
        time[k] = scene.time
        c = scene.contacts()
        penetration[k] = max(0.0, c["penetration"].max()) if len(c["penetration"]) else 0.0
        for p, name in enumerate(c["pairs"]):
            force.setdefault(name, np.zeros(steps))[k] = c["normal_force"][c["pair_index"] == p].sum()

    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 5.5))
    for name, f in sorted(force.items()):
        top.plot(time, f, label=name)
    top.set_ylabel("total normal force (N)")
    top.legend(fontsize=8)
    top.set_title("built-in scene: cube and ball dropped on a floor")
    bottom.plot(time, 1e3 * penetration, color="tab:red")
    bottom.set_ylabel("max penetration (mm)")
    bottom.set_xlabel("time (s)")
    fig.tight_layout()
    path = out / "contact_force.png"
    fig.savefig(path, dpi=110)
    # once everything rests, the floor carries both weights (cube 1 kg + ball 0.5 kg) on average
    floor = sum(f for name, f in force.items() if "floor" in name)
    print(f"{path}: mean floor force over the last 0.5 s {floor[-100:].mean():.3f} N "
          f"(weight of 1.5 kg: {1.5 * 9.81:.3f} N)")


if __name__ == "__main__":
    main()
