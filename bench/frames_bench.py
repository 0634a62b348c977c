#!/usr/bin/env python3
"""The cost of --frames (tools/bench.sh --frames): ms per step and peak memory with and
without frames, measured so that a noisy shared machine cancels out as far as it can.

Each repetition runs, per integrator and thread count, three runs back to back: without
frames (STEPS steps), with frames (STEPS steps: N frames) and with frames for 2 x STEPS steps
(2N frames); the order of the three turns round from one repetition to the next, so a drift
of the machine's load hits each kind alike. ms per step is the step loop's wall time
(`loop_time_s`: steps, checks, the frame copies and any wait for the writer) over the steps;
the slowdown is the median of the ratios of runs taken side by side. Peak RSS comes from
wait4(), so it counts everything the process held, the frame ring included.

Usage: frames_bench.py --bin DIR --config YAML --results DIR [--reps R] [--steps S]
                       [--threads T ...] [--integrators NAME ...] [--rate HZ]
Writes RESULTS/frames.md, frames.json and runs/frames-*.json."""
import argparse
import json
import os
import pathlib
import platform
import shutil
import statistics
import subprocess
import sys
import time


def run_case(args, integrator, threads, steps, frames_dir, json_path):
    """Runs clothlab once; returns its summary and its peak RSS in bytes."""
    command = [str(args.bin / "clothlab"), "--config", args.config, "--integrator", integrator,
               "--scenario", "flag", "--steps", str(steps), "--threads", str(threads), "--quiet",
               "--json", str(json_path)]
    if frames_dir is not None:
        shutil.rmtree(frames_dir, ignore_errors=True)
        command += ["--frames", str(frames_dir), "--set", f"frames.rate={args.rate}"]
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(process.pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"frames_bench: {' '.join(command)} exited {os.waitstatus_to_exitcode(status)}")
    summary = json.loads(json_path.read_text())
    frames = None
    if frames_dir is not None:
        run = json.loads((frames_dir / "run.json").read_text())
        frames = run["frames"]
    return {"summary": summary, "peak_rss_bytes": usage.ru_maxrss * 1024, "frames": frames}


def ms_per_step(run):
    return 1e3 * run["summary"]["loop_time_s"] / run["summary"]["steps"]


def machine_description():
    model = platform.processor()
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            if line.startswith("Model name:"):
                model = line.split(":", 1)[1].strip()
    except OSError:
        pass
    return f"{model}, {os.cpu_count()} CPUs, {platform.system()} {platform.release()}"


