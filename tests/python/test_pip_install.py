"""`pip install --no-build-isolation .` into a fresh venv gives a working module that finds its
plugins inside the package, not in the build tree."""

import os
import pathlib
import subprocess
import sys

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[2]

CHECK = """
import pathlib, sys, clothlab
package = pathlib.Path(clothlab.__file__).parent
assert package.is_relative_to(sys.prefix), package
listing = clothlab.plugins()
assert listing["search_path"] == str(package / "plugins"), listing["search_path"]
sim = clothlab.Simulation({"integrator": "verlet", "scenario": "sheet", "steps": 10})
assert sim.step(10) == 10 and sim.finished
print("ok", sim.verdict)
"""


def test_pip_install_into_a_fresh_venv(tmp_path):
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)
    environment = {key: value for key, value in os.environ.items()
                   if key not in ("PYTHONPATH", "CLOTHLAB_PLUGIN_PATH")}
    subprocess.run([str(venv / "bin" / "pip"), "install", "--no-build-isolation", "--no-index",
                    "--quiet", str(SOURCE_DIR)], check=True, env=environment, timeout=600)
    done = subprocess.run([str(venv / "bin" / "python"), "-c", CHECK], cwd=tmp_path,
                          env=environment, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("ok stable: 10 steps")
