#!/usr/bin/env python3
"""The grid frames (output.grid_fields, issue 41): the particles' fields projected to the grid's
nodes, m_i q_i = sum_p S_ip m_p q_p, in grid_NNNNNN.vtu beside every particle frame and grid.pvd.

Runs examples/column_self_weight/column_grid.toml (2D) and column_3d.toml with grid fields on:
  - the sum of the nodal masses is the particles' total mass (to 1e-12 relative), every frame;
  - at rest, sigma_yy at the nodes of the vertical line x = 0.1 m with 0.15 <= y <= 0.85 is
    -rho g (H - y) within 0.5 % of rho g H (2D at 0.05 m cells; 3D at 0.1 m), half the particles'
    own error at 0.05 m (examples/column_self_weight/README.md: 0.94 % at mid-height; the nodes
    reach 0.08 %: the mass-weighted average over a node's symmetric support cancels the error
    that is odd within a cell);
  - a restart from a checkpoint at t = 0.3 s continues grid.pvd and the grid frames byte for byte;
  - without the key no grid file is written, and a rerun without it removes an earlier run's;
  - where pvpython and xvfb-run are installed: particles_view.py opens grid.pvd beside the
    particles, and ParaView's Plot Over Line through it returns sigma_yy along the line, masked
    (vtkValidPointMask = 0) above the column.

usage: grid_fields_test.py TSUCHI_BINARY
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tools"))
from vtu import read_pvd, read_vtu  # noqa: E402

EXAMPLE = os.path.join(ROOT, "examples", "column_self_weight")
RHO_G, H = 2000.0 * 9.81, 1.0
TOLERANCE = 0.005  # of rho g H

failures = []


def check(cond, what, detail=""):
    if not cond:
        failures.append(what + ("\n--- " + detail if detail else ""))
    return cond


def run(tsuchi, *args, cwd=None):
    r = subprocess.run([tsuchi, "run", "-q", *args], cwd=cwd, capture_output=True, text=True, timeout=300)
    check(r.returncode == 0, f"tsuchi run {' '.join(args)}: exit {r.returncode}", r.stdout[-2000:] + r.stderr[-2000:])
    return r


def check_frames(out, dim, h, nodes_on_line):
    """Mass conservation in every frame, sigma_yy along x = 0.1 in the last; returns the worst error."""
    grid, particles = read_pvd(os.path.join(out, "grid.pvd")), read_pvd(os.path.join(out, "particles.pvd"))
    check([t for t, _ in grid] == [t for t, _ in particles], "grid.pvd lists the particle frames' times",
          f"{grid} / {particles}")
    worst_mass = 0.0
    for (_, gf), (_, pf) in zip(grid, particles):
        g, p = read_vtu(os.path.join(out, gf)), read_vtu(os.path.join(out, pf))
        total = float(p["mass"].sum())
        worst_mass = max(worst_mass, abs(float(g["mass"].sum()) - total) / total)
    print(f"{dim}D: nodal mass against the particles' over {len(grid)} frames: {worst_mass:.3g} relative")
    check(worst_mass < 1e-12, f"{dim}D: sum of nodal masses = particle mass to 1e-12 ({worst_mass:.3g})")
    g = read_vtu(os.path.join(out, grid[-1][1]))
    x = g["points"]
    on = (abs(x[:, 0] - 0.1) < 1e-9) & (x[:, 1] >= 0.15 - 1e-9) & (x[:, 1] <= 0.85 + 1e-9)
    if dim == 3:
        on &= abs(x[:, 2] - 0.1) < 1e-9
    syy, ref = g["stress"][on, 1], -RHO_G * (H - x[on, 1])
    check(on.sum() == nodes_on_line, f"{dim}D: {nodes_on_line} nodes on x = 0.1, 0.15 <= y <= 0.85 ({on.sum()})")
    err = float(abs(syy - ref).max()) / (RHO_G * H) if on.any() else 1.0
    print(f"{dim}D: sigma_yy at the nodes of x = 0.1: worst {err * 100:.3f} % of rho g H")
    check(err < TOLERANCE, f"{dim}D: sigma_yy = -rho g (H - y) at the nodes within 0.5 % of rho g H ({err * 100:.3f} %)")
    # Nodes no particle reaches are not points: none above the column's top and its GIMP reach.
    check(x[:, 1].max() <= H + h + 1e-9 and (g["mass"] > 0).all(), f"{dim}D: only nodes with mass are written")
    check(g["types"].min() == g["types"].max() == (9 if dim == 2 else 12), f"{dim}D: quad / hexahedron cells")
    return err


def paraview(out):
    pvpython, xvfb = shutil.which("pvpython"), shutil.which("xvfb-run")
    if not (pvpython and xvfb):
        print("note: pvpython or xvfb-run not installed: Plot Over Line not run in ParaView")
        return
    # The example's own script: particles_view.py, then Plot Over Line on grid.pvd.
    script = os.path.join(EXAMPLE, "plot_over_line.py")
    csv = os.path.join(out, "stress_over_line.csv")
    rows = []
    for attempt in range(2):
        r = subprocess.run([xvfb, "-a", pvpython, script, out], capture_output=True, text=True, timeout=300)
        if os.path.exists(csv):
            with open(csv) as f:
                rows = [tuple(float(v) for v in line.split(",")[:3]) for line in f.read().splitlines()[1:]]
            break
        print(f"note: attempt {attempt + 1}: pvpython exit {r.returncode}: {r.stderr[-500:]}")
    if not check(len(rows) == 29, f"ParaView's Plot Over Line through grid.pvd ran ({len(rows)} points)",
                 r.stdout[-2000:] + r.stderr[-2000:]):
        return
    inner = [(y, s) for y, s, m in rows if m == 1 and 0.15 - 1e-6 <= y <= 0.85 + 1e-6]  # float32 points
    err = max(abs(s + RHO_G * (H - y)) for y, s in inner) / (RHO_G * H) if inner else 1.0
    print(f"ParaView Plot Over Line: {len(inner)} points in 0.15..0.85 m, worst {err * 100:.3f} % of rho g H")
    check(len(inner) == 15 and err < TOLERANCE, f"Plot Over Line gives sigma_yy along the line ({len(inner)}, {err})")
    above = [m for y, s, m in rows if y > H + 0.1]
    check(above and all(m == 0 for m in above), "no value above the column (vtkValidPointMask = 0)", str(rows))


def main():
    tsuchi = os.path.abspath(sys.argv[1])
    with tempfile.TemporaryDirectory(prefix="tsuchi_grid_") as tmp:
        # 2D: the example as it is.
        out = os.path.join(tmp, "column")
        run(tsuchi, os.path.join(EXAMPLE, "column_grid.toml"), "-o", out)
        if os.path.exists(os.path.join(out, "grid.pvd")):
            check_frames(out, 2, 0.05, 15)
            with open(os.path.join(out, "particles_view.py")) as f:
                check("grid.pvd" in f.read(), "particles_view.py opens grid.pvd")
            paraview(out)
        else:
            check(False, "grid.pvd written", str(os.listdir(out)))

        # Restart: to 0.3 s with a checkpoint at the end, then on to 0.6 s.
        part = os.path.join(tmp, "part")
        run(tsuchi, os.path.join(EXAMPLE, "column_grid.toml"), "-o", part, "--set", "time.end=0.3",
            "--set", "checkpoint.every_steps=100000")
        run(tsuchi, os.path.join(EXAMPLE, "column_grid.toml"), "-o", part, "--restart",
            os.path.join(part, "checkpoint.tsuchi"))
        names = sorted(n for n in os.listdir(out) if n.startswith("grid"))
        check(len(names) == 14 and names == sorted(n for n in os.listdir(part) if n.startswith("grid")),
              "the restart writes the grid frames of the uninterrupted run", f"{names}")
        for n in names:
            with open(os.path.join(out, n), "rb") as a, open(os.path.join(part, n), "rb") as b:
                check(a.read() == b.read(), f"{n}: the restart's bytes are the uninterrupted run's")

        # Off: no grid file, and those of an earlier run in the directory removed.
        run(tsuchi, os.path.join(EXAMPLE, "column.toml"), "-o", out, "--set", "time.end=0.1")
        left = [n for n in os.listdir(out) if n.startswith("grid")]
        check(not left, "a run without grid_fields leaves no grid file", str(left))
        with open(os.path.join(out, "particles_view.py")) as f:
            check("grid" not in f.read(), "particles_view.py without grid frames names no grid")

        # 3D: the example's 3D column with the key given on the command line, at 0.1 m cells (0.3 s).
        out3 = os.path.join(tmp, "column_3d")
        run(tsuchi, os.path.join(EXAMPLE, "column_3d.toml"), "-o", out3, "--set", "output.grid_fields=true",
            "--set", "output.interval=0.3", "--set", "grid.cell_size=0.1")
        if check(os.path.exists(os.path.join(out3, "grid.pvd")), "3D: grid.pvd written"):
            check_frames(out3, 3, 0.1, 7)
    for f in failures:
        print("FAIL:", f)
    print(f"{'FAILED' if failures else 'passed'}: grid fields")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
