#!/usr/bin/env python3
"""Unit tests of the judge's own geometry and witnesses: python3 test_geom.py"""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from geom import Box, Polyline, Road, boundary_at, boxes_overlap, classify_contact  # noqa: E402


class SeparatingAxis(unittest.TestCase):
    def test_disjoint_and_overlapping(self):
        a = Box(0, 0, 0, 4, 2)
        self.assertTrue(boxes_overlap(a, Box(3.9, 0, 0, 4, 2)))
        self.assertFalse(boxes_overlap(a, Box(4.1, 0, 0, 4, 2)))
        self.assertTrue(boxes_overlap(a, Box(4.0, 0, 0, 4, 2)))      # touching counts

    def test_rotated_corner_case(self):
        # a 45-degree box whose corner points at a's side: separated only by its own axis
        a = Box(0, 0, 0, 2, 2)
        d = 1 + math.sqrt(2) + 0.05
        self.assertFalse(boxes_overlap(a, Box(d, 0, math.pi / 4, 2, 2)))
        self.assertTrue(boxes_overlap(a, Box(d - 0.1, 0, math.pi / 4, 2, 2)))
        # diagonal neighbours separated by a's axes only
        self.assertFalse(boxes_overlap(a, Box(2.05, 2.05, 0, 2, 2)))

    def test_brute_force_agreement(self):
        import random
        rng = random.Random(3)
        for _ in range(400):
            a = Box(0, 0, rng.uniform(-3, 3), rng.uniform(0.5, 5), rng.uniform(0.5, 2.5))
            b = Box(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-3, 3),
                    rng.uniform(0.5, 5), rng.uniform(0.5, 2.5))
            self.assertEqual(boxes_overlap(a, b), sampled_overlap(a, b, 60))


def inside(box, x, y):
    c, s = math.cos(box.heading), math.sin(box.heading)
    dx, dy = x - box.cx, y - box.cy
    return abs(dx * c + dy * s) <= box.length / 2 and abs(-dx * s + dy * c) <= box.width / 2


def sampled_overlap(a, b, n):
    """Brute force: any point of a dense grid over b (edges included) inside a, or vice versa."""
    for p, q in ((a, b), (b, a)):
        c, s = math.cos(p.heading), math.sin(p.heading)
        for i in range(n + 1):
            for j in range(n + 1):
                u = (i / n - 0.5) * p.length
                v = (j / n - 0.5) * p.width
                if inside(q, p.cx + u * c - v * s, p.cy + u * s + v * c):
                    return True
    return False


class RoadFrame(unittest.TestCase):
    def test_circle_radius(self):
        r = 50.0
        road = Road(0, 0, 0, math.pi * r, lambda s: 1 / r, ds=0.5)
        x, y, th, k = road.pose(math.pi * r)
        self.assertAlmostEqual(x, 0.0, delta=1e-3)   # linear between 0.5 m samples: c^2/8R
        self.assertAlmostEqual(y, 2 * r, delta=1e-3)
        pl = Polyline(road.polyline(0.5))
        s, l, _, _ = pl.project(*road.to_xy(40.0, 1.5))
        self.assertAlmostEqual(s, 40.0, delta=0.05)
        self.assertAlmostEqual(l, 1.5, delta=0.01)

    def test_boundary_table(self):
        b = [[0, 1.0], [10, 1.0], [20, 3.0]]
        self.assertEqual(boundary_at(b, -5), 1.0)
        self.assertAlmostEqual(boundary_at(b, 15), 2.0)
        self.assertEqual(boundary_at(b, 99), 3.0)


class Classification(unittest.TestCase):
    def test_rear_end_by_ego(self):
        ego, lead = Box(0, 0, 0, 4.8, 1.9), Box(4.7, 0, 0, 4.5, 1.8)
        c = classify_contact(ego, (10, 0), lead, (5, 0))
        self.assertEqual((c["who"], c["location"]), ("ran_into", "front"))

    def test_hit_from_behind_while_stopped(self):
        ego, car = Box(0, 0, 0, 4.8, 1.9), Box(-4.7, 0, 0, 4.5, 1.8)
        c = classify_contact(ego, (0, 0), car, (8, 0))
        self.assertEqual((c["who"], c["location"]), ("hit", "rear"))

    def test_side_swipe_by_cut_in(self):
        ego, car = Box(0, 0, 0, 4.8, 1.9), Box(0.5, 1.9, 0.2, 4.5, 1.8)
        c = classify_contact(ego, (10, 0), car, (10 * math.cos(0.2), -1.5))
        self.assertEqual((c["who"], c["location"]), ("hit", "left"))


    def test_deep_step_into_offset_car_is_a_rear_end(self):
        # one 0.1 s step at 12 m/s into a car offset 1.2 m to the side: the least-penetration
        # axis now is lateral, but the step before says they met front-to-rear
        before, after = Box(0, 0, 0, 4.8, 1.9), Box(1.2, 0, 0, 4.8, 1.9)
        car = Box(5.6, 1.2, 0, 4.5, 1.8)
        c = classify_contact(after, (12, 0), car, (0, 0), before, car)
        self.assertEqual(c["who"], "ran_into")
        self.assertGreater(c["ego_share"], 11.0)


if __name__ == "__main__":
    unittest.main()
