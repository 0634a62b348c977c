"""Two integrators on the cotton flag (configs/default.yaml's scene, 2 s at 60 frames per
second): the warp/weft stretch and the energy over time, sampled every frame, in one figure.

    PYTHONPATH=build/python python3 examples/python/flag_two_integrators.py [--out flag.png]
"""

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import clothlab  # noqa: E402

CONFIG = pathlib.Path(__file__).resolve().parents[2] / "configs" / "default.yaml"
RUNS = {"verlet": {"substeps": 128}, "implicit_euler": {"substeps": 4}}

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", default="flag-two-integrators.png")
arguments = parser.parse_args()

figure, (stretch_axes, energy_axes) = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
for integrator, settings in RUNS.items():
    # Frames for `clothlab view results/python-flag-verlet results/python-flag-implicit_euler`.
    sim = clothlab.Simulation(CONFIG, overrides={"integrator": integrator, **settings,
                                                 "frames.dir": f"results/python-flag-{integrator}"})
    times, stretch, energy = [0.0], [sim.stretch()["max_away_from_pins"]], [sim.energies()["total"]]
    while not sim.finished:
        sim.step(settings["substeps"])  # one frame
        times.append(sim.time)
        stretch.append(sim.stretch()["max_away_from_pins"])
        energy.append(sim.energies()["total"])
    summary = sim.summary()
    label = (f"{integrator}, {settings['substeps']} substeps "
             f"({summary['ms_per_step']['median']:.3f} ms/step)")
    stretch_axes.plot(times, stretch, label=label)
    energy_axes.plot(times, energy, label=label)
    print(f"{integrator}: {sim.verdict}; stretch away from the pins over the run "
          f"{summary['max_stretch_away_from_pins']['over_run']:.4f}")
stretch_axes.set_ylabel("warp/weft stretch away from pins (x rest)")
energy_axes.set_ylabel("total energy (J)")
energy_axes.set_xlabel("time (s)")
stretch_axes.legend()
figure.suptitle("Cotton flag, 32 x 32, 60 frames per second")
figure.tight_layout()
figure.savefig(arguments.out, dpi=100)
print("wrote", arguments.out)
