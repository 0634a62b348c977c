#!/usr/bin/python3
"""Warp/weft springs and tether distances of a clothlab --state-out CSV (a grid cloth).

  state_springs.py s.csv [--width 1] [--height 1] [--longest 10] [--threshold 0.05]
      the longest warp springs, (r,c)-(r+1,c), and weft springs, (r,c)-(r,c+1), as length /
      rest length with their particles; how many are longer than 1 + threshold and shorter than
      1 - threshold. Rest lengths are the grid's spacing: height / (rows - 1) along a column,
      width / (cols - 1) along a row (both built-in scenarios start flat and unstretched).
  ... --column C --rows A:B
      per row r in A..B: the warp spring (r,C)-(r+1,C) and the weft spring (r,C)-(r,C+1).
  ... --row R --cols A:B
      per column c in A..B: the weft spring (R,c)-(R,c+1) and the warp spring (R,c)-(R+1,c).
  ... --tether-pin ROW,COL [--tether-pin own,0 ...]
      for every other particle, its distance to that particle against the straight-line rest
      distance on the grid (the rest length of an xpbd tether): the share of particles beyond
      it (by more than float32 rounding, 1e-6), beyond it by more than each --tether-levels
      fraction, and the largest ratio. ROW
      'own' means the particle's own row (the flag's pole pin at its height).

Bad input: one line on stderr naming the file (and line) or the option, exit code 1.
"""
import argparse
import csv
import math
import sys

COLUMNS = ("row", "col", "x", "y", "z")
# A float32 state rounds positions to ~6e-8 relative: a pinned particle's distance to another pin
# can come out that much over its rest. Beyond the rest distance means beyond by more than this.
ROUNDING = 1e-6


class InputProblem(Exception):
    """Bad input: reported as one line, exit code 1."""


def read_state(path):
    """{(row, col): (x, y, z)} and the grid's rows, cols from a --state-out CSV."""
    points = {}
    try:
        with open(path, newline="") as stream:
            reader = csv.DictReader(stream)
            missing = [c for c in COLUMNS if c not in (reader.fieldnames or [])]
            if missing:
                raise InputProblem(f"{path}:1: not a clothlab --state-out CSV: no column "
                                   f"{', '.join(missing)} (expected row,col,x,y,z,vx,vy,vz)")
            for record in reader:
                where = f"{path}:{reader.line_num}"
                try:
                    key = (int(record["row"]), int(record["col"]))
                    point = tuple(float(record[c]) for c in ("x", "y", "z"))
                except (TypeError, ValueError):
                    raise InputProblem(f"{where}: row, col must be integers and x, y, z numbers")
                if key[0] < 0 or key[1] < 0 or not all(map(math.isfinite, point)):
                    raise InputProblem(f"{where}: row, col must be >= 0 and x, y, z finite")
                if key in points:
                    raise InputProblem(f"{where}: particle ({key[0]},{key[1]}) appears twice")
                points[key] = point
    except OSError as error:
        raise InputProblem(f"{path}: cannot read state: {error.strerror}")
    except csv.Error as error:
        raise InputProblem(f"{path}: not a CSV file: {error}")
    if not points:
        raise InputProblem(f"{path}: no particles")
    rows = 1 + max(r for r, _ in points)
    cols = 1 + max(c for _, c in points)
    if len(points) != rows * cols:
        raise InputProblem(f"{path}: {len(points)} particles do not fill a {rows} x {cols} grid")
    return points, rows, cols


