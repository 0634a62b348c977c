#!/usr/bin/env python3
"""Fuzz harness for the clothlab program: mutated config files, sweep files and command lines.

Each generated input runs in a fresh folder under a wall-clock limit. An input fails when
  crash      the program died by a signal, exited outside 0..3, or a sanitizer/terminate report
             appeared on stderr;
  hang       it outlived the wall-clock limit (each run gets --set timeout=3, so only the
             program itself, not a long simulation, can);
  partial    a temporary file was left behind, or a JSON output does not parse;
  bad error  it exited 1 (bad input) with stderr that is not exactly one line
             "clothlab: error: ..." naming its source (the config file, a --flag or the command
             line).
Prints one line of counts; exits 1 if any input failed (their reproducers go to --failures).
Deterministic for a given --seed.
"""
import argparse
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time

CORPUS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fuzz", "corpus")

SPECIAL_VALUES = [
    "", "0", "-1", "1e309", "nan", "inf", "-0", "1e-320", "0x10", "1,5", "4096", "4097",
    "1e1", "1.5", "99999999999999999999", "true", "[1, 2, 3]", "[]", "{}", "~", "null",
    "\"a\\nb\"", "\"\\xff\"", "'\t'", "a" * 3000, "9" * 400, "&x 1", "*x", "!!binary aGk=",
    "[[1]]", "{a: {b: {c: {d: 1}}}}", "float16", "rk5", "../../etc/passwd", "/dev/zero",
]
SPECIAL_KEYS = [
    "dt", "steps", "duration", "precision", "threads", "timeout", "integrator", "scenario",
    "scenario.rows", "scenario.cols", "integrator.damping", "plugin_params.verlett.damping",
    "stability.interval", "find_max_dt.dt_min", "sweep.mode", "sweep.matrix.dt", "mesh", "?",
    "a.b.c", "[x]", "", "sweep", "sweep.name",
]


def respelled_numbers(rng, text):
    """A valid variant: every number spelt another way (0.002 -> 2e-3, 4 -> 4.0)."""
    import re

    def respell(match):
        value = float(match.group(0))
        return rng.choice(["%r" % value, "%e" % value, "%g" % value])

    return re.sub(r"(?<![\w.])\d+(\.\d+)?(e-?\d+)?(?![\w.])", respell, text).encode()


def yaml_mutation(rng, text):
    lines = text.splitlines()
    if rng.random() < 0.3:
        return respelled_numbers(rng, text)
    choice = rng.randrange(12)
    if choice == 0 and lines:  # replace a value
        i = rng.randrange(len(lines))
        if ":" in lines[i]:
            head = lines[i].split(":", 1)[0]
            lines[i] = head + ": " + rng.choice(SPECIAL_VALUES)
    elif choice == 1 and lines:  # duplicate a line (repeated key)
        i = rng.randrange(len(lines))
        lines.insert(i, lines[i])
    elif choice == 2 and lines:  # delete a line
        del lines[rng.randrange(len(lines))]
    elif choice == 3:  # add a top-level key
        lines.insert(rng.randrange(len(lines) + 1),
                     rng.choice(SPECIAL_KEYS) + ": " + rng.choice(SPECIAL_VALUES))
    elif choice == 4:  # a second document
        lines += ["---", "steps: 5"]
    elif choice == 5:  # alias bomb
        bomb = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"]
        for level in range(1, rng.randrange(2, 9)):
            bomb.append("a%d: &a%d [%s]" % (level, level, ", ".join(["*a%d" % (level - 1)] * 10)))
        lines = bomb + lines
    elif choice == 6 and lines:  # byte flip
        blob = bytearray("\n".join(lines).encode())
        for _ in range(rng.randrange(1, 4)):
            blob[rng.randrange(len(blob))] = rng.randrange(256)
        return bytes(blob)
    elif choice == 7 and lines:  # re-indent a line
        i = rng.randrange(len(lines))
        lines[i] = " " * rng.randrange(0, 7) + lines[i].lstrip()
    elif choice == 8:  # a huge matrix
        axes = rng.choice([3, 17, 20, 63, 64])
        extra = ["    scenario.k%d: [1, 2]" % k for k in range(axes)]
        lines += ["sweep:", "  name: big", "  matrix:", "    integrator: [rk4]",
                  "    dt: [0.001]"] + extra
    elif choice == 9 and lines:  # truncate
        return "\n".join(lines)[: rng.randrange(len("\n".join(lines)) + 1)].encode()
    elif choice == 10:  # a complex key or deep nesting
        lines.append(rng.choice(["? [a, b]\n: 1", "x: " + "{a: " * 40 + "1" + "}" * 40,
                                 "dt: {}", "scenario: {}", "[1]: 2"]))
    else:  # a very long plugin id or sweep name
        lines.append(rng.choice(["integrator: ", "sweep: {name: "]) + "a" * 30000)
    return ("\n".join(lines) + "\n").encode()


