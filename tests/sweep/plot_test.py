#!/usr/bin/python3
"""tools/plot.py on small synthetic results: every plot kind writes PNG and SVG; bad input is
one line on stderr and exit code 1."""
import contextlib
import csv
import io
import json
import os
import sys
import tempfile
import types
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import plot  # noqa: E402  (tools/plot.py, found through the path above)


def run_plot(*args):
    """plot.py's main as its command line runs it (`sys.exit(main())`), in this process: one
    matplotlib import for every case instead of one per case. Its exit code and what it wrote."""
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        try:
            code = plot.main(list(args))
        except SystemExit as exit_:  # argparse's refusals
            code = exit_.code
    plot.plt.close("all")
    return types.SimpleNamespace(returncode=code, stdout=stdout.getvalue(),
                                 stderr=stderr.getvalue())


def work_precision_rows():
    rows = [{"key": "ref", "kind": "reference", "scenario": "sheet", "T": 0.5,
             "reference_error_estimate": 1e-13}]
    for integrator, order in (("euler", 1), ("rk4", 4)):
        for precision in ("float64", "float32"):
            for level in range(5):
                dt = 0.002 / 2 ** level
                rows.append({"key": f"{integrator}{precision}{level}", "kind": "ladder",
                             "scenario": "sheet", "integrator": integrator, "mesh": "20x20",
                             "precision": precision, "dt": dt, "T": 0.5,
                             "error": 3.0 * dt ** order + (1e-7 if precision == "float32" else 0),
                             "wall_per_sim_s": 1e-4 / dt, "stable": True})
            # euler's fit is made out of its asymptotic range: its order must not be shown.
            rows.append({"key": f"fit{integrator}{precision}", "kind": "fit", "scenario": "sheet",
                         "integrator": integrator, "mesh": "20x20", "precision": precision,
                         "order": float(order), "fit_valid": True,
                         "r_squared": 0.5 if integrator == "euler" else 0.9999,
                         "fit_points": 3 if precision == "float32" else 5})
    return rows


