"""Energy balance of a damped bounce, with penalty.PenaltyForceField alone: a 1 kg point dropped
from 0.1 m on a plane, contact damping c = 20 N·s/m. Kinetic + gravitational + stored in the
contact + dissipated by the contact stays at its initial value up to the integrator's error.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/energy_balance.py [OUT_DIR]

The picture goes into OUT_DIR, by default out/ in the current folder.
"""
import numpy as np

import _common
import matplotlib.pyplot as plt

import penalty

MASS, KS, DAMPING, G, DT, STEPS = 1.0, 1.0e4, 20.0, 9.81, 1.0e-5, 60000


def main():
    out = _common.output_dir()
    ff = penalty.PenaltyForceField(damping=DAMPING, time_step=DT)
    plane = np.zeros((1, 3))
    x = np.array([[0.0, 0.1, 0.0]])
    v = np.zeros((1, 3))
    ff.add_contacts([0], [0], [[0.0, 1.0, 0.0]], 0.0, KS)
    rows = np.empty((STEPS, 5))
    for k in range(STEPS):
        ff.renew_contacts()
        _, f = ff.add_force(plane, x, np.zeros((1, 3)), v)
        kinetic = 0.5 * MASS * float(v @ v.T)
        rows[k] = [k * DT, kinetic, MASS * G * x[0, 1], ff.potential_energy(), ff.dissipated_energy]
        f[0, 1] -= MASS * G
        v += DT * f / MASS
        x += DT * v
    t, kinetic, gravity, stored, dissipated = rows.T
    total = kinetic + gravity + stored + dissipated
    fig, ax = plt.subplots(figsize=(7, 4))
    for y, label in ((kinetic, "kinetic"), (gravity, "gravity"), (stored, "stored in the contact"),
                     (dissipated, "dissipated by contact damping"), (total, "sum")):
        ax.plot(t, y, label=label, lw=2 if label == "sum" else 1)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy (J)")
    ax.set_title("damped bounce: energy balance")
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = out / "energy_balance.png"
    fig.savefig(path, dpi=110)
    print(f"{path}: initial energy {total[0]:.6f} J, final {total[-1]:.6f} J, "
          f"largest drift {np.abs(total - total[0]).max():.2e} J")


if __name__ == "__main__":
    main()