def command_mutation(rng, words):
    words = list(words)
    choice = rng.randrange(8)
    if choice == 0 and words:
        words[rng.randrange(len(words))] = rng.choice(SPECIAL_VALUES) or "''"
    elif choice == 1:
        words += ["--set", rng.choice(SPECIAL_KEYS) + "=" + rng.choice(SPECIAL_VALUES)]
    elif choice == 2:
        flag = rng.choice(["--dt", "--steps", "--duration", "--threads", "--precision",
                           "--integrator", "--scenario", "--json", "--state-out", "--config",
                           "--out", "--plugin-path"])
        words += [flag, rng.choice(SPECIAL_VALUES + ["/dev/full", "/dev/null", ".", "fifo"])]
    elif choice == 3 and words:
        del words[rng.randrange(len(words))]
    elif choice == 4:
        words += ["--set", "dt=0.002", "--dt", "0.001"]
    elif choice == 5:
        words += [rng.choice(["--resume", "--find-max-dt", "--quiet", "--bogus", "stray"])]
    elif choice == 6 and words:
        i = rng.randrange(len(words))
        words.insert(i, words[i])
    else:
        words += ["--threads", rng.choice(["4096", "256", "-1", "1e9"])]
    return words


def shell_quote(word):
    return "'" + word.replace("'", "'\\''") + "'"


def generate(rng, corpus_files, command_lines):
    """One input: (config file name or None, config bytes, argument list)."""
    if rng.random() < 0.55:
        name = rng.choice(corpus_files)
        with open(os.path.join(CORPUS, name), "rb") as f:
            text = f.read().decode()
        data = text.encode()
        for _ in range(rng.randrange(1, 3)):
            data = yaml_mutation(rng, data.decode(errors="replace"))
        args = ["--config", name] + (["--out", "results"] if "sweep" in text else [])
        if rng.random() < 0.3:
            args = command_mutation(rng, args)
        return name, data, args
    words = rng.choice(command_lines).split()
    for _ in range(rng.randrange(1, 3)):
        words = command_mutation(rng, words)
    return None, None, words


def names_a_source(line, config_name, args):
    """Whether the error names where the bad input came from: the config file, a flag, an
    argument's value (a file named on the command line) or the command line itself."""
    if config_name is not None and config_name in line:
        return True
    if "--" in line or "command line" in line:
        return True
    return any(len(word) > 1 and word in line for word in args)


def check(result, folder, config_name, args):
    """Returns the failure kind or None."""
    code, err = result
    if code is None:
        return "hang"
    if code < 0 or code > 3:
        return "crash"
    for marker in ("AddressSanitizer", "runtime error:", "terminate called", "LeakSanitizer",
                   "Segmentation fault"):
        if marker in err:
            return "crash"
    for root, _, files in os.walk(folder):
        for name in files:
            path = os.path.join(root, name)
            if ".tmp-" in name or ".tmp." in name:
                return "partial"
            if name.endswith(".json") and not os.path.islink(path):
                try:
                    with open(path, "rb") as f:
                        json.load(f)
                except (ValueError, OSError):
                    return "partial"
    if code == 1:
        lines = err.splitlines()
        if len(lines) != 1 or not lines[0].startswith("clothlab: error: "):
            return "bad error (lines)"
        if not names_a_source(lines[0], config_name, args):
            return "bad error (no source)"
    return None


