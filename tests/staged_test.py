"""Staged analyses ([[stages]]) end to end, through the tsuchi program (about 5 s on one thread).

  - examples/staged_load: an elastic column between rollers at rest under gravity (stage 1), then
    a top pressure p with the displacements reset (stage 2). Stage 2's displacement must be the
    response to p alone, 1D constrained compression u_y = -p y / M, M = E (1 - nu) / ((1 + nu)
    (1 - 2 nu)) (E, nu, p read from the input), within 2 %:
      * the top row (recorder top_uy_mm, its initial centre height y0): measured -1.1 %;
      * every particle row of the last frame of particles_stage2.pvd, against its height at the
        start of stage 2 (examples/staged_load/check.py): measured -0.2 % (-0.5 % at the top row).
    Also: stages.csv has two rows, both ended by "equilibrium", and recorders.csv's stage column
    runs 1 ... 1, 2 ... 2.
  - examples/excavation (cut of H = 10 m in Tresca clay, removed in stage 2, 1 m cells, 5 s):
      * at gamma H / c = 3.0 (the input's default) the face moves towards the cut (face_top_mm < 0;
        measured -34 mm), the mean horizontal stress of the ground's face column falls from its
        K0 value (88.3 kPa) to below 10 % of it (measured -1.1 kPa) and the crest settles less
        than 30 mm (measured 12.5 mm): the cut stands;
      * at gamma H / c = 4.5 (c by --set) the crest settles more than 150 mm (measured 304 mm):
        the cut fails (exact limit 3.776; on this grid the limit lies near 4.0-4.1, README).
  - restart: the excavation at 4.5 with stage 2 cut to 2 s, stopped by time.max_steps inside
    stage 2 (and once right at the end of stage 1, which stops at the start of stage 2) and continued with --restart from its
    checkpoint, ends with every file of its output directory byte-identical to an unstopped run.

usage: staged_test.py PATH_TO_TSUCHI
"""
import csv
import importlib.util
import os
import shutil
import subprocess
import sys
import tempfile
import tomllib
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, ".."))
TSUCHI = sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(REPO, "build", "app", "tsuchi")

STAGED_LOAD = os.path.join(REPO, "examples", "staged_load", "staged_load.toml")
EXCAVATION = os.path.join(REPO, "examples", "excavation", "excavation.toml")

DISPLACEMENT_TOLERANCE = 0.02   # relative, stage 2 against -p y / M
FACE_STRESS_LEFT = 0.10         # the face column's sigma_xx after removal, as a fraction of its K0 value
STANDS_BELOW_MM = 30.0          # crest settlement of the standing cut (gamma H / c = 3.0)
FAILS_ABOVE_MM = 150.0          # crest settlement of the failing cut (gamma H / c = 4.5)


def load_module(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


check = load_module("staged_load_check", os.path.join(REPO, "examples", "staged_load", "check.py"))
excavation = load_module("excavation_study", os.path.join(REPO, "examples", "excavation", "study.py"))


def run(*args):
    r = subprocess.run([TSUCHI, "run", *args, "-q", "-j", "1"], stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True, timeout=120)
    return r


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def snapshot(directory):
    """Every regular file of a directory by name, with its bytes."""
    files = {}
    for name in sorted(os.listdir(directory)):
        p = os.path.join(directory, name)
        if os.path.isfile(p):
            with open(p, "rb") as f:
                files[name] = f.read()
    return files


class Tmp(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="tsuchi_staged_")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)


