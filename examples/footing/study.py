#!/usr/bin/python3
"""Strip footing on Tresca soil: the bearing pressure q/c against Prandtl's N_c at three grids
(10, 20, 40 cells per footing width), nu = 0.49 and 0.3, with and without the anti-locking remedy.

    /usr/bin/python3 examples/footing/study.py [--tsuchi build/app/tsuchi] [--out results/footing_study]
                                               [--quick] [--plot-only]

--quick runs the 10 and 20 cell grids only. Writes table.md and footing.png into --out.
q/c is the mean of the reaction recorder over settlements s/B = 0.05 to 0.10 (the plateau)."""
import argparse
import csv
import math
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
INPUT = os.path.join(HERE, "footing.toml")
PHI = 0.1  # degrees, as in footing.toml


def prandtl_nc(phi_deg):
    """N_c = (N_q - 1) cot(phi), N_q = e^(pi tan phi) tan^2(45 + phi/2); 2 + pi at phi = 0."""
    if phi_deg == 0.0:
        return 2.0 + math.pi
    phi = math.radians(phi_deg)
    nq = math.exp(math.pi * math.tan(phi)) * math.tan(math.pi / 4 + phi / 2) ** 2
    return (nq - 1.0) / math.tan(phi)


def cases(quick):
    cells = [0.1, 0.05] if quick else [0.1, 0.05, 0.025]
    return [(h, nu, remedy) for nu in (0.49, 0.3) for remedy in ("node", "none") for h in cells]


def name(h, nu, remedy):
    return f"h{h:g}_nu{nu:g}_{remedy}"


def run(tsuchi, out, h, nu, remedy):
    cmd = [tsuchi, "run", INPUT, "-q", "--threads", "1", "--output", out, "--set", "output.frames=false",
           "--set", f"grid.cell_size={h}", "--set", f"materials.0.poisson_ratio={nu}",
           "--set", f'solver.anti_locking="{remedy}"']
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


def plateau(s, q):
    late = [qq for ss, qq in zip(s, q) if 0.05 <= ss <= 0.1 + 1e-9]
    return sum(late) / len(late) if late else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tsuchi", default=os.path.join(HERE, "..", "..", "build", "app", "tsuchi"))
    ap.add_argument("--out", default="results/footing_study")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--plot-only", action="store_true")
    a = ap.parse_args()
    nc = prandtl_nc(PHI)
    os.makedirs(a.out, exist_ok=True)
    results = {}
    for h, nu, remedy in cases(a.quick):
        out = os.path.join(a.out, name(h, nu, remedy))
        if not a.plot_only:
            print(f"running {name(h, nu, remedy)} ...", flush=True)
            run(a.tsuchi, out, h, nu, remedy)
        if os.path.exists(os.path.join(out, "recorders.csv")):
            results[(h, nu, remedy)] = curve(out)
    lines = [f"q/c over s/B = 0.05-0.10 against Prandtl's N_c = {nc:.3f} (phi = {PHI} deg; 2 + pi = 5.142)", "",
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
        ax.set_xlim(0, 0.1)
        ax.set_ylim(0, 7)
    axes[0].set_ylabel("q / c")
    axes[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "footing.png"), dpi=120)


if __name__ == "__main__":
    main()
