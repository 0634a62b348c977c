#!/usr/bin/python3
"""Plots ClothLab sweep results (the .json or .csv a sweep writes) as PNG and SVG.

  plot.py work-precision results/work-precision.json --out plots/
      per scenario: error at T against wall time per simulated second, and against dt,
      log-log, one line per integrator (solid float64, dashed float32), the fitted order in
      the legend where the fit is in the asymptotic range (r^2 >= 0.99 over >= 4 points).
  plot.py stability results/stability.json [--matrix results/seed-2016-matrix.json] --out plots/
      per scenario and integrator: largest stable dt against mesh size, measured (bisection)
      and predicted (linearised system); with --matrix, each run of a run-mode sweep as a
      stable (o) or unstable (x) cell, in a panel of its own (its cloth differs); the
      60 Hz and 30 Hz frame steps (16.7 ms, 33.3 ms) as horizontal lines.
  plot.py cost results/seed-2016-matrix.json [--metric ms_per_step] [--dt 0.001] --out plots/
      per scenario: the metric against particle count, one line per integrator.
  plot.py choose results/choose-cotton-flag-200.json --out plots/
      clothlab --choose probes: cost per frame against position error, one colour per
      integrator (filled: the probe passed every criterion; hollow: it failed one), with the
      tolerance as a line.
  plot.py scaling results/choose-cotton-flag-{50,100,200,300}-ranked.json --out docs/img
      clothlab --choose's ranked files of one scene at several meshes: ms per frame of each
      integrator's cheapest passing setting against particle count, log-log, with n^1 and
      n^1.5 guides; --table PATH also writes the Markdown table (setting, ms/frame, robust
      stretch, error per method and mesh, and each method's growth from --growth-from to the
      largest mesh against the particle ratio).
  plot.py front results/choose-cotton-flag-300.json --out docs/img [--table front.md]
      clothlab --choose probes of one scene that ran at its mesh (cost, error and robust
      stretch all measured): real-time factor against error, one colour per integrator,
      filled where no other probe is at least as good in all three (the front), each front
      point labelled with its stretch; --table PATH writes the front as Markdown.
  plot.py energy energy-verlet.csv energy-xpbd.csv ... --out plots/
      total energy over time from clothlab --energy-out files, one line per file (named by
      the run's integrator): numerical damping made visible.

Every plot names the mesh, the cloth, the precision and the machine under its title
(--cloth, --matrix-cloth, --machine; the machine defaults to this one's CPU).
Needs Debian's python3-matplotlib (Agg backend, no display).
"""
import argparse
import csv
import json
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the backend)

plt.rcParams["svg.fonttype"] = "none"  # text stays text in SVG: searchable, and testable
plt.rcParams["legend.fontsize"] = 8
plt.rcParams["legend.framealpha"] = 0.85
# Frame steps a reader compares dt_max with: 60 and 30 frames per second.
FRAME_STEPS = ((1 / 60, "60 Hz frame (16.7 ms)"), (1 / 30, "30 Hz frame (33.3 ms)"))
ASYMPTOTIC_R_SQUARED = 0.99
# Three points cannot tell a power law from a curve bending onto its round-off floor.
ASYMPTOTIC_POINTS = 4

FORMATS = ("png", "svg")
COLOURS = {"euler": "tab:blue", "midpoint": "tab:orange", "rk4": "tab:green",
           "verlet": "tab:red", "forward-euler": "tab:purple", "implicit_euler": "tab:brown",
           "projective_dynamics": "tab:pink", "xpbd": "tab:olive", "xpbd_tethers": "tab:cyan",
           "vbd": "tab:gray", "bdf2": "black"}


class InputProblem(Exception):
    """Bad input: reported as one line, exit code 1."""


def parse_cell(text):
    if text == "":
        return None
    if text in ("true", "false"):
        return text == "true"
    try:
        return float(text)
    except ValueError:
        return text


