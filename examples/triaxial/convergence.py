"""Convergence of the triaxial case (cap fixed) with grid, imperfection seed and loading rate.

usage: /usr/bin/python3 examples/triaxial/convergence.py [--tests test1 test2] [--families grid seed rate] [--jobs N]
           [--results results/triaxial] [--tsuchi build/app/tsuchi] [--no-run]
           [--quick]

For test 1 and test 2 of the paper with the cap fixed (examples/triaxial/TEST_fixed.toml, the
inputs of the main job) it runs three families of variants around the main input (2 mm cells,
2 x 2 particles per cell, seed 2015, cap at 0.02 m/s):

  grid   cells of 4, 2 and 1 mm        (to 15, 15 and 8 % axial strain)
  seed   imperfection seeds 2015, 1, 2 (to 15 %)
  rate   cap speeds 0.02, 0.01, 0.005 m/s (to 15, 8 and 8 %; axial strain rates 0.2, 0.1, 0.05 /s)

and reports, per run: the peak deviator q and its strain against the Mohr-Coulomb peak, q at 5,
10 and 15 %, the band pattern (X, single band or none) with the bands' angles (deformed and at the
initial positions) and widths at 8 % and 15 %, and the wall time. The bottom-row recorders of the
input are moved to each grid's bottom row (particles that start below half a cell). The runs go
to RESULTS/convergence/RUN/; the script writes RESULTS/convergence.md (beside study.py's report.md),
RESULTS/convergence.json and RESULTS/convergence.png (q against strain of every family). --quick runs every variant to 3 % only (a smoke run; ctest runs the seed family of test 1 so).
Exit status: 0 if every run finished, 1 otherwise (the report is written anyway).
"""
import argparse
import json
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(REPO, "tools"))
import numpy as np  # noqa: E402
from bands import find_bands  # noqa: E402
from plot import CONFINING_KPA, mc_peak  # noqa: E402
from vtu import read_pvd, read_vtu  # noqa: E402

HEIGHT = 0.1  # specimen height, m: axial strain = cap settlement / HEIGHT
BASE = {"cell": 0.002, "seed": 2015, "speed": 0.02}
FAMILIES = {  # family -> [(variant key, value, stop strain)]
    "grid": [("cell", 0.004, 0.15), ("cell", 0.002, 0.15), ("cell", 0.001, 0.08)],
    "seed": [("seed", 2015, 0.15), ("seed", 1, 0.15), ("seed", 2, 0.15)],
    "rate": [("speed", 0.02, 0.15), ("speed", 0.01, 0.08), ("speed", 0.005, 0.08)],
}
REPORT_Q_STRAINS = (0.05, 0.10, 0.15)
BAND_STRAINS = (0.08, 0.15)
STRAIN_TOL = 0.0025


def variants(tests, families):
    """Every distinct run: (name, test, cell, seed, speed, stop strain). The base run is shared."""
    runs = {}
    for test in tests:
        for family in families:
            members = FAMILIES[family]
            for key, value, strain in members:
                v = dict(BASE, **{key: value})
                name = f"{test}_c{v['cell'] * 1e3:g}mm_s{v['seed']}_v{v['speed'] * 1e3:g}mm"
                old = runs.get(name)
                runs[name] = dict(name=name, test=test, strain=max(strain, old["strain"] if old else 0),
                                  families=(old["families"] if old else []) + [family], **v)
    return list(runs.values())


def command(run, args, out):
    cell, speed, strain = run["cell"], run["speed"], run["strain"]
    row = f"[1.0, {cell / 2:g}]"  # particles starting below half a cell: the bottom row
    frame_every = 0.01 * HEIGHT / speed  # a frame per 1 % of axial strain
    return [args.tsuchi, "run", os.path.join(HERE, f"{run['test']}_fixed.toml"), "--output", out,
            "--threads", str(args.threads), "-q",
            "--set", f"grid.cell_size={cell:g}",
            "--set", "grid.extent=[0.168, 0.12]",  # whole cells of 1, 2 and 4 mm
            "--set", f"bodies.0.imperfection.seed={run['seed']}",
            "--set", f"bodies.1.prescribed_velocity.y={-speed:g}",
            "--set", f"recorders.0.stop_above={strain:g}",
            "--set", f"recorders.1.max={row}", "--set", f"recorders.2.max={row}",
            "--set", f"time.end={1.2 * strain * HEIGHT / speed + 0.05:g}",
            "--set", f"output.interval={frame_every:g}",
            "--set", f"output.global_interval={frame_every / 10:g}"]


