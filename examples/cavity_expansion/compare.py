#!/usr/bin/env python3
"""The cavity's radius against Gibson and Anderson's closed form (README.md).

    /usr/bin/python3 compare.py [RESULTS_DIR or FRAME.vtu]   (default: results/)

prints the pressure-expansion curve of every frame (the applied pressure, the measured radius, the
closed form's pressure at it) and, for the last frame, the closed form's radii at 44 kPa.

The particles at the wall (initial distance r0 from the axis below a0 + s, s the particle spacing)
give the cavity's radius a: the clay flows at constant volume (nu = 0.49), so every ring of
material keeps its area, r^2 - r0^2 = a^2 - a0^2, and a = sqrt(a0^2 + mean(r^2 - r0^2)). Against it:
the closed form's pressure at that radius, and its radius at the applied pressure,

    p - p0 = c_u [1 + ln((G / c_u)(1 - a0^2 / a^2))]        (plastic phase, Yu 2000 eq 4.39)

and the radius a dead load of the same pressure would reach: it keeps the force p a0 per radian of
the initial wall, so the wall sees the true pressure p a0 / a.
"""
import glob
import math
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from vtu import read_vtu  # noqa: E402

A0, P0, CU, G = 1.0, 20.0e3, 10.0e3, 100.0e3
P_END = 44.0e3


def closed_form_pressure(a):
    """Gibson and Anderson's cavity pressure at radius a (elastic phase below first yield)."""
    elastic = 2.0 * G * (a * a - A0 * A0) / (2.0 * a * a)  # p - p0 = 2 G u/a, small strain, u/a ~ (a^2 - a0^2) / 2a^2
    plastic_at = 1.0 / math.sqrt(1.0 - CU / G)  # a / a0 at first yield, where (G/c_u)(1 - a0^2/a^2) = 1
    if a < plastic_at * A0:
        return P0 + elastic
    return P0 + CU * (1.0 + math.log((G / CU) * (1.0 - A0 * A0 / (a * a))))


def closed_form_radius(p, dead=False):
    """The radius at which the closed form's pressure is p (a follower), or p a0 / a (a dead load)."""
    lo, hi = A0 * (1.0 + 1e-12), 100.0 * A0
    target = (lambda a: p * A0 / a) if dead else (lambda a: p)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if closed_form_pressure(mid) < target(mid):
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def cavity_radius(frame):
    f = read_vtu(frame)
    x, u = f["points"][:, :2], f["displacement"][:, :2]
    x0 = x - u
    # The lattice's first column lies at x = s/2 (rollers at x = 0): the particle spacing s.
    s = 2.0 * float(np.min(x0[:, 0]))
    r0 = np.hypot(x0[:, 0], x0[:, 1])
    r = np.hypot(x[:, 0], x[:, 1])
    ring = r0 < A0 + s  # every particle whose centre started within a spacing of the wall
    return math.sqrt(A0 * A0 + float(np.mean(r[ring] ** 2 - r0[ring] ** 2))), int(ring.sum())


def report(frame, p=P_END):
    a, n = cavity_radius(frame)
    out = {
        "a": a,
        "particles": n,
        "p_closed_form": closed_form_pressure(a),
        "a_follower": closed_form_radius(p),
        "a_dead": closed_form_radius(p, dead=True),
    }
    print(f"cavity radius a = {a:.4f} m from {n} wall particles (a/a0 - 1 = {100 * (a / A0 - 1):.1f} %)")
    print(f"closed form at this radius: p = {out['p_closed_form'] / 1e3:.2f} kPa against {p / 1e3:.2f} kPa applied "
          f"(p - p0 {100 * ((out['p_closed_form'] - P0) / (p - P0) - 1):+.1f} %)")
    print(f"closed form at {p / 1e3:.1f} kPa: a = {out['a_follower']:.4f} m (follower), {out['a_dead']:.4f} m "
          f"(a dead load, which the wall sees as p a0 / a)")
    return out


def applied_pressure(t, ramp=8.0):
    """The input's cavity pressure at time t: p0 to P_END over the ramp, then P_END."""
    return P0 + (P_END - P0) * min(t / ramp, 1.0)


def curve(results, ramp=8.0):
    """Every frame of results/particles.pvd: applied pressure, measured radius, the closed form's
    pressure at that radius."""
    text = open(os.path.join(results, "particles.pvd")).read()
    rows = []
    for t, name in re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', text):
        a, _ = cavity_radius(os.path.join(results, name))
        rows.append((float(t), applied_pressure(float(t), ramp), a, closed_form_pressure(a)))
    print("    t s   p kPa   a/a0   closed form p(a) kPa")
    for t, p, a, pc in rows:
        print(f"{t:7.2f} {p / 1e3:7.2f} {a / A0:7.4f} {pc / 1e3:9.2f}")
    return rows


if __name__ == "__main__":
    results = sys.argv[1] if len(sys.argv) > 1 else "results"
    if os.path.isdir(results):
        curve(results)
        frame = sorted(glob.glob(os.path.join(results, "particles_*.vtu")))[-1]
    else:
        frame = results
    report(frame)
