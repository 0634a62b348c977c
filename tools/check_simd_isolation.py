#!/usr/bin/python3
"""Checks that a portable build's wide SIMD code stays in its targets' namespaces.

  check_simd_isolation.py FILE...

A portable build compiles the engine and xpbd's grid sweep once per SIMD target, each copy in a
namespace of its own (docs/reference/simd-dispatch.md). Should a function compiled for AVX2 or
AVX-512 lose that namespace (an inline function of a header the prelude left out, say), the
linker may keep its copy for every caller, and a CPU without the target would stop on an
illegal instruction. This disassembles each file (objdump) and fails, naming the functions,
where a function outside the `avx2` and `avx512` namespaces and entry points uses a ymm or zmm
register, which the portable target never does.
"""
import re
import subprocess
import sys

FUNCTION = re.compile(r"^[0-9a-f]+ <(.*)>:$")
WIDE_REGISTER = re.compile(r"%[yz]mm[0-9]")
# Demangled, or still mangled where objdump cannot demangle the name (some lambdas' closures):
# a function of, or local to a function of, a target's namespace.
TARGET = re.compile(r"::(avx2|avx512)::|_(avx2|avx512)\(|^_ZZ?N8clothlab(7builtin|6detail)(4avx2|6avx512)")


def leaks(path):
    listing = subprocess.run(["objdump", "-d", "--no-show-raw-insn", "-C", path], check=True,
                             capture_output=True, text=True).stdout
    found, function = set(), None
    for line in listing.splitlines():
        match = FUNCTION.match(line)
        if match:
            function = match.group(1)
        elif function and WIDE_REGISTER.search(line) and not TARGET.search(function):
            found.add(function)
    return sorted(found)


def main(paths):
    if not paths:
        sys.exit(__doc__)
    status = 0
    for path in paths:
        found = leaks(path)
        if found:
            status = 1
            print(f"{path}: {len(found)} function(s) outside the SIMD targets' namespaces use "
                  f"ymm/zmm registers: {'; '.join(found[:5])}")
        else:
            print(f"{path}: no wide SIMD code outside the targets' namespaces")
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
