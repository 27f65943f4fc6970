"""Cap-specimen friction study of the plane-strain triaxial test (Kiriyama 2015 left it open).

usage: /usr/bin/python3 examples/triaxial/friction/study.py [--tests test1 test2 test3]
           [--cases fixed free mu0 mu0.1 mu0.2 mu0.3 mu0.5 rough] [--jobs 2] [--strain 0.15]
           [--results results/triaxial/friction] [--tsuchi build/app/tsuchi] [--no-run]
           [--set KEY=VALUE ...] [--snapshots]

For each test and case it writes a variant of examples/triaxial/TEST_fixed.toml (or _free) into
RESULTS/TEST_CASE/input.toml and runs it with --threads 1, --jobs runs at a time:
  fixed   the input as it is: cap held (x = 0, y = -0.02 m/s), bonded to the specimen (one field)
  free    cap bonded, x free (TEST_free.toml)
  muM     cap rigid (x = 0, y = -0.02 m/s) in [[contact]] with the specimen, friction = M
  rough   the same with friction = "rough" (no slip, may separate)
  bonded  the same with friction = "bonded": must equal "fixed" (one field)
Every variant gets three more recorders: cap_reaction_y (N/m), the force that holds the cap,
top_dx_m (mean horizontal displacement of the specimen's top row of particles) and cap_dx_m is
already there. The deviator is taken from the cap's reaction, q = -reaction_y / 0.05 m (the cap
width), kPa; with subtract = true the specimen's internal force is that of sigma - sigma0, so the
reaction is the deviatoric load (the confining pressure holds itself). The input's own q_kPa
(the bottom row's sigma_yy - sigma_m0) is kept as q_bottom for comparison.
Then it writes RESULTS/report.md, RESULTS/q_TEST.png and RESULTS/TEST_CASE/shear_strain.png.
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
TRIAX = os.path.dirname(HERE)
REPO = os.path.normpath(os.path.join(TRIAX, "..", ".."))
sys.path.insert(0, TRIAX)
sys.path.insert(0, os.path.join(REPO, "tools"))
import numpy as np  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import plot  # noqa: E402  (examples/triaxial/plot.py: recorders, frames, bands, snapshots)
from vtu import read_vtu  # noqa: E402

CAP_WIDTH = 0.05  # m
TESTS = ["test1", "test2", "test3"]
CASES = ["fixed", "free", "mu0", "mu0.1", "mu0.2", "mu0.3", "mu0.5", "rough"]
ALL_CASES = CASES + ["bonded"]
STRAINS = (0.05, 0.10, 0.15)
DONE_RE = re.compile(r"done: (\d+) steps to t = (\S+) s in (\S+) s \((\S+) particle-steps/s\)")
LOCK = threading.Lock()

EXTRA_RECORDERS = """
# --- added by examples/triaxial/friction/study.py ---
[[recorders]]
name = "cap_reaction_y"
body = "cap"
quantity = "reaction_y"

[[recorders]]
name = "top_dx_m"
body = "specimen"
min = [-1.0, 0.099]   # the top row of particles (centres at y = 0.0995)
quantity = "displacement_x"
"""


def friction_of(case):
    if case.startswith("mu"):
        return case[2:]
    if case in ("rough", "bonded"):
        return f'"{case}"'
    return None


def variant(test, case, out):
    """The input text of one case."""
    base = "free" if case == "free" else "fixed"
    with open(os.path.join(TRIAX, f"{test}_{base}.toml")) as f:
        text = f.read()
    text = re.sub(r'directory = "[^"]*"', f'directory = "{out}"', text)
    fr = friction_of(case)
    if fr is not None:
        text = re.sub(r'title = "([^"]*)"', rf'title = "\1, cap rigid in contact, friction {fr.strip(chr(34))}"', text)
        text += f"""
