#!/usr/bin/env bash
# `clothlab --slurm` on a machine without Slurm (PATH without sbatch): one line, exit 1.
set -uo pipefail
clothlab=$1 sweep=$2
empty=$(mktemp -d)
trap 'rm -rf "$empty"' EXIT
message=$(PATH=$empty "$clothlab" --config "$sweep" --out "$empty/out" --slurm 2>&1)
status=$?
echo "exit $status: $message"
[ "$status" -eq 1 ] || { echo "expected exit 1"; exit 1; }
[ "$(printf '%s\n' "$message" | wc -l)" -eq 1 ] || { echo "expected one line"; exit 1; }
[[ "$message" == "clothlab: error: --slurm: sbatch not found on PATH"* ]] || exit 1
[ ! -e "$empty/out" ] || { echo "it wrote results"; exit 1; }
