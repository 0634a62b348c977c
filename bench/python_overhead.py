"""What stepping from Python costs over the engine: (1) step(1) on a 10 x 10 flag, the time per
call beyond the session's own time per step; (2) a 300 x 300 flag
stepped one step per call from Python against the clothlab program's step loop on the same
config (loop_time_s per step). Medians over repeats; a benchmark, not a test.

    PYTHONPATH=build/python python3 bench/python_overhead.py --clothlab build/bin/clothlab
"""

import argparse
import json
import pathlib
import statistics
import subprocess
import tempfile
import time

import clothlab

SOURCE = pathlib.Path(__file__).resolve().parents[1]
COTTON = SOURCE / "configs" / "materials" / "cotton.yaml"


def config_text(side, steps, dt):
    return (f"material: {COTTON}\nintegrator: verlet\nscenario: {{plugin: flag, rows: {side}, "
            f"cols: {side}}}\ndt: {dt}\nsteps: {steps}\nprecision: float32\nthreads: 1\n")


def small_overhead(folder, calls, repeats):
    """Per call of step(1) from Python, less the session's own time per step in one step(calls)
    call (loop_time_s: the steps and the monitor's checks), alternated so both see the same
    load."""
    config = folder / "small.yaml"
    config.write_text(config_text(10, calls, 1e-4))
    per_call, per_step = [], []
    for _ in range(repeats):
        looped = clothlab.Simulation(config)
        step = looped.step
        start = time.perf_counter()
        for _ in range(calls):
            step(1)
        per_call.append((time.perf_counter() - start) / calls)
        whole = clothlab.Simulation(config)
        whole.step(calls)
        per_step.append(whole.summary()["loop_time_s"] / calls)
    overheads = [a - b for a, b in zip(per_call, per_step)]
    return statistics.median(overheads), statistics.median(per_call), statistics.median(per_step)


def large_ratio(folder, executable, steps, repeats):
    config = folder / "large.yaml"
    config.write_text(config_text(300, steps, 2e-6))  # stable on cotton at 300
    python_s, cli_s = [], []
    for _ in range(repeats):
        out = folder / "run.json"
        subprocess.run([executable, "--config", str(config), "--json", str(out), "--quiet"],
                       check=True)
        cli_s.append(json.loads(out.read_text())["loop_time_s"] / steps)
        sim = clothlab.Simulation(config)
        start = time.perf_counter()
        while not sim.finished:
            sim.step(1)
        python_s.append((time.perf_counter() - start) / steps)
    return statistics.median(python_s), statistics.median(cli_s)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clothlab", required=True, help="the clothlab program of the build")
    parser.add_argument("--calls", type=int, default=20000)
    parser.add_argument("--large-steps", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=5)
    arguments = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        folder = pathlib.Path(folder)
        overhead, per_call, per_step = small_overhead(folder, arguments.calls, arguments.repeats)
        print(f"10x10: step(1) {per_call * 1e6:.2f} us per call, the session's loop "
              f"{per_step * 1e6:.2f} us per step, Python overhead {overhead * 1e6:.2f} us per "
              f"call (medians of {arguments.repeats} x {arguments.calls}; target < 20 us)")
        python_s, cli_s = large_ratio(folder, arguments.clothlab, arguments.large_steps,
                                      arguments.repeats)
        print(f"300x300: Python step(1) loop {python_s * 1e3:.3f} ms per step, CLI "
              f"{cli_s * 1e3:.3f} ms per step: {100 * (python_s / cli_s - 1):+.2f} % (medians of "
              f"{arguments.repeats} runs of {arguments.large_steps} steps; target within 2 %)")


if __name__ == "__main__":
    main()
