"""A work-precision diagram in a dozen lines: each integrator's position error after 0.1 s of
the 20 x 20 cotton flag against its time per simulated second, for a few step sizes; the
reference is rk4 at a step 8 times smaller than the smallest. Verlet's error stays flat: it
leaves out the springs' damping (it never passes velocities to the forces), so it converges to
the solution of another equation.

    PYTHONPATH=build/python python3 examples/python/work_precision.py [--out wp.png]
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import clothlab  # noqa: E402

config = {"material": "configs/materials/cotton.yaml", "scenario": {"plugin": "flag", "rows": 20,
          "cols": 20}, "duration": 0.1, "precision": "float64", "threads": 1}


def run(integrator, dt):
    sim = clothlab.Simulation(config, overrides={"integrator": integrator, "dt": dt})
    sim.step(sim.steps_left)
    return sim.positions.copy(), sim.summary()["wall_time_s"] / sim.time


reference, _ = run("rk4", 2.5e-5 / 8)
for integrator in ("verlet", "rk4", "implicit_euler"):
    points = [run(integrator, dt) for dt in (1e-4, 5e-5, 2.5e-5)]
    errors = [np.abs(positions - reference).max() for positions, _ in points]
    plt.loglog([cost for _, cost in points], errors, "o-", label=integrator)
plt.xlabel("wall time per simulated second (s)")
plt.ylabel("max position error at 0.1 s (m)")
plt.legend()
plt.savefig(sys.argv[sys.argv.index("--out") + 1] if "--out" in sys.argv else "work-precision.png")
