#!/usr/bin/python3
"""tools/state_springs.py on a hand-made 3 x 3 --state-out CSV with one known stretched spring;
bad input is one line on stderr and exit code 1."""
import os
import subprocess
import sys
import tempfile
import unittest

TOOL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools",
                    "state_springs.py")
HEADER = "row,col,x,y,z,vx,vy,vz\n"


def grid_state(moved=None):
    """A flat 1 m x 1 m 3 x 3 grid as clothlab writes it (row 0 at y = 1), spacing 0.5 m;
    moved: {(row, col): (dx, dy, dz)}."""
    lines = [HEADER]
    for r in range(3):
        for c in range(3):
            dx, dy, dz = (moved or {}).get((r, c), (0, 0, 0))
            lines.append(f"{r},{c},{0.5 * c + dx},{1 - 0.5 * r + dy},{dz},0,0,0\n")
    return "".join(lines)


class StateSpringsTest(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.folder.cleanup()

    def write(self, text, name="s.csv"):
        path = os.path.join(self.folder.name, name)
        with open(path, "w") as stream:
            stream.write(text)
        return path

    def run_tool(self, *args):
        return subprocess.run([sys.executable, TOOL, *args], capture_output=True, text=True)

    def report(self, *args):
        result = self.run_tool(*args)
        self.assertEqual(result.returncode, 0, result.stderr)
        return result.stdout

    def test_one_stretched_weft_spring_is_the_longest_and_the_only_one_beyond_5_percent(self):
        # (1,2) moved 0.1 m along the row: weft (1,1)-(1,2) at 0.6 / 0.5 = 1.2 x rest; the warp
        # springs to it at sqrt(0.5^2 + 0.1^2) / 0.5 = 1.0198 x rest, under the 5 % threshold.
        path = self.write(grid_state({(1, 2): (0.1, 0, 0)}))
        out = self.report(path, "--longest", "3")
        lines = out.splitlines()
        self.assertIn("12 warp/weft springs; rest lengths: warp 0.5 m, weft 0.5 m", out)
        self.assertEqual(lines[3], "  weft (1,1)-(1,2) 1.200000")
        self.assertEqual(sorted(lines[4:6]), ["  warp (0,2)-(1,2) 1.019804",
                                              "  warp (1,2)-(2,2) 1.019804"])
        self.assertIn("warp: 0 of 6 longer than 1.05 x rest, 0 shorter than 0.95 x rest", out)
        self.assertIn("weft: 1 of 6 longer than 1.05 x rest, 0 shorter than 0.95 x rest", out)
        self.assertIn("warp and weft: 1 of 12 longer than 1.05 x rest", out)
        # Above 1.2 nothing counts; the cloth's width sets the weft rest length.
        self.assertIn("weft: 0 of 6 longer than 1.25", self.report(path, "--threshold", "0.25"))
        wide = self.report(path, "--width", "2")
        self.assertIn("weft 1.0 m", wide)
        self.assertIn("weft: 0 of 6 longer than 1.05 x rest, 6 shorter than 0.95 x rest", wide)

    def test_springs_along_a_column_and_a_row(self):
        path = self.write(grid_state({(1, 2): (0.1, 0, 0)}))
        out = self.report(path, "--column", "1", "--rows", "0:2", "--row", "1", "--cols", "1:2")
        self.assertIn("  0 1.0000 1.0000\n  1 1.0000 1.2000\n  2 - 1.0000\n", out)
        self.assertIn("  1 1.2000 1.0000\n  2 - 1.0198\n", out)

    def test_tether_share_counts_the_particles_beyond_their_rest_distance(self):
        # (2,2) pulled 0.1 m away from (0,0) along the diagonal: 0.1 / sqrt(2) = 7.1 % beyond its
        # rest distance; (1,2) pushed towards it: inside. 1 of the 8 other particles.
        diagonal = 0.1 / 2 ** 0.5
        path = self.write(grid_state({(2, 2): (diagonal, -diagonal, 0), (1, 2): (-0.1, 0, 0)}))
        out = self.report(path, "--tether-pin", "0,0", "--tether-pin", "own,0")
        self.assertIn("tether to (0,0): 8 particles; farther than the rest distance: 12.5 % (1); "
                      "by more than 1 %: 12.5 %, by more than 2 %: 12.5 %, by more than 5 %: "
                      "12.5 %; largest 1.070711 x rest at (2,2)", out)
        # To its own row's pin (2,0), (2,2) is 1 m away at rest, sqrt(1.0707^2 + 0.0707^2) now.
        self.assertIn("tether to the own row's column 0: 6 particles; farther than the rest "
                      "distance: 16.7 % (1)", out)
        self.assertIn("largest 1.073043 x rest at (2,2)", out)

    def test_bad_input_is_one_line_naming_the_source_and_exit_code_1(self):
        cases = (
            (self.write("row,col,x,y\n0,0,0,0\n", "no-z.csv"), [], "no-z.csv:1:", "no column z"),
            (self.write(HEADER + "0,0,0,1,0,0,0,0\n0,0,0,1,0,0,0,0\n", "twice.csv"), [],
             "twice.csv:3:", "appears twice"),
            (self.write(HEADER + "0,0,0,1,0,0,0,0\n1,1,0,1,0,0,0,0\n", "holes.csv"), [],
             "holes.csv", "do not fill a 2 x 2 grid"),
            (self.write(HEADER + "0,a,0,1,0,0,0,0\n", "text.csv"), [], "text.csv:2:", "integers"),
            (self.write(grid_state()), ["--column", "1", "--rows", "0:3"], "--rows '0:3'", "<= 2"),
            (self.write(grid_state()), ["--column", "1"], "--column goes with --rows", ""),
            (self.write(grid_state()), ["--tether-pin", "0"], "--tether-pin '0'", "'own'"),
            (self.write(grid_state()), ["--width", "0"], "--width 0.0", "> 0"),
            (os.path.join(self.folder.name, "absent.csv"), [], "absent.csv", "cannot read"),
        )
        for path, args, source, detail in cases:
            with self.subTest(source=source):
                result = self.run_tool(path, *args)
                self.assertEqual(result.returncode, 1, result.stdout)
                self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
                self.assertIn(source, result.stderr)
                self.assertIn(detail, result.stderr)


if __name__ == "__main__":
    unittest.main()
