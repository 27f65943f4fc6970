"""Plots a 3D triaxial run of examples/triaxial_3d: q against axial strain (bottom row and cap
reaction, with the Mohr-Coulomb peak) and the maximum shear strain on the vertical section
through the specimen's axis (particles within one spacing of y = 0) in the last frame.

    /usr/bin/python3 examples/triaxial_3d/plot.py results/triaxial_3d/test2_cylinder
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from vtu import read_pvd, read_vtu  # noqa: E402


def main(run):
    rows = list(csv.DictReader(open(os.path.join(run, "recorders.csv"))))[1:]
    eps = [100 * float(r["axial_strain"]) for r in rows]
    s = math.sin(math.radians(30.5))
    n = (1 + s) / (1 - s)
    q_mc = 50 * (n - 1) + 2 * 8.5 * math.sqrt(n)
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4.5))
    a.plot(eps, [float(r["q_kPa"]) for r in rows], label="bottom row")
    a.plot(eps, [float(r["q_cap_kPa"]) for r in rows], "--", label="cap reaction / section")
    a.axhline(q_mc, color="k", lw=0.8, label=f"Mohr-Coulomb {q_mc:.1f} kPa")
    a.set_xlabel("axial strain (%)")
    a.set_ylabel("q (kPa)")
    a.legend()
    frames = read_pvd(os.path.join(run, "particles.pvd"))
    last = read_vtu(os.path.join(run, frames[-1][1]))
    p = last["points"]
    on = abs(p[:, 1]) < 0.0025
    sc = b.scatter(p[on, 0], p[on, 2], c=last["max_shear_strain"][on], s=4, cmap="viridis", vmax=0.3)
    b.set_aspect("equal")
    b.set_xlabel("x (m)")
    b.set_ylabel("z (m)")
    b.set_title("max shear strain, section y = 0")
    fig.colorbar(sc, ax=b)
    fig.tight_layout()
    out = os.path.join(run, "triaxial_3d.png")
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "results/triaxial_3d/test2_cylinder")