[[contact]]
bodies = ["cap", "specimen"]
friction = {fr}
"""
    return text + EXTRA_RECORDERS


def run_case(test, case, args):
    name = f"{test}_{case}"
    out = os.path.join(args.results, name)
    os.makedirs(out, exist_ok=True)
    for f in os.listdir(out):
        if f.startswith("particles_") or f in ("particles.pvd", "recorders.csv", "global.csv", "run.json"):
            os.remove(os.path.join(out, f))
    inp = os.path.join(out, "input.toml")
    with open(inp, "w") as f:
        f.write(variant(test, case, out))
    cmd = [args.tsuchi, "run", inp, "--output", out, "--threads", "1",
           "--set", f"recorders.0.stop_above={args.strain:g}",
           "--set", f"time.end={args.strain * 5 + 0.05:g}"]
    for extra in args.set:
        cmd += ["--set", extra]
    rec = {"case": name, "command": " ".join(cmd)}
    t0 = time.perf_counter()
    with open(os.path.join(out, "run.log"), "w") as log:
        log.write("$ " + rec["command"] + "\n")
        log.flush()
        rec["returncode"] = subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT, cwd=REPO).returncode
    rec["wall_s"] = time.perf_counter() - t0
    with open(os.path.join(out, "run.log")) as log:
        m = None
        for m in DONE_RE.finditer(log.read()):
            pass
    if m:
        rec.update(steps=int(m.group(1)), solver_s=float(m.group(3)), particle_steps_per_s=float(m.group(4)))
    rec["ok"] = rec["returncode"] == 0 and m is not None
    with open(os.path.join(out, "run.json"), "w") as f:
        json.dump(rec, f, indent=1)
    with LOCK:
        print(f"{name}: {'done' if rec['ok'] else 'FAILED'} in {rec['wall_s']:.0f} s", flush=True)
    return rec


def smooth(y, n=3):
    """Centred running mean over n rows (0.1 % strain each); the ends keep shorter windows."""
    if len(y) < n:
        return y
    k = np.ones(n)
    return np.convolve(y, k, "same") / np.convolve(np.ones_like(y), k, "same")


def load(case_dir):
    rec = plot.read_recorders(case_dir)
    if rec is None or "cap_reaction_y" not in rec:
        return None
    ok = np.isfinite(rec["cap_reaction_y"])
    rec = {k: v[ok] for k, v in rec.items()}
    rec["q_raw"] = -rec["cap_reaction_y"] / CAP_WIDTH * 1e-3
    rec["q"] = smooth(rec["q_raw"])
    rec["slide_mm"] = 1e3 * (rec["top_dx_m"] - rec["cap_dx_m"])
    return rec


def at(rec, key, strain):
    e = rec["axial_strain"]
    if e.max() < strain - 1e-3:
        return None
    return float(np.interp(strain, e, rec[key]))


def bands_at(case_dir, rec, strain):
    frames = plot.frames_with_strain(case_dir, rec)
    f = plot.frame_near(frames, strain)
    if f is None:
        return None
    return plot.specimen_bands(read_vtu(f[2]))


def overlap_mm(case_dir, rec, strain):
    """How far the specimen's particles reach into the cap at a frame: the largest
    (particle centre + half its initial spacing) - (cap's lowest particle centre - half spacing)
    over the specimen particles under the cap's face away from its corners (1.5 mm in from each
    edge), in mm (0.5 mm spacing halves, 2 x 2 particles per 2 mm cell); and the highest rise of
    specimen particles beside the cap (outside its width) above the cap's bottom face."""
    f = plot.frame_near(plot.frames_with_strain(case_dir, rec), strain)
    if f is None:
        return None, None
    v = read_vtu(f[2])
    p, b = v["points"], v["body"]
    cap, sp = p[b == 1], p[b == 0]
    face = cap[:, 1].min() - 0.0005
    lo, hi = cap[:, 0].min() - 0.0005, cap[:, 0].max() + 0.0005
    inner = (sp[:, 0] > lo + 0.0015) & (sp[:, 0] < hi - 0.0015)
    outside = (sp[:, 0] < lo) | (sp[:, 0] > hi)
    pen = 1e3 * (sp[inner, 1].max() + 0.0005 - face) if inner.any() else None
    rise = 1e3 * max(0.0, sp[outside, 1].max() + 0.0005 - face) if outside.any() else 0.0
    return pen, rise


def top_row_slide_mm(case_dir, rec, strain):
    """From the frame nearest `strain`: the specimen's top row of particles (initial y > 0.099 m)
    relative to the cap, horizontally: (shift, spread) in mm, shift = mean dx of the row - mean dx
    of the cap, spread = (mean dx of the row's right half - mean dx of its left half) / 2, the
    symmetric outward slide a mean hides."""
    f = plot.frame_near(plot.frames_with_strain(case_dir, rec), strain)
    if f is None:
        return None, None
    v = read_vtu(f[2])
    b, u = v["body"], v["displacement"]
    x0 = v["points"] - u
    top = (b == 0) & (x0[:, 1] > 0.099)
    cap_dx = u[b == 1, 0].mean()
    mid = 0.5 * (x0[b == 0, 0].min() + x0[b == 0, 0].max())
    right, left = top & (x0[:, 0] > mid), top & (x0[:, 0] < mid)
    return 1e3 * (u[top, 0].mean() - cap_dx), 1e3 * 0.5 * (u[right, 0].mean() - u[left, 0].mean())