def read_rows(path):
    """Rows of a results file, as dicts; numbers as floats, missing values as None."""
    try:
        with open(path, newline="") as stream:
            if path.endswith(".csv"):
                return [{k: parse_cell(v) for k, v in row.items()} for row in csv.DictReader(stream)]
            document = json.load(stream)
    except OSError as error:
        raise InputProblem(f"{path}: cannot read results: {error.strerror}")
    except (json.JSONDecodeError, csv.Error) as error:
        raise InputProblem(f"{path}: not a results file: {error}")
    if not isinstance(document, dict) or not isinstance(document.get("rows"), list):
        raise InputProblem(f"{path}: expected a JSON object with a \"rows\" list")
    return document["rows"]


def mesh_particles(mesh):
    """'50x40' -> 2000, '50' or 50.0 -> 2500."""
    text = str(mesh)
    if text.endswith(".0"):
        text = text[:-2]
    rows, _, cols = text.partition("x")
    try:
        return int(rows) * int(cols or rows)
    except ValueError:
        raise InputProblem(f"mesh value '{mesh}': expected ROWSxCOLS or N")


def number(value):
    return value if isinstance(value, (int, float)) and not isinstance(value, bool) \
        and math.isfinite(value) else None


def this_machine():
    """The CPU model and count from /proc/cpuinfo, as 'MODEL, N cores'."""
    try:
        with open("/proc/cpuinfo") as stream:
            models = [line.split(":", 1)[1].strip() for line in stream
                      if line.startswith("model name")]
    except OSError:
        models = []
    return f"{models[0]}, {len(models)} cores" if models else "unknown machine"


def values_of(rows, key):
    values = {str(r.get(key)) for r in rows if r.get(key) not in (None, "")}
    # Meshes by size (50x50, 100x100, 200x200), not as text (100x100 first).
    order = (lambda mesh: (mesh_particles(mesh), mesh)) if key == "mesh" else None
    return ", ".join(sorted(values, key=order))


def caption(rows, cloth, machine):
    """What a reader needs to judge a plot: mesh, cloth, precision, machine."""
    return (f"mesh {values_of(rows, 'mesh') or 'not recorded'}; cloth: {cloth}; "
            f"precision {values_of(rows, 'precision') or 'float32 (default)'}; machine: {machine}")


def asymptotic_order(fit):
    """The fitted order, or None when the fit is not in the asymptotic range."""
    order = number(fit.get("order"))
    r_squared = number(fit.get("r_squared"))
    if order is None or fit.get("fit_valid") is False:
        return None
    if r_squared is not None and r_squared < ASYMPTOTIC_R_SQUARED:
        return None
    points = number(fit.get("fit_points"))
    if points is not None and points < ASYMPTOTIC_POINTS:
        return None
    return order


def coordinate(value):
    """A matrix coordinate such as dt as a number: JSON results store them as strings."""
    if isinstance(value, str):
        try:
            value = float(value)
        except ValueError:
            return None
    return number(value)


def save(figure, out, name):
    os.makedirs(out, exist_ok=True)
    paths = []
    for extension in FORMATS:
        path = os.path.join(out, f"{name}.{extension}")
        figure.savefig(path, bbox_inches="tight", dpi=120)
        paths.append(path)
    plt.close(figure)
    return paths


def require(rows, kind, path):
    chosen = [r for r in rows if r.get("kind") == kind]
    if not chosen:
        raise InputProblem(f"{path}: no rows of kind '{kind}'")
    return chosen


