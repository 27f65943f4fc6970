"""The two-disk impact from the runs' CSV files: the disks' mean velocities along x (the diagonal's
component), the kinetic, strain and total energy, every 0.25 s, and the energy and rebound at the
end against the start. With matplotlib installed it also draws RESULTS_DIR/disks.png.

usage: plot.py RESULTS_DIR [RESULTS_DIR ...]   (each the output directory of one run of disks.toml)
"""
import csv
import os
import sys


def rows(path):
    with open(path, newline="") as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def report(directory):
    g = rows(os.path.join(directory, "global.csv"))
    r = rows(os.path.join(directory, "recorders.csv"))
    print(f"{directory}:")
    print(f"{'t (s)':>7} {'lower vx':>9} {'upper vx':>9} {'kinetic':>9} {'strain':>9} {'total':>9}  (J/m)")
    next_t = 0.0
    for gr, rr in zip(g, r):
        if gr["time"] + 1e-9 >= next_t or gr is g[-1]:
            print(f"{gr['time']:7.3f} {rr['lower_vx']:9.5f} {rr['upper_vx']:9.5f} {gr['kinetic_energy']:9.5f} "
                  f"{gr['strain_energy']:9.5f} {gr['kinetic_energy'] + gr['strain_energy']:9.5f}")
            next_t += 0.25
    e0 = g[0]["kinetic_energy"] + g[0]["strain_energy"]
    e1 = g[-1]["kinetic_energy"] + g[-1]["strain_energy"]
    v0 = r[0]["upper_vx"] - r[0]["lower_vx"]
    v1 = r[-1]["upper_vx"] - r[-1]["lower_vx"]
    print(f"energy at the end {100.0 * e1 / e0:.2f} % of the start's; relative velocity {v0:+.5f} -> {v1:+.5f} m/s "
          f"(coefficient of restitution {-v1 / v0:.3f})\n")
    return g, r


def main():
    runs = [(d, *report(d)) for d in sys.argv[1:]]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    for d, g, r in runs:
        name = os.path.basename(os.path.normpath(d))
        t = [x["time"] for x in g]
        ax1.plot(t, [x["lower_vx"] for x in r], label=f"{name}: lower disk")
        ax1.plot(t, [x["upper_vx"] for x in r], "--", label=f"{name}: upper disk")
        ax2.plot(t, [x["kinetic_energy"] + x["strain_energy"] for x in g], label=f"{name}: total")
        ax2.plot(t, [x["kinetic_energy"] for x in g], ":", label=f"{name}: kinetic")
    ax1.set_xlabel("t (s)"), ax1.set_ylabel("mean velocity x (m/s)"), ax1.legend(fontsize=7)
    ax2.set_xlabel("t (s)"), ax2.set_ylabel("energy (J/m)"), ax2.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(sys.argv[1], "disks.png"), dpi=120)


if __name__ == "__main__":
    main()
