#!/usr/bin/env python3
"""The training example (examples/python/train_go_to_ball.py) runs, writes
its learning curve, and learns: a short run (4 generations of 16 policies)
already touches the ball in many held-out episodes where the untrained policy
touches it in none. Deterministic: the run is seeded.

Run by ctest with PYTHONPATH=<build>/python; by hand:
    PYTHONPATH=build/python /usr/bin/python3 tests/python_train_example_test.py
"""

import csv
import os
import subprocess
import sys
import tempfile
import unittest

EXAMPLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples", "python", "train_go_to_ball.py")


class TestTrainingExample(unittest.TestCase):
    def test_learns_and_writes_its_curve(self):
        with tempfile.TemporaryDirectory() as tmp:
            table, image = os.path.join(tmp, "curve.csv"), os.path.join(tmp, "curve.png")
            out = subprocess.run([sys.executable, EXAMPLE, "--generations", "4", "--population", "16",
                                  "--episodes", "2", "--threads", "2", "--csv", table, "--plot", image],
                                 capture_output=True, text=True, timeout=300)
            self.assertEqual(out.returncode, 0, out.stderr)
            self.assertIn("hand-written controller", out.stdout)
            with open(table) as f:
                rows = list(csv.DictReader(f))
            self.assertEqual([int(r["generation"]) for r in rows], [0, 1, 2, 3, 4])
            self.assertEqual(float(rows[0]["eval_success"]), 0.0)  # all weights 0: the robot stands still
            self.assertGreaterEqual(float(rows[-1]["eval_success"]), 0.3)
            self.assertGreater(float(rows[-1]["eval_return"]), float(rows[0]["eval_return"]) + 5.0)
            with open(image, "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")

    def test_bad_arguments(self):
        for args in (["--population", "3"], ["--generations", "0"], ["--episodes", "-1"], ["--seed", "x"]):
            out = subprocess.run([sys.executable, EXAMPLE, *args], capture_output=True, text=True, timeout=60)
            self.assertEqual(out.returncode, 2, args)
            self.assertIn("error:", out.stderr)


if __name__ == "__main__":
    unittest.main()