def run_one(run, args):
    out = os.path.join(args.results, "convergence", run["name"])
    os.makedirs(out, exist_ok=True)
    for name in os.listdir(out):  # an earlier, longer run's frames must not be picked up
        if name.startswith("particles") or name.endswith(".csv"):
            os.remove(os.path.join(out, name))
    cmd = command(run, args, out)
    start = time.perf_counter()
    with open(os.path.join(out, "run.log"), "w") as log:
        log.write("$ " + " ".join(cmd) + "\n")
        log.flush()
        rc = subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT, cwd=REPO).returncode
    record = dict(run, returncode=rc, wall_s=time.perf_counter() - start)
    with open(os.path.join(out, "run.json"), "w") as f:
        json.dump(record, f, indent=1)
    print(f"{run['name']}: {'done' if rc == 0 else f'FAILED (exit {rc})'} in {record['wall_s']:.0f} s",
          flush=True)
    return record


def q_near(e, q, strain):
    """Mean q over +-0.25 % of axial strain around `strain` (damps the step-to-step noise)."""
    m = np.abs(e - strain) <= STRAIN_TOL
    return float(q[m].mean()) if m.any() and e.max() >= strain - STRAIN_TOL else None


def pattern(bands):
    if not bands:
        return "none"
    if len(bands) >= 2 and min(b.angle for b in bands) < 0 < max(b.angle for b in bands):
        return "X"
    return "single" if len(bands) == 1 else f"{len(bands)} parallel"


def bands_in(frame, reference):
    body = frame["body"] == 0
    pts = frame["points"] - frame["displacement"] if reference else frame["points"]
    return find_bands(pts[body, 0], pts[body, 1], frame["max_shear_strain"][body])


def analyse(run, args):
    out = os.path.join(args.results, "convergence", run["name"])
    row = dict(run)
    path = os.path.join(out, "recorders.csv")
    if not os.path.exists(path):
        return row
    rec = np.atleast_1d(np.genfromtxt(path, delimiter=",", names=True))
    e, q = rec["axial_strain"], rec["q_kPa"]
    k = int(np.argmax(np.where(e <= 0.15 + 1e-9, q, -np.inf)))
    row.update(peak_q=float(q[k]), peak_strain=float(e[k]), max_strain=float(e.max()),
               curve=[e[::5].round(5).tolist(), q[::5].round(3).tolist()])
    for s in REPORT_Q_STRAINS:
        row[f"q{round(100 * s)}"] = q_near(e, q, s)
    frames = []
    if os.path.exists(os.path.join(out, "particles.pvd")):
        times = np.asarray(rec["time"])
        for t, name in read_pvd(os.path.join(out, "particles.pvd")):
            frames.append((float(np.interp(t, times, e)), os.path.join(out, name)))
    for s in BAND_STRAINS:
        near = [f for f in frames if abs(f[0] - s) <= 0.005]
        if not near:
            continue
        frame = read_vtu(min(near, key=lambda f: abs(f[0] - s))[1])
        deformed, initial = bands_in(frame, False), bands_in(frame, True)
        row[f"bands{round(100 * s)}"] = dict(
            pattern=pattern(deformed),
            angles=[round(b.angle, 1) for b in deformed],
            initial=[round(b.angle, 1) for b in initial],
            width_mm=[round(1e3 * b.width, 1) for b in deformed])
    return row


def fmt(v, spec, missing="-"):
    return missing if v is None else format(v, spec)


def band_cells(row, s):
    b = row.get(f"bands{round(100 * s)}")
    if not b:
        return ["-", "-", "-"]
    ang = ", ".join(f"{a:+.1f}" for a in b["angles"]) or "-"
    ini = ", ".join(f"{a:+.1f}" for a in b["initial"]) or "-"
    wid = ", ".join(f"{w:.1f}" for w in b["width_mm"]) or "-"
    return [f"{b['pattern']} ({ang})", ini, wid]


