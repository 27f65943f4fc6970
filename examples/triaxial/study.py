"""Runs the plane-strain triaxial study (3 confining pressures x cap fixed / free) and reports.

usage: /usr/bin/python3 examples/triaxial/study.py [--strain 0.15] [--jobs N] [--results results/triaxial]
           [--tsuchi build/app/tsuchi] [--cases test1_fixed test2_free ...] [--no-run]

For each case it runs `tsuchi run examples/triaxial/CASE.toml --output RESULTS/CASE` with the
stop strain overridden (--set recorders.0.stop_above=S --set time.end=5 S + 0.05), --jobs runs at
a time (default: the number of cores), the run's output going to RESULTS/CASE/run.log and its
wall time and particle-steps/s to RESULTS/CASE/run.json. Then it draws the plots (plot.py), finds
the shear bands at 15 % and 50 % axial strain (tools/bands.py) and writes RESULTS/report.md.
--no-run skips the runs and reports on what is already in RESULTS.
Exit status: 0 if every run finished, 1 otherwise (the report is written anyway).
"""
import argparse
import json
import os
import re
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
import numpy as np  # noqa: E402
import plot  # noqa: E402
from plot import CASES, CONFINING_KPA, cap_of, mc_peak, test_of  # noqa: E402

sys.path.insert(0, os.path.join(REPO, "tools"))
sys.path.insert(1, os.path.join(REPO, "tests"))  # band_reference, the independent band estimate
from vtu import read_vtu  # noqa: E402

DONE_RE = re.compile(r"done: (\d+) steps to t = (\S+) s in (\S+) s \((\S+) particle-steps/s\); (\d+) frames")
REPORT_STRAINS = (0.15, 0.50)
PRINT_LOCK = threading.Lock()


