#!/usr/bin/env python3
"""examples/stl_embankment at 0.5 m cells: a body read from an STL file is filled to the prism's
volume (20 m^3, to 0.5 %), and at rest the vertical stress under the crest at the foundation's top
is the fill's weight gamma H plus the foundation above the recorded particles (within 10 %: the
fill spreads a little), the crest settling by the 1D compression of fill and foundation, 2.5 mm,
within 30 % (lateral spreading adds to it; 3.0 mm at 0.5 and at 0.25 m cells).

usage: stl_embankment_test.py TSUCHI_BINARY
"""
import csv
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
INPUT = os.path.join(HERE, "..", "examples", "stl_embankment", "embankment.toml")
G, H = 9.81, 2.0
FILL, FOUNDATION = 1900.0, 2000.0


def main():
    tsuchi = os.path.abspath(sys.argv[1])
    failures = []
    with tempfile.TemporaryDirectory(prefix="tsuchi_stl_") as tmp:
        out = os.path.join(tmp, "out")
        r = subprocess.run([tsuchi, "run", INPUT, "-o", out, "--set", "grid.cell_size=0.5",
                            "--set", "recorders.0.min=[5.5,1.5,0.0]", "--set", "recorders.1.min=[5.5,3.5,0.0]"],
                           capture_output=True, text=True, timeout=300)
        text = r.stdout + r.stderr
        if r.returncode != 0:
            print(text)
            print("FAILED: the run")
            return 1
        m = re.search(r"^body\s+embankment\s+(\d+) particles, a stl, (\S+) m\^3", r.stdout, re.M)
        volume = float(m.group(2)) if m else float("nan")
        if not abs(volume - 20.0) <= 0.005 * 20.0:
            failures.append(f"the STL body's volume {volume} m^3, expected 20")
        with open(os.path.join(out, "recorders.csv"), newline="") as f:
            last = list(csv.DictReader(f))[-1]
        # The recorded particles' centres at 0.5 m cells, 2 per cell: y = 1.625 and 1.875, a mean
        # depth of 0.25 m below the foundation's top.
        expected = -(FILL * G * H + FOUNDATION * G * 0.25)
        sigma = float(last["crest_base_stress"])
        if not abs(sigma - expected) <= 0.10 * abs(expected):
            failures.append(f"sigma_yy under the crest {sigma:.0f} Pa, expected {expected:.0f} Pa within 10 %")
        M = lambda E, nu: E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
        q = FILL * G * H
        oned = FILL * G * H * H / (2 * M(20e6, 0.3)) + q * 2.0 / M(50e6, 0.3)
        settle = float(last["crest_settlement"])
        if not abs(settle - oned) <= 0.30 * oned:
            failures.append(f"crest settlement {settle * 1e3:.2f} mm, expected the 1D {oned * 1e3:.2f} mm within 30 %")
        print(f"volume {volume} m^3, sigma_yy {sigma:.0f} Pa (expected {expected:.0f}), settlement "
              f"{settle * 1e3:.2f} mm (1D {oned * 1e3:.2f} mm)")
    for f in failures:
        print("FAIL:", f)
    print(f"{'FAILED' if failures else 'passed'}: STL embankment")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
