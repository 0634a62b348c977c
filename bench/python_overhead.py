"""What stepping from Python costs over the engine: (1) step(1) on a 10 x 10 flag, the time per
call beyond the session's own time per step; (2) a 300 x 300 flag
stepped one step per call from Python against the clothlab program's step loop on the same
config (loop_time_s per step), in separate processes; (3) the same in one process, against the
session's own loop, two simulations stepped in turns that swap ways. Medians over repeats; a
benchmark, not a test.

    PYTHONPATH=build/python python3 bench/python_overhead.py --clothlab build/bin/clothlab
"""

import argparse
import json
import pathlib
import resource
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


def cli_cpu_seconds(executable, config):
    """CPU seconds (user + system) of one clothlab run, its child processes included."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([executable, "--config", str(config), "--quiet"], check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def large_ratio(folder, executable, steps, repeats):
    """Per step, wall (the CLI's loop_time_s against Python's loop) and CPU time (the CLI's run
    of 1 + steps less its run of 1 step, against Python's loop): CPU time does not count the
    waits of a loaded machine, wall time does. Separate processes: the spread between runs is
    as large as the difference."""
    config, one_step = folder / "large.yaml", folder / "large-1.yaml"
    config.write_text(config_text(300, steps, 2e-6))  # stable on cotton at 300
    one_step.write_text(config_text(300, 1, 2e-6))
    long_run = folder / "large-long.yaml"
    long_run.write_text(config_text(300, steps + 1, 2e-6))
    python_s, cli_s, python_cpu, cli_cpu = [], [], [], []
    for _ in range(repeats):
        out = folder / "run.json"
        subprocess.run([executable, "--config", str(config), "--json", str(out), "--quiet"],
                       check=True)
        cli_s.append(json.loads(out.read_text())["loop_time_s"] / steps)
        cli_cpu.append((cli_cpu_seconds(executable, long_run) -
                        cli_cpu_seconds(executable, one_step)) / steps)
        sim = clothlab.Simulation(config)
        start, start_cpu = time.perf_counter(), time.process_time()
        while not sim.finished:
            sim.step(1)
        python_s.append((time.perf_counter() - start) / steps)
        python_cpu.append((time.process_time() - start_cpu) / steps)
    median = statistics.median
    return median(python_s), median(cli_s), median(python_cpu), median(cli_cpu)


def paired_ratios(folder, steps, chunk):
    """In one process, two simulations a and b of the same 300 x 300 run, stepped in turns,
    chunk steps at a time, each chunk either by step(1) calls from Python or by one step(chunk)
    call, the session's own loop, which is what the CLI runs (Simulation::run is step(steps)
    then record()). The two swap ways every chunk: a by calls and b by its loop, then a by its
    loop and b by calls. Two simulations differ by a per cent or so however they are stepped
    (where their arrays lie in memory), and the one stepped first sees other caches, so each
    ratio takes both simulations both ways, each first once: (a by calls + b by calls) over
    (a by its loop + b by its loop) for each two chunks. The median ratio, its quartiles and the
    ratio of the totals."""
    config = folder / "paired.yaml"
    config.write_text(config_text(300, steps, 2e-6))
    a, b = clothlab.Simulation(config), clothlab.Simulation(config)

    def timed(sim, by_calls):
        start = time.process_time()
        if by_calls:
            for _ in range(chunk):
                sim.step(1)
        else:
            sim.step(chunk)
        return time.process_time() - start

    calls_s, loop_s = [], []
    for _ in range(steps // (2 * chunk)):
        a_calls, b_loop = timed(a, True), timed(b, False)
        a_loop, b_calls = timed(a, False), timed(b, True)
        calls_s.append(a_calls + b_calls)
        loop_s.append(a_loop + b_loop)
    ratios = sorted(c / l for c, l in zip(calls_s, loop_s))
    quartiles = statistics.quantiles(ratios, n=4)
    return statistics.median(ratios), quartiles[0], quartiles[2], sum(calls_s) / sum(loop_s)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clothlab", required=True, help="the clothlab program of the build")
    parser.add_argument("--calls", type=int, default=20000)
    parser.add_argument("--large-steps", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--paired-steps", type=int, default=4000)
    parser.add_argument("--chunk", type=int, default=20)
    arguments = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        folder = pathlib.Path(folder)
        overhead, per_call, per_step = small_overhead(folder, arguments.calls, arguments.repeats)
        print(f"10x10: step(1) {per_call * 1e6:.2f} us per call, the session's loop "
              f"{per_step * 1e6:.2f} us per step, Python overhead {overhead * 1e6:.2f} us per "
              f"call (medians of {arguments.repeats} x {arguments.calls}; target < 20 us)")
        python_s, cli_s, python_cpu, cli_cpu = large_ratio(
            folder, arguments.clothlab, arguments.large_steps, arguments.repeats)
        print(f"300x300 wall: Python step(1) loop {python_s * 1e3:.3f} ms per step, CLI "
              f"{cli_s * 1e3:.3f} ms per step: {100 * (python_s / cli_s - 1):+.2f} %")
        print(f"300x300 CPU:  Python step(1) loop {python_cpu * 1e3:.3f} ms per step, CLI "
              f"{cli_cpu * 1e3:.3f} ms per step: {100 * (python_cpu / cli_cpu - 1):+.2f} % "
              f"(medians of {arguments.repeats} runs of {arguments.large_steps} steps; target "
              "within 2 %)")
        median, low, high, total = paired_ratios(folder, arguments.paired_steps, arguments.chunk)
        print(f"300x300 in one process, chunks of {arguments.chunk} steps: step(1) "
              f"calls against one step({arguments.chunk}) call, CPU time {100 * (median - 1):+.2f} % "
              f"(median over {arguments.paired_steps // (2 * arguments.chunk)} ratios, quartiles "
              f"{100 * (low - 1):+.2f} % and {100 * (high - 1):+.2f} %; totals "
              f"{100 * (total - 1):+.2f} %; target within 2 %)")

if __name__ == "__main__":
    main()
