#!/usr/bin/env python3
"""Tests of escape.py against closed-form answers on a straight road: python3 test_escape.py"""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from escape import best_witness, box_distance, drive, escape  # noqa: E402
from geom import Box  # noqa: E402

EGO = {"x": 0.0, "y": 0.0, "heading": 0.0, "v": 0.0, "a": 0.0, "kappa": 0.0,
       "length": 4.5, "width": 1.8, "wheelbase": 2.7}
FRONT = EGO["wheelbase"] / 2 + EGO["length"] / 2       # rear axle to front bumper
REAR = EGO["length"] / 2 - EGO["wheelbase"] / 2        # rear overhang


def scene(v0=0.0, statics=(), movers=(), duration=6.0):
    ego = dict(EGO, v=v0)
    return {"format": "scene/1", "duration": duration, "ego": ego,
            "reference_line": [[-100.0, 0.0], [300.0, 0.0]],
            "road": {"left_boundary": 5.0, "right_boundary": -5.0, "speed_limit": 30.0},
            "static_obstacles": list(statics), "dynamic_obstacles": list(movers)}


def follower(gap, speed, length=4.5, duration=6.0):
    """A car in the ego's lane `gap` metres behind its rear bumper, at constant `speed`."""
    x0 = -REAR - gap - length / 2
    traj = [{"t": 0.1 * k, "x": x0 + speed * 0.1 * k, "y": 0.0, "heading": 0.0, "v": speed}
            for k in range(int(duration * 10) + 1)]
    return {"id": 7, "length": length, "width": 1.8, "trajectory": traj}


def wall(distance):
    """A box across the lane whose near face is `distance` metres ahead of the ego's front."""
    return {"id": 3, "x": FRONT + distance + 0.5, "y": 0.0, "heading": 0.0, "length": 1.0,
            "width": 4.0}


class ClosedForm(unittest.TestCase):
    def test_follower_outrun_iff_gap_exceeds_u2_over_2a(self):
        # from rest at a_max the gap is g - u t + a t^2 / 2, smallest at t = u / a
        u, a = 6.0, 3.0
        critical = u * u / (2 * a)                     # 6 m
        ok = escape(scene(movers=[follower(critical + 0.4, u)]), 0.0, a_max=a)
        self.assertIsNone(ok["empty_at"])
        hit = escape(scene(movers=[follower(critical - 0.4, u)]), 0.0, a_max=a)
        self.assertIsNotNone(hit["empty_at"])
        self.assertEqual(hit["blockers"], [7])
        # the closest approach is at u / a = 2 s, so the set runs empty at about then
        self.assertGreater(hit["empty_at"], 1.0)
        self.assertLess(hit["empty_at"], 2.6)

    def test_wall_ahead_stopped_iff_room_exceeds_v2_over_2b(self):
        v0, b = 10.0, 6.0
        critical = v0 * v0 / (2 * b)                   # 8.33 m
        self.assertIsNone(escape(scene(v0, statics=[wall(critical + 0.3)]), 0.0, a_min=-b)["empty_at"])
        hit = escape(scene(v0, statics=[wall(critical - 0.3)]), 0.0, a_min=-b)
        self.assertIsNotNone(hit["empty_at"])
        self.assertEqual(hit["blockers"], [3])
        # with a gentler limit the same room is not enough
        self.assertIsNotNone(escape(scene(v0, statics=[wall(critical + 0.3)]), 0.0, a_min=-4.0)["empty_at"])

    def test_sandwich_between_wall_and_follower(self):
        # at most 1 m forward; the follower at 5 m/s closes 3 m + 1 m within 0.8 s
        s = scene(statics=[wall(1.0)], movers=[follower(3.0, 5.0)])
        r = escape(s, 0.0)
        self.assertIsNotNone(r["empty_at"])
        self.assertLessEqual(r["empty_at"], 0.9)
        self.assertIn(7, r["blockers"])
        # without the wall it outruns the follower? 25 / 6 = 4.2 m > 3 m: no; with a 5 m gap, yes
        self.assertIsNotNone(escape(scene(movers=[follower(3.0, 5.0)]), 0.0)["empty_at"])
        self.assertIsNone(escape(scene(movers=[follower(5.0, 5.0)]), 0.0)["empty_at"])

    def test_lateral_offset_passes_a_narrow_box(self):
        # a 0.6 m wide box at l = +1.6 (its edge at 1.3): the ego (half width 0.9) passes at
        # l = 0 and l = -0.3, not at l = +0.5; the ego starts at 10 m/s and cannot stop in 5 m
        box = {"id": 9, "x": FRONT + 5.0 + 0.5, "y": 1.6, "heading": 0.0, "length": 1.0, "width": 0.6}
        s = scene(10.0, statics=[box])
        self.assertIsNone(escape(s, 0.0)["empty_at"])
        self.assertIsNone(escape(s, -0.3)["empty_at"])
        self.assertIsNotNone(escape(s, 0.5)["empty_at"])


class Witness(unittest.TestCase):
    def test_box_distance(self):
        a = Box(0, 0, 0, 4, 2)
        self.assertAlmostEqual(box_distance(a, Box(5.5, 0, 0, 4, 2)), 1.5)
        self.assertAlmostEqual(box_distance(a, Box(0, 3.0, 0, 4, 2)), 1.0)
        self.assertAlmostEqual(box_distance(a, Box(4, 3, 0, 2, 2)), math.hypot(1, 1))
        # a 45-degree square whose corner points at a's right side: corner-to-edge
        d = 2 + math.sqrt(2) + 0.3
        self.assertAlmostEqual(box_distance(a, Box(d, 0, math.pi / 4, 2, 2)), 0.3)
        self.assertEqual(box_distance(a, Box(1, 1, 0.3, 4, 2)), 0.0)

    def test_drive_and_witness_outrun_a_follower(self):
        # gap 7 m, follower at 6 m/s: at 3 m/s^2 from t = 0 the smallest gap is 7 - 6 = 1 m
        s = scene(movers=[follower(7.0, 6.0)])
        contact, nearest = drive(s, 0.0, 3.0, 0.0)
        self.assertIsNone(contact)
        self.assertAlmostEqual(nearest[7][0], 1.0, delta=0.03)
        self.assertIsNotNone(drive(s, 0.0, 1.0, 0.0)[0])     # too gentle: caught
        w = best_witness(s, 0.0)
        self.assertEqual((w[0], w[1]), (3.0, 0.0))
        self.assertAlmostEqual(w[2], 1.0, delta=0.03)


if __name__ == "__main__":
    unittest.main()
