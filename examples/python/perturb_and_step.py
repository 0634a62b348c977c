"""Perturb and step: two copies of the cotton flag settle for 0.5 s; one has its free edge pushed
out of its plane through the velocity view (the engine's own memory, written between steps);
both step on, and the distance between them shows how the push travels (a flag in the wind
amplifies it).

    PYTHONPATH=build/python python3 examples/python/perturb_and_step.py
"""

import pathlib

import numpy as np

import clothlab

CONFIG = pathlib.Path(__file__).resolve().parents[2] / "configs" / "default.yaml"
# Frames for `clothlab view results/python-pushed results/python-control`, side by side.
pushed = clothlab.Simulation(CONFIG, overrides={"frames.dir": "results/python-pushed"})
control = clothlab.Simulation(CONFIG, overrides={"frames.dir": "results/python-control"})
for sim in (pushed, control):
    sim.advance(0.5)  # settle
assert np.array_equal(pushed.positions, control.positions)

# The column of particles farthest from the pole (the pinned column), 0.5 m/s along z.
pinned_columns = np.flatnonzero(pushed.inverse_masses == 0) % pushed.cols
free_column = pushed.cols - 1 if pinned_columns.mean() < pushed.cols / 2 else 0
free_edge = np.arange(free_column, pushed.particle_count, pushed.cols)
pushed.velocities[2, free_edge] += 0.5
pushed.state_written()  # the integrator drops its history (Verlet's last step), reads v
print(f"t = {pushed.time:.2f} s: pushed {free_edge.size} particles of the free edge by 0.5 m/s")
while not pushed.finished and pushed.time < 1.0 - 1e-9:
    for sim in (pushed, control):
        sim.advance(0.05)
    apart = np.linalg.norm(pushed.positions - control.positions, axis=0)
    print(f"t = {pushed.time:.2f} s: copies apart by {apart.max() * 1e3:6.2f} mm at most, "
          f"{apart.mean() * 1e3:6.2f} mm on average; kinetic energy "
          f"{pushed.energies()['kinetic']:.4f} J vs {control.energies()['kinetic']:.4f} J")
print("pushed:", pushed.verdict)