def run_one(executable, plugin_dir, config_name, data, args, limit_s, work_root):
    folder = tempfile.mkdtemp(prefix="case-", dir=work_root)
    try:
        for name in os.listdir(CORPUS):  # command lines may name the corpus files
            if name.endswith(".yaml"):
                shutil.copy(os.path.join(CORPUS, name), folder)
        if config_name is not None:
            with open(os.path.join(folder, config_name), "wb") as f:
                f.write(data)
        if "fifo" in args:
            os.mkfifo(os.path.join(folder, "fifo"))
        # Every run or case is bounded by the program's own timeout key, so legitimately long
        # work (duration=4096) ends; only the program itself can outlive the harness's limit.
        command = [executable, "--plugin-path", plugin_dir] + args + ["--set", "timeout=3"]
        env = dict(os.environ, UBSAN_OPTIONS="halt_on_error=1", CLOTHLAB_PLUGIN_PATH="")
        try:
            done = subprocess.run(command, cwd=folder, stdin=subprocess.DEVNULL,
                                  capture_output=True, timeout=limit_s, env=env)
            result = (done.returncode, done.stderr.decode(errors="replace"))
        except subprocess.TimeoutExpired:
            result = (None, "")
        return check(result, folder, config_name, args), result
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("executable")
    parser.add_argument("--plugin-dir", default=None)
    parser.add_argument("--count", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=12)
    parser.add_argument("--limit", type=float, default=120.0, help="seconds per input")
    parser.add_argument("--failures", default="fuzz-failures.txt")
    options = parser.parse_args()
    executable = os.path.abspath(options.executable)
    plugin_dir = options.plugin_dir or os.path.join(
        os.path.dirname(os.path.dirname(executable)), "lib", "clothlab", "plugins")
    corpus_files = sorted(n for n in os.listdir(CORPUS) if n.endswith(".yaml"))
    with open(os.path.join(CORPUS, "command_lines.txt")) as f:
        command_lines = [line.strip() for line in f if line.strip()]
    rng = random.Random(options.seed)
    counts = {}
    failures = []
    exit_codes = {}
    start = time.time()
    work_root = tempfile.mkdtemp(prefix="clothlab-fuzz-")
    try:
        for index in range(options.count):
            config_name, data, args = generate(rng, corpus_files, command_lines)
            kind, (code, err) = run_one(executable, plugin_dir, config_name, data, args,
                                        options.limit, work_root)
            exit_codes[code] = exit_codes.get(code, 0) + 1
            if kind:
                counts[kind] = counts.get(kind, 0) + 1
                failures.append("#%d %s exit %s\n  args: %s\n  config %s: %r\n  stderr: %r\n" % (
                    index, kind, code, " ".join(shell_quote(a) for a in args), config_name,
                    data[:2000] if data else None, err[:2000]))
    finally:
        shutil.rmtree(work_root, ignore_errors=True)
    if failures:
        with open(options.failures, "w") as f:
            f.writelines(failures)
    elif os.path.exists(options.failures):
        os.remove(options.failures)
    kinds = ["crash", "hang", "partial", "bad error (lines)", "bad error (no source)"]
    print("fuzz: %d inputs (seed %d) in %.0f s: %s; exit codes %s%s" % (
        options.count, options.seed, time.time() - start,
        ", ".join("%d %s" % (counts.get(k, 0), k) for k in kinds),
        ", ".join("%s: %d" % (k, v) for k, v in sorted(exit_codes.items(), key=str)),
        "; failures in " + options.failures if failures else ""))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