def pattern(bands):
    if bands is None:
        return "-"
    clear = [b for b in bands if b.clear]
    faint = [b for b in bands if not b.clear]
    senses = {b.angle > 0 for b in clear}
    if len(clear) >= 2 and len(senses) == 2:
        kind = "X"
    elif len(clear) >= 1:
        kind = "one" if len(clear) == 1 else f"{len(clear)} parallel"
    else:
        kind = "none clear"
    ang = ", ".join(f"{b.inclination:.0f}°{'↗' if b.angle > 0 else '↖'}" for b in clear)
    fa = ", ".join(f"{b.inclination:.0f}°{'↗' if b.angle > 0 else '↖'}" for b in faint)
    text = kind + (f": {ang}" if ang else "")
    return text + (f" (faint {fa})" if fa else "")


def fmt(v, spec):
    return "-" if v is None else format(v, spec)


def label(case):
    return {"fixed": "fixed (bonded, held)", "free": "free (bonded, x free)",
            "rough": "rigid, rough", "bonded": "rigid, bonded contact"}.get(case, f"rigid, μ = {case[2:]}")


def report(args):
    lines = ["# Cap-specimen friction in the plane-strain triaxial test", "",
             "Written by examples/triaxial/friction/study.py. q = −(cap reaction_y) / 0.05 m, a centred "
             "running mean over 3 recorder rows (0.3 % strain); q_bottom is the inputs' own q_kPa "
             "(mean σ_yy of the specimen's bottom row of particles − σ_m0). Slide = mean horizontal "
             "displacement of the specimen's top row of particles − that of the cap (mm; + to the right; "
             "the plot, from recorders); in the table from the frames: shift = the same, outward slide = "
             "half the difference of the mean horizontal displacements of the row's right and left "
             "halves (a symmetric spreading under the cap, which the mean hides). Overlap: how far the "
             "specimen's particles (centre + half spacing) reach past the cap's bottom face away from "
             "its corners; rise: how high specimen particles beside the cap (outside its width) rise "
             "above its bottom face, both at the last frame.",
             ""]
    if args.set:
        lines += ["Every run with " + ", ".join(f"`--set {x}`" for x in args.set) + ".", ""]
    curves = {}
    for test in args.tests:
        for case in ALL_CASES:
            d = os.path.join(args.results, f"{test}_{case}")
            rec = load(d) if os.path.isdir(d) else None
            if rec is not None:
                curves[(test, case)] = rec
    # Figures: one panel per test.
    tests = [t for t in args.tests if any((t, c) in curves for c in ALL_CASES)]
    if tests:
        fig, axes = plt.subplots(1, len(tests), figsize=(5.2 * len(tests), 4.6), squeeze=False)
        cmap = plt.get_cmap("viridis")
        mus = [c for c in CASES if c.startswith("mu")] + ["rough"]
        for ax, test in zip(axes[0], tests):
            for case in ALL_CASES:
                rec = curves.get((test, case))
                if rec is None:
                    continue
                if case == "fixed":
                    st = dict(color="k", ls="-", lw=2.0)
                elif case == "free":
                    st = dict(color="k", ls="--", lw=2.0)
                elif case == "bonded":
                    st = dict(color="r", ls=":", lw=1.5)
                else:
                    st = dict(color=cmap(mus.index(case) / (len(mus) - 1) * 0.9), ls="-", lw=1.2)
                ax.plot(100 * rec["axial_strain"], rec["q"], label=label(case), **st)
            ax.axhline(plot.mc_peak(plot.CONFINING_KPA[test]), color="0.5", ls=":", lw=1, label="Mohr-Coulomb peak")
            ax.set_title(f"{test} (σ_m0 = {plot.CONFINING_KPA[test]:g} kPa)")
            ax.set_xlabel("axial strain (%)")
            ax.set_ylabel("q from the cap's reaction (kPa)")
            ax.set_xlim(0, 100 * args.strain)
            ax.set_ylim(bottom=0)
            ax.grid(alpha=0.3)
        axes[0][-1].legend(fontsize=7, loc="lower right")
        fig.tight_layout()
        fig.savefig(os.path.join(args.results, "q_friction.png"), dpi=110)
        plt.close(fig)
        lines += ["![q against axial strain](q_friction.png)", ""]
        # Slide
        fig, axes = plt.subplots(1, len(tests), figsize=(5.2 * len(tests), 3.8), squeeze=False)
        for ax, test in zip(axes[0], tests):
            for case in ALL_CASES:
                rec = curves.get((test, case))
                if rec is None or case == "bonded":
                    continue
                st = (dict(color="k", ls="-", lw=2) if case == "fixed" else dict(color="k", ls="--", lw=2)
                      if case == "free" else dict(color=cmap(mus.index(case) / (len(mus) - 1) * 0.9), lw=1.2))
                ax.plot(100 * rec["axial_strain"], rec["slide_mm"], label=label(case), **st)
            ax.set_title(f"{test}: top row − cap, horizontal")
            ax.set_xlabel("axial strain (%)")
            ax.set_ylabel("slide (mm)")
            ax.grid(alpha=0.3)
        axes[0][-1].legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(args.results, "slide.png"), dpi=110)
        plt.close(fig)
        lines += ["![slide](slide.png)", ""]
    lines += ["## Deviator, band pattern and slide", "",
              "| test | case | peak q (kPa) | at (%) | q 5 % | q 10 % | q 15 % | q_bottom 15 % | bands 5 % | bands 10 % "
              "| bands 15 % | top row vs cap: shift, outward slide at 5 / 10 / 15 % (mm) | cap dx 15 % (mm) | overlap / rise beside the cap, last frame (mm) | reached (%) | wall (s) |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    agreement = []
    for test in args.tests:
        for case in ALL_CASES:
            d = os.path.join(args.results, f"{test}_{case}")
            rec = curves.get((test, case))
            if rec is None:
                continue
            run = {}
            if os.path.exists(os.path.join(d, "run.json")):
                with open(os.path.join(d, "run.json")) as f:
                    run = json.load(f)
            e = rec["axial_strain"]
            early = e <= 0.15 + 1e-9
            k = int(np.argmax(np.where(early, rec["q"], -np.inf)))
            qs = [at(rec, "q", s) for s in STRAINS]
            bands = [pattern(bands_at(d, plot.read_recorders(d), s)) for s in STRAINS]
            raw = plot.read_recorders(d)
            slides = [top_row_slide_mm(d, raw, s) for s in STRAINS]
            capdx = at(rec, "cap_dx_m", 0.15)
            pen, rise = overlap_mm(d, plot.read_recorders(d), float(e.max()))
            lines.append("| " + " | ".join([
                test, label(case), f"{rec['q'][k]:.1f}", f"{100 * e[k]:.1f}", *[fmt(q, ".1f") for q in qs],
                fmt(at(rec, "q_kPa", 0.15), ".1f"), *bands,
                " / ".join(f"{fmt(a, '+.2f')}, {fmt(b, '+.2f')}" for a, b in slides), fmt(None if capdx is None else 1e3 * capdx, "+.2f"),
                f"{fmt(pen, '+.2f')} / {fmt(rise, '.1f')}", f"{100 * e.max():.1f}"
                + ("" if run.get("ok", True) else " (failed)"), fmt(run.get("wall_s"), ".0f")]) + " |")
            if True:
                # The two q definitions over the curve, 1 % to the end, both smoothed alike.
                sel = e >= 0.01
                qb = smooth(rec["q_kPa"])[sel]
                qr = rec["q"][sel]
                agreement.append((test, case, float(np.max(np.abs(qr - qb) / np.abs(qb))),
                                  float(np.mean(np.abs(qr - qb) / np.abs(qb))),
                                  float(np.max(rec["q"][early]) / np.max(smooth(rec["q_kPa"])[early]) - 1)))
    lines += ["", "## The two definitions of q", "",
              "Relative difference between q from the cap's reaction and the inputs' q_kPa (bottom row's "
              "σ_yy − σ_m0), both smoothed as above, over 1-15 % strain, and the ratio of their peaks:", "",
              "| test | case | max | mean | peak ratio − 1 |", "|---|---|---|---|---|"]
    for t, c, mx, mn, pk in agreement:
        lines.append(f"| {t} | {c} | {100 * mx:.2f} % | {100 * mn:.2f} % | {100 * pk:+.2f} % |")
    with open(os.path.join(args.results, "report.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("wrote", os.path.join(args.results, "report.md"))


def main(argv=None):
    p = argparse.ArgumentParser()
    p.add_argument("--tests", nargs="+", default=TESTS, choices=TESTS)
    p.add_argument("--cases", nargs="+", default=CASES, choices=ALL_CASES)
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--strain", type=float, default=0.15)
    p.add_argument("--results", default=os.path.join(REPO, "results", "triaxial", "friction"))
    p.add_argument("--tsuchi", default=os.path.join(REPO, "build", "app", "tsuchi"))
    p.add_argument("--no-run", action="store_true")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="one more override for every run, e.g. 'solver.anti_locking=\"none\"'")
    p.add_argument("--snapshots", action="store_true", help="draw shear-strain snapshots per case")
    args = p.parse_args(argv)
    args.results = os.path.abspath(args.results)
    args.tsuchi = os.path.abspath(args.tsuchi)
    os.makedirs(args.results, exist_ok=True)
    ok = True
    if not args.no_run:
        jobs = [(t, c) for t in args.tests for c in args.cases]
        with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            for rec in pool.map(lambda tc: run_case(tc[0], tc[1], args), jobs):
                ok &= rec["ok"]
    if args.snapshots:
        for t in args.tests:
            for c in ALL_CASES:
                d = os.path.join(args.results, f"{t}_{c}")
                if os.path.exists(os.path.join(d, "particles.pvd")):
                    plot.plot_snapshots(d, f"{t}, {label(c)}", os.path.join(d, "shear_strain.png"))
    report(args)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