def median(values):
    return statistics.median(values)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bin", type=pathlib.Path, required=True)
    parser.add_argument("--config", required=True)
    parser.add_argument("--results", type=pathlib.Path, required=True)
    parser.add_argument("--reps", type=int, default=7)
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--threads", type=int, nargs="+", default=[0])
    parser.add_argument("--integrators", nargs="+", default=["euler", "rk4"])
    parser.add_argument("--rate", type=float, default=60)
    args = parser.parse_args()
    if args.reps < 1 or args.steps < 1:
        sys.exit(f"frames_bench: --reps {args.reps} and --steps {args.steps} must be >= 1")
    runs_dir = args.results / "runs"
    runs_dir.mkdir(parents=True, exist_ok=True)

    kinds = ["without", "with_n", "with_2n"]
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    load_before = os.getloadavg()
    loads = []
    measured = {}
    for rep in range(args.reps):
        for threads in args.threads:
            for integrator in args.integrators:
                case = (integrator, threads)
                order = kinds[rep % 3:] + kinds[:rep % 3]
                for kind in order:
                    name = f"frames-{kind}-{integrator}-t{threads}-{rep + 1}"
                    steps = 2 * args.steps if kind == "with_2n" else args.steps
                    frames_dir = None if kind == "without" else args.results / f"frames-{kind}"
                    loads.append(os.getloadavg()[0])
                    run = run_case(args, integrator, threads, steps, frames_dir,
                                   runs_dir / f"{name}.json")
                    measured.setdefault(case, {k: [] for k in kinds})[kind].append(run)
    finished = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())

    rows = []
    for (integrator, threads), runs in measured.items():
        without, with_n, with_2n = (runs[k] for k in kinds)
        ratios = [ms_per_step(b) / ms_per_step(a) for a, b in zip(without, with_n)]
        first = without[0]["summary"]
        frame_bytes = 4 * 7 * first["rows"] * first["cols"]  # positions, velocities, stretch
        rows.append({
            "integrator": integrator, "threads": first["threads"], "pairs": len(ratios),
            "rows": first["rows"], "cols": first["cols"], "dt": first["dt"],
            "steps": args.steps, "frames_n": with_n[0]["frames"]["written"],
            "frames_2n": with_2n[0]["frames"]["written"],
            "every_steps": with_n[0]["frames"]["every_steps"],
            "ms_per_step_without": median(ms_per_step(r) for r in without),
            "ms_per_step_with_n": median(ms_per_step(r) for r in with_n),
            "ms_per_step_with_2n": median(ms_per_step(r) for r in with_2n),
            "median_step_ms_without": median(r["summary"]["ms_per_step"]["median"]
                                             for r in without),
            "median_step_ms_with_n": median(r["summary"]["ms_per_step"]["median"]
                                            for r in with_n),
            "writer_ms_per_frame": 1e3 * median(r["frames"]["writer_s_per_frame"]
                                                for r in with_n),
            # CPU time: absent from runs of builds before it was reported
            "writer_cpu_ms_per_frame": 1e3 * median(r["frames"]["writer_cpu_s_per_frame"]
                                                    for r in with_n)
                                       if "writer_cpu_s_per_frame" in with_n[0]["frames"]
                                       else None,
            "slowdown_median": median(ratios) - 1,
            "slowdown_quartiles": [q - 1 for q in statistics.quantiles(ratios, n=4)]
                                  if len(ratios) > 1 else [ratios[0] - 1] * 3,
            "peak_rss_mib_without": median(r["peak_rss_bytes"] for r in without) / 2**20,
            "peak_rss_mib_with_n": median(r["peak_rss_bytes"] for r in with_n) / 2**20,
            "peak_rss_mib_with_2n": median(r["peak_rss_bytes"] for r in with_2n) / 2**20,
            "frame_data_mib": frame_bytes / 2**20,
        })

    machine = machine_description()
    header = {"machine": machine, "started": started, "finished": finished,
              "load_average_1min": {"before": load_before[0], "median": median(loads),
                                    "max": max(loads)},
              "command": " ".join(sys.argv), "rate_hz": args.rate}
    lines = [
        f"Frames on/off: {machine}; {started} to {finished}; 1-minute load average at the "
        f"runs' starts: median {median(loads):.1f}, max {max(loads):.1f}.",
        f"ms/step = step loop wall time (steps, checks, frame copies, waits) / steps, median of "
        f"{args.reps} runs; slowdown = median [quartiles] of the paired with/without ratios - 1; "
        f"frames at {args.rate:g} Hz of simulated time.", "",
        "| integrator | mesh | threads | frames N / 2N | ms/step without | with N frames "
        "| with 2N | slowdown | writer ms/frame (CPU ms) | peak RSS without / N / 2N (MiB) |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        q = r["slowdown_quartiles"]
        cpu = r["writer_cpu_ms_per_frame"]
        lines.append(
            f"| {r['integrator']} | {r['rows']}x{r['cols']} | {r['threads']} | "
            f"{r['frames_n']} / {r['frames_2n']} (every {r['every_steps']} steps) | "
            f"{r['ms_per_step_without']:.3f} | {r['ms_per_step_with_n']:.3f} | "
            f"{r['ms_per_step_with_2n']:.3f} | {100 * r['slowdown_median']:+.1f} % "
            f"[{100 * q[0]:+.1f}, {100 * q[2]:+.1f}] | {r['writer_ms_per_frame']:.1f} "
            f"({'n/a' if cpu is None else f'{cpu:.1f}'}) | "
            f"{r['peak_rss_mib_without']:.1f} / {r['peak_rss_mib_with_n']:.1f} / "
            f"{r['peak_rss_mib_with_2n']:.1f} |")
    (args.results / "frames.md").write_text("\n".join(lines) + "\n")
    (args.results / "frames.json").write_text(
        json.dumps({**header, "rows": rows}, indent=2) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
