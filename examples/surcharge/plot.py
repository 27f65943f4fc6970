"""The vertical stress under the centre of the strip at rest against the elastic strip-load
solution, and the settlement of the strip's centre against the layer's compression under that
stress field.

usage: plot.py RESULTS_DIR   (prints the table of README.md, writes RESULTS_DIR/surcharge.png)
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import numpy as np  # noqa: E402
from vtu import read_pvd, read_vtu  # noqa: E402

Q, B, E, NU = 50.0e3, 1.0, 20.0e6, 0.3  # as in surcharge.toml
H = 8.0  # the layer's depth: set from the results (the top particles lie half a spacing below it)


def strip_stress(x, z, n=4000):
    """sigma_z, sigma_x (compression positive) at (x, depth z) under a uniform pressure Q on
    |xi| <= B of an elastic half-space: Flamant's line load, 2 q z^3 / (pi r^4) and
    2 q z (x - xi)^2 / (pi r^4), integrated over the strip (midpoint rule, n pieces)."""
    xi = -B + (np.arange(n) + 0.5) * (2 * B / n)
    r2 = (x - xi) ** 2 + z ** 2
    w = 2 * B / n * 2 * Q / np.pi
    return np.sum(w * z ** 3 / r2 ** 2), np.sum(w * z * (x - xi) ** 2 / r2 ** 2)


def settlement_reference(n=4000):
    """Plane-strain compression of the layer under the centre, int_0^H eps_z dz with the half-space
    stresses (the rigid base's effect on them left out): eps_z = ((1 - nu^2) s_z - nu (1 + nu) s_x) / E."""
    z = (np.arange(n) + 0.5) * (H / n)
    s = np.array([strip_stress(0.0, zz) for zz in z])
    eps = ((1 - NU ** 2) * s[:, 0] - NU * (1 + NU) * s[:, 1]) / E
    return np.sum(eps) * H / n


def compare(results):
    global H
    time, name = read_pvd(os.path.join(results, "particles.pvd"))[-1]
    f = read_vtu(os.path.join(results, name))
    x0 = f["points"][:, 0] - f["displacement"][:, 0]
    y0 = f["points"][:, 1] - f["displacement"][:, 1]
    column = x0 < x0.min() + 1e-6  # the particles nearest the axis
    H = y0.max() + x0[column].mean()  # the first column's centres lie half a spacing from x = 0
    rows = []
    for i in np.argsort(-y0[column]):
        k = np.flatnonzero(column)[i]
        z = H - y0[k]
        ref = strip_stress(x0[k], z)[0]
        rows.append((z, -f["stress"][k, 1], ref))
    top = column & (y0 > y0.max() - 1e-6)
    return time, np.array(rows), -f["displacement"][top, 1].mean(), x0[column].mean()


if __name__ == "__main__":
    results = sys.argv[1] if len(sys.argv) > 1 else "results"
    time, rows, settle, x = compare(results)
    print(f"t = {time:.3g} s, column x0 = {x:.4g} m")
    print("| depth z (m) | z / b | sigma_z tsuchi (kPa) | strip solution (kPa) | difference |")
    print("|---|---|---|---|---|")
    for z, s, ref in rows:
        if z <= 4.0 * B + 1e-9:
            print(f"| {z:.3f} | {z / B:.2f} | {s / 1e3:.2f} | {ref / 1e3:.2f} | {100 * (s - ref) / ref:+.1f} % |")
    ref = settlement_reference()
    print(f"settlement of the centre: {settle * 1e3:.3f} mm; half-space stresses over the layer: {ref * 1e3:.3f} mm")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(5, 5))
        zz = np.linspace(0.05, H, 200)
        ax.plot([strip_stress(x, z)[0] / Q for z in zz], zz, "k-", lw=1, label="strip load on a half-space")
        ax.plot(rows[:, 1] / Q, rows[:, 0], "o", ms=3, label=f"tsuchi, particles at x = {x:.3g} m")
        ax.invert_yaxis()
        ax.set_xlabel(r"$\sigma_z / q$")
        ax.set_ylabel("depth z (m)")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(results, "surcharge.png"), dpi=120)
    except ImportError:
        pass
