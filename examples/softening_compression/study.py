#!/usr/bin/python3
"""Mesh dependence of a softening plane-strain compression, and its regularisation.

Runs specimen.toml at two cell sizes (2.5 and 1.25 mm), each with the cohesion table as given and
with softening_length L = 2.5 mm (the table's k scaled by L / h: 1 on the coarse grid, 2 on the fine
one), then writes into reports/:
curves.csv (axial strain and q of every run), curves.png (the four curves), bands.png (the
last frames) and summary.md (peak
q, the axial strain from the peak to the half drop, q at 2.5, 3, 4 and 5 % axial strain, the band
measures of the last frame), also printed.

usage: study.py [--tsuchi PATH] [--jobs N] [--strain 0.05] [--results DIR]
"""
import argparse
import math
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(REPO, "tools"))
from vtu import read_pvd, read_vtu  # noqa: E402

CONFINING_KPA = 10.0
PEAK_C_KPA, RESIDUAL_C_KPA, PHI_DEG = 8.5, 1.0, 30.5
LENGTH = 0.0025  # m, softening_length of the regularised runs: the coarse cell, so the coarse run is the same with and without it

CASES = [  # name, cell size (m), softening_length (m) or None
    ("h2.5_table", 0.0025, None),
    ("h1.25_table", 0.00125, None),
    ("h2.5_L2.5", 0.0025, LENGTH),
    ("h1.25_L2.5", 0.00125, LENGTH),
]


def mohr_coulomb_q(c_kpa, sigma3_kpa=CONFINING_KPA, phi_deg=PHI_DEG):
    """Plane-strain Mohr-Coulomb deviator q = sigma3 (N - 1) + 2 c sqrt(N), kPa."""
    s = math.sin(math.radians(phi_deg))
    n = (1 + s) / (1 - s)
    return sigma3_kpa * (n - 1) + 2 * c_kpa * math.sqrt(n)


def run_case(tsuchi, out, cell, length, strain, extra=()):
    """Runs specimen.toml into `out`; returns (seconds, completed process)."""
    cmd = [tsuchi, "run", os.path.join(HERE, "specimen.toml"), "-q", "--output", out,
           "--set", f"grid.cell_size={cell}", "--set", f"recorders.0.stop_above={strain}"]
    if length is not None:
        cmd += ["--set", f"materials.0.softening_length={length}"]
    for e in extra:
        cmd += ["--set", e]
    t0 = time.time()
    r = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
    return time.time() - t0, r


def band_measures(frame_path, field="plastic_shear_strain", top=0.10):
    """Localisation of `field` in a frame's specimen (body 0), at the particles' initial positions:
    share: the part of the field's sum carried by the top 10 % of particles (0.10 if uniform);
    spread: sqrt(minor / major principal variance) of the positions of those particles, weighted
    by the field: near 0 for one straight band, about 0.5-1 for an X of two or a diffuse zone;
    angle: the inclination of their major axis from horizontal (degrees)."""
    f = read_vtu(frame_path)
    sel = f["body"] == 0
    pos = (f["points"] - f["displacement"])[sel, :2]
    g = f[field][sel]
    order = np.argsort(g)[::-1]
    n = max(1, int(top * len(g)))
    hot = order[:n]
    share = g[hot].sum() / max(g.sum(), 1e-300)
    w = g[hot] / g[hot].sum()
    centre = (w[:, None] * pos[hot]).sum(axis=0)
    d = pos[hot] - centre
    cov = (w[:, None, None] * np.einsum("ni,nj->nij", d, d)).sum(axis=0)
    vals, vecs = np.linalg.eigh(cov)
    spread = math.sqrt(max(vals[0], 0.0) / vals[1])
    major = vecs[:, 1]
    angle = math.degrees(math.atan2(abs(major[1]), abs(major[0])))
    return {"share": share, "spread": spread, "angle": angle}


def read_curve(out):
    rec = np.genfromtxt(os.path.join(out, "recorders.csv"), delimiter=",", names=True)
    return rec["axial_strain"], rec["q_kPa"]


def q_at(strain, q, at):
    """q at axial strain `at`, the mean over +-0.1 % (the curve oscillates slightly)."""
    sel = np.abs(strain - at) <= 0.001
    return float(q[sel].mean()) if sel.any() else float("nan")


