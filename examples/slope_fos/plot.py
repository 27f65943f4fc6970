"""The failure mechanism of a `tsuchi fos` search: the particles of DIR/fos/mechanism.vtu (the
trial at the upper end of the bracket, the smallest factor found to fail) coloured by their
plastic shear strain and by their displacement since the trial's start, over the slope's outline.

usage: plot.py RESULTS_DIR [--out PNG]   (default RESULTS_DIR/fos/mechanism.png)

Prints the bracket and the trials of RESULTS_DIR/fos/trials.csv. Needs numpy and matplotlib.
"""
import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import numpy as np  # noqa: E402
from vtu import read_pvd, read_vtu  # noqa: E402

OUTLINE = [(20.0, 0.0), (52.0, 0.0), (52.0, 10.0), (40.0, 10.0), (20.0, 0.0)]  # slope_fos.toml
SLOPE_AREA = 220.0  # m^2, the polygon's


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("results", help="the output directory of `tsuchi fos` (holds fos/)")
    p.add_argument("--out", help="the picture to write (default RESULTS/fos/mechanism.png)")
    a = p.parse_args()
    fos = os.path.join(a.results, "fos")
    with open(os.path.join(fos, "trials.csv"), newline="") as f:
        trials = list(csv.DictReader(f))
    for t in trials:
        print(f"trial {t['trial']:>2}  F = {float(t['factor']):.5f}  {t['result']:<6} ({t['reason']}), "
              f"{t['steps']} steps, largest displacement {1e3 * float(t['max_displacement']):.1f} mm")
    (f_stable, _), (f_fails, name) = read_pvd(os.path.join(fos, "fos.pvd"))
    print(f"bracket: stands at F = {f_stable:.4f}, fails at F = {f_fails:.4f}; "
          f"factor of safety {0.5 * (f_stable + f_fails):.3f}")

    frame = read_vtu(os.path.join(fos, name))
    xy = frame["points"][:, :2]
    eps_p = frame["plastic_shear_strain"]
    u = np.linalg.norm(frame["displacement"][:, :2], axis=1)
    spacing = np.sqrt(SLOPE_AREA / len(xy))  # the particles' spacing (they start on a regular lattice)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    fig, axes = plt.subplots(2, 1, figsize=(8, 6.2), sharex=True)
    ox, oy = zip(*OUTLINE)
    for ax, value, label in ((axes[0], eps_p, "plastic shear strain"),
                             (axes[1], 1e3 * u, "displacement in the trial (mm)")):
        # Each particle a square of its spacing around its position (in the current shape).
        half = 0.55 * spacing  # a little more than half: no gaps where the lattice has sheared
        corners = np.array([[-half, -half], [half, -half], [half, half], [-half, half]])
        sc = PolyCollection(xy[:, None, :] + corners[None, :, :], array=value, cmap="viridis", linewidths=0)
        ax.add_collection(sc)
        ax.plot(ox, oy, "k-", lw=0.6)
        ax.set_aspect("equal")
        ax.set_xlim(14, 53)
        ax.set_ylim(-0.5, 11)
        ax.set_ylabel("y (m)")
        fig.colorbar(sc, ax=ax, label=label, shrink=0.85)
    axes[1].set_xlabel("x (m)")
    axes[0].set_title(f"Griffiths & Lane (1999) ex. 1, h = {spacing * 2:g} m cells: mechanism at F = {f_fails:.4f} "
                      f"(stands at {f_stable:.4f})", fontsize=9)
    fig.tight_layout()
    out = a.out or os.path.join(fos, "mechanism.png")
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
