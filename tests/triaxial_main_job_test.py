"""The main job (README, scripts/setup.sh) checked against the paper's statements, at full size:
examples/triaxial/test1_fixed.toml unchanged (2 mm cells, 5000 + 500 particles) to 15 % axial
strain. The paper (Kiriyama 2015, section 3.4.1) reports for this case an X of two shear bands and
a deviator that stays "almost steady" after the initial yield, while particles at the centre
separate in tension.

  - q at 15 % (mean over 14.75-15 %) >= 0.85 of the peak q;
  - an X at 15 %: two bands of opposite sense, each 40-60 deg from the horizontal (deformed);
  - with psi = 0 no particle compacts plastically: plastic volumetric strain >= -1e-6 for every
    particle (a tension release only opens, a shear return with psi = 0 changes no volume);
  - the specimen keeps its mass, and the peak q is within 2 % of Mohr-Coulomb.

usage: triaxial_main_job_test.py PATH_TO_TSUCHI   (about 35 s on one core)
"""
import os
import shutil
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from triaxial_support import mohr_coulomb_peak, run_example, tsuchi_from_argv  # noqa: E402
import numpy as np  # noqa: E402
from bands import find_bands  # noqa: E402
from vtu import read_pvd, read_vtu  # noqa: E402

TSUCHI = tsuchi_from_argv()


class MainJob(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.out, cls.run_result = run_example(TSUCHI, "test1_fixed", "tsuchi_main_job_")
        cls.rec = np.genfromtxt(os.path.join(cls.out, "recorders.csv"), delimiter=",", names=True)
        _, last = read_pvd(os.path.join(cls.out, "particles.pvd"))[-1]
        cls.frame = read_vtu(os.path.join(cls.out, last))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.out, ignore_errors=True)

    def test_run_reaches_15_percent(self):
        self.assertEqual(self.run_result.returncode, 0, self.run_result.stderr)
        self.assertGreaterEqual(self.rec["axial_strain"][-1], 0.15)

    def test_deviator_almost_steady(self):
        e, q = self.rec["axial_strain"], self.rec["q_kPa"]
        peak = q.max()
        q15 = q[(e >= 0.1475) & (e <= 0.1501)].mean()
        print(f"peak q {peak:.2f} kPa (Mohr-Coulomb {mohr_coulomb_peak(10):.2f}), q at 15 % {q15:.2f} kPa "
              f"= {q15 / peak:.3f} of the peak")
        self.assertGreaterEqual(q15 / peak, 0.85)
        self.assertLess(abs(peak / mohr_coulomb_peak(10.0) - 1), 0.02)
        self.assertLess(np.ptp(self.rec["specimen_mass"]), 1e-12 * self.rec["specimen_mass"][0])

    def test_an_x_at_15_percent(self):
        body = self.frame["body"] == 0
        pts = self.frame["points"][body]
        bands = find_bands(pts[:, 0], pts[:, 1], self.frame["max_shear_strain"][body])
        for b in bands:
            print(f"band {b.angle:+.1f} deg ({b.sense}), width {1e3 * b.width:.1f} mm")
        self.assertGreaterEqual(len(bands), 2)
        rising_right = [b for b in bands if b.angle > 0]
        rising_left = [b for b in bands if b.angle < 0]
        self.assertTrue(rising_right and rising_left, "an X needs one band of each sense")
        for b in (rising_right[0], rising_left[0]):
            self.assertGreaterEqual(b.inclination, 40.0)
            self.assertLessEqual(b.inclination, 60.0)

    def test_no_plastic_compaction(self):
        body = self.frame["body"] == 0
        ev = self.frame["plastic_volumetric_strain"][body]
        print(f"plastic volumetric strain: min {ev.min():.3g}, max {ev.max():.3g}")
        self.assertGreaterEqual(ev.min(), -1e-6)


if __name__ == "__main__":
    unittest.main()
