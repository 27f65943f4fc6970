"""Plots the column's vertical stress at rest against -rho g (H - y0), and its kinetic energy.

usage: plot.py RESULTS_DIR   (writes RESULTS_DIR/stress_profile.png)
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from vtu import read_pvd, read_vtu  # noqa: E402

RHO, G, H = 2000.0, 9.81, 1.0  # as in column.toml

results = sys.argv[1] if len(sys.argv) > 1 else "results"
time, name = read_pvd(os.path.join(results, "particles.pvd"))[-1]
frame = read_vtu(os.path.join(results, name))
y0 = frame["points"][:, 1] - frame["displacement"][:, 1]
syy = frame["stress"][:, 1] / 1e3
history = np.genfromtxt(os.path.join(results, "global.csv"), delimiter=",", names=True)

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.5))
ax1.plot(syy, y0, ".", ms=3, label="tsuchi, particles")
y = np.linspace(0, H, 50)
ax1.plot(-RHO * G * (H - y) / 1e3, y, "k-", lw=1, label=r"$-\rho g (H - y_0)$")
ax1.set_xlabel(r"$\sigma_{yy}$ (kPa, tension positive)")
ax1.set_ylabel(r"initial height $y_0$ (m)")
ax1.set_title(f"vertical stress at t = {time:.3g} s")
ax1.legend()
ke = history["kinetic_energy"]
ax2.semilogy(history["time"][1:], ke[1:])
ax2.set_ylim(1e-12 * ke.max(), 2 * ke.max())
ax2.set_xlabel("time (s)")
ax2.set_ylabel("kinetic energy (J/m)")
ax2.set_title("approach to rest (local damping)")
fig.tight_layout()
out = os.path.join(results, "stress_profile.png")
fig.savefig(out, dpi=120)
print(f"wrote {out}")
