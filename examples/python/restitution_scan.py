"""Restitution vs contact damping, with penalty.PenaltyForceField alone inside a tiny Python
integrator (a point of mass m hitting a fixed plane at speed v0, no gravity, symplectic Euler).

A linear spring-dashpot contact (ks, c) has damping ratio zeta = c / (2 sqrt(ks m)) and restitution
e = exp(-pi zeta / sqrt(1 - zeta^2)); the scan compares the simulated e = v_out / v0 with it.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/restitution_scan.py [OUT_DIR]

The picture goes into OUT_DIR, by default out/ in the current folder.
"""
import numpy as np

import _common
import matplotlib.pyplot as plt

import penalty

MASS, KS, V0, DT = 1.0, 1.0e4, 1.0, 1.0e-5   # kg, N/m, m/s, s
NORMAL = np.array([[0.0, 1.0, 0.0]])          # plane normal, from the plane (side 1) to the point


def bounce(damping: float) -> float:
    """Exit speed / entry speed of one impact."""
    ff = penalty.PenaltyForceField(damping=damping, time_step=DT)
    plane = np.zeros((1, 3))
    x = np.array([[0.0, 1e-6, 0.0]])
    v = np.array([[0.0, -V0, 0.0]])
    ff.add_contacts([0], [0], NORMAL, 0.0, KS)          # pen = 0 − (x − plane)·n: active below the plane
    for _ in range(200000):
        ff.renew_contacts()                              # same contact, next step
        _, f = ff.add_force(plane, x, np.zeros((1, 3)), v)
        v += DT * f / MASS
        x += DT * v
        if x[0, 1] > 0.0 and v[0, 1] > 0.0:
            return v[0, 1] / V0
    raise RuntimeError("the point did not leave the plane")


def main():
    out = _common.output_dir()
    zeta = np.linspace(0.0, 0.6, 13)
    damping = 2.0 * zeta * np.sqrt(KS * MASS)
    simulated = np.array([bounce(c) for c in damping])
    theory = np.exp(-np.pi * zeta / np.sqrt(1.0 - zeta**2))
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(damping, theory, "-", label=r"spring–dashpot: $e = \exp(-\pi\zeta/\sqrt{1-\zeta^2})$")
    ax.plot(damping, simulated, "o", label="PenaltyForceField + symplectic Euler")
    ax.set_xlabel("contact damping c (N·s/m)")
    ax.set_ylabel("restitution e = v_out / v_in")
    ax.set_title(f"m = {MASS} kg, ks = {KS:g} N/m, dt = {DT:g} s")
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = out / "restitution_scan.png"
    fig.savefig(path, dpi=110)
    print(f"{path}: largest |e_sim − e_theory| = {np.abs(simulated - theory).max():.2e}")


if __name__ == "__main__":
    main()
