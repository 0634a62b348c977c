"""Shared fixtures: the clothlab program of the same build (CLOTHLAB_EXECUTABLE, set by CTest)
and small configs written as YAML files, so that the CLI and the module read the same text."""

import os
import pathlib
import subprocess

import pytest

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def clothlab_executable():
    path = os.environ.get("CLOTHLAB_EXECUTABLE")
    assert path, "CLOTHLAB_EXECUTABLE must name the clothlab program (CTest sets it)"
    return path


@pytest.fixture
def write_config(tmp_path):
    def write(text, name="run.yaml"):
        path = tmp_path / name
        path.write_text(text)
        return path

    return write


@pytest.fixture
def run_cli(clothlab_executable):
    """Runs the program; returns (exit code, stdout, stderr)."""

    def run(*arguments):
        done = subprocess.run([clothlab_executable, *map(str, arguments)], capture_output=True,
                              text=True, timeout=120)
        return done.returncode, done.stdout, done.stderr

    return run


def cli_error(stderr):
    """The one-line message of `clothlab: error: MESSAGE`."""
    lines = [line for line in stderr.splitlines() if line.startswith("clothlab: error: ")]
    assert len(lines) == 1, stderr
    return lines[0][len("clothlab: error: "):]


FLAG_10 = """\
material: {material}
integrator: verlet
scenario:
  plugin: flag
  rows: 10
  cols: 10
dt: 0.0005
steps: 120
precision: {precision}
threads: 1
""".replace("{material}", str(SOURCE_DIR / "configs/materials/cotton.yaml"))
