"""clothlab.choose, clothlab.sweep, clothlab.conformance and clothlab.view against the clothlab
programs: the same tables as dicts, the same files, the same one-line errors. Tiny grids only."""

import json
import os
import pathlib
import subprocess

import pytest

import clothlab
from conftest import cli_error

CONFORMANCE = pathlib.Path(os.environ.get("CLOTHLAB_EXECUTABLE", "")).with_name(
    "clothlab-conformance")

CHOOSE_6 = {"scenario": {"plugin": "flag", "rows": 6, "cols": 6}, "frame_rate": 60,
            "choose": {"duration": 0.05, "integrators": ["euler"], "max_substeps": 16}}

SWEEP = """\
steps: 5
threads: 1
scenario: {{plugin: sheet, rows: 4, cols: 5}}
sweep:
  name: tiny
  output: {output}
  matrix:
    integrator: [euler, rk4]
    dt: [0.001]
"""


def test_choose_returns_the_ranking_the_cli_writes(run_cli, tmp_path):
    ranking = clothlab.choose(CHOOSE_6, overrides={"choose.output": str(tmp_path / "py")})
    assert [row["integrator"] for row in ranking] == ["euler"]
    assert ranking == json.loads((tmp_path / "py-ranked.json").read_text())["ranking"]
    config = tmp_path / "choose.yaml"
    config.write_text(json.dumps(CHOOSE_6))
    code, _, stderr = run_cli("--choose", "--config", config, "--set",
                              f"choose.output={tmp_path / 'cli'}")
    assert code == 0, stderr
    cli = json.loads((tmp_path / "cli-ranked.json").read_text())["ranking"]
    assert ranking[0].keys() == cli[0].keys()
    # The fewest passing substeps do not depend on timing with one candidate.
    assert ranking[0]["substeps"] == cli[0]["substeps"] and ranking[0]["rank"] == 1


def test_choose_without_a_frame_rate_raises_the_cli_message(run_cli, tmp_path):
    config = dict(CHOOSE_6)
    del config["frame_rate"]
    with pytest.raises(clothlab.InputError) as raised:
        clothlab.choose(config)
    path = tmp_path / "c.yaml"
    path.write_text(json.dumps(config))
    _, _, stderr = run_cli("--choose", "--config", path)
    assert str(raised.value) == cli_error(stderr)


def test_sweep_returns_the_rows_the_cli_writes(run_cli, tmp_path):
    python_file = tmp_path / "python.yaml"
    python_file.write_text(SWEEP.format(output=tmp_path / "python"))
    rows = clothlab.sweep(python_file)
    assert [(row["integrator"], row["status"]) for row in rows] == [("euler", "stable"),
                                                                    ("rk4", "stable")]
    cli_file = tmp_path / "cli.yaml"
    cli_file.write_text(SWEEP.format(output=tmp_path / "cli"))
    code, _, stderr = run_cli("--config", cli_file)
    assert code == 0, stderr
    cli_rows = json.loads((tmp_path / "cli.json").read_text())["rows"]
    assert [row.keys() for row in rows] == [row.keys() for row in cli_rows]
    assert [row["steps"] for row in rows] == [row["steps"] for row in cli_rows] == [5, 5]


def test_sweep_with_an_override_and_errors(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text(SWEEP.format(output=tmp_path / "s"))
    rows = clothlab.sweep(path, overrides={"steps": 3})
    assert [row["steps"] for row in rows] == [3, 3]
    with pytest.raises(clothlab.InputError, match="missing.yaml"):
        clothlab.sweep(tmp_path / "missing.yaml")
    single = tmp_path / "single.yaml"
    single.write_text("steps: 3\n")
    with pytest.raises(clothlab.InputError, match="single.yaml has no sweep: section"):
        clothlab.sweep(single)
    path.write_text(SWEEP.format(output=tmp_path / "s").replace("rk4", "nosuch"))
    with pytest.raises(clothlab.InputError, match="s.yaml:8:25: integrator = nosuch"):
        clothlab.sweep(path)


def test_conformance_returns_the_checks_the_runner_reports(tmp_path):
    checks = clothlab.conformance("euler", filter="descriptor", seed=7)
    assert checks and all(check["passed"] for check in checks), checks
    euler = next(library["path"] for library in clothlab.plugins()["libraries"]
                 if any(c["id"] == "euler" for c in library["integrators"]))
    report = tmp_path / "report.json"
    subprocess.run([str(CONFORMANCE), "--seed", "7", "--filter", "descriptor", "--json",
                    str(report), euler], check=True, capture_output=True)
    cli = json.loads(report.read_text())["checks"]
    assert [(c["component"], c["check"], c["passed"]) for c in checks] == \
        [(c["component"], c["check"], c["passed"]) for c in cli]


def test_conformance_bad_input_raises():
    with pytest.raises(clothlab.InputError, match="matched no check"):
        clothlab.conformance("euler", filter="no-such-check")
    with pytest.raises(clothlab.InputError, match="not a valid regular expression"):
        clothlab.conformance("euler", filter="(")
    with pytest.raises(clothlab.PluginLoadError, match="no nosuch.so"):
        clothlab.conformance("nosuch")


def test_view_writes_the_page_of_the_frames(run_cli, tmp_path):
    frames = tmp_path / "frames"
    sim = clothlab.Simulation({"integrator": "euler", "scenario": "sheet", "steps": 4},
                              overrides={"frames.dir": str(frames), "frames.every": 2})
    sim.step(sim.steps_left)
    del sim
    index = clothlab.view([str(frames)], str(tmp_path / "page"))
    assert pathlib.Path(index) == tmp_path / "page" / "index.html" and pathlib.Path(index).is_file()
    code, _, stderr = run_cli("view", frames, "--out", tmp_path / "cli-page")
    assert code == 0, stderr
    assert sorted(p.name for p in (tmp_path / "page").iterdir()) == \
        sorted(p.name for p in (tmp_path / "cli-page").iterdir())
    assert (tmp_path / "page" / "runs.js").read_bytes() == \
        (tmp_path / "cli-page" / "runs.js").read_bytes()
    with pytest.raises(clothlab.InputError, match="no frames folder"):
        clothlab.view([], str(tmp_path / "none"))
