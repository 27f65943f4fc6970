#!/usr/bin/python3
"""Strip footing on Tresca soil: the bearing pressure q/c against Prandtl's N_c at three grids
(10, 20, 40 cells per footing width), nu = 0.49 and 0.3, with and without the anti-locking remedy.

    /usr/bin/python3 examples/footing/study.py [--tsuchi build/app/tsuchi] [--out results/footing_study]
                                               [--quick] [--plot-only] [--jobs N]

--quick runs the 10 and 20 cell grids only. Writes table.md and footing.png into --out.
q/c is the mean of the reaction recorder over settlements s/B = 0.01 to 0.02 (the plateau: with
G/c = 1000 the limit is reached by s/B = 0.01). Without --quick it also runs the 20 cell grid at
half the loading rate (the rate check). --jobs runs that many cases at once, each on one thread."""
import argparse
import concurrent.futures
import csv
import math
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
INPUT = os.path.join(HERE, "footing.toml")
PHI = 0.1  # degrees, as in footing.toml
WINDOW = (0.01, 0.02)  # s/B over which the plateau is averaged; footing.toml stops at 0.02


def prandtl_nc(phi_deg):
    """N_c = (N_q - 1) cot(phi), N_q = e^(pi tan phi) tan^2(45 + phi/2); 2 + pi at phi = 0."""
    if phi_deg == 0.0:
        return 2.0 + math.pi
    phi = math.radians(phi_deg)
    nq = math.exp(math.pi * math.tan(phi)) * math.tan(math.pi / 4 + phi / 2) ** 2
    return (nq - 1.0) / math.tan(phi)


def cases(quick):
    """(cell, nu, remedy, rate factor): the remedy on all grids, off on the 10 and 20 cell grids
    (off at 40 cells costs half an hour and says nothing the two coarser grids do not)."""
    cells = [0.1, 0.05] if quick else [0.1, 0.05, 0.025]
    out = [(h, nu, remedy, 1.0) for nu in (0.49, 0.3) for remedy in ("node", "none") for h in cells
           if remedy == "node" or h >= 0.05]
    if not quick:
        out.append((0.05, 0.49, "node", 0.5))
    return out


def name(h, nu, remedy, rate):
    return f"h{h:g}_nu{nu:g}_{remedy}" + ("" if rate == 1.0 else f"_rate{rate:g}")


def run(tsuchi, out, h, nu, remedy, rate):
    cmd = [tsuchi, "run", INPUT, "-q", "--threads", "1", "--output", out, "--set", "output.frames=false",
           "--set", f"grid.cell_size={h}", "--set", f"materials.0.poisson_ratio={nu}",
           "--set", f'solver.anti_locking="{remedy}"']
    if rate != 1.0:  # footing.toml pushes at 1 cm/s for at most 3 s
        cmd += ["--set", f"bodies.1.prescribed_velocity={{ x = 0.0, y = {-0.01 * rate:g} }}",
                "--set", f"time.end={3.0 / rate:g}", "--set", f"output.global_interval={0.01 / rate:g}"]
    start = time.monotonic()
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({r.returncode}): {r.stderr.strip()}")
    with open(os.path.join(out, "wall_time.txt"), "w") as f:
        f.write(f"{time.monotonic() - start:.1f}\n")


def curve(out):
    with open(os.path.join(out, "recorders.csv")) as f:
        rows = list(csv.DictReader(f))
    s = [float(r["settlement_B"]) for r in rows[1:]]
    q = [float(r["q_over_c"]) for r in rows[1:]]
    return s, q


def plateau(s, q, window=WINDOW):
    late = [qq for ss, qq in zip(s, q) if window[0] <= ss <= window[1] + 1e-9]
    return sum(late) / len(late) if late else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tsuchi", default=os.path.join(HERE, "..", "..", "build", "app", "tsuchi"))
    ap.add_argument("--out", default="results/footing_study")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--plot-only", action="store_true")
    ap.add_argument("--jobs", type=int, default=1)
    a = ap.parse_args()
    nc = prandtl_nc(PHI)
    os.makedirs(a.out, exist_ok=True)
    todo = cases(a.quick)
    if not a.plot_only:
        def one(case):
            print(f"running {name(*case)} ...", flush=True)
            run(a.tsuchi, os.path.join(a.out, name(*case)), *case)
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
            # The finest, stiffest (nu = 0.49) cases first, so that the pool ends together.
            list(pool.map(one, sorted(todo, key=lambda c: (c[0], -c[1], c[3]))))
    results, rate_check = {}, {}
    for h, nu, remedy, rate in todo:
        out = os.path.join(a.out, name(h, nu, remedy, rate))
        if os.path.exists(os.path.join(out, "recorders.csv")):
            if rate == 1.0:
                results[(h, nu, remedy)] = curve(out)
            else:
                rate_check[(h, nu, remedy, rate)] = curve(out)
    lines = [f"q/c over s/B = {WINDOW[0]:g}-{WINDOW[1]:g} against Prandtl's N_c = {nc:.3f} "
             f"(phi = {PHI} deg; 2 + pi = 5.142)", "",
             "| nu | anti_locking | " + " | ".join(f"{1 / h:g} cells/B" for h in sorted({k[0] for k in results}, reverse=True)) + " |",
             "|---|---|" + "---|" * len({k[0] for k in results})]
    for nu in (0.49, 0.3):
        for remedy in ("node", "none"):
            cells = []
            for h in sorted({k[0] for k in results}, reverse=True):
                if (h, nu, remedy) in results:
                    v = plateau(*results[(h, nu, remedy)])
                    cells.append(f"{v:.3f} ({100 * (v / nc - 1):+.1f} %)")
                else:
                    cells.append("")
            lines.append(f"| {nu} | {remedy} | " + " | ".join(cells) + " |")
    for (h, nu, remedy, rate), sq in sorted(rate_check.items()):
        base = results.get((h, nu, remedy))
        v = plateau(*sq)
        ref = f", {100 * (v / plateau(*base) - 1):+.1f} % against the full rate" if base else ""
        lines.append("")
        lines.append(f"Rate check: {1 / h:g} cells/B, nu = {nu}, {remedy}, footing at {rate:g} x 1 cm/s: "
                     f"{v:.3f} ({100 * (v / nc - 1):+.1f} % against N_c{ref})")
    table = "\n".join(lines) + "\n"
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write(table)
    print(table)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, nu in zip(axes, (0.49, 0.3)):
        for (h, n, remedy), (s, q) in sorted(results.items()):
            if n != nu:
                continue
            ax.plot(s, q, "-" if remedy == "node" else ":", label=f"{1 / h:g} cells/B, {remedy}")
        ax.axhline(nc, color="k", lw=0.8)
        ax.text(0.002, nc + 0.05, "Prandtl", fontsize=8)
        ax.set_xlabel("settlement s / B")
        ax.set_title(f"nu = {nu}")
        ax.set_xlim(0, WINDOW[1])
        ax.set_ylim(0, 7)
    axes[0].set_ylabel("q / c")
    axes[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "footing.png"), dpi=120)


if __name__ == "__main__":
    main()
