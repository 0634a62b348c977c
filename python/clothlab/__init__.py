"""ClothLab from Python: load the plugins, build a simulation from a configuration (the keys of
`clothlab --set`), step it, and read and change its state as numpy views of the engine's memory.

    import clothlab
    sim = clothlab.Simulation({"scenario": "flag", "frame_rate": 60}, overrides={"substeps": 8})
    sim.step(100)
    sim.positions        # (3, n) view: rows x, y, z; .T is (n, 3)

docs/guide/python.md has the whole API.
"""

from ._clothlab import (
    DivergedError,
    InputError,
    PluginError,
    PluginLoadError,
    Simulation,
    choose,
    conformance,
    plugins,
    sweep,
    view,
)

__all__ = [
    "DivergedError",
    "InputError",
    "PluginError",
    "PluginLoadError",
    "Simulation",
    "choose",
    "conformance",
    "plugins",
    "sweep",
    "view",
]
