#!/usr/bin/env python3
"""Turns the raw runs of tools/bench.sh into its tables (markdown: cotton, then the issue-4
soft-cloth kernel table), summary.json and runs.csv.  Usage: bench_table.py RESULTS_DIR MACHINE_NAME"""
import csv
import datetime
import json
import pathlib
import statistics
import sys

INTEGRATORS = ["euler", "verlet", "midpoint", "rk4"]
SCENARIOS = ["sheet", "flag"]
SIDES = [50, 100, 200, 300, 500, 1000]


def load(path):
    with open(path) as file:
        return json.load(file)


def table_rows(runs, prefix):
    """One row per scenario x integrator from the runs named PREFIX<scenario>-<integrator>-N."""
    rows, csv_rows = [], []
    for scenario in SCENARIOS:
        for integrator in INTEGRATORS:
            reps = [load(p) for p in sorted(runs.glob(f"{prefix}{scenario}-{integrator}-*.json"))]
            step_ms = [r["ms_per_step"]["median"] for r in reps]
            p10_ms = [r["ms_per_step"]["p10"] for r in reps]
            springs = [r["springs_per_second"] for r in reps]
            # Per-step medians resist the stalls of a shared, oversubscribed machine; the
            # host's springs_per_second divides by the total internal-force time instead.
            springs_median = [r["springs"] * r["force_evals"] / r["steps"]
                              / (r["phase_ms"]["internal_forces"] * 1e-3) for r in reps]
            dt = reps[0]["dt"]
            row = {
                "scenario": scenario,
                "integrator": integrator,
                "runs": len(reps),
                "steps_per_run": reps[0]["steps"],
                "threads": reps[0]["threads"],
                "dt": dt,
                "substeps": reps[0].get("substeps", 1),
                "ms_per_step_median": statistics.median(step_ms),
                "ms_per_step_p10": statistics.median(p10_ms),
                "real_time_factor": dt * 1e3 / statistics.median(step_ms),
                "springs_per_second_median": statistics.median(springs_median),
                "springs_per_second_total_time": statistics.median(springs),
                "all_finite": all(r["stable"] for r in reps),
            }
            rows.append(row)
            for index, r in enumerate(reps):
                csv_rows.append([prefix + scenario, integrator, index + 1, r["steps"],
                                 r["threads"], r["ms_per_step"]["median"],
                                 r["ms_per_step"]["p10"], r["phase_ms"]["internal_forces"],
                                 r["springs_per_second"], r["stable"]])
    return rows, csv_rows


def markdown_rows(rows, per_frame):
    lines = []
    for r in rows:
        frame = (f"{r['ms_per_step_median'] * r['substeps']:.1f} | " if per_frame else "")
        lines.append(f"| {r['scenario']} | {r['integrator']} | {r['ms_per_step_median']:.3f} | "
                     f"{r['ms_per_step_p10']:.3f} | {frame}{r['real_time_factor']:.3g} | "
                     f"{r['springs_per_second_median']:.3g} | "
                     f"{r['springs_per_second_total_time']:.3g} | {r['all_finite']} |")
    return lines


def main(results_dir, machine):
    results = pathlib.Path(results_dir)
    runs = results / "runs"
    cotton, cotton_csv = table_rows(runs, "cotton-")
    rows, csv_rows = table_rows(runs, "")
    csv_rows = cotton_csv + csv_rows
    speedup = load(results / "speedup.json")
    scaling = []
    for side in SIDES:
        r = load(runs / f"scaling-{side}.json")
        ms = r["ms_per_step"]["median"]
        scaling.append({"side": side, "particles": side * side, "springs": r["springs"],
                        "ms_per_step_median": ms, "ns_per_spring": ms * 1e6 / r["springs"],
                        "finite": r["stable"]})

    peak_springs = max(r["springs_per_second_median"] for r in rows)
    summary = {
        "machine": machine,
        "date_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "config": "configs/bench-300-soft.yaml",
        "rows": rows,
        "cotton_config": "configs/bench-300.yaml",
        "cotton_rows": cotton,
        "speedup_euler_flag": speedup,
        "scaling_euler_flag": scaling,
        "targets": {
            "springs_per_second_ge_2e9": peak_springs >= 2e9,
            "every_rtf_ge_1": all(r["real_time_factor"] >= 1 for r in rows),
            "speedup_ge_15": speedup["speedup"] >= 15,
        },
    }
    (results / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    with open(results / "runs.csv", "w", newline="") as file:
        writer = csv.writer(file)
        writer.writerow(["scenario", "integrator", "run", "steps", "threads", "ms_per_step_median",
                         "ms_per_step_p10", "internal_forces_ms_median",
                         "springs_per_second_total_time", "finite"])
        writer.writerows(csv_rows)

    c = cotton[0]
    lines = [f"Machine: {machine}; {summary['date_utc']}; {c['runs']} runs x "
             f"{c['steps_per_run']} steps, {c['threads']} threads (medians)", "",
             f"Cotton (configs/bench-300.yaml), 300 x 300, float32, 60 Hz x {c['substeps']} "
             f"substeps (dt {c['dt'] * 1e6:.3g} us):", "",
             "| scenario | integrator | ms/step (median) | ms/step (p10) | ms/frame | "
             "real-time factor | springs/s (median step) | springs/s (total time) | finite |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    lines += markdown_rows(cotton, True)
    lines += ["", "Soft cloth (configs/bench-300-soft.yaml: cotton diverges with every explicit "
              "method at this step), 300 x 300, float32, dt 1 ms:", "",
              "| scenario | integrator | ms/step (median) | ms/step (p10) | real-time factor | "
              "springs/s (median step) | springs/s (total time) | finite |",
              "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    lines += markdown_rows(rows, False)
    lines += ["", f"Euler flag, in-run baseline (reference forces + same Euler update, 1 thread): "
              f"{speedup['baseline_ms_per_step_median']:.3f} ms/step; fast: "
              f"{speedup['fast_ms_per_step_median']:.3f} ms/step ({speedup['fast_threads']} "
              f"threads); speed-up {speedup['speedup']:.1f}x (finite: {speedup['finite']})", "",
              "| euler flag side | particles | springs | ms/step (median) | ns/spring |",
              "| --- | --- | --- | --- | --- |"]
    for s in scaling:
        lines.append(f"| {s['side']} | {s['particles']} | {s['springs']} | "
                     f"{s['ms_per_step_median']:.3f} | {s['ns_per_spring']:.3f} |")
    t = summary["targets"]
    lines += ["", f"Targets: springs/s >= 2e9: {t['springs_per_second_ge_2e9']}; "
              f"every RTF >= 1: {t['every_rtf_ge_1']}; speed-up >= 15x: {t['speedup_ge_15']}"]
    table = "\n".join(lines) + "\n"
    (results / "table.md").write_text(table)
    print(table, end="")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else "unknown")
