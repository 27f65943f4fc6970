"""Granular column collapse at three aspect ratios against the experimental scaling laws of Lube et
al. (2005), and at a = 2 the velocity transfers (APIC, FLIP, PIC blends) and the anti-locking
remedies (node, the default; none; cell with --extra) compared.

Runs collapse.toml one case after another on one thread, measures each final deposit and writes
into RESULTS (default results/column_collapse):
  CASE/                  each run's output (particles.pvd, global.csv)
  table.md, table.csv    a, transfer, anti-locking, cells across w0, runout, final height, the laws,
                         KE ratio, particles released in tension at the end, wall time
  collapse.png           runout and final height against a on the laws, kinetic energy, deposits

usage: study.py [--tsuchi PATH] [--results DIR] [--extra] [--plot-only] [--small-png PATH]
  --extra      also the grid study at a = 2 (w0/10 and w0/40), anti_locking = "cell" at a = 2 and
               phi = 19.8 deg at a = 0.5 and 2
  --plot-only  measure and plot the runs already in RESULTS (none is run)
  --small-png  also a copy of collapse.png 1000 pixels wide in 64 colours (about 60 kB), the one
               README.md shows: --small-png examples/column_collapse/collapse.png
About 4 minutes on one core (and 3.5 more with --extra).
"""
import argparse
import csv
import math
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(REPO, "tools"))
import numpy as np  # noqa: E402
from vtu import read_pvd, read_vtu  # noqa: E402

INPUT = os.path.join(HERE, "collapse.toml")
W0 = 0.2                 # m, the column's width (collapse.toml)
PARTICLES_PER_CELL = 2   # collapse.toml
KE_REST = 1e-6           # at rest: kinetic energy below this fraction of its peak
TAIL = 0.5               # s: the largest kinetic energy over the last TAIL of a run is reported too


# --- Lube, Huppert, Sparks and Freundt (2005), two-dimensional (channel) collapses -----------------
def lube_runout(a):
    """(L_inf - L0) / L0 as the range (low, high) of Lube et al.'s fits: 1.2 a for a < 1.8 and
    1.9 a^(2/3) for a > 2.8; between the two (no fit given) the range spans both expressions."""
    lin, power = 1.2 * a, 1.9 * a ** (2.0 / 3.0)
    if a < 1.8:
        return lin, lin
    if a > 2.8:
        return power, power
    return min(lin, power), max(lin, power)


def lube_height(a):
    """H_inf / L0: a for a < 1.15 (the top of the column is left standing), a^(2/5) above."""
    return a if a < 1.15 else a ** 0.4


# --- the cases ------------------------------------------------------------------------------------
def whole_cells(length, cell):
    """length rounded up to a whole number of cells (grid.extent must be one)."""
    return round(math.ceil(length / cell - 1e-9) * cell, 9)


def geometry(a, cell=0.01):
    """--set overrides for aspect ratio a: the column w0 x a w0 and a grid with room for the runout."""
    h0 = round(a * W0, 9)
    width = {0.5: 0.8, 2.0: 1.6, 6.0: 3.2}.get(a, W0 * (2 + 2.2 * a))
    height = whole_cells(h0 + max(0.1, 0.1 * h0), cell)
    end = {0.5: 2.0, 2.0: 2.0, 6.0: 3.0}.get(a, 2.0)
    return [f"bodies.0.max=[{W0}, {h0}]", f"grid.extent=[{width}, {height}]", f"grid.cell_size={cell}",
            f"time.end={end}"]


# velocity_transfer = "apic" is the solver's default (and collapse.toml's); it is set here anyway
# so that a case means the same whatever the defaults.
TRANSFERS = {
    "apic": ['solver.velocity_transfer="apic"'],
    "flip": ['solver.velocity_transfer="flip"', "solver.pic_fraction=0.0"],
    "pic0.05": ['solver.velocity_transfer="flip"', "solver.pic_fraction=0.05"],
    "pic1": ['solver.velocity_transfer="flip"', "solver.pic_fraction=1.0"],
}


# solver.anti_locking: "node" is the solver's default (and collapse.toml's), "none" the particle's
# own volumetric strain increment, "cell" that of its cell's centre.
ANTI_LOCKING = ("node", "none", "cell")