def plot_work_precision(args):
    rows = read_rows(args.results)
    ladder = require(rows, "ladder", args.results)
    fits = {(r.get("scenario"), r.get("integrator"), r.get("precision"), r.get("mesh")): r
            for r in rows if r.get("kind") == "fit"}
    # The shared reference of each scenario (self references carry an integrator).
    references = {r.get("scenario"): r for r in rows
                  if r.get("kind") == "reference" and not r.get("integrator")}
    written = []
    for scenario in sorted({str(r.get("scenario")) for r in ladder}):
        figure, (by_cost, by_dt) = plt.subplots(1, 2, figsize=(12, 5))
        curves = {}
        for r in ladder:
            if str(r.get("scenario")) != scenario or number(r.get("error")) is None:
                continue
            key = (r.get("integrator"), r.get("precision"), r.get("mesh"))
            curves.setdefault(key, []).append(r)
        for (integrator, precision, mesh), points in sorted(curves.items(), key=str):
            points.sort(key=lambda r: r["dt"])
            fit = fits.get((scenario, integrator, precision, mesh), {})
            order = asymptotic_order(fit)
            label = f"{integrator} {precision or ''}".strip()
            if order is not None:
                label += f" (order {order:.2f})"
            style = dict(color=COLOURS.get(integrator), marker="o", markersize=4,
                         linestyle="--" if precision == "float32" else "-")
            by_cost.loglog([r["wall_per_sim_s"] for r in points], [r["error"] for r in points],
                           label=label, **style)
            by_dt.loglog([r["dt"] for r in points], [r["error"] for r in points], label=label,
                         **style)
        reference = references.get(scenario, {})
        t_end = number(reference.get("T")) or number(ladder[0].get("T"))
        estimate = number(reference.get("reference_error_estimate"))
        title = f"{scenario}: error at T = {t_end:g} s" if t_end else scenario
        if estimate is not None:
            by_dt.axhline(estimate, color="grey", linestyle=":", label="reference error (est.)")
            title += f" (reference error ~{estimate:.1e})"
        by_cost.set_xlabel("wall time per simulated second (s)")
        by_dt.set_xlabel("dt (s)")
        for axis in (by_cost, by_dt):
            axis.set_ylabel("RMS position error / diagonal")
            axis.grid(True, which="both", alpha=0.3)
            # Below the axes: with a dozen curves a legend inside hides some of them.
            axis.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2)
        mine = [r for r in ladder if str(r.get("scenario")) == scenario]
        figure.suptitle(title + "\n" + caption(mine, args.cloth, args.machine), fontsize=10)
        written += save(figure, args.out, f"work-precision-{scenario}")
    return written


def plot_stability(args):
    rows = read_rows(args.results)
    search = require(rows, "stability", args.results)
    matrix = read_rows(args.matrix) if args.matrix else []
    matrix = [r for r in matrix
              if coordinate(r.get("dt")) is not None and r.get("mesh") is not None]
    scenarios = sorted({str(r.get("scenario")) for r in search})
    integrators = sorted({str(r.get("integrator")) for r in search})
    # The matrix ran another cloth: its cells get panels of their own, never the lines' axes.
    kinds = ["search"] + (["matrix"] if matrix else [])
    panel_rows = [(scenario, kind) for scenario in scenarios for kind in kinds]
    figure, axes = plt.subplots(len(panel_rows), len(integrators), squeeze=False,
                                figsize=(4 * len(integrators), 3.8 * len(panel_rows)),
                                sharey=True)
    for i, (scenario, kind) in enumerate(panel_rows):
        for j, integrator in enumerate(integrators):
            axis = axes[i][j]
            if kind == "search":
                mine = sorted((r for r in search if str(r.get("scenario")) == scenario
                               and str(r.get("integrator")) == integrator),
                              key=lambda r: mesh_particles(r.get("mesh")))
                sizes = [math.sqrt(mesh_particles(r.get("mesh"))) for r in mine]
                measured = [number(r.get("dt_max")) for r in mine]
                predicted = [number(r.get("predicted_dt_max")) for r in mine]
                axis.semilogy(sizes, [m if m else float("nan") for m in measured], "k-o",
                              label="measured dt_max")
                if any(p for p in predicted):
                    axis.semilogy(sizes, [p if p else float("nan") for p in predicted], "b--",
                                  label="predicted dt_max")
                axis.set_title(f"{integrator} / {scenario}: {args.cloth}", fontsize=9)
            else:
                cells = [r for r in matrix if str(r.get("scenario")) == scenario
                         and str(r.get("integrator")) == integrator]
                for stable, marker, colour in ((True, "o", "tab:green"), (False, "x", "tab:red")):
                    chosen = [r for r in cells if bool(r.get("stable")) == stable]
                    if chosen:
                        axis.scatter([math.sqrt(mesh_particles(r["mesh"])) for r in chosen],
                                     [coordinate(r["dt"]) for r in chosen], marker=marker,
                                     color=colour,
                                     label="run: stable" if stable else "run: unstable")
                axis.set_yscale("log")
                axis.set_title(f"{integrator} / {scenario}: {args.matrix_cloth}", fontsize=9)
            for step, label in FRAME_STEPS:
                axis.axhline(step, color="grey", linestyle=":" if step < 0.02 else "-.",
                             linewidth=1, label=label)
            axis.set_xlabel("mesh side N (N x N)")
            axis.grid(True, which="both", alpha=0.3)
            axis.legend(loc="lower left")
            if j == 0:
                axis.set_ylabel("dt (s)")
    figure.suptitle("Largest stable dt against mesh size\n"
                    + caption(search + matrix, args.cloth + (f" / {args.matrix_cloth}"
                                                              if matrix else ""), args.machine),
                    fontsize=10)
    # Else each row's x label runs into the titles below it; the top half inch stays for the
    # two-line title, which tight_layout does not place.
    figure.tight_layout(rect=(0, 0, 1, 1 - 0.5 / figure.get_figheight()))
    return save(figure, args.out, "stability-map")


