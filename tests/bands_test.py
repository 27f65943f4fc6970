"""Tests of tools/bands.py on synthetic shear-strain fields.

usage: /usr/bin/python3 tests/bands_test.py   (unittest; exit status 1 on failure)

Each field is a 5 x 10 cm lattice of particles at 1 mm spacing, like the triaxial specimen, with
gamma = seeded background noise + Gaussian ridges along known lines.
"""
import math
import os
import sys
import time
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from bands import find_bands  # noqa: E402

WIDTH, HEIGHT, SPACING = 0.05, 0.10, 0.001


def lattice():
    xs = np.arange(SPACING / 2, WIDTH, SPACING)
    ys = np.arange(SPACING / 2, HEIGHT, SPACING)
    x, y = np.meshgrid(xs, ys)
    return x.ravel(), y.ravel()


def field(ridges, noise=0.01, level=0.02, seed=1):
    """Lattice plus gamma = level + |noise| background + ridges.

    ridges: list of (angle_deg, (px, py), amplitude, sigma_m): a Gaussian ridge
    amplitude * exp(-d^2 / 2 sigma^2), d = distance from the line through (px, py) at angle_deg.
    """
    x, y = lattice()
    rng = np.random.default_rng(seed)
    gamma = level + noise * np.abs(rng.standard_normal(len(x)))
    for angle, (px, py), amplitude, sigma in ridges:
        a = math.radians(angle)
        d = -(x - px) * math.sin(a) + (y - py) * math.cos(a)
        gamma += amplitude * np.exp(-0.5 * (d / sigma) ** 2)
    return x, y, gamma


def angle_error(found, expected):
    """Difference of two line directions, folded so that 89.9 and -89.9 are 0.2 apart."""
    d = (found - expected) % 180.0
    return min(d, 180.0 - d)


def distance_to_line(b, px, py):
    a = math.radians(b.angle)
    return abs(-(px - b.cx) * math.sin(a) + (py - b.cy) * math.cos(a))


CENTRE = (0.025, 0.05)


class SingleBand(unittest.TestCase):
    def check_single(self, angle, point, tol, **kw):
        x, y, g = field([(angle, point, 0.3, 0.002)], **kw)
        bands = find_bands(x, y, g)
        self.assertEqual(len(bands), 1, [b.angle for b in bands])
        b = bands[0]
        self.assertLess(angle_error(b.angle, angle), tol, b)
        self.assertLess(distance_to_line(b, *point), 1e-3, b)
        self.assertEqual(b.sense, "rising right" if angle > 0 else "rising left")
        return b

    def test_50_degrees(self):
        b = self.check_single(50.0, CENTRE, 1.0)
        self.assertAlmostEqual(b.inclination, 50.0, delta=1.0)
        # Width: FWHM of the Gaussian ridge, 2.355 sigma = 4.7 mm.
        self.assertAlmostEqual(b.width, 2.355 * 0.002, delta=0.25 * 2.355 * 0.002)
        self.assertGreater(b.explained, 0.8)
        self.assertGreater(b.r2, 0.95)

    def test_minus_50_degrees(self):
        self.check_single(-50.0, CENTRE, 1.0)

    def test_45_degrees(self):
        self.check_single(45.0, (0.02, 0.06), 1.0)

    def test_60_degrees(self):
        self.check_single(60.0, (0.03, 0.045), 1.0)

    def test_near_edge(self):
        # Rises to the left from the bottom (x = 35 mm) to the left side (y = 42 mm); the
        # ridge's lower-left flank is partly outside the specimen.
        self.check_single(-50.0, (0.01, 0.03), 1.0)

    def test_along_right_edge(self):
        # Nearly vertical band 3 mm from the right side: one flank cut by the edge.
        self.check_single(85.0, (0.047, 0.05), 1.0)

    def test_noisy_background(self):
        # Ridge only 4 times the noise's scale, background noise 5 times stronger than above.
        x, y, g = field([(50.0, CENTRE, 0.2, 0.002)], noise=0.05, seed=7)
        bands = find_bands(x, y, g)
        self.assertEqual(len(bands), 1, [b.angle for b in bands])
        self.assertLess(angle_error(bands[0].angle, 50.0), 1.0)