class StagedLoad(Tmp):
    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.out = os.path.join(cls.tmp, "staged_load")
        cls.result = run(STAGED_LOAD, "-o", cls.out)

    def setUp(self):
        self.assertEqual(self.result.returncode, 0, self.result.stdout)

    def test_stage_two_is_the_response_to_the_pressure_alone(self):
        with open(STAGED_LOAD, "rb") as f:
            cfg = tomllib.load(f)
        prm = check.parameters(STAGED_LOAD)
        M = check.constrained_modulus(prm["E"], prm["nu"])
        spacing = cfg["grid"]["cell_size"] / cfg["bodies"][0]["particles_per_cell"]
        y_top = prm["H"] - spacing / 2  # the top row's initial centre
        rows = read_rows(os.path.join(self.out, "recorders.csv"))
        measured = float(rows[-1]["top_uy_mm"]) / 1e3
        expected = -prm["p"] * y_top / M
        print(f"top row: stage-2 u_y {1e3 * measured:.3f} mm, -p y0 / M = {1e3 * expected:.3f} mm "
              f"({100 * (measured / expected - 1):+.2f} %)")
        self.assertLess(abs(measured / expected - 1), DISPLACEMENT_TOLERANCE)
        # stage 1 left the column settled by ~36 mm at the top: the reset must have removed it
        end1 = [r for r in rows if r["stage"] == "1"][-1]
        self.assertLess(float(end1["top_uy_mm"]), -10.0)

        profile = check.profile(self.out, STAGED_LOAD)
        err = profile[:, 1] / profile[:, 2] - 1
        print(f"rows of the last stage-2 frame: {len(profile)}, differences {100 * err.min():+.2f} % "
              f"to {100 * err.max():+.2f} % (top {100 * err[-1]:+.2f} %)")
        self.assertGreater(len(profile), 40)
        self.assertLess(abs(err).max(), DISPLACEMENT_TOLERANCE)

    def test_stages_csv_and_stage_column(self):
        stages = read_rows(os.path.join(self.out, "stages.csv"))
        self.assertEqual([s["stage"] for s in stages], ["1", "2"])
        self.assertEqual([s["name"] for s in stages], ["gravity", "load"])
        self.assertEqual([s["end"] for s in stages], ["equilibrium", "equilibrium"])
        for s in stages:
            self.assertLess(float(s["unbalanced_force_ratio"]), 1e-6)
        rows = read_rows(os.path.join(self.out, "recorders.csv"))
        column = [int(r["stage"]) for r in rows]
        first2 = column.index(2)
        self.assertEqual(column[0], 1)
        self.assertTrue(all(c == 1 for c in column[:first2]) and all(c == 2 for c in column[first2:]))
        # the first row of stage 2 is the first step after stage 1's last
        self.assertEqual(int(rows[first2 - 1]["step"]), int(stages[0]["end_step"]))
        for name in ("particles_stage1.pvd", "particles_stage2.pvd"):
            self.assertTrue(os.path.isfile(os.path.join(self.out, name)), name)


class Excavation(Tmp):
    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.standing = os.path.join(cls.tmp, "ratio_3.0")
        cls.failing = os.path.join(cls.tmp, "ratio_4.5")
        cls.r_standing = run(EXCAVATION, "-o", cls.standing)  # the input's default: gamma H / c = 3.0
        cls.r_failing = run(EXCAVATION, "-o", cls.failing,
                            "--set", f"materials.0.cohesion={excavation.cohesion(4.5, EXCAVATION):.6g}")

    def test_input_default_is_ratio_3(self):
        with open(EXCAVATION, "rb") as f:
            c = tomllib.load(f)["materials"][0]["cohesion"]
        self.assertAlmostEqual(excavation.unit_weight(EXCAVATION) * excavation.DEPTH / c, 3.0, places=3)

    def test_removal_unloads_the_face(self):
        self.assertEqual(self.r_standing.returncode, 0, self.r_standing.stdout)
        stages = read_rows(os.path.join(self.standing, "stages.csv"))
        self.assertEqual([s["end"] for s in stages], ["equilibrium", "duration"])
        s = excavation.summary(self.standing)
        print(f"gamma H / c = 3.0: face top u_x {s['face_top_mm']:.1f} mm, face sigma_xx "
              f"{s['face_sxx_kPa_before']:.1f} -> {s['face_sxx_kPa']:.2f} kPa, crest {s['crest_mm']:.1f} mm")
        self.assertLess(s["face_top_mm"], 0.0)
        self.assertLess(s["face_min_mm"], 0.0)
        self.assertGreater(s["face_sxx_kPa_before"], 50.0)  # the K0 state: about 88 kPa
        self.assertLess(abs(s["face_sxx_kPa"]), FACE_STRESS_LEFT * s["face_sxx_kPa_before"])
        self.assertLess(s["crest_mm"], STANDS_BELOW_MM)

    def test_steeper_ratio_fails(self):
        self.assertEqual(self.r_failing.returncode, 0, self.r_failing.stdout)
        s = excavation.summary(self.failing)
        print(f"gamma H / c = 4.5: crest {s['crest_mm']:.1f} mm, pss_max {s['pss_max']:.2f}")
        self.assertGreater(s["crest_mm"], FAILS_ABOVE_MM)