def plot_cost(args):
    rows = read_rows(args.results)
    runs = [r for r in rows if number(r.get(args.metric)) is not None and r.get("mesh") is not None]
    if not runs:
        raise InputProblem(f"{args.results}: no rows with a numeric '{args.metric}' and a mesh")
    dts = sorted({coordinate(r.get("dt")) for r in runs} - {None})
    chosen_dt = args.dt if args.dt is not None else (dts[0] if dts else None)
    if chosen_dt is not None and dts:
        runs = [r for r in runs if coordinate(r.get("dt")) is not None
                and math.isclose(coordinate(r["dt"]), chosen_dt, rel_tol=1e-9)]
        if not runs:
            raise InputProblem(f"--dt {chosen_dt:g}: no rows at that step; steps present: "
                               + ", ".join(f"{d:g}" for d in dts))
    # A sweep that does not vary the scenario has no scenario column: one figure, "cost".
    def scene(row):
        return str(row.get("scenario") or "")

    written = []
    for scenario in sorted({scene(r) for r in runs}):
        figure, axis = plt.subplots(figsize=(6, 4.5))
        for integrator in sorted({str(r.get("integrator")) for r in runs}):
            points = sorted(((mesh_particles(r["mesh"]), r[args.metric]) for r in runs
                             if scene(r) == scenario and str(r.get("integrator")) == integrator))
            if points:
                axis.loglog(*zip(*points), "o-", color=COLOURS.get(integrator), label=integrator)
        axis.set_xlabel("particles")
        axis.set_ylabel(args.metric)
        title = f"{scenario + ': ' if scenario else ''}{args.metric} vs mesh size"
        title += f" (dt = {chosen_dt:g} s)" if chosen_dt is not None else ""
        mine = [r for r in runs if scene(r) == scenario]
        axis.set_title(title + "\n" + caption(mine, args.cloth, args.machine), fontsize=8)
        axis.grid(True, which="both", alpha=0.3)
        axis.legend(loc="best")
        written += save(figure, args.out, f"cost-{scenario}" if scenario else "cost")
    return written