def run_case(case, args):
    """Runs one case; returns its run record (also saved as CASE/run.json)."""
    out = os.path.join(args.results, case)
    os.makedirs(out, exist_ok=True)
    # Old frames would outlive a shorter rerun and be picked up by the plots.
    for name in os.listdir(out):
        if (name.startswith("particles_") and name.endswith(".vtu")) or name in (
                "particles.pvd", "recorders.csv", "global.csv", "shear_strain.png", "run.json"):
            os.remove(os.path.join(out, name))
    cmd = [args.tsuchi, "run", os.path.join(HERE, f"{case}.toml"), "--output", out,
           "--set", f"recorders.0.stop_above={args.strain:g}",
           "--set", f"time.end={args.strain * 5 + 0.05:g}",
           # Share the cores between the runs: more threads than cores would make each run crawl.
           "--threads", str(max(1, (os.cpu_count() or 1) // max(1, args.jobs)))]
    record = {"case": case, "command": " ".join(cmd)}
    start = time.perf_counter()
    with open(os.path.join(out, "run.log"), "w") as log:
        log.write("$ " + record["command"] + "\n")
        log.flush()
        try:
            proc = subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT, cwd=REPO)
            record["returncode"] = proc.returncode
        except OSError as e:
            log.write(f"could not start: {e}\n")
            record["returncode"] = None
    record["wall_s"] = time.perf_counter() - start
    with open(os.path.join(out, "run.log")) as log:
        text = log.read()
    m = None
    for m in DONE_RE.finditer(text):
        pass
    if m:
        record.update(steps=int(m.group(1)), end_time=float(m.group(2)), solver_s=float(m.group(3)),
                      particle_steps_per_s=float(m.group(4)), frames=int(m.group(5)))
    record["ok"] = record["returncode"] == 0 and m is not None
    with open(os.path.join(out, "run.json"), "w") as f:
        json.dump(record, f, indent=1)
    status = "done" if record["ok"] else f"FAILED (exit {record['returncode']})"
    with PRINT_LOCK:  # runs finish in worker threads; keep their lines whole
        print(f"{case}: {status} in {record['wall_s']:.1f} s", flush=True)
    return record


def load_record(case_dir):
    path = os.path.join(case_dir, "run.json")
    if os.path.exists(path):
        with open(path) as f:
            return json.load(f)
    return None


def band_text(bands):
    if not bands:
        return "none", "-"
    angles = ", ".join(f"{b.inclination:.1f}° {'↗' if b.angle > 0 else '↖'}{'' if b.clear else ' (faint)'}"
                       for b in bands)
    quality = ", ".join(f"{b.explained:.2f}/{b.r2:.3f}" for b in bands)
    return angles, quality


def analyse_case(case_dir):
    """Peak q, q at 15 %, and the bands at 15 % and 50 % of one case."""
    rec = plot.read_recorders(case_dir)
    row = {}
    if rec is not None and "q_kPa" in rec and len(rec["q_kPa"]) > 0:
        # The peak of the test is the first maximum, within the paper's 15 % of strain: beyond 40 %
        # a fixed cap squeezes the flattened specimen between two rough plates and q climbs again,
        # which is not the soil's strength.
        early = rec["axial_strain"] <= 0.15 + 1e-9
        k = int(np.argmax(np.where(early, rec["q_kPa"], -np.inf)))
        row["peak_q"] = float(rec["q_kPa"][k])
        row["peak_strain"] = float(rec["axial_strain"][k])
        row["max_strain"] = float(rec["axial_strain"].max())
        if row["max_strain"] >= 0.15 - 1e-9:
            # Strain grows monotonically with time under the pushed cap.
            row["q15"] = float(np.interp(0.15, rec["axial_strain"], rec["q_kPa"]))
    frames = plot.frames_with_strain(case_dir, rec)
    for target in REPORT_STRAINS:
        f = plot.frame_near(frames, target)
        if f is not None:
            frame = read_vtu(f[2])
            # The same particles at their initial positions: the bands' orientation in the
            # undeformed specimen (compression flattens them in the deformed one).
            initial = dict(frame, points=frame["points"] - frame["displacement"])
            key = f"bands{int(round(100 * target))}"
            row[key] = plot.specimen_bands(frame)
            row[key + "_initial"] = plot.specimen_bands(initial)
            if target == 0.15:  # the report's independent column is at 15 %
                row[key + "_check"] = independent_check(f[2])
    return row


def independent_check(path):
    """Per band of bands.py, the angle of the independent ridge estimate (tests/band_reference.py,
    a Hessian ridge detector on the gridded field) and the difference, deformed configuration;
    None where scipy, which that estimate needs, is missing."""
    try:
        from band_reference import compare_frame
    except ImportError:
        return None
    _, pairs = compare_frame(path)
    return [(p["angle"], p["reference"]) for p in pairs if p["arm"] is None]


def check_text(pairs):
    if pairs is None:
        return "-"
    if not pairs:
        return "none"
    return ", ".join(f"{a:+.1f} / {'-' if r is None else format(r, '+.1f')}" for a, r in pairs)


def pct(fraction):
    return None if fraction is None else 100 * fraction


def fmt(value, spec, missing="-"):
    return missing if value is None else format(value, spec)


def write_report(args, cases, records):
    how = ("Post-processed the results already" if args.no_run
           else f"Ran to {100 * args.strain:g} % axial strain with `{args.tsuchi}`, {args.jobs} at a time,")
    lines = ["# Plane-strain triaxial compression study", "",
             f"{how} in `{args.results}`. "
             "Mohr-Coulomb peak: q = p (N - 1) + 2 c sqrt(N), N = (1 + sin phi) / (1 - sin phi), "
             f"c = {plot.COHESION_KPA} kPa, phi = {plot.FRICTION_DEG} deg.", "",
             "Bands: inclination from the horizontal, ↗ rising to the right, ↖ rising to the left "
             "(tools/bands.py). Fit quality: explained / r2 per band, where *explained* is the share "
             "of the high-strain weight lying within one band width of the band's centre line and "
             "*r2* = 1 - lambda_min / lambda_max of the band particles' weighted covariance. "
             "Angles are measured in the deformed specimen (as in the snapshots) and, in the "
             "*initial positions* columns, with every particle put back at its initial position. "
             "A band's angle is that of the straight parts of its arms (the ridge traced slice by "
             "slice; tools/README-bands.md); *faint* bands do not pass the detector's fit gate. The "
             "*independent* column gives, per band, bands.py's signed angle and that of a separate "
             "method (tests/band_reference.py: ridges of the Hessian of the gridded field), deformed.",
             "",
             "| test | cap | p (kPa) | reached strain (%) | peak q up to 15 % (kPa) | at strain (%) "
             "| MC peak (kPa) | error (%) | q at 15 % (kPa) "
             "| bands at 15 % | fit quality | same, initial positions | bands.py / independent at 15 % "
             "| bands at 50 % | fit quality "
             "| same, initial positions | wall time (s) | particle-steps/s | run |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for case in cases:
        d = os.path.join(args.results, case)
        test, cap = test_of(case), cap_of(case)
        p = CONFINING_KPA.get(test)
        q_mc = mc_peak(p) if p is not None else None
        row = analyse_case(d) if os.path.isdir(d) else {}
        peak = row.get("peak_q")
        err = 100 * (peak - q_mc) / q_mc if peak is not None and q_mc else None
        b15 = band_text(row["bands15"]) if "bands15" in row else ("-", "-")
        b50 = band_text(row["bands50"]) if "bands50" in row else ("-", "-")
        i15 = band_text(row["bands15_initial"])[0] if "bands15" in row else "-"
        i50 = band_text(row["bands50_initial"])[0] if "bands50" in row else "-"
        rec = records.get(case) or load_record(d) or {}
        if not rec:
            status = "not run"
        else:
            status = "ok" if rec.get("ok") else f"failed ({rec.get('returncode')})"
        cells = [test, cap, fmt(p, "g"), fmt(pct(row.get("max_strain")), ".1f"), fmt(peak, ".1f"),
                 fmt(pct(row.get("peak_strain")), ".1f"), fmt(q_mc, ".1f"), fmt(err, "+.1f"),
                 fmt(row.get("q15"), ".1f"), b15[0], b15[1], i15, check_text(row.get("bands15_check")),
                 b50[0], b50[1], i50,
                 fmt(rec.get("wall_s"), ".0f"), fmt(rec.get("particle_steps_per_s"), ".3g"), status]
        lines.append("| " + " | ".join(cells) + " |")
    if os.path.exists(os.path.join(args.results, "convergence.md")):
        lines += ["", "Convergence of the cap-fixed cases with grid, imperfection seed and loading rate: "
                  "[convergence.md](convergence.md) (examples/triaxial/convergence.py)."]
    lines += ["", "## Stress-strain curves", "", "![q against axial strain](stress_strain.png)", "",
              "## Maximum shear strain", ""]
    for case in cases:
        png = os.path.join(args.results, case, "shear_strain.png")
        if os.path.exists(png):
            lines += [f"### {case}", "", f"![{case}]({case}/shear_strain.png)", ""]
    lines += [
        "## What to look for", "",
        "- **Peak**: q should level off close to the Mohr-Coulomb peak of its test (dotted lines "
        "in the plot, the error column in the table).",
        "- **Cap fixed**: the cap cannot slide, so two shear bands of opposite inclination form an X "
        "(one ↗, one ↖, both about 45-60° from the horizontal; the paper saw about 50°), and q stays "
        "roughly constant after the peak.",
        "- **Cap free**: one diagonal band dominates, the upper block slides along it and the cap "
        "moves sideways (recorders.csv, cap_dx_m); q falls after about 2 % axial strain.",
        "- **Band angles** between 45° + psi/2 = 45° (Roscoe, dilatancy angle psi = 0 in the inputs) "
        "and 45° + phi/2 = 60.25° (Coulomb); the paper's ~50° lies in between. The deformed "
        "specimen's bands are flatter than the same particles' in their initial positions. A missing "
        "band at 15 % or angles outside 45-60° deserve a look at the snapshots.", ""]
    path = os.path.join(args.results, "report.md")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"wrote {path}")


def main(argv=None):
    p = argparse.ArgumentParser(description="Runs the triaxial study and writes report.md.")
    p.add_argument("--strain", type=float, default=0.15, help="axial strain at which runs stop (fraction)")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="runs at a time")
    p.add_argument("--results", default=os.path.join(REPO, "results", "triaxial"))
    p.add_argument("--tsuchi", default=os.path.join(REPO, "build", "app", "tsuchi"))
    p.add_argument("--cases", nargs="+", default=CASES, choices=CASES, metavar="CASE")
    p.add_argument("--no-run", action="store_true", help="only post-process existing results")
    args = p.parse_args(argv)
    args.results = os.path.abspath(args.results)
    args.tsuchi = os.path.abspath(args.tsuchi)
    os.makedirs(args.results, exist_ok=True)

    records = {}
    if not args.no_run:
        if not os.access(args.tsuchi, os.X_OK):
            print(f"{args.tsuchi}: not found or not executable", file=sys.stderr)
            return 1
        with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            for rec in pool.map(lambda c: run_case(c, args), args.cases):
                records[rec["case"]] = rec

    present = plot.present_cases(args.results, args.cases)
    if present:
        subprocess.run([sys.executable, os.path.join(HERE, "plot.py"), args.results] + present, check=False)
    write_report(args, args.cases, records)
    failed = [c for c, r in records.items() if not r.get("ok")]
    if failed:
        print("failed: " + ", ".join(failed), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