def last_frame(out):
    _, last = read_pvd(os.path.join(out, "particles.pvd"))[-1]
    return os.path.join(out, last)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tsuchi", default=os.path.join(REPO, "build", "app", "tsuchi"))
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--strain", type=float, default=0.06)
    ap.add_argument("--results", default=os.path.join(REPO, "results", "softening_compression"))
    args = ap.parse_args()

    def one(case):
        name, cell, length = case
        out = os.path.join(args.results, name)
        seconds, r = run_case(args.tsuchi, out, cell, length, args.strain)
        if r.returncode != 0:
            raise SystemExit(f"{name} failed ({r.returncode}):\n{r.stdout}\n{r.stderr}")
        print(f"{name}: {seconds:.0f} s", flush=True)
        return name, cell, length, seconds, out

    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        runs = list(pool.map(one, CASES))

    reports = os.path.join(HERE, "reports")
    os.makedirs(reports, exist_ok=True)
    rows, lines = [], []
    peak_mc, res_mc = mohr_coulomb_q(PEAK_C_KPA), mohr_coulomb_q(RESIDUAL_C_KPA)
    lines.append(f"Mohr-Coulomb plane-strain q at sigma3 = 10 kPa: peak (c = 8.5 kPa) {peak_mc:.2f} kPa, "
                 f"residual (c = 1 kPa) {res_mc:.2f} kPa.\n")
    at = (0.025, 0.03, 0.04, 0.05)
    lines.append("| run | cell (mm) | softening_length | peak q (kPa) | at axial strain | peak to half drop | "
                 + " | ".join(f"q at {100 * a:g} %" for a in at) + " | band share | band spread | band angle (deg) | "
                 "wall time (s) |")
    lines.append("|---" * (10 + len(at)) + "|")
    for name, cell, length, seconds, out in runs:
        strain, q = read_curve(out)
        for e, v in zip(strain, q):
            rows.append(f"{name},{cell},{length if length else ''},{e:.6g},{v:.6g}")
        k = int(np.argmax(q))
        # Softening strain: from the peak to the first row below half-way to the residual.
        below = np.nonzero(q[k:] < 0.5 * (q[k] + res_mc))[0]
        drop = f"{100 * (strain[k + below[0]] - strain[k]):.2f} %" if len(below) else "-"
        b = band_measures(last_frame(out))
        lines.append(f"| {name} | {cell * 1e3:g} | {f'{length * 1e3:g} mm' if length else 'none'} | {q[k]:.2f} | "
                     f"{100 * strain[k]:.2f} % | {drop} | " + " | ".join(f"{q_at(strain, q, a):.2f}" for a in at)
                     + f" | {b['share']:.2f} | {b['spread']:.2f} | {b['angle']:.1f} | {seconds:.0f} |")
    with open(os.path.join(reports, "curves.csv"), "w") as f:
        f.write("run,cell_size_m,softening_length_m,axial_strain,q_kPa\n" + "\n".join(rows) + "\n")
    summary = "\n".join(lines) + "\n"
    with open(os.path.join(reports, "summary.md"), "w") as f:
        f.write(summary)
    print(summary)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.5))
    styles = {"h2.5_table": ("C0", "-"), "h1.25_table": ("C1", "-"), "h2.5_L2.5": ("C0", "--"), "h1.25_L2.5": ("C1", "--")}
    for name, cell, length, seconds, out in runs:
        strain, q = read_curve(out)
        colour, dash = styles[name]
        label = f"h = {cell * 1e3:g} mm, " + (f"softening_length = {length * 1e3:g} mm" if length else "table as given")
        if length and abs(length - cell) < 1e-12:
            label += " (= table as given)"
        ax.plot(100 * strain, q, color=colour, linestyle=dash, label=label)
    ax.axhline(peak_mc, color="grey", lw=0.8, ls=":")
    ax.axhline(res_mc, color="grey", lw=0.8, ls=":")
    ax.text(0.1, peak_mc + 0.8, "MC peak (c = 8.5 kPa)", fontsize=8, color="grey")
    ax.text(0.1, res_mc + 0.8, "MC residual (c = 1 kPa)", fontsize=8, color="grey")
    ax.set_xlabel("axial strain (%)")
    ax.set_ylabel("q = mean vertical stress of the bottom 2.5 mm - 10 kPa (kPa)")
    ax.set_title("softening plane-strain compression, sigma3 = 10 kPa")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(reports, "curves.png"), dpi=120)

    # The last frame of each run: plastic shear strain on the deformed specimen.
    fig, axes = plt.subplots(1, len(runs), figsize=(3 * len(runs), 4.8))
    for ax, (name, cell, length, seconds, out) in zip(axes, runs):
        f = read_vtu(last_frame(out))
        sel = f["body"] == 0
        p = f["points"][sel]
        ax.scatter(p[:, 0], p[:, 1], c=f["plastic_shear_strain"][sel], s=0.3 if cell < 0.002 else 1.2, cmap="viridis")
        ax.set_aspect("equal")
        ax.set_title(name, fontsize=9)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.suptitle(f"plastic shear strain at {100 * args.strain:g} % axial strain")
    fig.tight_layout()
    fig.savefig(os.path.join(reports, "bands.png"), dpi=60)


if __name__ == "__main__":
    main()
