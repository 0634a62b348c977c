#!/usr/bin/env python3
"""The cost of --frames (tools/bench.sh): ms per step with and without frames, from runs
taken in alternation.  Usage: frames_table.py RESULTS_DIR MACHINE_NAME

Frames cost only at frame steps, so the per-step median would hide them: the figure here is
the mean, stepping wall time / steps, which includes copying the state for the writer and any
wait for it. Writes frames.md and frames.json."""
import json
import pathlib
import statistics
import sys


def load(path):
    with open(path) as file:
        return json.load(file)


def mean_ms(run):
    return 1e3 * run["wall_time_s"] / run["steps"]


def main(results_dir, machine):
    results = pathlib.Path(results_dir)
    runs = results / "runs"
    rows = []
    for path in sorted(runs.glob("frames-off-*-1.json")):
        case = path.name[len("frames-off-"):-len("-1.json")]
        off = [load(p) for p in sorted(runs.glob(f"frames-off-{case}-*.json"))]
        on = [load(p) for p in sorted(runs.glob(f"frames-on-{case}-*.json"))]
        # Pairs ran back to back, so their ratio cancels most of the machine's drift.
        ratios = [mean_ms(b) / mean_ms(a) for a, b in zip(off, on)]
        rows.append({
            "case": case, "runs": len(ratios), "steps": off[0]["steps"], "dt": off[0]["dt"],
            "rows": off[0]["rows"], "cols": off[0]["cols"], "threads": off[0]["threads"],
            "ms_per_step_without": statistics.median(mean_ms(r) for r in off),
            "ms_per_step_with": statistics.median(mean_ms(r) for r in on),
            "median_step_ms_without": statistics.median(r["ms_per_step"]["median"] for r in off),
            "median_step_ms_with": statistics.median(r["ms_per_step"]["median"] for r in on),
            "slowdown_median": statistics.median(ratios) - 1,
            "slowdown_min": min(ratios) - 1, "slowdown_max": max(ratios) - 1,
        })
    lines = [f"Frames on/off, {machine}: ms per step = stepping wall time / steps, median of "
             f"the runs; slowdown = median (min..max) of the paired ratios - 1", "",
             "| case | mesh | threads | runs | ms/step without | ms/step with frames | slowdown |",
             "| --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        lines.append(f"| {r['case']} | {r['rows']}x{r['cols']} | {r['threads']} | {r['runs']} | "
                     f"{r['ms_per_step_without']:.3f} | {r['ms_per_step_with']:.3f} | "
                     f"{100 * r['slowdown_median']:+.1f} % ({100 * r['slowdown_min']:+.1f}.."
                     f"{100 * r['slowdown_max']:+.1f} %) |")
    (results / "frames.md").write_text("\n".join(lines) + "\n")
    (results / "frames.json").write_text(json.dumps(rows, indent=2) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main(*sys.argv[1:3])