class StagedRestart(Tmp):
    SETS = ["--set", "stages.1.duration=2.0",
            "--set", f"materials.0.cohesion={excavation.cohesion(4.5, EXCAVATION):.6g}"]

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.whole = os.path.join(cls.tmp, "whole")
        cls.r_whole = run(EXCAVATION, "-o", cls.whole, *cls.SETS)

    def split_at(self, steps):
        self.assertEqual(self.r_whole.returncode, 0, self.r_whole.stdout)
        parts = os.path.join(self.tmp, f"parts_{steps}")
        r = run(EXCAVATION, "-o", parts, *self.SETS, "--set", f"time.max_steps={steps}")
        self.assertEqual(r.returncode, 0, r.stdout)
        rows = read_rows(os.path.join(parts, "recorders.csv"))
        self.assertEqual(int(rows[-1]["step"]), steps)
        ck = os.path.join(parts, "checkpoint.tsuchi")
        with open(ck, "rb") as f:
            ck_copy = f.read()
        r = run(EXCAVATION, "-o", parts, *self.SETS, "--restart", ck)
        self.assertEqual(r.returncode, 0, r.stdout)
        x, y = snapshot(self.whole), snapshot(parts)
        self.assertGreater(len(x), 6)
        self.assertEqual(sorted(x), sorted(y))
        for name, data in x.items():
            self.assertTrue(y[name] == data, f"{name} differs after the restart")
        self.assertNotEqual(ck_copy, x["checkpoint.tsuchi"], "the comparison is of a later state than the split")
        return rows

    def test_stopped_inside_the_removal_stage(self):
        rows = self.split_at(300)
        self.assertEqual(rows[-1]["stage"], "2")

    def test_stopped_at_the_end_of_stage_one(self):
        # Stage 1 (greenfield, at rest from the start) ends at its 20th step, where equilibrium is
        # first judged; the run then stops at the start of stage 2, after its removal.
        rows = self.split_at(20)
        self.assertEqual(rows[-1]["stage"], "1")

    def test_restart_from_an_earlier_stage_drops_the_later_stage_pvd(self):
        # A run that went on past its checkpoint wrote particles_stage2.pvd; a restart from the
        # checkpoint in stage 1 that stops before stage 2 must not leave it listing removed frames.
        self.assertEqual(self.r_whole.returncode, 0, self.r_whole.stdout)
        out = os.path.join(self.tmp, "earlier")
        r = run(EXCAVATION, "-o", out, *self.SETS, "--set", "time.max_steps=10")
        self.assertEqual(r.returncode, 0, r.stdout)
        ck = os.path.join(self.tmp, "earlier.tsuchi")
        shutil.copyfile(os.path.join(out, "checkpoint.tsuchi"), ck)
        r = run(EXCAVATION, "-o", out, *self.SETS, "--restart", ck)
        self.assertEqual(r.returncode, 0, r.stdout)
        self.assertTrue(os.path.exists(os.path.join(out, "particles_stage2.pvd")))
        r = run(EXCAVATION, "-o", out, *self.SETS, "--restart", ck, "--set", "time.max_steps=15")
        self.assertEqual(r.returncode, 0, r.stdout)
        self.assertFalse(os.path.exists(os.path.join(out, "particles_stage2.pvd")))
        self.assertEqual(len(read_rows(os.path.join(out, "stages.csv"))), 0)


if __name__ == "__main__":
    unittest.main(verbosity=2)
