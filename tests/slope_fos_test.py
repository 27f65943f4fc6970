"""`tsuchi fos`, the factor of safety by strength reduction, on examples/slope_fos at 1 m cells
(--set grid.cell_size=1.0 --set fos.max_steps=16000: four times the example's 400 H / h steps per
trial at that grid; BudgetConvergence and BudgetBound compare 4,000; 15-50 s on
one thread in all, depending on the load).

  - slope_fos.toml, Griffiths and Lane (1999) example 1 (2:1, H = 10 m, phi = 20 deg,
    c / (gamma H) = 0.05, no foundation layer): F within 5 % of their 1.4 (the issue's tolerance;
    measured 1.438, +2.7 %; 1.401 at the example's 0.5 m cells). trials.csv agrees with the printed
    bracket: every trial that stands lies below every trial that fails, the largest stand and the
    smallest failure are the bracket's ends, F is their mean and (upper - lower) / lower <=
    fos.tolerance.
  - The same search with -j1 and -j2 (two trials side by side): trials.csv's factor and result
    columns are identical.
  - slope_fos_phi0.toml, the same slope in Tresca clay (phi = 0, c = 35 kPa) against Taylor's chart
    (Ns = 0.124 for beta = 26.57 deg, D = 1: F = 1.411 with gamma = 20.0 kN/m^3). Tolerance 12 %,
    above the 5 % of phi = 20 deg, from measurements: F = 1.537 at 1 m cells (+8.9 %), 1.475 at
    0.5 m (+4.5 %). The excess halves with the cell size, and it is the overshoot this code shows
    on its other Tresca limits at such resolutions (the footing's +7 % at 20 cells per width,
    docs/input.md, anti_locking, put down to volumetric locking under isochoric plastic flow; the
    excavation example's +6-8 %). The 12 % holds the 1 m value with a margin of 3 points, about the
    uncertainty of the reference itself (Ns = 0.124 is a circular-arc search's and one chart
    digitisation's value; another digitisation of the D = 1 curve lies up to 13 % away).
  - Input errors of `tsuchi fos` (exit 2, nothing written): an input without [fos], and an input
    whose materials are all linear_elastic ("no material to reduce"). The [fos] keys' own errors,
    which `tsuchi run` reports too, are tests/bad_input/fos_*.toml.

usage: slope_fos_test.py PATH_TO_TSUCHI
"""
import csv
import os
import re
import subprocess
import sys
import tempfile
import tomllib
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, ".."))
TSUCHI = sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(REPO, "build", "app", "tsuchi")

EXAMPLE = os.path.join(REPO, "examples", "slope_fos")
SLOPE = os.path.join(EXAMPLE, "slope_fos.toml")
SLOPE_PHI0 = os.path.join(EXAMPLE, "slope_fos_phi0.toml")
COARSE = ["--set", "grid.cell_size=1.0", "--set", "fos.max_steps=16000"]

GRIFFITHS_LANE = 1.4          # their finite-element F (Bishop and Morgenstern's charts: 1.38)
GL_TOLERANCE = 0.05           # relative
TAYLOR_NS = 0.124             # Taylor's chart, phi = 0, beta = 26.57 deg, D = 1
TAYLOR_TOLERANCE = 0.12       # relative; see the module's text


def fos(input_file, out, *args, threads=1):
    return subprocess.run([TSUCHI, "fos", input_file, "-o", out, "-j", str(threads), *args],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)


def factor(output):
    m = re.search(r"^factor of safety: (\S+)$", output, re.M)
    return float(m.group(1)) if m else None


def bracket(output):
    m = re.search(r"^bracket: stands at F = (\S+), fails at F = (\S+) ", output, re.M)
    return (float(m.group(1)), float(m.group(2))) if m else None


def trials(out):
    with open(os.path.join(out, "fos", "trials.csv"), newline="") as f:
        return list(csv.DictReader(f))


def fos_table(path):
    with open(path, "rb") as f:
        return tomllib.load(f)["fos"]


class SearchResult:
    """One search, run once for all the tests that read it."""

    def __init__(self, input_file, *args, threads=1):
        self.tmp = tempfile.TemporaryDirectory(prefix="tsuchi_fos_")
        self.out = os.path.join(self.tmp.name, "out")
        self.run = fos(input_file, self.out, *args, threads=threads)
        self.output = self.run.stdout


_cache = {}


def search(key, *a, **k):
    if key not in _cache:
        _cache[key] = SearchResult(*a, **k)
    return _cache[key]