def cases(extra):
    """(name, a, transfer, cell, friction angle, anti-locking) of every run."""
    out = [(f"a{a:g}_apic", a, "apic", 0.01, 30.0, "node") for a in (0.5, 2.0, 6.0)]
    out += [(f"a2_{t}", 2.0, t, 0.01, 30.0, "node") for t in ("flip", "pic0.05", "pic1")]
    out += [("a2_apic_lock_none", 2.0, "apic", 0.01, 30.0, "none")]
    if extra:
        out += [("a2_apic_lock_cell", 2.0, "apic", 0.01, 30.0, "cell")]
        out += [("a2_apic_h0.02", 2.0, "apic", 0.02, 30.0, "node"), ("a2_apic_h0.005", 2.0, "apic", 0.005, 30.0, "node")]
        out += [(f"a{a:g}_apic_phi19.8", a, "apic", 0.01, 19.8, "node") for a in (0.5, 2.0)]
    return out


def overrides(a, transfer, cell, phi, anti_locking="node"):
    if anti_locking not in ANTI_LOCKING:
        raise ValueError(f"anti_locking {anti_locking!r}: expected one of {ANTI_LOCKING}")
    sets = geometry(a, cell) + TRANSFERS[transfer] + [f'solver.anti_locking="{anti_locking}"']
    if phi != 30.0:
        # Wider grid for the more mobile material; K0 = 1 - sin(phi) stays inside the surface.
        sets[1] = f"grid.extent=[{3.0 if a >= 2 else 1.2}, {whole_cells(a * W0 * 1.25, cell)}]"
        sets += [f"materials.0.friction_angle={phi}",
                 f"bodies.0.initial_stress.k0={1 - math.sin(math.radians(phi)):.4f}"]
    return sets


def run_case(tsuchi, out, sets):
    cmd = [tsuchi, "run", INPUT, "-q", "--threads", "1", "--output", out]
    for s in sets:
        cmd += ["--set", s]
    start = time.monotonic()
    result = subprocess.run(cmd, capture_output=True, text=True)
    elapsed = time.monotonic() - start
    if result.returncode != 0:
        sys.exit(f"{' '.join(cmd)}\nfailed ({result.returncode}): {result.stderr.strip()}")
    with open(os.path.join(out, "wall_time.txt"), "w") as f:
        f.write(f"{elapsed:.1f}\n")
    return cmd


# --- measurements ---------------------------------------------------------------------------------
def measure(out, cell):
    """The final deposit and the approach to rest of one run. L_inf and H_inf are the furthest
    right and highest particle plus half the initial particle spacing (the edge of its initial
    domain), so that at t = 0 they give exactly w0 and h0."""
    half = 0.5 * cell / PARTICLES_PER_CELL
    frames = read_pvd(os.path.join(out, "particles.pvd"))
    first = read_vtu(os.path.join(out, frames[0][1]))["points"]
    t_end, last = frames[-1]
    pts = read_vtu(os.path.join(out, last))["points"]
    l0, h0 = first[:, 0].max() + half, first[:, 1].max() + half
    g = np.genfromtxt(os.path.join(out, "global.csv"), delimiter=",", names=True)
    ke, t = g["kinetic_energy"], g["time"]
    released = g["released_particles"] if "released_particles" in g.dtype.names else np.full_like(t, np.nan)
    peak = ke.max()
    # At rest for good: from the sample after the last one at or above KE_REST of the peak (a run
    # can dip below it and rise again as its deposit rings elastically).
    above = np.nonzero(ke >= KE_REST * peak)[0]
    settled = above[-1] + 1 if len(above) else 0
    wall = os.path.join(out, "wall_time.txt")
    seconds = float("nan")
    if os.path.exists(wall):
        with open(wall) as f:
            seconds = float(f.read())
    return {
        "a": h0 / l0,
        "runout": (pts[:, 0].max() + half - l0) / l0,
        "height": (pts[:, 1].max() + half) / l0,
        "ke_ratio": ke[-1] / peak,
        "t_rest": t[settled] if settled < len(t) else float("nan"),
        "ke_tail_max": ke[t >= t[-1] - TAIL].max() / peak,
        "t_end": t_end,
        "released_end": released[-1],
        "released_max": released.max(),
        "particles": len(pts),
        "time": t,
        "ke": ke / peak,
        "points": pts,
        "l0": l0,
        "wall": seconds,
    }


