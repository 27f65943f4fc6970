#!/usr/bin/python3
"""Rigid strip footing in contact with the soil: q/c against Prandtl's N_c for a rough and a smooth
footing (footing_rough.toml, footing_smooth.toml) at 10, 20 (and 40) cells per footing width,
beside the bonded footing of footing.toml run with the same soil (G/c = 100: BONDED_G100 below).

    /usr/bin/python3 examples/footing/contact_study.py [--tsuchi build/app/tsuchi]
        [--out results/footing_contact] [--cells 10 20 40] [--kinds rough smooth bonded]
        [--jobs 2] [--plot-only] [--set KEY=VALUE ...]

Runs --jobs at a time with --threads 1; writes table.md and footing_contact.png into --out.
q/c is the mean of the reaction recorder over s/B = 0.05 to 0.10 (study.py's plateau)."""
import argparse
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from study import PHI, curve, plateau, prandtl_nc  # noqa: E402

EXTRA = []  # --set overrides for every run
INPUTS = {"rough": "footing_rough.toml", "smooth": "footing_smooth.toml", "bonded": "footing.toml"}
WINDOW = (0.05, 0.10)  # the plateau of the G/c = 100 soil the contact inputs use
# footing.toml uses G/c = 1000 and stops at s/B = 0.02; the bonded comparison takes the contact
# inputs' soil, loading rate and end instead.
BONDED_G100 = ["materials.0.shear_modulus=1e6", "bodies.1.prescribed_velocity={ x = 0.0, y = -0.05 }",
               "time.end=3", "recorders.0.stop_above=0.1"]


def run(tsuchi, out, kind, cells):
    os.makedirs(out, exist_ok=True)
    cmd = [tsuchi, "run", os.path.join(HERE, INPUTS[kind]), "-q", "--threads", "1", "--output", out,
           "--set", "output.frames=false", "--set", f"grid.cell_size={1.0 / cells:g}"]
    for extra in (BONDED_G100 if kind == "bonded" else []) + EXTRA:
        cmd += ["--set", extra]
    start = time.monotonic()
    r = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - start
    with open(os.path.join(out, "wall_time.txt"), "w") as f:
        f.write(f"{wall:.1f}\n")
    with open(os.path.join(out, "run.log"), "w") as f:
        f.write(" ".join(cmd) + "\n" + r.stdout + r.stderr)
    print(f"{kind} {cells} cells/B: exit {r.returncode} in {wall:.0f} s", flush=True)
    return r.returncode


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tsuchi", default=os.path.join(HERE, "..", "..", "build", "app", "tsuchi"))
    ap.add_argument("--out", default="results/footing_contact")
    ap.add_argument("--cells", nargs="+", type=int, default=[10, 20, 40])
    ap.add_argument("--kinds", nargs="+", default=["rough", "smooth"], choices=list(INPUTS))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--plot-only", action="store_true")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="one more override for every run, e.g. 'solver.anti_locking=\"none\"'")
    a = ap.parse_args()
    EXTRA.extend(a.set)
    nc = prandtl_nc(PHI)
    os.makedirs(a.out, exist_ok=True)
    jobs = [(k, c) for c in a.cells for k in a.kinds]
    if not a.plot_only:
        with ThreadPoolExecutor(max_workers=a.jobs) as pool:
            list(pool.map(lambda kc: run(os.path.abspath(a.tsuchi), os.path.join(a.out, f"{kc[0]}_{kc[1]}"), *kc), jobs))
    results = {}
    for k, c in jobs:
        out = os.path.join(a.out, f"{k}_{c}")
        if os.path.exists(os.path.join(out, "recorders.csv")):
            results[(k, c)] = curve(out)
    lines = [f"q/c over s/B = 0.05-0.10 against Prandtl's N_c = {nc:.3f} (phi = {PHI} deg; 2 + pi = 5.142)"
             + "".join(f"; --set {x}" for x in a.set), "",
             "| footing | " + " | ".join(f"{c} cells/B" for c in a.cells) + " |", "|---|" + "---|" * len(a.cells)]
    for k in a.kinds:
        cells = []
        for c in a.cells:
            if (k, c) in results:
                s, q = results[(k, c)]
                v = plateau(s, q, WINDOW)
                reached = max(s) if s else 0.0
                note = "" if reached >= 0.1 - 1e-6 else f", to s/B = {reached:.3f}"
                cells.append(f"{v:.3f} ({100 * (v / nc - 1):+.1f} %{note})")
            else:
                cells.append("")
        lines.append(f"| {k} | " + " | ".join(cells) + " |")
    table = "\n".join(lines) + "\n"
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write(table)
    print(table)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    styles = {"rough": "-", "smooth": "--", "bonded": ":"}
    for (k, c), (s, q) in sorted(results.items()):
        ax.plot(s, q, styles[k], color={10: "tab:blue", 20: "tab:orange", 40: "tab:green"}.get(c, "k"),
                label=f"{k}, {c} cells/B")
    ax.axhline(nc, color="k", lw=0.8)
    ax.text(0.002, nc + 0.05, "Prandtl", fontsize=8)
    ax.set_xlabel("settlement s / B")
    ax.set_ylabel("q / c")
    ax.set_xlim(0, 0.1)
    ax.set_ylim(0, 7)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "footing_contact.png"), dpi=120)


if __name__ == "__main__":
    main()
