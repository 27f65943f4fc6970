"""The reduced triaxial run of ctest, end to end: tsuchi runs test 1 with the cap fixed on a
2.5 mm grid (3200 + 320 particles) to 6 % axial strain, then the band detector must find the X of
two bands of opposite sense, inclined 44-61.25 degrees from horizontal in the deformed configuration,
and the recorded peak q must be within 10 % of the Mohr-Coulomb value.

usage: triaxial_bands_test.py PATH_TO_TSUCHI
"""
import os
import shutil
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from triaxial_support import mohr_coulomb_peak, run_example, tsuchi_from_argv  # noqa: E402
import numpy as np  # noqa: E402
from bands import bands_of_frame  # noqa: E402
from vtu import read_pvd  # noqa: E402

TSUCHI = tsuchi_from_argv()


class ReducedTriaxial(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.out, cls.run_result = run_example(TSUCHI, "test1_fixed", "tsuchi_triaxial_", [
            "grid.cell_size=0.0025", "recorders.1.max=[1.0, 0.00125]", "recorders.2.max=[1.0, 0.00125]",
            "recorders.0.stop_above=0.06", "output.interval=0.3"])

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.out, ignore_errors=True)

    def test_run_finishes_at_the_stop_strain(self):
        self.assertEqual(self.run_result.returncode, 0, self.run_result.stderr)
        self.assertIn("stopped: axial_strain reached", self.run_result.stdout)

    def test_peak_deviator_within_ten_percent(self):
        rec = np.genfromtxt(os.path.join(self.out, "recorders.csv"), delimiter=",", names=True)
        peak, expected = rec["q_kPa"].max(), mohr_coulomb_peak(10.0)
        print(f"reduced test 1, cap fixed: peak q {peak:.2f} kPa, Mohr-Coulomb {expected:.2f} kPa")
        self.assertLess(abs(peak / expected - 1), 0.10)
        self.assertLess(np.ptp(rec["specimen_mass"]), 1e-12 * rec["specimen_mass"][0])

    def test_an_x_of_two_bands(self):
        _, last = read_pvd(os.path.join(self.out, "particles.pvd"))[-1]
        bands, *_ = bands_of_frame(os.path.join(self.out, last), reference=True)
        deformed, *_ = bands_of_frame(os.path.join(self.out, last), reference=False)
        for b in bands:
            print(f"band {b.angle:+.1f} deg ({b.sense}), explained {b.explained:.2f} (initial positions)")
        for b in deformed:
            print(f"band {b.angle:+.1f} deg ({b.sense}), explained {b.explained:.2f} (deformed)")
        self.assertEqual(len(bands), 2)
        self.assertLess(bands[0].angle * bands[1].angle, 0, "opposite senses")
        self.assertEqual(len(deformed), 2)
        # In the deformed specimen (the angle that compares with the paper's photographs and
        # plots, README-bands): between the Roscoe (45 + psi/2 = 45) and Coulomb (45 + phi/2 =
        # 60.25) angles, less and more the detector's 1 degree (its agreement with
        # tests/band_reference.py on real frames). With the node-averaged volumetric strain the
        # initial-position angles of this coarse, early X are 43.4 and 43.7 degrees, the deformed
        # ones 46.4 and 47.0 (at the full size, 2 mm and 15 %: 50.7-53.3 deformed).
        for b in deformed:
            self.assertGreaterEqual(b.inclination, 44.0)
            self.assertLessEqual(b.inclination, 61.25)


if __name__ == "__main__":
    unittest.main()
