#!/usr/bin/env python3
"""examples/cavity_expansion at 0.2 m cells (5 cells across the cavity's radius) with the ramp over
4 s: a follower pressure of 44 kPa expands the cavity to the closed form's radius, a = 1.297 a0 (30 %
hoop strain), the closed form's pressure at the measured radius within 4 % of p - p0 = 24 kPa
(measured -2.1 %: a = 1.276 a0); the same pressure as a dead load stops near the radius the closed
form gives for the pressure p a0 / a it then exerts, 1.143 a0, within 3 % (measured 1.150 a0, +0.6 %),
and more than 8 % short of the follower's (the follower is what makes it right). About 7 s.

usage: cavity_expansion_test.py TSUCHI_BINARY
"""
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(HERE, "..", "examples", "cavity_expansion")
sys.path.insert(0, EXAMPLE)
import compare  # noqa: E402

# 0.2 m cells, the ramp over 4 s and 1 s at 44 kPa (8 s and 2 s in the example).
SMALL = ["grid.cell_size=0.2", "loads.0.max=[1.1,1.1]", "functions.0.table=[[0.0,0.454545454545454545],[4.0,1.0]]",
         "time.end=5.0", "output.interval=5.0"]


def run(tsuchi, out, extra):
    r = subprocess.run([tsuchi, "run", os.path.join(EXAMPLE, "cavity.toml"), "-q", "-o", out] +
                       [a for s in SMALL + extra for a in ("--set", s)], capture_output=True, text=True, timeout=300)
    if r.returncode != 0:
        print(r.stdout + r.stderr)
        raise SystemExit("FAILED: the run")
    frames = sorted(f for f in os.listdir(out) if f.startswith("particles_") and f.endswith(".vtu"))
    return os.path.join(out, frames[-1])


def main():
    tsuchi = os.path.abspath(sys.argv[1])
    failures = []
    with tempfile.TemporaryDirectory(prefix="tsuchi_cavity_") as tmp:
        print("follower:")
        f = compare.report(run(tsuchi, os.path.join(tmp, "follow"), []))
        print("dead load:")
        d = compare.report(run(tsuchi, os.path.join(tmp, "dead"), ["loads.0.follow=false"]))
    excess = compare.P_END - compare.P0
    err = (f["p_closed_form"] - compare.P0) / excess - 1.0
    if not abs(err) <= 0.04:
        failures.append(f"follower: the closed form's p - p0 at a = {f['a']:.4f} m is {100 * err:+.1f} % off the "
                        f"applied {excess / 1e3:.0f} kPa, expected within 4 %")
    if not f["a"] / compare.A0 - 1.0 >= 0.25:
        failures.append(f"follower: a / a0 = {f['a']:.4f}, expected a strain of tens of percent (the closed form's 1.297)")
    if not abs(d["a"] / d["a_dead"] - 1.0) <= 0.03:
        failures.append(f"dead load: a = {d['a']:.4f} m, expected the dead load's {d['a_dead']:.4f} m within 3 %")
    if not d["a"] < 0.92 * f["a_follower"]:
        failures.append(f"dead load: a = {d['a']:.4f} m, expected well short of the follower's {f['a_follower']:.4f} m")
    for msg in failures:
        print("FAIL:", msg)
    print(f"{'FAILED' if failures else 'passed'}: cavity expansion")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
