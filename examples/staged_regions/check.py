"""examples/staged_regions against 1D constrained compression, stage by stage.

Each stage resets the displacements, so a recorder's value at the stage's end is the response to
that stage's change alone: a part of thickness t and density rho added on top of (or removed from)
the column changes the vertical stress below it uniformly by ds = -/+ rho g t, which moves a point
at height y by u_y = ds y / M, M = E (1 - nu) / ((1 + nu)(1 - 2 nu)) (the ground's). The base
carries the weight of what is there. Prints the table and exits 1 when a value is off by more than
the tolerances (0.5 % of a displacement, 1e-4 of the weight).

usage: check.py RESULTS_DIR
"""
import csv
import os
import sys

G = 9.81
RHO_GROUND, RHO_FILL = 2000.0, 1800.0
E, NU = 20.0e6, 0.3
M = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))
TOP_ROW, CUT_ROW = 7.875, 6.875  # the recorders' particle rows (centres), m
DISPLACEMENT_TOLERANCE, WEIGHT_TOLERANCE = 5e-3, 1e-4

# stage: (recorder, expected displacement in mm, expected base reaction in kN/m)
EXPECTED = {
    "lift 1": ("top_uy_mm", -RHO_FILL * G * 1.0 * TOP_ROW / M * 1e3, (RHO_GROUND * 8 + RHO_FILL * 1) * G * 1e-3),
    "lift 2": ("top_uy_mm", -RHO_FILL * G * 1.0 * TOP_ROW / M * 1e3, (RHO_GROUND * 8 + RHO_FILL * 2) * G * 1e-3),
    "unload": ("top_uy_mm", RHO_FILL * G * 2.0 * TOP_ROW / M * 1e3, RHO_GROUND * 8 * G * 1e-3),
    "cut": ("cut_uy_mm", RHO_GROUND * G * 1.0 * CUT_ROW / M * 1e3, RHO_GROUND * 7 * G * 1e-3),
}


def stage_ends(results):
    """{stage name: the recorders' row at its last step}."""
    with open(os.path.join(results, "recorders.csv")) as f:
        rows = list(csv.DictReader(f))
    with open(os.path.join(results, "stages.csv")) as f:
        stages = list(csv.DictReader(f))
    ends = {}
    for s in stages:
        at = [r for r in rows if int(r["step"]) == int(s["end_step"])]
        ends[s["name"]] = (s, at[-1])
    return ends


def compare(results):
    """Rows (stage, end, u measured, u expected, reaction measured, reaction expected) and the failures."""
    ends = stage_ends(results)
    rows, failures = [], []
    for name, (recorder, u_ref, w_ref) in EXPECTED.items():
        stage, r = ends[name]
        u, w = float(r[recorder]), float(r["base_reaction_kN"])
        rows.append((name, stage["end"], u, u_ref, w, w_ref))
        if stage["end"] != "equilibrium":
            failures.append(f"stage {name} ended by {stage['end']}, not in equilibrium")
        if not abs(u / u_ref - 1) <= DISPLACEMENT_TOLERANCE:
            failures.append(f"stage {name}: {recorder} {u:.4f} mm against {u_ref:.4f} mm")
        if not abs(w / w_ref - 1) <= WEIGHT_TOLERANCE:
            failures.append(f"stage {name}: base reaction {w:.4f} kN/m against the weight {w_ref:.4f} kN/m")
    return rows, failures


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    rows, failures = compare(sys.argv[1])
    print("stage    end          u_y (mm)  1D (mm)   diff      base (kN/m)  weight (kN/m)")
    for name, end, u, u_ref, w, w_ref in rows:
        print(f"{name:8s} {end:12s} {u:8.4f}  {u_ref:8.4f}  {100 * (u / u_ref - 1):+6.2f} %  {w:11.4f}  {w_ref:11.4f}")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
