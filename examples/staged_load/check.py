"""Stage 2 of examples/staged_load against 1D constrained compression: with the displacements reset
at the start of stage 2, the displacement at rest is the response to the pressure alone,
u_y(y) = -p y / M, M = E (1 - nu) / ((1 + nu)(1 - 2 nu)), y the particle's height at the start of
stage 2 (the frame's position minus its stage-2 displacement: the column as stage 1 left it).

usage: check.py RESULTS_DIR [INPUT.toml]   (prints a table by height, writes RESULTS_DIR/staged_load.png;
                                            INPUT defaults to staged_load.toml beside this script)
"""
import os
import sys
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
import numpy as np  # noqa: E402
from vtu import read_pvd, read_vtu  # noqa: E402

INPUT = os.path.join(HERE, "staged_load.toml")


def parameters(path=INPUT):
    """E, nu, the stage-2 pressure p and the column height H, from the input file."""
    with open(path, "rb") as f:
        cfg = tomllib.load(f)
    mat = cfg["materials"][0]
    load = cfg["stages"][1]["loads"][0]
    return {"E": mat["youngs_modulus"], "nu": mat["poisson_ratio"], "p": load["pressure"],
            "H": cfg["bodies"][0]["max"][1]}


def constrained_modulus(E, nu):
    return E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))


def stage_frames(results, stage):
    """(time, path) of the frames of one stage, from particles_stageN.pvd."""
    return [(t, os.path.join(results, f)) for t, f in read_pvd(os.path.join(results, f"particles_stage{stage}.pvd"))]


def profile(results, input_path=INPUT):
    """Rows (y, u_y measured, u_y reference) in m, one per particle row, at the end of stage 2; y is
    the row's height at the start of stage 2 (the displacement in the frame is stage 2's alone)."""
    prm = parameters(input_path)
    M = constrained_modulus(prm["E"], prm["nu"])
    f = read_vtu(stage_frames(results, 2)[-1][1])
    u = f["displacement"][:, 1]
    y = f["points"][:, 1] - u
    # Rows: the particles of one row differ in height by round-off; rows lie a spacing apart.
    order = np.argsort(y)
    breaks = np.flatnonzero(np.diff(y[order]) > 1e-6) + 1
    rows = []
    for idx in np.split(order, breaks):
        ym = y[idx].mean()
        rows.append((ym, u[idx].mean(), -prm["p"] * ym / M))
    return np.array(rows)


def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    results = sys.argv[1]
    input_path = sys.argv[2] if len(sys.argv) > 2 else INPUT
    rows = profile(results, input_path)
    print("  y (m)   u_y (mm)   -p y/M (mm)   difference")
    for y, u, ref in rows[::-8][::-1]:
        print(f"{y:7.4f}  {1e3 * u:9.3f}  {1e3 * ref:11.3f}   {100 * (u / ref - 1):+6.2f} %")
    top = rows[-1]
    print(f"top row: {1e3 * top[1]:.3f} mm against {1e3 * top[2]:.3f} mm ({100 * (top[1] / top[2] - 1):+.2f} %)")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(4.5, 5))
    ax.plot(-1e3 * rows[:, 2], rows[:, 0], "k-", label="1D compression, p y / M")
    ax.plot(-1e3 * rows[:, 1], rows[:, 0], "o", ms=3, mfc="none", label="tsuchi, stage 2")
    ax.set_xlabel("settlement in stage 2 (mm)")
    ax.set_ylabel("height at the start of stage 2, y (m)")
    ax.legend(loc="upper left")
    fig.tight_layout()
    out = os.path.join(results, "staged_load.png")
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
