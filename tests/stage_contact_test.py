#!/usr/bin/env python3
"""Contact per stage (issue 41): examples/sliding_block/released.toml places a block on a 30 deg
incline bonded to a rigid base (no [[contact]]), releases it in stage 2 ([[stages.contact]],
mu = 0.2) and glues it again in stage 3 (contact = []). Checks: the block at rest in stage 1
(|v| < 1e-3 m/s; sliding, it would reach 0.16 m/s); its acceleration in stage 2 within 0.5 % of Coulomb's g (sin th - mu cos th);
global.csv's rows all as long as its header, which has contact_nodes; contact.pvd lists exactly the
contact frames there are, none of stage 1; a run stopped inside stage 2 and restarted from its
checkpoint ends byte-identical.

usage: stage_contact_test.py TSUCHI_BINARY
"""
import csv
import filecmp
import math
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
MODEL = os.path.join(HERE, "..", "examples", "sliding_block", "released.toml")
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def run(tsuchi, args, cwd):
    r = subprocess.run([tsuchi, "run", "-q", MODEL, *args], cwd=cwd, capture_output=True, text=True, timeout=300)
    if r.returncode != 0:
        print(r.stdout + r.stderr)
        sys.exit(f"tsuchi run {' '.join(args)}: exit {r.returncode}")


def main():
    tsuchi = os.path.abspath(sys.argv[1])
    with tempfile.TemporaryDirectory(prefix="tsuchi_stage_contact_") as tmp:
        run(tsuchi, ["-o", "full"], tmp)
        full = os.path.join(tmp, "full")
        with open(os.path.join(full, "recorders.csv")) as f:
            rows = [(float(r["time"]), float(r["velocity"]), int(r["stage"])) for r in csv.DictReader(f)]
        placed = [abs(v) for t, v, s in rows if s == 1]
        check(max(placed) < 1e-3, f"stage 1: the bonded block moves at up to {max(placed):.3g} m/s")

        def at(t):
            return min((r for r in rows if r[2] == 2), key=lambda r: abs(r[0] - t))
        (t1, v1, _), (t2, v2, _) = at(0.08), at(0.2)
        a = (v2 - v1) / (t2 - t1)
        coulomb = 9.81 * (math.sin(math.radians(30)) - 0.2 * math.cos(math.radians(30)))
        print(f"stage 2: a = {a:.5f} m/s^2 against Coulomb's {coulomb:.5f} ({100 * (a / coulomb - 1):+.3f} %)")
        check(abs(a / coulomb - 1) < 5e-3, f"stage 2: a = {a:.5f} m/s^2 against {coulomb:.5f}")

        with open(os.path.join(full, "global.csv")) as f:
            lines = f.read().splitlines()
        header = lines[0].split(",")
        check("contact_nodes" in header, "global.csv has no contact_nodes column")
        check(all(len(l.split(",")) == len(header) for l in lines[1:]), "global.csv rows of unequal length")
        with open(os.path.join(full, "contact.pvd")) as f:
            listed = re.findall(r'file="([^"]+)"', f.read())
        present = sorted(n for n in os.listdir(full) if n.startswith("contact_") and n.endswith(".vtu"))
        check(listed == present, f"contact.pvd lists {listed}, the directory holds {present}")
        with open(os.path.join(full, "stages.csv")) as f:
            first_of_stage2 = int(list(csv.DictReader(f))[1]["first_frame"])
        check(all(int(n[8:14]) > first_of_stage2 for n in listed),
              f"contact.pvd lists a frame of stage 1 (stage 2 opens with frame {first_of_stage2}): {listed}")

        run(tsuchi, ["-o", "part", "--set", "time.max_steps=2500"], tmp)
        run(tsuchi, ["-o", "part", "--restart", "part/checkpoint.tsuchi"], tmp)
        for name in ("recorders.csv", "global.csv", "stages.csv", "contact.pvd", "checkpoint.tsuchi"):
            check(filecmp.cmp(os.path.join(full, name), os.path.join(tmp, "part", name), shallow=False),
                  f"{name} after a restart inside stage 2 differs from the run without")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