def write_report(rows, args):
    lines = ["# Triaxial case, cap fixed: convergence with grid, seed and loading rate", "",
             "Generated by `examples/triaxial/convergence.py`. Base run: the main job's input "
             "(2 mm cells, 2 x 2 particles per cell, imperfection seed 2015, cap at 0.02 m/s, i.e. "
             "an axial strain rate of 0.2 /s). Each family varies one of these. q: deviator from the "
             "bottom row of particles, kPa, mean over +-0.25 % of strain. Bands: angle from the "
             "horizontal, + rising to the right (tools/bands.py), in the deformed specimen and with "
             "the particles at their initial positions; width = full width at half maximum of the "
             "maximum shear strain across the band.", ""]
    head = ("| run | family | cell (mm) | seed | cap (m/s) | peak q (kPa) | vs MC (%) | at (%) "
            "| q 5 % | q 10 % | q 15 % | q15 / peak | bands at 8 % (deformed) | initial | width (mm) "
            "| bands at 15 % (deformed) | initial | width (mm) | wall (s) |")
    lines += [head, "|" + "---|" * (head.count("|") - 1)]
    for r in rows:
        p = CONFINING_KPA[r["test"]]
        peak = r.get("peak_q")
        err = None if peak is None else 100 * (peak / mc_peak(p) - 1)
        ratio = None if peak is None or r.get("q15") is None else r["q15"] / peak
        cells = [r["name"], "+".join(r["families"]), f"{1e3 * r['cell']:g}", str(r["seed"]),
                 f"{r['speed']:g}", fmt(peak, ".2f"), fmt(err, "+.1f"),
                 fmt(None if peak is None else 100 * r["peak_strain"], ".1f"),
                 fmt(r.get("q5"), ".1f"), fmt(r.get("q10"), ".1f"), fmt(r.get("q15"), ".1f"),
                 fmt(ratio, ".2f")] + band_cells(r, 0.08) + band_cells(r, 0.15) + [
                 fmt(r.get("wall_s"), ".0f")]
        lines.append("| " + " | ".join(cells) + " |")
    lines += ["", "Mohr-Coulomb peaks: " + ", ".join(
        f"{t} {mc_peak(CONFINING_KPA[t]):.2f} kPa" for t in sorted({r['test'] for r in rows})) + ".",
        "", "![q against axial strain](convergence.png)", ""]
    path = os.path.join(args.results, "convergence.md")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(args.results, "convergence.json"), "w") as f:
        json.dump(rows, f, indent=1)
    print(f"wrote {path}")


def plot(rows, args):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    tests = sorted({r["test"] for r in rows})
    fig, axes = plt.subplots(len(tests), len(args.families), figsize=(4.4 * len(args.families), 3.6 * len(tests)),
                             squeeze=False)
    for i, test in enumerate(tests):
        for j, family in enumerate(args.families):
            ax = axes[i][j]
            for r in rows:
                if r["test"] != test or family not in r["families"] or "curve" not in r:
                    continue
                label = {"grid": f"{1e3 * r['cell']:g} mm", "seed": f"seed {r['seed']}",
                         "rate": f"{r['speed']:g} m/s"}[family]
                ax.plot(100 * np.asarray(r["curve"][0]), r["curve"][1], lw=1.2, label=label)
            ax.axhline(mc_peak(CONFINING_KPA[test]), color="k", ls=":", lw=1, label="Mohr-Coulomb peak")
            ax.set_title(f"{test}, cap fixed: {family}")
            ax.set_xlabel("axial strain (%)")
            ax.set_ylabel("q (kPa)")
            ax.set_xlim(0, 15)
            ax.set_ylim(0, 1.25 * mc_peak(CONFINING_KPA[test]))
            ax.legend(fontsize=8, loc="lower right")
            ax.grid(alpha=0.3)
    fig.tight_layout()
    path = os.path.join(args.results, "convergence.png")
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def main(argv=None):
    ap = argparse.ArgumentParser(description="Grid, seed and rate convergence of the triaxial case.")
    ap.add_argument("--tests", nargs="+", default=["test1", "test2"], choices=sorted(CONFINING_KPA))
    ap.add_argument("--families", nargs="+", default=list(FAMILIES), choices=list(FAMILIES))
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="runs at a time")
    ap.add_argument("--threads", type=int, default=1, help="threads per run")
    ap.add_argument("--results", default=os.path.join(REPO, "results", "triaxial"))
    ap.add_argument("--tsuchi", default=os.path.join(REPO, "build", "app", "tsuchi"))
    ap.add_argument("--no-run", action="store_true", help="only analyse existing results")
    ap.add_argument("--quick", action="store_true", help="every run to 3 % only")
    args = ap.parse_args(argv)
    args.results, args.tsuchi = os.path.abspath(args.results), os.path.abspath(args.tsuchi)
    os.makedirs(args.results, exist_ok=True)
    runs = variants(args.tests, args.families)
    if args.quick:
        for r in runs:
            r["strain"] = 0.03
    # The longest runs first, so that the pool does not end on one long run.
    cost = lambda r: r["strain"] / (r["speed"] * r["cell"] ** 3)  # noqa: E731
    runs.sort(key=cost, reverse=True)
    records = {}
    if not args.no_run:
        with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            for rec in pool.map(lambda r: run_one(r, args), runs):
                records[rec["name"]] = rec
    rows = []
    for r in sorted(runs, key=lambda r: (r["test"], -r["cell"], r["seed"] != 2015, r["seed"], -r["speed"])):
        rec = records.get(r["name"])
        if rec is None:
            jpath = os.path.join(args.results, "convergence", r["name"], "run.json")
            if os.path.exists(jpath):
                with open(jpath) as f:
                    rec = json.load(f)
        row = analyse(r, args)
        if rec:
            row["wall_s"], row["returncode"] = rec.get("wall_s"), rec.get("returncode")
        rows.append(row)
    write_report(rows, args)
    plot(rows, args)
    return 1 if any(r.get("returncode") not in (0, None) for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