def plot_choose(args):
    rows = read_rows(args.results)
    probes = [r for r in rows if r.get("kind") == "probe" and number(r.get("error")) is not None
              and number(r.get("ms_per_frame")) is not None]
    if not probes:
        raise InputProblem(f"{args.results}: no choose probes with an error and a cost")
    tolerance = None
    with open(args.results) as stream:
        document = json.load(stream) if args.results.endswith(".json") else {}
    tolerance = number(document.get("sweep", {}).get("error_tolerance"))
    figure, axis = plt.subplots(figsize=(6.5, 4.5))
    for integrator in sorted({str(r.get("integrator")) for r in probes}):
        mine = [r for r in probes if str(r.get("integrator")) == integrator]
        colour = COLOURS.get(integrator)
        for passed, marker in ((True, "o"), (False, "o")):
            chosen = [r for r in mine if bool(r.get("passed")) == passed]
            if chosen:
                axis.loglog([r["error"] for r in chosen], [r["ms_per_frame"] for r in chosen],
                            marker, color=colour, markerfacecolor=colour if passed else "none",
                            linestyle="none", label=integrator if passed or len(chosen) == len(mine)
                            else None)
    if tolerance is not None:
        axis.axvline(tolerance, color="grey", linestyle="--", label=f"tolerance {tolerance:g}")
    axis.set_xlabel("RMS position error / cloth diagonal")
    axis.set_ylabel("ms per frame")
    # The probes carry no mesh coordinate (the scene's mesh is the --cloth text); the error
    # mesh is theirs.
    axis.set_title("choose: cost per frame vs error (filled: passed)\n"
                   + caption(probes, args.cloth, args.machine)
                   + f"; error measured at {values_of(probes, 'error_mesh')}", fontsize=8)
    axis.grid(True, which="both", alpha=0.3)
    axis.legend(fontsize=8)
    return save(figure, args.out, "choose-cost-error")


def read_ranked(path):
    """A clothlab --choose ranked file: (scene mesh, its settings, its ranking rows)."""
    try:
        with open(path) as stream:
            document = json.load(stream)
    except OSError as error:
        raise InputProblem(f"{path}: cannot read results: {error.strerror}")
    except json.JSONDecodeError as error:
        raise InputProblem(f"{path}: not a results file: {error}")
    if not isinstance(document, dict) or not isinstance(document.get("ranking"), list):
        raise InputProblem(f"{path}: expected clothlab --choose's -ranked.json (a \"ranking\" list)")
    settings = document.get("settings") or {}
    mesh = settings.get("mesh")
    if not mesh:
        raise InputProblem(f"{path}: settings.mesh missing: rerun --choose with scenario.rows and "
                           "scenario.cols (or mesh) set")
    return str(mesh), settings, document["ranking"]


def setting_text(row):
    iterations = number(row.get("iterations"))
    text = f"{int(row['substeps'])} substeps"
    return text + (f" x {int(iterations)} iterations" if iterations else "")


def cost_bound(verdict):
    """The least ms/frame a search stopped by --choose's cost budget proves for its
    integrator's passing settings, from the verdict ("so 65 to 128 substeps cost at least X
    ms/frame", or where the stopped setting is the first candidate, "its fastest of 5 first
    frames took X ms"); None for any other verdict."""
    if not verdict.startswith("slower than"):
        return None
    found = re.search(r"cost at least ([0-9.e+]+) ms/frame", verdict) or \
        re.search(r"first frames took ([0-9.e+]+) ms", verdict)
    return float(found.group(1)) if found else None


