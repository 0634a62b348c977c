#!/usr/bin/env python3
"""The engine on a shared machine (issue 23): per-step median and p90 of a scene, quiet and with
one co-running busy process that this script starts before the run and stops after it. Scenes
(--scene): rk4-300, the 300 x 300 rk4 flag (configs/bench-300-soft.yaml), a long step;
verlet-200, the 200 x 200 cotton flag with verlet at 832 substeps per frame
(configs/choose-cotton-flag-200.yaml), a step about a tenth as long (lab/performance.md).
Float32, 2 threads, 400 steps.

Each repetition runs every variant as a pair back to back, quiet then contended, so a drift of
the machine's load hits both halves of a pair alike; the load average is read before each run.
A variant is a label and what it changes: environment assignments (OMP_WAIT_POLICY=passive)
and clothlab arguments (--threads 1, which replaces --threads T, or --set thread_team=fixed), e.g.
  tools/shared-machine-bench.py default 'passive: OMP_WAIT_POLICY=passive'
The figures of a variant are the medians over repetitions of each run's median and p90, and
the median over repetitions of the pairs' contended-p90 / quiet-p90 ratio; solo_q and solo_c
are the steps the adaptive team ran on one thread (the run's counters.steps_on_one_thread).

Usage: tools/shared-machine-bench.py [--bin DIR] [--scene rk4-300|verlet-200] [--reps R]
                                     [--steps S] [--threads T] [--busy N] [--results DIR]
                                     [VARIANT ...]
Environment: none needed; the variants' assignments are added to this script's own."""
import argparse
import json
import os
import pathlib
import signal
import statistics
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
SCENES = {
    "rk4-300": ("rk4 flag 300x300", ["--config", str(ROOT / "configs/bench-300-soft.yaml"),
                                     "--integrator", "rk4", "--scenario", "flag"]),
    "verlet-200": ("verlet cotton flag 200x200 at 832 substeps",
                   ["--config", str(ROOT / "configs/choose-cotton-flag-200.yaml"),
                    "--set", "integrator=verlet", "--set", "substeps=832"]),
}


def parse_variant(text):
    """'label: VAR=value --arg value' -> (label, {VAR: value}, [--arg, value])."""
    label, _, rest = text.partition(":")
    words = rest.split() if rest else []
    env, args = {}, []
    for word in words:
        if not args and "=" in word and not word.startswith("-"):
            key, _, value = word.partition("=")
            env[key] = value
        else:
            args.append(word)
    return label.strip(), env, args


def load_average():
    return pathlib.Path("/proc/loadavg").read_text().split()[0]


def run_once(args, env, extra, json_path):
    threads = [] if "--threads" in extra else ["--threads", str(args.threads)]
    command = [str(args.bin / "clothlab")] + SCENES[args.scene][1] + [
        "--steps", str(args.steps), "--quiet", "--json", str(json_path)] + threads + extra
    result = subprocess.run(command, env={**os.environ, **env}, stdout=subprocess.DEVNULL)
    if result.returncode != 0:
        sys.exit(f"shared-machine-bench: {' '.join(command)} exited {result.returncode}")
    summary = json.loads(json_path.read_text())
    return (summary["ms_per_step"]["median"], summary["ms_per_step"]["p90"],
            summary["counters"]["steps_on_one_thread"])


def start_busy(count):
    """`count` processes that spin on a core each until stopped."""
    return [subprocess.Popen(["yes"], stdout=subprocess.DEVNULL) for _ in range(count)]


def stop_busy(processes):
    for process in processes:
        process.terminate()
    for process in processes:
        process.wait()


def stop_on_signal(signum, _frame):
    """SIGTERM or SIGHUP: leave through the `finally` that stops the busy processes."""
    sys.exit(f"shared-machine-bench: stopped by signal {signum}")


def main():
    signal.signal(signal.SIGTERM, stop_on_signal)
    signal.signal(signal.SIGHUP, stop_on_signal)
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bin", type=pathlib.Path, default=ROOT / "build/bin")
    parser.add_argument("--scene", choices=sorted(SCENES), default="rk4-300")
    parser.add_argument("--reps", type=int, default=5)
    parser.add_argument("--steps", type=int, default=400)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--busy", type=int, default=1, help="busy processes in a contended run")
    parser.add_argument("--results", type=pathlib.Path, default=ROOT / "results/shared-machine")
    parser.add_argument("variants", nargs="*", default=["default"])
    args = parser.parse_args()
    if args.reps < 1 or args.steps < 1 or args.threads < 1 or args.busy < 1:
        sys.exit("shared-machine-bench: --reps, --steps, --threads and --busy must be >= 1, got "
                 f"{args.reps}, {args.steps}, {args.threads}, {args.busy}")
    variants = [parse_variant(text) for text in args.variants]
    args.results.mkdir(parents=True, exist_ok=True)
    lscpu = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
    model = next((line.split(":", 1)[1].strip() for line in lscpu.splitlines()
                  if line.startswith("Model name:")), "unknown CPU")
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    if subprocess.run(["git", "-C", str(ROOT), "diff", "--quiet", "HEAD"]).returncode != 0:
        commit += " (with local changes)"
    print(f"# {model}, {os.cpu_count()} CPUs; {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())};"
          f" commit {commit}; {SCENES[args.scene][0]}, {args.threads} threads, {args.steps} steps, "
          f"{args.reps} pairs, {args.busy} busy process(es) when contended")
    print("variant  rep  load_q  quiet_median  quiet_p90  load_c  contended_median  contended_p90"
          "  p90_ratio  solo_q  solo_c")
    rows = {label: [] for label, _, _ in variants}
    json_path = args.results / "run.json"
    for rep in range(args.reps):
        for label, env, extra in variants:
            load_quiet = load_average()
            quiet = run_once(args, env, extra, json_path)
            busy = start_busy(args.busy)
            try:
                time.sleep(0.2)  # let the busy process reach its core
                load_contended = load_average()
                contended = run_once(args, env, extra, json_path)
            finally:
                stop_busy(busy)
            ratio = contended[1] / quiet[1]
            rows[label].append((quiet, contended, ratio))
            print(f"{label}  {rep + 1}  {load_quiet}  {quiet[0]:.3f}  {quiet[1]:.3f}  "
                  f"{load_contended}  {contended[0]:.3f}  {contended[1]:.3f}  {ratio:.2f}  "
                  f"{quiet[2]}  {contended[2]}", flush=True)
    print()
    print("| variant | quiet median ms | quiet p90 ms | contended median ms | contended p90 ms "
          "| contended p90 / quiet p90 |")
    print("| --- | --- | --- | --- | --- | --- |")
    for label, runs in rows.items():
        med = statistics.median
        print(f"| {label} | {med(r[0][0] for r in runs):.3f} | {med(r[0][1] for r in runs):.3f} "
              f"| {med(r[1][0] for r in runs):.3f} | {med(r[1][1] for r in runs):.3f} "
              f"| {med(r[2] for r in runs):.2f} |")
    (args.results / "summary.json").write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
