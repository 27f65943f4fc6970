#!/usr/bin/env python3
"""Hoop stress at the tunnel wall against Kirsch's solution.

    python3 compare.py results/particles_NNNNNN.vtu   (default: the last frame of results/)

Particles of the first ring around the hole (initial distance from the centre below a + 2 s, s the
particle spacing) within 15 degrees of the springline (theta = 0) and of the crown (theta = 90):
their mean hoop stress against Kirsch's sigma_theta at the same r and theta under the far field
S_v = rho g (depth of the tunnel's centre), S_h = K0 S_v (compression positive):

    sigma_theta = (S_h + S_v)/2 (1 + a^2/r^2) - (S_h - S_v)/2 (1 + 3 a^4/r^4) cos(2 theta).
"""
import glob
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from vtu import read_vtu  # noqa: E402

A, XC, YC, SURFACE, RHO, G, K0 = 1.0, 0.0, 8.0, 16.0, 2000.0, 9.81, 0.5


def kirsch_hoop(r, theta, sv, sh):
    return 0.5 * (sh + sv) * (1 + A**2 / r**2) - 0.5 * (sh - sv) * (1 + 3 * A**4 / r**4) * math.cos(2 * theta)


def compare(frame):
    f = read_vtu(frame)
    x, u, s = f["points"], f["displacement"], f["stress"]
    x0 = x - u
    spacing = 2.0 * float(np.median(f["radius"]))
    dx, dy = x0[:, 0] - XC, x0[:, 1] - YC
    r = np.hypot(dx, dy)
    theta = np.arctan2(dy, dx)
    sv = RHO * G * (SURFACE - YC)
    sh = K0 * sv
    hoop = -(s[:, 0] * np.sin(theta) ** 2 + s[:, 1] * np.cos(theta) ** 2 - 2 * s[:, 3] * np.sin(theta) * np.cos(theta))
    ring = r < A + 2 * spacing
    out = {}
    for name, at in (("springline", 0.0), ("crown", math.pi / 2)):
        sel = ring & (np.abs(theta - at) < math.radians(15))
        ref = np.array([kirsch_hoop(ri, ti, sv, sh) for ri, ti in zip(r[sel], theta[sel])])
        out[name] = (float(hoop[sel].mean()), float(ref.mean()), int(sel.sum()))
        print(f"{name:10s}: hoop stress {out[name][0] / 1e3:8.2f} kPa, Kirsch {out[name][1] / 1e3:8.2f} kPa "
              f"({(out[name][0] / out[name][1] - 1) * 100:+.1f} %), {out[name][2]} particles; at the wall "
              f"{(3 * sv - sh if at == 0 else 3 * sh - sv) / 1e3:.2f} kPa")
    return out


if __name__ == "__main__":
    frame = sys.argv[1] if len(sys.argv) > 1 else sorted(glob.glob("results/particles_*.vtu"))[-1]
    compare(frame)