def growth_table(meshes, growth_from):
    """Markdown: per integrator and mesh the cheapest passing setting and its figures, then
    the growth of ms/frame from growth_from to the largest mesh against the particle ratio."""
    largest = meshes[-1][0]
    ratio = mesh_particles(largest) / mesh_particles(growth_from)
    integrators = []
    for _, _, ranking in meshes:
        integrators += [str(r.get("integrator")) for r in ranking
                        if str(r.get("integrator")) not in integrators]
    header = ["method"] + [mesh for mesh, _, _ in meshes] + [
        f"growth {growth_from} to {largest} (particles x{ratio:g})"]
    lines = ["| " + " | ".join(header) + " |", "|" + " --- |" * len(header)]
    for integrator in integrators:
        cells, cost = [], {}
        for mesh, _, ranking in meshes:
            row = next((r for r in ranking if str(r.get("integrator")) == integrator), None)
            if row is None:
                cells.append("not searched")
            elif number(row.get("ms_per_frame")) is None or row.get("rank") is None:
                bound = cost_bound(str(row.get("verdict", "")))
                cells.append(f">= {bound:.4g} ms (stopped by the cost budget)" if bound else
                             "no pass: " + str(row.get("verdict", "")).split(";")[0][:90])
            else:
                cost[mesh] = row["ms_per_frame"]
                stretch = number(row.get("max_stretch_away_from_pins"))
                cells.append(f"**{row['ms_per_frame']:.4g}** ms; {setting_text(row)}; "
                             + (f"stretch {100 * (stretch - 1):.2f} %; " if stretch else "")
                             + f"error {100 * row['error']:.2f} %")
        if growth_from in cost and largest in cost:
            growth = cost[largest] / cost[growth_from]
            cells.append(f"x{growth:.3g} ({growth / ratio:.2f} x the particle ratio)")
        else:
            cells.append("-")
        lines.append("| " + " | ".join([integrator] + cells) + " |")
    return "\n".join(lines) + "\n"


def plot_scaling(args):
    meshes = sorted((read_ranked(path) for path in args.results),
                    key=lambda entry: mesh_particles(entry[0]))
    names = [mesh for mesh, _, _ in meshes]
    if len(set(names)) != len(names):
        raise InputProblem("scaling: two files of the same mesh (" + ", ".join(names) + ")")
    if args.growth_from not in names:
        raise InputProblem(f"--growth-from {args.growth_from}: not among the meshes "
                           + ", ".join(names))
    figure, axis = plt.subplots(figsize=(6.5, 4.8))
    integrators = sorted({str(r.get("integrator")) for _, _, ranking in meshes for r in ranking})
    anchors = []
    for integrator in integrators:
        points = [(mesh_particles(mesh), r["ms_per_frame"]) for mesh, _, ranking in meshes
                  for r in ranking if str(r.get("integrator")) == integrator
                  and r.get("rank") is not None and number(r.get("ms_per_frame")) is not None]
        # A search stopped by the cost budget: the least cost its verdict proves, hollow.
        bounds = [(mesh_particles(mesh), cost_bound(str(r.get("verdict", ""))))
                  for mesh, _, ranking in meshes for r in ranking
                  if str(r.get("integrator")) == integrator and r.get("rank") is None]
        bounds = [(n, bound) for n, bound in bounds if bound]
        if bounds:
            axis.loglog(*zip(*bounds), "^", color=COLOURS.get(integrator), markerfacecolor="none",
                        linestyle="none", label=f"{integrator}: at least (stopped)")
        if not points:
            continue
        anchors.append(points[0])
        label = integrator
        if len(points) >= 2:
            (n0, c0), (n1, c1) = points[0], points[-1]
            label += f" (slope {math.log(c1 / c0) / math.log(n1 / n0):.2f})"
        axis.loglog(*zip(*points), "o-", color=COLOURS.get(integrator), label=label)
    if not anchors:
        raise InputProblem("scaling: no integrator passed at any mesh")
    # The guides start at the cheapest method's first point, so that a line parallel to one
    # reads as that growth.
    n0, c0 = min(anchors, key=lambda point: (point[0], point[1]))
    n1 = mesh_particles(names[-1])
    for power, style in ((1.0, ":"), (1.5, "--")):
        axis.loglog([n0, n1], [c0, c0 * (n1 / n0) ** power], style, color="black", linewidth=1,
                    label=f"n^{power:g} guide")
    axis.axhline(1000 / float(meshes[0][1].get("frame_rate") or 60), color="grey",
                 linestyle="-.", linewidth=1, label="real time (one frame)")
    axis.set_xlabel("particles n")
    axis.set_ylabel("ms per frame at the cheapest passing setting")
    axis.set_title("choose: cost per frame against mesh size\n"
                   f"meshes {', '.join(names)}; cloth: {args.cloth}; machine: {args.machine}",
                   fontsize=8)
    axis.grid(True, which="both", alpha=0.3)
    axis.legend(fontsize=7, loc="upper left")
    written = save(figure, args.out, "scaling")
    if args.table:
        with open(args.table, "w") as stream:
            stream.write(growth_table(meshes, args.growth_from))
        written.append(args.table)
    return written


