"""clothlab.Simulation against the clothlab program: the same state bit for bit, the numpy
views are the engine's memory, and every error is the CLI's one-line message."""

import gc
import json
import signal
import threading

import numpy as np
import pytest

import clothlab
from conftest import FLAG_10, cli_error


def state_csv(sim):
    """The text `clothlab --state-out` writes, from the module's views."""
    x = sim.positions.astype(np.float64)
    v = sim.velocities.astype(np.float64)
    lines = ["row,col,x,y,z,vx,vy,vz"]
    for i in range(sim.particle_count):
        values = ",".join("%.17g" % value for value in (*x[:, i], *v[:, i]))
        lines.append("%d,%d,%s" % (i // sim.cols, i % sim.cols, values))
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("precision", ["float32", "float64"])
def test_stepped_state_equals_cli_state_out_bit_for_bit(precision, write_config, run_cli, tmp_path):
    config = write_config(FLAG_10.replace("{precision}", precision))
    state_file = tmp_path / "state.csv"
    code, _, stderr = run_cli("--config", config, "--state-out", state_file, "--quiet")
    assert code == 0, stderr
    sim = clothlab.Simulation(config)
    assert sim.positions.dtype == np.dtype(precision)
    # In uneven pieces: the session's steps are the run's whatever the caller's grouping.
    assert sim.step(7) == 7
    assert sim.advance(13 * sim.dt) == 13
    assert sim.step(sim.steps_left) == 100
    assert sim.finished
    assert state_csv(sim) == state_file.read_text()


def test_summary_has_the_json_fields_and_values(write_config, run_cli, tmp_path):
    config = write_config(FLAG_10.replace("{precision}", "float64"))
    json_file = tmp_path / "run.json"
    code, _, stderr = run_cli("--config", config, "--json", json_file, "--quiet")
    assert code == 0, stderr
    cli = json.loads(json_file.read_text())
    sim = clothlab.Simulation(config)
    sim.step(sim.steps_left)
    summary = sim.summary()
    assert summary.keys() == cli.keys()
    for key in ("verdict", "stable", "steps", "max_stretch", "p99_stretch", "mean_stretch"):
        assert summary[key] == cli[key], key
    assert sim.verdict == cli["verdict"]


def test_views_are_the_engines_memory(write_config):
    sim = clothlab.Simulation(write_config(FLAG_10.replace("{precision}", "float32")))
    positions = sim.positions
    assert positions.shape == (3, 100) and positions.T.shape == (100, 3)
    assert not positions.flags.owndata
    address = positions.__array_interface__["data"][0]
    before = positions.copy()
    sim.step(5)
    # The same memory, changed in place by the step.
    assert not np.array_equal(positions, before)
    assert sim.positions.__array_interface__["data"][0] == address
    np.testing.assert_array_equal(positions, sim.positions)
    # The rows are the engine's padded stride apart: the padding is not in the view.
    assert positions.strides[0] >= 100 * positions.itemsize and positions.strides[1] == 4


def test_a_view_keeps_its_simulation_alive(write_config):
    velocities = clothlab.Simulation(write_config(FLAG_10.replace("{precision}", "float64"))).velocities
    gc.collect()
    assert np.all(velocities == 0)
    assert isinstance(velocities.base, clothlab.Simulation)


def test_perturb_before_the_first_step(write_config):
    sim = clothlab.Simulation(write_config(FLAG_10.replace("{precision}", "float64")))
    sim.velocities[2, :] = 0.5  # every particle's z velocity, pinned ones included
    assert sim.energies()["kinetic"] > 0
    sim.step(1)
    moved = sim.positions[2, sim.inverse_masses > 0]
    assert np.all(moved > 0), "the step started from the perturbed velocities"


def test_perturb_between_steps(write_config):
    config = write_config(FLAG_10.replace("{precision}", "float64"))
    pushed, control = clothlab.Simulation(config), clothlab.Simulation(config)
    pushed.step(20)
    control.step(20)
    pushed.velocities[2, :] += 0.5
    pushed.state_written()  # verlet drops its last displacement, starts from the velocities
    pushed.step(1)
    control.step(1)
    free = pushed.inverse_masses > 0
    apart = pushed.positions[2, free] - control.positions[2, free]
    np.testing.assert_allclose(apart, 0.5 * pushed.dt, rtol=0.05)


def test_read_only_views(write_config):
    sim = clothlab.Simulation(write_config(FLAG_10.replace("{precision}", "float32")))
    assert sim.inverse_masses.shape == (100,)
    assert (sim.inverse_masses == 0).sum() >= 2  # the pole's pins
    springs = sim.springs
    assert springs["first"].shape == springs["second"].shape
    assert set(np.unique(springs["family"])) <= {0, 1, 2}
    assert sim.triangles.shape == (2 * 9 * 9, 3)
    for view in (sim.inverse_masses, springs["ks"], sim.triangles):
        with pytest.raises(ValueError):
            view[0] = 1


def test_state_written_with_wrong_shape_or_dtype_raises(write_config):
    sim = clothlab.Simulation(write_config(FLAG_10.replace("{precision}", "float32")))
    sim.positions = np.zeros((100, 3), np.float32)  # (n, 3) is accepted
    assert np.all(sim.positions == 0)
    with pytest.raises(clothlab.InputError, match=r"positions: dtype float64; allowed: float32"):
        sim.positions = np.zeros((3, 100))
    with pytest.raises(clothlab.InputError, match=r"velocities: shape \(3, 99\); allowed"):
        sim.velocities = np.zeros((3, 99), np.float32)


def test_bad_key_and_value_raise_the_cli_message(write_config, run_cli):
    for line in ("dtt: 0.001", "stability: {max_stretch: -1}", "scenario: {rows: 0}"):
        config = write_config(FLAG_10.replace("{precision}", "float32") + line + "\n")
        code, _, stderr = run_cli("--config", config)
        assert code == 1
        with pytest.raises(clothlab.InputError) as raised:
            clothlab.Simulation(config)
        assert str(raised.value) == cli_error(stderr)
    config = write_config(FLAG_10.replace("{precision}", "float32"))
    with pytest.raises(clothlab.InputError, match=r"^overrides: unknown key dtt"):
        clothlab.Simulation(config, overrides={"dtt": 1})
    with pytest.raises(clothlab.InputError, match=r"^overrides: precision = float16: "):
        clothlab.Simulation(config, overrides={"precision": "float16"})


def test_missing_plugin_raises_the_cli_message(write_config, run_cli):
    config = write_config(FLAG_10.replace("{precision}", "float32").replace("verlet", "no_such"))
    code, _, stderr = run_cli("--config", config)
    assert code == 2
    with pytest.raises(clothlab.PluginLoadError) as raised:
        clothlab.Simulation(config)
    assert str(raised.value) == cli_error(stderr)
    assert "integrator = no_such" in str(raised.value)


def test_diverged_run_raises_with_its_step_and_check(write_config, run_cli):
    text = FLAG_10.replace("{precision}", "float64").replace("verlet", "euler")
    config = write_config(text.replace("dt: 0.0005", "dt: 0.01"))
    code, _, stderr = run_cli("--config", config)
    assert code == 3
    sim = clothlab.Simulation(config)
    with pytest.raises(clothlab.DivergedError) as raised:
        sim.step(sim.steps_left)
    assert str(raised.value) == cli_error(stderr)
    assert raised.value.step == sim.steps_taken
    assert raised.value.check in ("non-finite", "stretch", "energy")
    assert sim.finished and sim.steps_left == 0


def test_stepping_past_the_end_raises(write_config):
    sim = clothlab.Simulation(write_config(FLAG_10.replace("{precision}", "float32")))
    with pytest.raises(clothlab.InputError, match=r"step\(121\): the run has 120 steps left"):
        sim.step(121)
    with pytest.raises(clothlab.InputError, match=r"advance\(-1 s\)"):
        sim.advance(-1)


def test_a_dict_config_and_overrides(write_config):
    from_file = clothlab.Simulation(write_config(FLAG_10.replace("{precision}", "float32")))
    config = {"integrator": "verlet", "scenario": {"plugin": "flag", "rows": 10, "cols": 10},
              "material": str(pathlib_cotton()), "dt": 0.0005, "steps": 120,
              "precision": "float64", "threads": 1}
    sim = clothlab.Simulation(config, overrides={"precision": "float32", "steps": 20})
    assert sim.precision == "float32" and sim.steps_left == 20
    sim.step(20)
    from_file.step(20)
    np.testing.assert_array_equal(sim.positions, from_file.positions)


def pathlib_cotton():
    from conftest import SOURCE_DIR
    return SOURCE_DIR / "configs/materials/cotton.yaml"


def test_two_threads_at_once_raise_not_crash(write_config):
    text = FLAG_10.replace("{precision}", "float32").replace("rows: 10", "rows: 80")
    text = text.replace("cols: 10", "cols: 80").replace("steps: 120", "steps: 100000")
    sim = clothlab.Simulation(write_config(text.replace("dt: 0.0005", "dt: 0.00002")))
    refused = []

    def step_many():
        try:
            sim.step(3000)
        except RuntimeError as error:
            refused.append(str(error))

    stepping = threading.Thread(target=step_many)
    stepping.start()
    while stepping.is_alive() and not refused:
        try:
            sim.step(1)
        except RuntimeError as error:
            refused.append(str(error))
    stepping.join()
    assert refused and "in use by another thread" in refused[0]


def test_plugins_lists_what_list_plugins_shows(run_cli):
    listing = clothlab.plugins()
    assert listing["schema_version"] == 1
    ids = {c["id"] for library in listing["libraries"]
           for c in library["integrators"] + library["scenarios"]}
    assert {"verlet", "rk4", "flag", "sheet"} <= ids
    code, stdout, _ = run_cli("--list-plugins")
    assert code == 0
    for library in listing["libraries"]:
        assert library["path"] in stdout
        for kind in ("integrator", "scenario"):
            for component in library[kind + "s"]:
                assert f"{kind} {component['id']}: {component['name']}" in stdout
                for parameter in component["parameters"]:
                    assert f"{parameter['key']} = {parameter['default']}" in stdout


def test_progress_is_reported_and_may_look_at_the_simulation(write_config):
    text = FLAG_10.replace("{precision}", "float32").replace("rows: 10", "rows: 60")
    sim = clothlab.Simulation(write_config(text.replace("cols: 10", "cols: 60").replace(
        "steps: 120", "steps: 4000").replace("dt: 0.0005", "dt: 0.00002")))
    reports = []
    sim.step(4000, progress=lambda taken, asked: reports.append((taken, asked, sim.time)))
    assert len(reports) >= 2
    assert [asked for _, asked, _ in reports] == [4000] * len(reports)
    taken = [taken for taken, _, _ in reports]
    assert taken == sorted(taken) and taken[-1] == 4000
    assert reports[-1][2] == pytest.approx(4000 * sim.dt)


def test_ctrl_c_stops_a_long_step_between_steps(write_config):
    text = FLAG_10.replace("{precision}", "float32").replace("rows: 10", "rows: 60")
    sim = clothlab.Simulation(write_config(text.replace("cols: 10", "cols: 60").replace(
        "steps: 120", "steps: 10000000").replace("dt: 0.0005", "dt: 0.00002")))
    timer = threading.Timer(0.3, signal.raise_signal, (signal.SIGINT,))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sim.step(sim.steps_left)
    timer.join()
    assert 0 < sim.steps_taken < 10000000
    sim.step(1)  # the run goes on from where it stopped


def test_frames_are_written_as_the_cli_writes_them(write_config, run_cli, tmp_path):
    text = FLAG_10.replace("{precision}", "float32") + "frames: {every: 20, format: [vtp, obj]}\n"
    config = write_config(text)
    code, _, stderr = run_cli("--config", config, "--set", f"frames.dir={tmp_path / 'cli'}",
                              "--quiet")
    assert code == 0, stderr
    sim = clothlab.Simulation(config, overrides={"frames.dir": str(tmp_path / "python")})
    sim.step(50)
    sim.step(sim.steps_left)
    written = sorted(path.name for path in (tmp_path / "python").iterdir())
    assert written == sorted(path.name for path in (tmp_path / "cli").iterdir())
    assert len([name for name in written if name.endswith(".vtp")]) == 7  # steps 0, 20, ... 120
    for name in written:
        if name.endswith(".obj"):
            assert (tmp_path / "python" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    run = json.loads((tmp_path / "python" / "run.json").read_text())
    cli_run = json.loads((tmp_path / "cli" / "run.json").read_text())
    assert run.keys() == cli_run.keys()
    assert run["status"] == "finished" and run["summary"]["verdict"] == sim.verdict


def test_a_run_left_early_gets_its_summary_so_far_in_run_json(write_config, tmp_path):
    config = write_config(FLAG_10.replace("{precision}", "float32"))
    sim = clothlab.Simulation(config, overrides={"frames.dir": str(tmp_path / "frames")})
    sim.step(30)
    run_json = tmp_path / "frames" / "run.json"
    assert json.loads(run_json.read_text())["status"] == "running"
    del sim
    gc.collect()
    run = json.loads(run_json.read_text())
    assert run["status"] == "finished" and run["summary"]["steps"] == 30
