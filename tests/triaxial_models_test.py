"""examples/triaxial/models/study.py at the element level (`tsuchi element`, plane-strain
compression of one point at the paper's three confining pressures, to 15 %), about 5 s:
- Drucker-Prager with match = "plane_strain" reaches Mohr-Coulomb's plane-strain peak
  (50.36, 132.81, 235.87 kPa) within 0.5 % by 15 % axial strain;
- Modified Cam-Clay as the study calibrates it (M = 0.94, p_c = 100 kPa for all three): the normally
  consolidated test 3 is at its plane-strain critical state 2 M sigma3 / (sqrt3 - M) = 237.4 kPa
  within 1 % at 15 %; the heavily overconsolidated test 1 peaks within 3 % of Mohr-Coulomb's 50.36
  kPa and then softens (q at 15 % below 0.6 of its peak); test 2 hardens (q at 15 % is its peak).

usage: triaxial_models_test.py PATH_TO_TSUCHI
"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from triaxial_support import REPO, mohr_coulomb_peak, tsuchi_from_argv  # noqa: E402

TSUCHI = tsuchi_from_argv()
SIGMA3 = {"test1": 10.0, "test2": 50.0, "test3": 100.0}  # kPa


class ModelsStudy(unittest.TestCase):
    def test_element_level(self):
        out = tempfile.mkdtemp(prefix="tsuchi_models_")
        try:
            proc = subprocess.run(
                [sys.executable, os.path.join(REPO, "examples", "triaxial", "models", "study.py"), "--no-solver",
                 "--results", out, "--tsuchi", TSUCHI], capture_output=True, text=True)
            self.assertEqual(proc.returncode, 0, proc.stdout + proc.stderr)
            with open(os.path.join(out, "summary.json")) as f:
                el = json.load(f)["element"]
            self.assertEqual(len(el), 9)
            for test, s3 in SIGMA3.items():
                mc = mohr_coulomb_peak(s3)
                self.assertLess(abs(el[f"{test}_mc"]["peak"] / mc - 1), 1e-6, test)
                self.assertLess(abs(el[f"{test}_dp"]["q_15"] / mc - 1), 0.005, test)
            M = 0.94
            cs3 = 2 * M * 100.0 / (math.sqrt(3) - M)
            print(f"MCC test3 q at 15 % {el['test3_mcc']['q_15']:.2f} kPa, critical state {cs3:.2f}; "
                  f"test1 peak {el['test1_mcc']['peak']:.2f} (MC {mohr_coulomb_peak(10.0):.2f}), "
                  f"q at 15 % {el['test1_mcc']['q_15']:.2f}")
            self.assertLess(abs(el["test3_mcc"]["q_15"] / cs3 - 1), 0.01)
            self.assertLess(abs(el["test1_mcc"]["peak"] / mohr_coulomb_peak(10.0) - 1), 0.03)
            self.assertLess(el["test1_mcc"]["q_15"], 0.6 * el["test1_mcc"]["peak"])
            self.assertGreater(el["test2_mcc"]["q_15"], 0.999 * el["test2_mcc"]["peak"])
            for name in ("report.md", "q_element.png"):
                self.assertTrue(os.path.exists(os.path.join(out, name)), name)
        finally:
            shutil.rmtree(out, ignore_errors=True)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])