class Grid:
    def __init__(self, points, rows, cols, width, height):
        self.points, self.rows, self.cols = points, rows, cols
        self.weft_rest = width / (cols - 1) if cols > 1 else None
        self.warp_rest = height / (rows - 1) if rows > 1 else None

    def ratio(self, a, b, rest):
        return math.dist(self.points[a], self.points[b]) / rest

    def warp(self, r, c):
        """(r,c)-(r+1,c) over its rest length, or None past the last row."""
        return self.ratio((r, c), (r + 1, c), self.warp_rest) if r + 1 < self.rows else None

    def weft(self, r, c):
        return self.ratio((r, c), (r, c + 1), self.weft_rest) if c + 1 < self.cols else None

    def springs(self):
        """(kind, (r, c), (r2, c2), length / rest) for every warp and weft spring."""
        for r in range(self.rows):
            for c in range(self.cols):
                if r + 1 < self.rows:
                    yield "warp", (r, c), (r + 1, c), self.warp(r, c)
                if c + 1 < self.cols:
                    yield "weft", (r, c), (r, c + 1), self.weft(r, c)


def particle(key):
    return f"({key[0]},{key[1]})"


def shown(ratio):
    return "-" if ratio is None else f"{ratio:.4f}"


def report_springs(grid, longest, threshold):
    springs = list(grid.springs())
    print(f"{len(springs)} warp/weft springs; rest lengths: warp {grid.warp_rest} m, "
          f"weft {grid.weft_rest} m")
    print(f"longest {longest} (length / rest):")
    for kind, a, b, ratio in sorted(springs, key=lambda s: -s[3])[:longest]:
        print(f"  {kind} {particle(a)}-{particle(b)} {ratio:.6f}")
    for kind in ("warp", "weft"):
        ratios = [s[3] for s in springs if s[0] == kind]
        longer = sum(ratio > 1 + threshold for ratio in ratios)
        shorter = sum(ratio < 1 - threshold for ratio in ratios)
        print(f"{kind}: {longer} of {len(ratios)} longer than {1 + threshold:g} x rest, "
              f"{shorter} shorter than {1 - threshold:g} x rest")
    longer = sum(s[3] > 1 + threshold for s in springs)
    print(f"warp and weft: {longer} of {len(springs)} longer than {1 + threshold:g} x rest")


def report_line(grid, fixed, span, along_column):
    first, last = span
    if along_column:
        print(f"column {fixed}, rows {first}-{last}: row, warp (r,{fixed})-(r+1,{fixed}), "
              f"weft (r,{fixed})-(r,{fixed + 1})")
        for r in range(first, last + 1):
            print(f"  {r} {shown(grid.warp(r, fixed))} {shown(grid.weft(r, fixed))}")
    else:
        print(f"row {fixed}, columns {first}-{last}: column, weft ({fixed},c)-({fixed},c+1), "
              f"warp ({fixed},c)-({fixed + 1},c)")
        for c in range(first, last + 1):
            print(f"  {c} {shown(grid.weft(fixed, c))} {shown(grid.warp(fixed, c))}")


def report_tether(grid, pin, levels):
    pin_row, pin_col = pin
    beyond, worst, counted = [0] * (len(levels) + 1), (0.0, None), 0
    for (r, c), point in grid.points.items():
        anchor = (r if pin_row == "own" else pin_row, pin_col)
        if anchor == (r, c):
            continue
        rest = math.hypot((r - anchor[0]) * grid.warp_rest, (c - anchor[1]) * grid.weft_rest)
        ratio = math.dist(point, grid.points[anchor]) / rest
        counted += 1
        for k, level in enumerate((ROUNDING, *levels)):
            beyond[k] += ratio > 1 + level
        worst = max(worst, (ratio, (r, c)), key=lambda w: w[0])
    name = f"the own row's column {pin_col}" if pin_row == "own" else particle(pin)
    shares = ", ".join(f"by more than {100 * level:g} %: {100 * n / counted:.1f} %"
                       for level, n in zip(levels, beyond[1:]))
    print(f"tether to {name}: {counted} particles; farther than the rest distance: "
          f"{100 * beyond[0] / counted:.1f} % ({beyond[0]}); {shares}; largest {worst[0]:.6f} x rest "
          f"at {particle(worst[1]) if worst[1] else '-'}")