def dominates(a, b):
    """a is at least as good as b in cost, error and robust stretch, and better in one."""
    keys = ("ms_per_frame", "error", "max_stretch_away_from_pins")
    return all(a[k] <= b[k] for k in keys) and any(a[k] < b[k] for k in keys)


def plot_front(args):
    rows = read_rows(args.results)
    probes = [r for r in rows if r.get("kind") == "probe" and number(r.get("ms_per_frame"))
              and number(r.get("error")) is not None
              and number(r.get("max_stretch_away_from_pins")) is not None]
    if not probes:
        raise InputProblem(f"{args.results}: no choose probes with a cost, an error and a "
                           "robust stretch (none ran at the scene's mesh)")
    with open(args.results) as stream:
        document = json.load(stream) if args.results.endswith(".json") else {}
    sweep = document.get("sweep", {})
    frame_ms = 1000 / (number(sweep.get("frame_rate")) or 60)
    front = [p for p in probes if not any(dominates(q, p) for q in probes)]
    figure, axis = plt.subplots(figsize=(7, 5))
    for integrator in sorted({str(r.get("integrator")) for r in probes}):
        colour = COLOURS.get(integrator)
        for on_front in (True, False):
            chosen = [r for r in probes if str(r.get("integrator")) == integrator
                      and (r in front) == on_front]
            if chosen:
                axis.loglog([r["error"] for r in chosen],
                            [frame_ms / r["ms_per_frame"] for r in chosen], "o", color=colour,
                            markerfacecolor=colour if on_front else "none", linestyle="none",
                            label=integrator + ("" if on_front else " (dominated)"))
    for r in front:
        axis.annotate(f"{100 * (r['max_stretch_away_from_pins'] - 1):.1f} %",
                      (r["error"], frame_ms / r["ms_per_frame"]), fontsize=6,
                      xytext=(3, 3), textcoords="offset points")
    tolerance = number(sweep.get("error_tolerance"))
    if tolerance is not None:
        axis.axvline(tolerance, color="grey", linestyle="--", label=f"tolerance {tolerance:g}")
    axis.axhline(1, color="grey", linestyle="-.", label="real time (RTF 1)")
    axis.set_xlabel("RMS position error / cloth diagonal"
                    + (f" (at {values_of(probes, 'error_mesh')})" if values_of(probes, "error_mesh")
                       else ""))
    axis.set_ylabel("real-time factor")
    axis.set_title("choose: the front of real-time factor, error and robust stretch (filled; "
                   "labels: stretch away from the pins)\n"
                   f"cloth: {args.cloth}; machine: {args.machine}", fontsize=8)
    axis.grid(True, which="both", alpha=0.3)
    axis.legend(fontsize=6, loc="best")
    written = save(figure, args.out, "choose-front")
    if args.table:
        lines = ["| method | setting | ms/frame | RTF | error | stretch away from the pins "
                 "| passed (or why not) |", "|" + " --- |" * 7]
        for r in sorted(front, key=lambda r: r["ms_per_frame"]):
            lines.append(f"| {r.get('integrator')} | {setting_text(r)} | {r['ms_per_frame']:.4g} | "
                         f"{frame_ms / r['ms_per_frame']:.3g} | {100 * r['error']:.2f} % | "
                         f"{100 * (r['max_stretch_away_from_pins'] - 1):.2f} % | "
                         + ("yes" if r.get("passed") else str(r.get("why", ""))[:120]) + " |")
        with open(args.table, "w") as stream:
            stream.write("\n".join(lines) + "\n")
        written.append(args.table)
    return written


