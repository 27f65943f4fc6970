"""Runs examples/excavation at several gamma H / c (default 3.0, 3.5, 4.0, 4.5; the cohesion is set
by --set materials.0.cohesion) and writes OUT/study.csv (one row per ratio) and OUT/study.png
(crest settlement against time in stage 2, and the plastic shear strain of the last ratio at the end).

usage: study.py OUT [--ratios 3.0 4.5 ...] [--tsuchi PATH] [--set KEY=VALUE ...]
"""
import argparse
import csv
import os
import subprocess
import sys
import time
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(REPO, "tools"))
import numpy as np  # noqa: E402
from vtu import read_pvd, read_vtu  # noqa: E402

INPUT = os.path.join(HERE, "excavation.toml")
DEPTH = 10.0          # H, m: the cut's depth (crest y = 15 m, floor y = 5 m)
FAIL_MM = 100.0       # crest settlement above H / 100 at the end of stage 2: the cut has failed


def unit_weight(input_path=INPUT):
    with open(input_path, "rb") as f:
        cfg = tomllib.load(f)
    return cfg["materials"][0]["density"] * abs(cfg["model"]["gravity"][1])


def cohesion(ratio, input_path=INPUT):
    """c (Pa) that gives gamma H / c = ratio."""
    return unit_weight(input_path) * DEPTH / ratio


def run_case(tsuchi, out, ratio, sets=(), threads=1, input_path=INPUT):
    """Runs the input at gamma H / c = ratio into out; (wall seconds, CompletedProcess)."""
    cmd = [tsuchi, "run", input_path, "-o", out, "-q", "-j", str(threads),
           "--set", f"materials.0.cohesion={cohesion(ratio, input_path):.6g}"]
    for s in sets:
        cmd += ["--set", s]
    start = time.monotonic()
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    return time.monotonic() - start, r


def read_csv(path):
    """Columns of a tsuchi CSV as arrays (name -> array); string columns stay lists."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    out = {}
    for j, name in enumerate(rows[0]):
        col = [r[j] for r in rows[1:]]
        try:
            out[name] = np.array([float(v) for v in col])
        except ValueError:
            out[name] = col
    return out


def summary(out):
    """The stage-2 numbers of one run: values at the end of stage 1 and at the end of the run."""
    rec = read_csv(os.path.join(out, "recorders.csv"))
    s1 = np.flatnonzero(rec["stage"] == 1)[-1]
    end = len(rec["stage"]) - 1
    s = {k: rec[k][end] for k in ("crest_mm", "face_top_mm", "face_min_mm", "face_sxx_kPa",
                                  "floor_heave_mm", "pss_max")}
    s["face_sxx_kPa_before"] = rec["face_sxx_kPa"][s1]
    # crest settlement over the last 60 % of stage 2: a standing cut has stopped, a failing one creeps on
    t = rec["time"]
    t2 = t[rec["stage"] == 2]
    mid = np.flatnonzero((rec["stage"] == 2) & (t >= t2[0] + 0.4 * (t2[-1] - t2[0])))[0]
    s["creep_mm"] = rec["crest_mm"][end] - rec["crest_mm"][mid]
    s["stands"] = bool(s["crest_mm"] < FAIL_MM)
    return s


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--ratios", type=float, nargs="+", default=[3.0, 3.5, 4.0, 4.5])
    ap.add_argument("--tsuchi", default=os.path.join(REPO, "build", "app", "tsuchi"))
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--set", dest="sets", action="append", default=[])
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for ratio in a.ratios:
        out = os.path.join(a.out, f"ratio_{ratio:.2f}")
        seconds, r = run_case(a.tsuchi, out, ratio, a.sets, a.threads)
        if r.returncode != 0:
            print(r.stderr, file=sys.stderr)
            return 1
        s = summary(out)
        s.update(ratio=ratio, cohesion_kPa=cohesion(ratio) / 1e3, wall_s=seconds, dir=out)
        rows.append(s)
        print(f"gamma H / c = {ratio:.2f} (c = {s['cohesion_kPa']:.1f} kPa): "
              f"{'stands' if s['stands'] else 'FAILS '}  crest {s['crest_mm']:7.1f} mm "
              f"(creep {s['creep_mm']:5.1f}), face top {s['face_top_mm']:7.1f} mm, "
              f"face min {s['face_min_mm']:7.1f} mm, floor heave {s['floor_heave_mm']:5.1f} mm, "
              f"pss_max {s['pss_max']:.3f}, face sigma_xx {s['face_sxx_kPa_before']:.1f} -> "
              f"{s['face_sxx_kPa']:.1f} kPa  [{seconds:.1f} s]")
    cols = ["ratio", "cohesion_kPa", "stands", "crest_mm", "creep_mm", "face_top_mm", "face_min_mm",
            "floor_heave_mm", "pss_max", "face_sxx_kPa_before", "face_sxx_kPa", "wall_s"]
    with open(os.path.join(a.out, "study.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for s in rows:
            w.writerow([f"{s[c]:.6g}" if isinstance(s[c], float) else s[c] for c in cols])
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2), gridspec_kw={"width_ratios": [1, 1.6]})
    for s in rows:
        rec = read_csv(os.path.join(s["dir"], "recorders.csv"))
        m = rec["stage"] == 2
        ax.plot(rec["time"][m] - rec["time"][m][0], rec["crest_mm"][m], label=f"γH/c = {s['ratio']:.2f}")
    ax.axhline(FAIL_MM, color="grey", lw=0.8, ls="--")
    ax.set_yscale("log")
    ax.set_xlabel("time in stage 2 (s)")
    ax.set_ylabel("crest settlement (mm)")
    ax.legend()
    last = rows[-1]
    frame = read_vtu(os.path.join(last["dir"], read_pvd(os.path.join(last["dir"], "particles_stage2.pvd"))[-1][1]))
    p = frame["points"]
    sc = bx.scatter(p[:, 0], p[:, 1], c=frame["plastic_shear_strain"], s=6, cmap="viridis",
                    vmin=0, vmax=max(0.05, float(np.percentile(frame["plastic_shear_strain"], 99))))
    fig.colorbar(sc, ax=bx, label="plastic shear strain")
    bx.set_aspect("equal")
    bx.set_title(f"end of stage 2, γH/c = {last['ratio']:.2f}")
    bx.set_xlabel("x (m)")
    bx.set_ylabel("y (m)")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "study.png"), dpi=120)
    print(f"wrote {os.path.join(a.out, 'study.csv')} and study.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