def span_option(text, option, size):
    first, sep, last = text.partition(":")
    try:
        span = (int(first), int(last if sep else first))
    except ValueError:
        raise InputProblem(f"{option} '{text}': expected FIRST:LAST (integers)")
    if not 0 <= span[0] <= span[1] < size:
        raise InputProblem(f"{option} '{text}': expected 0 <= FIRST <= LAST <= {size - 1}")
    return span


def index_option(value, option, size):
    if not 0 <= value < size:
        raise InputProblem(f"{option} {value}: expected 0..{size - 1}")
    return value


def pin_option(text, rows, cols):
    row, sep, col = text.partition(",")
    try:
        pin = (row if row == "own" else int(row), int(col))
    except ValueError:
        pin = None
    if not sep or pin is None or not 0 <= pin[1] < cols \
            or (pin[0] != "own" and not 0 <= pin[0] < rows):
        raise InputProblem(f"--tether-pin '{text}': expected ROW,COL with ROW 0..{rows - 1} "
                           f"or 'own', COL 0..{cols - 1}")
    return pin


def fractions_option(text):
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if not values or not all(0 <= v < 10 for v in values):
        raise InputProblem(f"--tether-levels '{text}': expected fractions in [0, 10), "
                           "comma-separated (0.01 = 1 %)")
    return values


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("state", help="a clothlab --state-out CSV")
    parser.add_argument("--width", type=float, default=1.0, help="cloth width (m), default 1")
    parser.add_argument("--height", type=float, default=1.0, help="cloth height (m), default 1")
    parser.add_argument("--longest", type=int, default=10, help="springs listed (default 10)")
    parser.add_argument("--threshold", type=float, default=0.05,
                        help="stretch counted beyond (default 0.05: 1.05 x rest)")
    parser.add_argument("--column", type=int, help="list the springs along this column")
    parser.add_argument("--rows", help="with --column: FIRST:LAST")
    parser.add_argument("--row", type=int, help="list the springs along this row")
    parser.add_argument("--cols", help="with --row: FIRST:LAST")
    parser.add_argument("--tether-pin", action="append", default=[], metavar="ROW,COL",
                        help="distances to this particle against their rest (repeatable)")
    parser.add_argument("--tether-levels", default="0.01,0.02,0.05",
                        help="fractions beyond the rest distance to count (default 0.01,0.02,0.05)")
    args = parser.parse_args(argv)
    try:
        for option, value in (("--width", args.width), ("--height", args.height)):
            if not (math.isfinite(value) and value > 0):
                raise InputProblem(f"{option} {value}: expected a length > 0 (m)")
        if args.longest < 0 or not (math.isfinite(args.threshold) and 0 <= args.threshold < 10):
            raise InputProblem(f"--longest {args.longest} / --threshold {args.threshold}: "
                               "expected --longest >= 0 and --threshold in [0, 10)")
        if (args.column is None) != (args.rows is None) or (args.row is None) != (args.cols is None):
            raise InputProblem("--column goes with --rows FIRST:LAST, --row with --cols FIRST:LAST")
        points, rows, cols = read_state(args.state)
        if rows < 2 or cols < 2:
            raise InputProblem(f"{args.state}: a {rows} x {cols} grid has no warp or no weft springs")
        grid = Grid(points, rows, cols, args.width, args.height)
        lines = []
        if args.column is not None:
            lines.append((index_option(args.column, "--column", cols),
                          span_option(args.rows, "--rows", rows), True))
        if args.row is not None:
            lines.append((index_option(args.row, "--row", rows),
                          span_option(args.cols, "--cols", cols), False))
        pins = [pin_option(text, rows, cols) for text in args.tether_pin]
        levels = fractions_option(args.tether_levels)
        print(f"{args.state}: {rows} x {cols} particles, {args.width:g} m x {args.height:g} m")
        report_springs(grid, args.longest, args.threshold)
        for fixed, span, along_column in lines:
            report_line(grid, fixed, span, along_column)
        for pin in pins:
            report_tether(grid, pin, levels)
    except InputProblem as problem:
        print(f"state_springs.py: {problem}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