class CrossingBands(unittest.TestCase):
    def test_x_pair(self):
        x, y, g = field([(52.0, CENTRE, 0.3, 0.002), (-52.0, CENTRE, 0.3, 0.002)])
        bands = find_bands(x, y, g)
        self.assertEqual(len(bands), 2, [b.angle for b in bands])
        angles = sorted(b.angle for b in bands)
        self.assertLess(angle_error(angles[0], -52.0), 1.5, angles)
        self.assertLess(angle_error(angles[1], 52.0), 1.5, angles)
        self.assertEqual({b.sense for b in bands}, {"rising right", "rising left"})
        for b in bands:
            self.assertLess(distance_to_line(b, *CENTRE), 1e-3, b)
            self.assertGreater(b.explained, 0.35)

    def test_x_pair_off_centre_unequal(self):
        # Crossing below the middle and one arm weaker, as when one band dominates.
        x, y, g = field([(55.0, (0.025, 0.04), 0.3, 0.002), (-55.0, (0.025, 0.04), 0.15, 0.002)],
                        noise=0.01, seed=3)
        bands = find_bands(x, y, g)
        self.assertEqual(len(bands), 2, [b.angle for b in bands])
        self.assertLess(angle_error(bands[0].angle, 55.0), 1.5)  # the stronger one first
        self.assertLess(angle_error(bands[1].angle, -55.0), 1.5)


    def test_parallel_pair(self):
        # Two parallel bands 15 mm apart (a free cap can leave a second, weaker one).
        x, y, g = field([(50.0, (0.015, 0.05), 0.3, 0.002), (50.0, (0.035, 0.05), 0.2, 0.002)])
        bands = find_bands(x, y, g)
        self.assertEqual(len(bands), 2, [b.angle for b in bands])
        for b in bands:
            self.assertLess(angle_error(b.angle, 50.0), 1.0)
        self.assertLess(distance_to_line(bands[0], 0.015, 0.05), 1e-3)
        self.assertLess(distance_to_line(bands[1], 0.035, 0.05), 1e-3)

    def test_band_dying_out(self):
        # A band from the lower left that stops in the middle of the specimen (its end is cut
        # obliquely, which must not tilt the fit).
        x, y, g = field([])
        a = math.radians(50.0)
        d = -(x - 0.025) * math.sin(a) + (y - 0.05) * math.cos(a)
        g = g + 0.3 * np.exp(-0.5 * (d / 0.002) ** 2) * (x < 0.025)
        bands = find_bands(x, y, g)
        self.assertEqual(len(bands), 1)
        self.assertLess(angle_error(bands[0].angle, 50.0), 1.0)
        self.assertLess(bands[0].length, 0.045)


class NoBand(unittest.TestCase):
    def test_uniform_noise(self):
        for seed in (1, 2, 3):
            x, y, g = field([], noise=0.05, seed=seed)
            self.assertEqual(find_bands(x, y, g), [], f"seed {seed}")

    def test_constant(self):
        x, y, _ = field([])
        self.assertEqual(find_bands(x, y, np.full(len(x), 0.02)), [])

    def test_smooth_gradient(self):
        # Diffuse deformation growing towards the top is not a band.
        x, y, g = field([], noise=0.002)
        self.assertEqual(find_bands(x, y, g + 0.05 * y / HEIGHT), [])


class Behaviour(unittest.TestCase):
    def test_deterministic(self):
        x, y, g = field([(52.0, CENTRE, 0.3, 0.002), (-52.0, CENTRE, 0.3, 0.002)], noise=0.03)
        self.assertEqual(find_bands(x, y, g), find_bands(x, y, g))

    def test_scattered_particles(self):
        # Irregular particle positions (deformed specimen) instead of a lattice.
        x, y, _ = field([])
        rng = np.random.default_rng(5)
        x = x + rng.uniform(-0.4, 0.4, len(x)) * SPACING
        y = y + rng.uniform(-0.4, 0.4, len(y)) * SPACING
        a = math.radians(48.0)
        d = -(x - 0.025) * math.sin(a) + (y - 0.05) * math.cos(a)
        g = 0.02 + 0.01 * np.abs(rng.standard_normal(len(x))) + 0.3 * np.exp(-0.5 * (d / 0.002) ** 2)
        bands = find_bands(x, y, g)
        self.assertEqual(len(bands), 1)
        self.assertLess(angle_error(bands[0].angle, 48.0), 1.0)


if __name__ == "__main__":
    start = time.perf_counter()
    result = unittest.main(exit=False, verbosity=2).result
    print(f"{time.perf_counter() - start:.2f} s")
    sys.exit(0 if result.wasSuccessful() else 1)
