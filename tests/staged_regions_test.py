#!/usr/bin/env python3
"""examples/staged_regions (issue 41, staged regions): a fill added in two lifts by regions of `add`,
taken off by a half-space of `remove`, then a box of the ground cut out; each stage's displacement
against 1D constrained compression (0.5 %) and the base reaction against the weight there (1e-4),
through the example's check.py. Also: the run restarted from the checkpoint written at the end of
stage "lift 2" ends byte-identical.

usage: staged_regions_test.py TSUCHI_BINARY
"""
import filecmp
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(HERE, "..", "examples", "staged_regions")
sys.path.insert(0, EXAMPLE)
import check  # noqa: E402


def run(tsuchi, args, cwd):
    r = subprocess.run([tsuchi, "run", "-q", *args], cwd=cwd, capture_output=True, text=True, timeout=600)
    if r.returncode != 0:
        print(r.stdout + r.stderr)
        sys.exit(f"tsuchi run {' '.join(args)}: exit {r.returncode}")


def main():
    tsuchi = os.path.abspath(sys.argv[1])
    model = os.path.join(EXAMPLE, "staged_regions.toml")
    with tempfile.TemporaryDirectory(prefix="tsuchi_regions_") as tmp:
        run(tsuchi, [model, "-o", "full"], tmp)
        rows, failures = check.compare(os.path.join(tmp, "full"))
        for name, end, u, u_ref, w, w_ref in rows:
            print(f"{name:8s} {end:12s} u_y {u:8.4f} mm (1D {u_ref:8.4f}, {100 * (u / u_ref - 1):+.2f} %)  "
                  f"base {w:.4f} kN/m (weight {w_ref:.4f})")
        # Stop at the end of stage 3 ("lift 2", step from stages.csv) and restart from there.
        ends = check.stage_ends(os.path.join(tmp, "full"))
        stop = int(ends["lift 2"][0]["end_step"])
        run(tsuchi, [model, "-o", "part", "--set", f"time.max_steps={stop}"], tmp)
        run(tsuchi, [model, "-o", "part", "--restart", "part/checkpoint.tsuchi"], tmp)
        for name in ("recorders.csv", "stages.csv", "checkpoint.tsuchi"):
            if not filecmp.cmp(os.path.join(tmp, "full", name), os.path.join(tmp, "part", name), shallow=False):
                failures.append(f"{name} after a restart at the end of stage \"lift 2\" differs from the run without")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