def read_energy(path):
    try:
        with open(path, newline="") as stream:
            rows = list(csv.DictReader(stream))
    except OSError as error:
        raise InputProblem(f"{path}: cannot read energy trace: {error.strerror}")
    if not rows or "t" not in rows[0] or "total" not in rows[0]:
        raise InputProblem(f"{path}: expected clothlab --energy-out CSV (t, ..., total)")
    return [float(r["t"]) for r in rows], [float(r["total"]) for r in rows], rows[0].get("integrator")


def plot_energy(args):
    figure, axis = plt.subplots(figsize=(6.5, 4.5))
    for path in args.traces:
        times, totals, integrator = read_energy(path)
        label = integrator or os.path.splitext(os.path.basename(path))[0]
        axis.plot(times, totals, color=COLOURS.get(label), label=label)
    axis.set_xlabel("t (s)")
    axis.set_ylabel("total energy (J): kinetic + springs + gravity")
    axis.set_title(f"energy over time per integrator\ncloth: {args.cloth}; machine: {args.machine}",
                   fontsize=8)
    axis.grid(True, alpha=0.3)
    axis.legend(fontsize=8)
    return save(figure, args.out, "energy")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    commands = parser.add_subparsers(dest="command", required=True)
    wp = commands.add_parser("work-precision", help="error vs cost and vs dt")
    wp.add_argument("results")
    wp.set_defaults(run=plot_work_precision)
    st = commands.add_parser("stability", help="measured and predicted dt_max vs mesh")
    st.add_argument("results")
    st.add_argument("--matrix", help="a run-mode sweep's results, drawn as stable/unstable cells")
    st.set_defaults(run=plot_stability)
    cost = commands.add_parser("cost", help="a cost metric vs mesh size")
    cost.add_argument("results")
    cost.add_argument("--metric", default="ms_per_step", help="column to plot (default ms_per_step)")
    cost.add_argument("--dt", type=float, help="time step to plot (default: the smallest)")
    cost.set_defaults(run=plot_cost)
    st.add_argument("--matrix-cloth", default="the matrix's cloth",
                    help="the cloth of the --matrix runs, for their panels' titles")
    choose = commands.add_parser("choose", help="clothlab --choose: cost per frame vs error")
    choose.add_argument("results")
    choose.set_defaults(run=plot_choose)
    scaling = commands.add_parser("scaling", help="clothlab --choose at several meshes: "
                                  "ms per frame vs particles")
    scaling.add_argument("results", nargs="+", help="the -ranked.json of each mesh")
    scaling.add_argument("--table", help="also write the Markdown table to this path")
    scaling.add_argument("--growth-from", default="100x100",
                         help="the mesh the growth column starts from (default 100x100)")
    scaling.set_defaults(run=plot_scaling)
    front = commands.add_parser("front", help="clothlab --choose probes: RTF vs error vs stretch")
    front.add_argument("results")
    front.add_argument("--table", help="also write the front as a Markdown table to this path")
    front.set_defaults(run=plot_front)
    energy = commands.add_parser("energy", help="energy over time per integrator")
    energy.add_argument("traces", nargs="+")
    energy.set_defaults(run=plot_energy)
    for command in (wp, st, cost, choose, scaling, front, energy):
        command.add_argument("--out", default="plots", help="output folder (default plots)")
        command.add_argument("--cloth", default="default cloth (plugins/README.md)",
                             help="the cloth (material) of the results, for the caption")
        command.add_argument("--machine", default=this_machine(),
                             help="the machine the results came from (default: this one)")
    args = parser.parse_args(argv)
    try:
        for path in args.run(args):
            print(path)
    except InputProblem as problem:
        print(f"plot.py: {problem}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
