"""examples/column_collapse at a small size: a = 2 only, 10 cells across the column (w0 / 10, 800
particles), with the solver's defaults (APIC, anti_locking = "node", hold_released_volume), to
t = 2 s (about 3 s on one core). Measured on this grid (examples/column_collapse/README.md):
runout 3.17, H_inf / L0 1.07, kinetic energy at most 2.7e-7 of its peak over the last 0.5 s
(7.2e-8 at the end). Checked:

  - runout (L_inf - L0) / L0 between Lube et al.'s (2005) lower fit at a = 2 (1.2 a = 2.40) and
    10 % above the upper one (1.9 a^(2/3) = 3.02, so 3.32). The measured 3.17 is 5 % above the
    upper fit; the band leaves 0.15 L0 (three initial particle spacings, the step in which the
    measured front moves) above it. On this grid a run more dissipative than the experiments
    fails the lower bound (pic_fraction 0.05: 1.98, PIC: 1.15) and one more mobile the upper
    (FLIP: 3.71, anti_locking = "cell": 3.48); anti_locking = "none" (3.08) passes. The runout
    grows with the grid (3.17, 4.19, 4.60 at w0 / 10, 20, 40), so the band holds for this grid,
    not for the example's own w0 / 20.
  - final height H_inf / L0 within 25 % of a^(2/5) = 1.32, i.e. 0.99 to 1.65. Measured 1.07,
    19 % below, the same on every grid (1.07, 1.08, 1.08): the departure is the model's, not the
    grid's. The band is that 19 % plus 6 % (0.08 L0, one and a half initial particle spacings:
    the highest particle, which H_inf measures, sits on one of them). Without anti-locking the
    deposit is higher (1.21 here, 1.18 on w0 / 20); the band does not tell the two apart.
  - at rest: kinetic energy below 1e-6 of its peak over the whole of the last 0.5 s (not only
    the last sample: on finer grids the deposit rings elastically, between 1e-8 and 1e-5 of the
    peak, and the last sample falls wherever the ringing happens to be). Measured at most 2.7e-7.
    This holds on this grid only: on w0 / 20 and w0 / 40 the ringing stays above 1e-6 (README).
    FLIP (3.3e-2 of the peak: particle noise), pic_fraction 0.05 (2.9e-6) and PIC (1.2e-2) fail
    it on this grid.

usage: column_collapse_test.py PATH_TO_TSUCHI
"""
import os
import shutil
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from triaxial_support import REPO, tsuchi_from_argv  # noqa: E402

sys.path.insert(0, os.path.join(REPO, "examples", "column_collapse"))
import study  # noqa: E402

TSUCHI = tsuchi_from_argv()
A, CELL = 2.0, 0.02
RUNOUT_ABOVE_UPPER_FIT = 0.10  # relative, above 1.9 a^(2/3)
HEIGHT_TOLERANCE = 0.25        # relative, around a^(2/5)


class ColumnCollapse(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.out = tempfile.mkdtemp(prefix="tsuchi_column_collapse_")
        study.run_case(TSUCHI, cls.out, study.overrides(A, "apic", CELL, 30.0, "node"))
        cls.m = study.measure(cls.out, CELL)
        print(f"a = {cls.m['a']:.3f}: runout {cls.m['runout']:.3f}, H/L0 {cls.m['height']:.3f}, "
              f"KE end / peak {cls.m['ke_ratio']:.2e}, largest over the last {study.TAIL:g} s "
              f"{cls.m['ke_tail_max']:.2e}")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.out, ignore_errors=True)

    def test_geometry(self):
        self.assertAlmostEqual(self.m["a"], A, places=9)

    def test_runout_near_lube(self):
        low, high = study.lube_runout(A)
        self.assertAlmostEqual(low, 2.4)
        self.assertAlmostEqual(high, 1.9 * A ** (2 / 3))
        self.assertGreaterEqual(self.m["runout"], low)
        self.assertLessEqual(self.m["runout"], (1 + RUNOUT_ABOVE_UPPER_FIT) * high)

    def test_final_height_near_lube(self):
        self.assertLess(abs(self.m["height"] / study.lube_height(A) - 1), HEIGHT_TOLERANCE)

    def test_comes_to_rest(self):
        self.assertLess(self.m["ke_tail_max"], study.KE_REST)


if __name__ == "__main__":
    unittest.main()
