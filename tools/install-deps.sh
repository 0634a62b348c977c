#!/usr/bin/env bash
# Installs the Debian 12 packages ClothLab needs (skips apt when all are present).
#   install-deps.sh run    what building and running needs (tools/run.sh): compiler, libraries,
#                          and npm's three.js for `clothlab view`
#   install-deps.sh test   that, plus what the tests need (tools/test.sh, CI): GoogleTest and
#                          Benchmark, Python with matplotlib and VTK, the Python module's
#                          pybind11, pytest and venv, Chromium for the viewer's browser test,
#                          Slurm for the --slurm test, Bullet for the peer benchmark
#                          (bench/peer_bullet.cpp)
set -euo pipefail
profile="${1:-test}"
packages=(
  cmake ninja-build g++ make pkg-config
  libboost-dev libboost-program-options-dev libboost-filesystem-dev
  libeigen3-dev libyaml-cpp-dev nlohmann-json3-dev libsqlite3-dev libsuitesparse-dev
  libassimp-dev
)
case "$profile" in
  run) ;;
  test)
    packages+=(
      libgtest-dev libgmock-dev libbenchmark-dev binutils libbullet-dev
      python3 python3-matplotlib python3-vtk9 python3-numpy python3-pil chromium
      python3-dev pybind11-dev python3-pytest python3-venv python3-setuptools python3-wheel
      slurmctld slurmd slurm-client munge
    )
    ;;
  *)
    echo "install-deps.sh: unknown profile '$profile'; allowed: run, test" >&2
    exit 1
    ;;
esac
# The viewer's three.js comes from npm (host/viewer/package-lock.json). Debian's nodejs and
# npm unless a Node.js with npm is already installed (e.g. from NodeSource).
command -v npm >/dev/null || packages+=(nodejs npm)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}" >&2
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
# Exactly the locked three.js, into host/viewer/node_modules (CMake copies it into the build).
viewer="$(dirname "$0")/../host/viewer"
if [ ! -f "$viewer/node_modules/three/build/three.min.js" ] ||
  [ "$viewer/package-lock.json" -nt "$viewer/node_modules/.package-lock.json" ]; then
  (cd "$viewer" && npm ci --no-audit --no-fund --loglevel=error)
fi