def write_csv(path, rows):
    columns = []
    for row in rows:
        columns += [c for c in row if c not in columns]
    with open(path, "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=columns)
        writer.writeheader()
        for row in rows:
            writer.writerow({k: ("true" if v is True else "false" if v is False else v)
                             for k, v in row.items()})


class PlotTest(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.TemporaryDirectory()
        self.out = os.path.join(self.folder.name, "plots")

    def tearDown(self):
        self.folder.cleanup()

    def path(self, name):
        return os.path.join(self.folder.name, name)

    def assert_written(self, result, names):
        self.assertEqual(result.returncode, 0, result.stderr)
        for name in names:
            for extension in ("png", "svg"):
                target = os.path.join(self.out, f"{name}.{extension}")
                self.assertTrue(os.path.getsize(target) > 1000, target)

    def svg(self, name):
        with open(os.path.join(self.out, f"{name}.svg")) as stream:
            return stream.read()

    def test_work_precision_from_csv(self):
        write_csv(self.path("wp.csv"), work_precision_rows())
        result = run_plot("work-precision", self.path("wp.csv"), "--out", self.out,
                          "--machine", "test machine", "--cloth", "test cloth")
        self.assert_written(result, ["work-precision-sheet"])
        svg = self.svg("work-precision-sheet")
        self.assertIn("rk4 float64 (order 4.00)", svg)
        self.assertIn("euler float64", svg)
        self.assertNotIn("euler float64 (order", svg)  # r^2 0.5: not asymptotic
        self.assertIn("rk4 float32", svg)
        self.assertNotIn("rk4 float32 (order", svg)  # a fit over 3 points only
        for fact in ("mesh 20x20", "cloth: test cloth", "precision float32, float64",
                     "machine: test machine"):
            self.assertIn(fact, svg)
        self.assertEqual(svg.count("reference error (est.)"), 1)
        self.assertGreaterEqual(svg.count(">rk4 float64 (order 4.00)<"), 2)  # both panels

    def test_stability_map_with_matrix_cells(self):
        search = [{"key": f"s{i}{j}", "kind": "stability", "integrator": integrator,
                   "scenario": "flag", "mesh": f"{n}x{n}", "dt_max": 0.05 / n,
                   "predicted_dt_max": 0.06 / n}
                  for i, integrator in enumerate(("euler", "verlet"))
                  for j, n in enumerate((50, 100, 200))]
        matrix = [{"key": f"m{n}{dt}{integrator}", "integrator": integrator, "scenario": "flag",
                   "mesh": f"{n}x{n}", "dt": dt, "stable": dt < 0.05 / n}
                  for integrator in ("euler", "verlet") for n in (50, 100) for dt in (1e-4, 1e-3)]
        with open(self.path("st.json"), "w") as stream:
            json.dump({"sweep": {}, "rows": search}, stream)
        with open(self.path("matrix.json"), "w") as stream:
            json.dump({"sweep": {}, "rows": matrix}, stream)
        result = run_plot("stability", self.path("st.json"), "--matrix", self.path("matrix.json"),
                          "--out", self.out, "--cloth", "soft cloth", "--matrix-cloth",
                          "seed cloth", "--machine", "test machine")
        self.assert_written(result, ["stability-map"])
        svg = self.svg("stability-map")
        # Lines and markers of different cloths never share a panel: 2 integrators x 2 kinds.
        self.assertEqual(svg.count("/ flag: soft cloth"), 2)
        self.assertEqual(svg.count("/ flag: seed cloth"), 2)
        self.assertEqual(svg.count(">60 Hz frame (16.7 ms)<"), 4)  # in every panel's legend
        self.assertEqual(svg.count(">30 Hz frame (33.3 ms)<"), 4)
        self.assertIn("machine: test machine", svg)
        self.assertIn("mesh 50x50, 100x100, 200x200;", svg)  # by size, not as text

    def test_cost_vs_mesh(self):
        rows = [{"key": f"{integrator}{n}", "integrator": integrator, "scenario": "sheet",
                 "mesh": f"{n}x{n}", "dt": 0.001, "ms_per_step": 1e-4 * n * n * cost}
                for integrator, cost in (("euler", 1), ("rk4", 4)) for n in (50, 100, 150)]
        write_csv(self.path("runs.csv"), rows)
        result = run_plot("cost", self.path("runs.csv"), "--out", self.out)
        self.assert_written(result, ["cost-sheet"])

    def test_cost_of_a_sweep_that_does_not_vary_the_scenario(self):
        # Its rows have no scenario column (configs/multigrid-scaling.yaml): one figure, no "None".
        rows = [{"key": f"{n}", "integrator": "implicit_euler", "mesh": f"{n}x{n}",
                 "ms_per_step": 1e-3 * n * n} for n in (50, 100, 200)]
        with open(self.path("runs.json"), "w") as stream:
            json.dump({"sweep": {}, "rows": rows}, stream)
        self.assert_written(run_plot("cost", self.path("runs.json"), "--out", self.out), ["cost"])
        self.assertNotIn("None", self.svg("cost"))

    def test_cost_picks_a_step_among_json_string_dts(self):
        # A run-mode sweep's JSON stores its matrix coordinates as strings.
        rows = [{"key": f"{n}{dt}", "integrator": "euler", "scenario": "sheet",
                 "mesh": f"{n}x{n}", "dt": dt, "ms_per_step": 1e-4 * n * n}
                for n in (50, 100) for dt in ("0.001", "0.002")]
        with open(self.path("runs.json"), "w") as stream:
            json.dump({"sweep": {}, "rows": rows}, stream)
        self.assert_written(run_plot("cost", self.path("runs.json"), "--out", self.out),
                            ["cost-sheet"])
        result = run_plot("cost", self.path("runs.json"), "--dt", "0.005", "--out", self.out)
        self.assertEqual(result.returncode, 1)
        self.assertIn("steps present: 0.001, 0.002", result.stderr)

    def write_ranked(self, side, ranking, mesh=True):
        path = self.path(f"choose-{side}-ranked.json")
        settings = {"frame_rate": 60.0, "error_tolerance": 0.01}
        if mesh:
            settings["mesh"] = f"{side}x{side}"
        with open(path, "w") as stream:
            json.dump({"scene": None, "settings": settings, "ranking": ranking}, stream)
        return path

    def test_scaling_across_meshes(self):
        # verlet grows as n^1.5, xpbd as n; vbd passes only at the smallest mesh.
        paths = []
        for side in (50, 100, 300):
            n = side * side
            ranking = [{"integrator": "verlet", "rank": 1, "substeps": side * 4,
                        "ms_per_frame": 1e-3 * n ** 1.5, "error": 0.004,
                        "max_stretch_away_from_pins": 1.05},
                       {"integrator": "xpbd", "rank": 2, "substeps": 64, "iterations": 2,
                        "ms_per_frame": 0.5 * n, "error": 0.008,
                        "max_stretch_away_from_pins": 1.08}]
            ranking.append({"integrator": "vbd", "rank": 3, "substeps": 8, "ms_per_frame": 9.0,
                            "error": 0.002} if side == 50 else
                           {"integrator": "vbd", "rank": None, "ms_per_frame": None,
                            "verdict": "no setting passed up to 4096 substeps"})
            # Stopped by the cost budget: the bound its verdict proves, first-frames form at
            # 100x100, the bracket's at 300x300.
            ranking.append({"integrator": "rk4", "rank": None, "ms_per_frame": None,
                            "verdict": "slower than verlet at 192 substeps (71.47 ms/frame): "
                            + ("its fastest of 5 first frames took 92.44 ms (twice), over 1 x "
                               "(stop_factor / 2); stopped at 1 substep" if side == 100 else
                               "its fastest of 5 first frames took 332.1 ms (twice), so 65 to "
                               "128 substeps cost at least 168.7 ms/frame, over 1 x")})
            paths.append(self.write_ranked(side, ranking))
        table = self.path("scaling.md")
        result = run_plot("scaling", *reversed(paths), "--out", self.out, "--table", table,
                          "--machine", "test machine", "--cloth", "cotton")
        self.assert_written(result, ["scaling"])
        svg = self.svg("scaling")
        self.assertIn("verlet (slope 1.50)", svg)
        self.assertIn("xpbd (slope 1.00)", svg)
        self.assertIn(">vbd<", svg)  # one point: no slope
        self.assertIn("rk4: at least (stopped)", svg)
        for fact in ("n^1 guide", "n^1.5 guide", "meshes 50x50, 100x100, 300x300",
                     "cloth: cotton", "machine: test machine"):
            self.assertIn(fact, svg)
        with open(table) as stream:
            lines = stream.read().splitlines()
        self.assertEqual(lines[0], "| method | 50x50 | 100x100 | 300x300 | "
                                   "growth 100x100 to 300x300 (particles x9) |")
        verlet = next(line for line in lines if line.startswith("| verlet "))
        self.assertIn("x27 (3.00 x the particle ratio)", verlet)
        self.assertIn("**2.7e+04** ms; 1200 substeps; stretch 5.00 %; error 0.40 %", verlet)
        xpbd = next(line for line in lines if line.startswith("| xpbd "))
        self.assertIn("64 substeps x 2 iterations", xpbd)
        self.assertIn("x9 (1.00 x the particle ratio)", xpbd)
        vbd = next(line for line in lines if line.startswith("| vbd "))
        self.assertIn("no pass: no setting passed up to 4096 substeps", vbd)
        self.assertTrue(vbd.endswith("| - |"), vbd)
        rk4 = next(line for line in lines if line.startswith("| rk4 "))
        self.assertEqual(rk4, "| rk4 | >= 168.7 ms (stopped by the cost budget) | >= 92.44 ms "
                              "(stopped by the cost budget) | >= 168.7 ms (stopped by the cost "
                              "budget) | - |")

    def test_scaling_refuses_files_it_cannot_place(self):
        row = [{"integrator": "euler", "rank": 1, "substeps": 4, "ms_per_frame": 2.0,
                "error": 0.001}]
        no_mesh = self.write_ranked(20, row, mesh=False)
        result = run_plot("scaling", no_mesh, "--out", self.out)
        self.assertEqual(result.returncode, 1)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
        self.assertIn("settings.mesh missing", result.stderr)
        twice = self.write_ranked(30, row)
        result = run_plot("scaling", twice, twice, "--growth-from", "30x30", "--out", self.out)
        self.assertEqual(result.returncode, 1)
        self.assertIn("two files of the same mesh (30x30, 30x30)", result.stderr)
        result = run_plot("scaling", twice, "--out", self.out)  # default --growth-from 100x100
        self.assertEqual(result.returncode, 1)
        self.assertIn("--growth-from 100x100: not among the meshes 30x30", result.stderr)

    def test_front_of_cost_error_and_stretch(self):
        def probe(integrator, substeps, iterations, ms, error, stretch, passed=False):
            return {"key": f"{integrator}{substeps}x{iterations}", "kind": "probe",
                    "integrator": integrator, "substeps": substeps, "iterations": iterations,
                    "ms_per_frame": ms, "error": error, "max_stretch_away_from_pins": stretch,
                    "error_mesh": "100x100", "passed": passed, "why": "" if passed else "too soft"}
        rows = [probe("verlet", 2048, 0, 1000.0, 0.002, 1.05, passed=True),
                probe("xpbd", 64, 1, 100.0, 0.03, 1.40),       # cheapest: on the front
                probe("xpbd", 128, 1, 200.0, 0.02, 1.30),      # better error and stretch: on it
                probe("xpbd", 256, 1, 400.0, 0.02, 1.30),      # dominated by 128 (cost)
                probe("vbd", 8, 4, 1500.0, 0.002, 1.05),       # dominated by verlet (cost)
                probe("euler", 64, 0, None, 0.5, None)]        # never ran at the scene's mesh
        with open(self.path("choose.json"), "w") as stream:
            json.dump({"sweep": {"frame_rate": 60, "error_tolerance": 0.01}, "rows": rows}, stream)
        table = self.path("front.md")
        result = run_plot("front", self.path("choose.json"), "--out", self.out, "--table", table)
        self.assert_written(result, ["choose-front"])
        svg = self.svg("choose-front")
        self.assertIn("xpbd (dominated)", svg)
        self.assertIn("vbd (dominated)", svg)
        self.assertNotIn("euler", svg)
        with open(table) as stream:
            lines = stream.read().splitlines()[2:]
        self.assertEqual([line.split(" | ")[0:2] for line in lines],
                         [["| xpbd", "64 substeps x 1 iterations"],
                          ["| xpbd", "128 substeps x 1 iterations"], ["| verlet", "2048 substeps"]])
        self.assertIn("| 1000 | 0.0167 | 0.20 % | 5.00 % | yes |", lines[2])
        self.assertTrue(lines[0].endswith("| too soft |"), lines[0])
        result = run_plot("front", self.path("missing.json"), "--out", self.out)
        self.assertEqual(result.returncode, 1)
        self.assertIn("missing.json", result.stderr)

    def test_bad_input_is_one_line_and_exit_code_1(self):
        with open(self.path("broken.json"), "w") as stream:
            stream.write("{\"rows\": [")
        result = run_plot("work-precision", self.path("broken.json"), "--out", self.out)
        self.assertEqual(result.returncode, 1)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
        self.assertIn("broken.json", result.stderr)
        result = run_plot("cost", self.path("missing.csv"), "--out", self.out)
        self.assertEqual(result.returncode, 1)
        self.assertIn("missing.csv", result.stderr)


if __name__ == "__main__":
    unittest.main()