def law_text(lo, hi):
    return f"{lo:.2f}" if abs(hi - lo) < 1e-12 else f"{lo:.2f}-{hi:.2f}"


def write_tables(rows, results):
    header = ["case", "a", "transfer", "anti_locking", "phi", "cells_w0", "runout", "runout_lube", "height",
              "height_lube", "ke_end_over_peak", "ke_max_last_0.5s_over_peak", "t_rest_s", "t_end_s", "released_end",
              "released_max", "particles", "wall_s"]
    with open(os.path.join(results, "table.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for name, a, transfer, cell, phi, lock, m in rows:
            lo, hi = lube_runout(a)
            w.writerow([name, f"{m['a']:.3f}", transfer, lock, phi, round(W0 / cell), f"{m['runout']:.3f}",
                        law_text(lo, hi), f"{m['height']:.3f}", f"{lube_height(a):.3f}", f"{m['ke_ratio']:.2e}",
                        f"{m['ke_tail_max']:.2e}", f"{m['t_rest']:.2f}", f"{m['t_end']:.2f}", f"{m['released_end']:.0f}",
                        f"{m['released_max']:.0f}", m["particles"], f"{m['wall']:.1f}"])
    lines = ["| a | transfer | anti-locking | phi | cells across w0 | runout (L-L0)/L0 | Lube 2005 | H/L0 | Lube 2005 | "
             "KE end / peak | max over last 0.5 s | KE < 1e-6 peak for good from t = | released at end (max) | wall time |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, a, transfer, cell, phi, lock, m in rows:
        lo, hi = lube_runout(a)
        rest = "never" if math.isnan(m["t_rest"]) else f"{m['t_rest']:.2f} s"
        lines.append(f"| {a:g} | {transfer} | {lock} | {phi:g} | {W0 / cell:.0f} | {m['runout']:.2f} | "
                     f"{law_text(lo, hi)} | {m['height']:.2f} | {lube_height(a):.2f} | {m['ke_ratio']:.1e} | "
                     f"{m['ke_tail_max']:.1e} | {rest} | "
                     f"{m['released_end']:.0f} ({m['released_max']:.0f}) of {m['particles']} | {m['wall']:.0f} s |")
    with open(os.path.join(results, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


def plot(rows, results, dpi=110, small=None):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ((ax1, ax2), (ax3, ax4)) = plt.subplots(2, 2, figsize=(12, 9))
    a_lin = np.linspace(0.3, 1.8, 20)
    a_pow = np.linspace(2.8, 10, 40)
    a_gap = np.linspace(1.8, 2.8, 20)
    for ax in (ax1, ax2):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("aspect ratio a = h0 / w0")
    ax1.plot(a_lin, 1.2 * a_lin, "k-", label="Lube et al. 2005: 1.2 a (a < 1.8)")
    ax1.plot(a_pow, 1.9 * a_pow ** (2 / 3), "k--", label="1.9 a^(2/3) (a > 2.8)")
    ax1.fill_between(a_gap, 1.2 * a_gap, 1.9 * a_gap ** (2 / 3), color="0.85", label="between the two fits")
    ax1.set_ylabel("runout (L_inf - L0) / L0")
    a_h1 = np.linspace(0.3, 1.15, 20)
    a_h2 = np.linspace(1.15, 10, 40)
    ax2.plot(a_h1, a_h1, "k-", label="Lube et al. 2005: a (a < 1.15)")
    ax2.plot(a_h2, a_h2 ** 0.4, "k--", label="a^(2/5) (a > 1.15)")
    ax2.set_ylabel("final height H_inf / L0")
    transfer_style = {"apic": ("o", "C0"), "flip": ("s", "C1"), "pic0.05": ("^", "C2"), "pic1": ("v", "C3")}
    a_colour = {0.5: "C0", 2.0: "C4", 6.0: "C5"}
    lock_style = {"none": ("X", "C6"), "cell": ("P", "C8")}
    for name, a, transfer, cell, phi, lock, m in rows:
        marker, colour = transfer_style[transfer]
        main = cell == 0.01 and phi == 30.0 and lock == "node"
        if main:
            label = f"tsuchi {transfer}" if a == 2.0 or transfer != "apic" else None
            kw = dict(marker=marker, color=colour, ms=8)
        elif lock != "node":
            marker, colour = lock_style[lock]
            label = f"{transfer}, anti_locking {lock}"
            kw = dict(marker=marker, color=colour, ms=8)
        elif phi != 30.0:
            label = f"{transfer}, phi {phi:g} deg" if a == 2.0 else None
            kw = dict(marker="D", color="0.4", mfc="none", ms=7)
        else:
            label = f"{transfer}, w0 / {W0 / cell:.0f}"
            kw = dict(marker="<" if cell > 0.01 else ">", color=colour, mfc="none", ms=8)
        ax1.plot(m["a"], m["runout"], ls="none", label=label, **kw)
        ax2.plot(m["a"], m["height"], ls="none", label=label, **kw)
        if main or (lock != "node" and cell == 0.01 and phi == 30.0):
            ax3.semilogy(m["time"][1:], np.maximum(m["ke"][1:], 1e-12),
                         color=a_colour[a] if transfer == "apic" and main else colour,
                         ls="-" if transfer == "apic" and main else ":",
                         label=f"a = {a:g}, {transfer}" + ("" if lock == "node" else f", anti_locking {lock}"))
            if transfer == "apic":
                x, y = m["points"][:, 0] / m["l0"], m["points"][:, 1] / m["l0"]
                edges = np.arange(0.0, x.max() + 0.1, 0.1)
                top = [y[(x >= e0) & (x < e1)].max(initial=0.0) for e0, e1 in zip(edges[:-1], edges[1:])]
                ax4.plot(0.5 * (edges[:-1] + edges[1:]), top, color=a_colour[a] if main else colour,
                         ls="-" if main else "--", label=f"a = {a:g}" + ("" if main else f", anti_locking {lock}"))
    ax1.legend(fontsize=8)
    ax2.legend(fontsize=8)
    ax3.axhline(KE_REST, color="k", lw=0.8)
    ax3.set_ylim(1e-12, 2)
    ax3.set_xlabel("time (s)")
    ax3.set_ylabel("kinetic energy / its peak")
    ax3.set_title("approach to rest (line: 1e-6)")
    ax3.legend(fontsize=8)
    ax4.set_xlabel("x / L0")
    ax4.set_ylabel("y / L0")
    ax4.set_title("final surfaces: highest particle per 0.1 L0 (APIC, w0 / 20)")
    ax4.legend(fontsize=8)
    fig.suptitle("granular column collapse, plane strain, c = 0, phi = 30 deg, rough floor "
                 "(anti_locking node unless named)")
    fig.tight_layout()
    out = os.path.join(results, "collapse.png")
    fig.savefig(out, dpi=dpi)
    print(f"wrote {out}")
    if small:
        # 1000 pixels wide in 64 colours (Pillow, which matplotlib needs anyway): about 60 kB, the
        # copy examples/column_collapse/collapse.png that README.md shows.
        from PIL import Image

        im = Image.open(out).convert("RGB")
        im = im.resize((1000, round(im.height * 1000 / im.width)), Image.LANCZOS).quantize(colors=64)
        im.save(small, optimize=True)
        print(f"wrote {small}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tsuchi", default=os.path.join(REPO, "build", "app", "tsuchi"))
    parser.add_argument("--results", default=os.path.join("results", "column_collapse"))
    parser.add_argument("--extra", action="store_true")
    parser.add_argument("--plot-only", action="store_true")
    parser.add_argument("--small-png", metavar="PATH", help="also write a small copy of the plot (for README.md)")
    args = parser.parse_args()
    os.makedirs(args.results, exist_ok=True)
    rows = []
    for name, a, transfer, cell, phi, lock in cases(args.extra):
        out = os.path.join(args.results, name)
        if not args.plot_only:
            cmd = run_case(args.tsuchi, out, overrides(a, transfer, cell, phi, lock))
            print(" ".join(cmd[:1] + [os.path.relpath(c) if c == INPUT else c for c in cmd[1:]]), flush=True)
        elif not os.path.exists(os.path.join(out, "particles.pvd")):
            continue
        rows.append((name, a, transfer, cell, phi, lock, measure(out, cell)))
    write_tables(rows, args.results)
    plot(rows, args.results, small=args.small_png)


if __name__ == "__main__":
    main()