class GriffithsLane(unittest.TestCase):
    def setUp(self):
        self.r = search("phi20_j1", SLOPE, *COARSE, threads=1)
        self.assertEqual(self.r.run.returncode, 0, self.r.output)

    def test_factor_of_safety(self):
        F = factor(self.r.output)
        self.assertIsNotNone(F, self.r.output)
        print(f"\nphi = 20 deg, 1 m cells: F = {F} (Griffiths and Lane {GRIFFITHS_LANE}, "
              f"{100 * (F - GRIFFITHS_LANE) / GRIFFITHS_LANE:+.1f} %)")
        self.assertLessEqual(abs(F - GRIFFITHS_LANE) / GRIFFITHS_LANE, GL_TOLERANCE, self.r.output)

    def test_trials_agree_with_the_bracket(self):
        rows = trials(self.r.out)
        self.assertTrue(rows, "trials.csv is empty")
        self.assertEqual([int(t["trial"]) for t in rows], list(range(1, len(rows) + 1)))
        self.assertTrue(all(t["result"] in ("stands", "fails") for t in rows), rows)
        stands = [float(t["factor"]) for t in rows if t["result"] == "stands"]
        fails = [float(t["factor"]) for t in rows if t["result"] == "fails"]
        self.assertTrue(stands and fails, rows)
        # The last stand (the last row that stands) lies below the first failure, and every stand
        # below every failure.
        self.assertLess(stands[-1], fails[0])
        self.assertLess(max(stands), min(fails))
        lower, upper = bracket(self.r.output)
        self.assertAlmostEqual(lower, max(stands), delta=1e-5 * lower)
        self.assertAlmostEqual(upper, min(fails), delta=1e-5 * upper)
        tolerance = fos_table(SLOPE).get("tolerance", 0.01)
        self.assertLessEqual((min(fails) - max(stands)) / max(stands), tolerance)
        self.assertAlmostEqual(factor(self.r.output), 0.5 * (max(stands) + min(fails)), delta=1e-3)
        for t in rows:  # a failure by displacement went past the limit; a stand did not
            if t["reason"] == "displacement":
                self.assertGreater(float(t["max_displacement"]), fos_table(SLOPE)["displacement_limit"])
            if t["result"] == "stands":
                self.assertLess(float(t["max_displacement"]), fos_table(SLOPE)["displacement_limit"])

    def test_output_files(self):
        for name in ("trials.csv", "stable.vtu", "mechanism.vtu", "fos.pvd"):
            self.assertTrue(os.path.isfile(os.path.join(self.r.out, "fos", name)), name)
        with open(os.path.join(self.r.out, "fos", "mechanism.vtu"), "rb") as f:
            head = f.read(20000)
        for field in (b"plastic_shear_strain", b"displacement"):
            self.assertIn(field, head)

    def test_same_trials_with_two_threads(self):
        r2 = search("phi20_j2", SLOPE, *COARSE, threads=2)
        self.assertEqual(r2.run.returncode, 0, r2.output)
        one = [(t["factor"], t["result"]) for t in trials(self.r.out)]
        two = [(t["factor"], t["result"]) for t in trials(r2.out)]
        self.assertEqual(one, two)
        self.assertEqual(factor(self.r.output), factor(r2.output))


class Taylor(unittest.TestCase):
    def test_phi_zero_against_taylor(self):
        r = search("phi0", SLOPE_PHI0, *COARSE)
        self.assertEqual(r.run.returncode, 0, r.output)
        with open(SLOPE_PHI0, "rb") as f:
            d = tomllib.load(f)
        m = d["materials"][0]
        self.assertEqual(m["friction_angle"], 0.0)
        gamma = m["density"] * 9.81
        H = 10.0
        reference = m["cohesion"] / (TAYLOR_NS * gamma * H)
        F = factor(r.output)
        self.assertIsNotNone(F, r.output)
        print(f"\nphi = 0, 1 m cells: F = {F} (Taylor {reference:.3f}, {100 * (F - reference) / reference:+.1f} %)")
        self.assertLessEqual(abs(F - reference) / reference, TAYLOR_TOLERANCE, r.output)


ELASTIC = """
[model]
dimension = 2
gravity = [0.0, -9.81]

[grid]
cell_size = 0.5
extent = [2.0, 2.0]

[[materials]]
name = "rock"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e8
poisson_ratio = 0.3

[[bodies]]
name = "ground"
material = "rock"
min = [0.0, 0.0]
max = [2.0, 1.0]

[boundary]
x_min = "roller"
x_max = "roller"
y_min = "fixed"

[[stages]]
name = "gravity"
unbalanced_force_ratio = 1e-4
max_steps = 1000
"""


class BudgetConvergence(unittest.TestCase):
    """The factor does not hang on the step budget (issue 41, defect 7). At 1 m cells the trial at
    F = 1.444 still creeps at 4,000 steps (4.6 cm of movement against the 0.1 m limit, 1.5 mm of it
    in the last fifth): judged at 4,000 steps it failed, and the search printed "at least 1.432"
    while 16,000 steps give 1.451. Its movement is slowing, so it is now given more steps (fifths of
    the budget, up to fos.extend = 4 times it) and comes to rest; 4,000 and 16,000 steps then give the
    same bracket, each end decided by the ground (rest or displacement), not by the budget."""

    def test_short_and_ample_budgets_agree(self):
        short = search("phi20_short", SLOPE, "--set", "grid.cell_size=1.0", "--set", "fos.max_steps=4000")
        ample = search("phi20_j1", SLOPE, *COARSE, threads=1)
        for r in (short, ample):
            self.assertEqual(r.run.returncode, 0, r.output)
            self.assertIsNotNone(factor(r.output), r.output)
        self.assertEqual(bracket(short.output), bracket(ample.output), short.output + ample.output)
        extended = [t for t in trials(short.out) if "slowing: extended" in t["reason"]]
        self.assertTrue(extended and all(int(t["steps"]) > 4000 for t in extended), trials(short.out))
        lo, hi = bracket(short.output)
        ends = {float(f"{float(t['factor']):.6g}"): t for t in trials(short.out)}
        self.assertEqual(ends[float(f"{hi:.6g}")]["reason"], "displacement")


class BudgetBound(unittest.TestCase):
    """A factor set by the step budget is said to be a bound (issue 41, defect 7). Without the
    extension (fos.extend = 1), at 1 m cells with 4,000 steps a trial, the trial that sets the upper
    end (F = 1.444) runs out of steps creeping, not collapsing. The output is then "at least" the
    lower end, with the reason, and that bound lies below the factor the ample budget finds."""

    def test_short_budget_gives_a_bound_below_the_factor(self):
        r = search("phi20_bound", SLOPE, "--set", "grid.cell_size=1.0", "--set", "fos.max_steps=4000",
                   "--set", "fos.extend=1")
        self.assertEqual(r.run.returncode, 0, r.output)
        m = re.search(r"^factor of safety: at least (\S+) \(a bound, not the factor\): the trial at F = (\S+) "
                      r"failed only by running out of steps \(fos\.max_steps = 4000\)", r.output, re.M)
        self.assertIsNotNone(m, r.output)
        lo, hi = bracket(r.output)
        self.assertEqual(float(m.group(1)), float(f"{lo:.4g}"))
        self.assertAlmostEqual(float(m.group(2)), hi, delta=1e-5 * hi)
        self.assertIsNone(factor(r.output))
        upper = [t for t in trials(r.out) if abs(float(t["factor"]) - hi) < 1e-5 * hi and t["result"] == "fails"]
        self.assertTrue(upper and upper[-1]["reason"] == "max_steps", upper)
        self.assertLess(float(upper[-1]["max_displacement"]), fos_table(SLOPE)["displacement_limit"])
        ample = search("phi20_j1", SLOPE, *COARSE, threads=1)
        F = factor(ample.output)
        self.assertIsNotNone(F, ample.output)
        self.assertLessEqual(lo, F)
        fails = [t for t in trials(ample.out) if t["result"] == "fails"]
        self.assertEqual(min(fails, key=lambda t: float(t["factor"]))["reason"], "displacement", fails)


class InputErrors(unittest.TestCase):
    def refused(self, text, expect):
        with tempfile.TemporaryDirectory(prefix="tsuchi_fos_bad_") as tmp:
            path = os.path.join(tmp, "bad.toml")
            with open(path, "w") as f:
                f.write(text)
            out = os.path.join(tmp, "out")
            r = fos(path, out)
            self.assertEqual(r.returncode, 2, r.stdout)
            self.assertIn(expect, r.stdout)
            self.assertIn("bad.toml", r.stdout)
            self.assertFalse(os.path.exists(out), "a refused input wrote its output directory")

    def test_no_fos_table(self):
        self.refused(ELASTIC, "missing table [fos]")

    def test_no_material_to_reduce(self):
        self.refused(ELASTIC + "\n[fos]\nmax_steps = 100\n", "no material to reduce")


if __name__ == "__main__":
    unittest.main(verbosity=2)
