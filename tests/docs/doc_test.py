#!/usr/bin/env python3
"""The doc test: README.md and docs/ cannot drift from the repository and the program.

  doc_test.py links ROOT
      Every relative link in README.md and docs/**/*.md resolves: the file or folder exists
      and a #anchor names a heading of the target page (GitHub's slugs); none leads into lab/,
      the notebook, which is not documentation. A code block marked
        <!-- doc-test: excerpt of PATH -->
      is quoted from PATH (relative to ROOT): its lines, stripped, appear there in the same order
      (a line "..." stands for lines left out), so a quoted example cannot drift from its source.
  doc_test.py commands ROOT CLOTHLAB
      Every `clothlab ...` line in a sh/bash code block of README.md and docs/guide/*.md is
      accepted by CLOTHLAB (the built program): run to its end, in a scratch folder that sees
      the repository's configs/, examples/ and assets/ and the build (build/bin/clothlab is
      CLOTHLAB), each block's commands in order so that later ones see earlier outputs.
      An HTML comment on the line before a block changes how its commands run:
        <!-- doc-test: dry-run -->        each gets --dry-run: checked, not stepped (minutes
                                          long runs, --choose, Slurm)
        <!-- doc-test: exit=3 -->         the exit code the block's commands must give
        <!-- doc-test: skip: REASON -->   not run here; REASON says what tests it instead
      A command that runs past TIMEOUT_S fails and asks for the dry-run marker.
  doc_test.py selftest CLOTHLAB
      Proves the checks can fail: a fixture with a broken link, a broken anchor, a link into lab/,
      an excerpt out of order and a rejected command must give exactly those five findings.
"""
import os
import re
import shlex
import subprocess
import sys
import tempfile
from pathlib import Path

TIMEOUT_S = 120
MARKER = re.compile(r"^<!--\s*doc-test:\s*(dry-run|exit=(\d+)|skip:\s*\S.*?)\s*-->$")
EXCERPT = re.compile(r"^<!--\s*doc-test:\s*excerpt of\s+(\S+)\s*-->$")
FENCE = re.compile(r"^(```+|~~~+)\s*([\w+-]*)")
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
HTML_LINK = re.compile(r"""<(?:img|a)\b[^>]*?\b(?:src|href)=["']([^"']+)["']""")
PROGRAM = re.compile(r"^(?:\S*/)?clothlab$")


def pages(root, folders):
    found = [root / "README.md"] if (root / "README.md").exists() else []
    for folder in folders:
        found += sorted((root / folder).rglob("*.md"))
    return found


def prose_lines(text, keep_code=False):
    """(line number, line) outside code blocks; inline code removed unless keep_code."""
    fence = None
    for number, line in enumerate(text.splitlines(), 1):
        match = FENCE.match(line.strip())
        if match:
            if fence is None:
                fence = match.group(1)[0] * 3
            elif line.strip().startswith(fence):
                fence = None
            continue
        if fence is None:
            yield number, line if keep_code else re.sub(r"`[^`]*`", "", line)


def slug(heading):
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"`|\*\*|__", "", heading.strip().lower())
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)  # a link keeps its text
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(page):
    seen = {}
    result = set()
    for _, line in prose_lines(page.read_text(encoding="utf-8"), keep_code=True):
        match = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if not match:
            continue
        base = slug(match.group(1))
        count = seen.get(base, 0)
        seen[base] = count + 1
        result.add(base if count == 0 else f"{base}-{count}")
    return result


def check_links(root, folders=("docs",)):
    root = root.resolve()
    findings = []
    anchor_cache = {}
    for page in pages(root, folders):
        findings += check_excerpts(root, page)
        for number, line in prose_lines(page.read_text(encoding="utf-8")):
            for target in LINK.findall(line) + HTML_LINK.findall(line):
                if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # http:, mailto:, file:
                    continue
                where = f"{page.relative_to(root)}:{number}: link {target}"
                path_part, _, anchor = target.partition("#")
                resolved = (page.parent / path_part).resolve() if path_part else page
                if not resolved.exists():
                    findings.append(f"{where}: no such file {resolved}")
                    continue
                if (root / "lab") in resolved.parents or resolved == root / "lab":
                    findings.append(f"{where}: cites the lab notebook; cite docs/ instead")
                    continue
                if anchor and resolved.suffix == ".md":
                    if resolved not in anchor_cache:
                        anchor_cache[resolved] = anchors(resolved)
                    if anchor not in anchor_cache[resolved]:
                        findings.append(f"{where}: no heading #{anchor} in {resolved.name}")
    return findings


def check_excerpts(root, page):
    """Findings for the blocks of page marked as excerpts whose lines are not in their source."""
    findings = []
    lines = page.read_text(encoding="utf-8").splitlines()
    for index, line in enumerate(lines):
        marker = EXCERPT.match(line.strip())
        if not marker or index + 1 >= len(lines) or not FENCE.match(lines[index + 1].strip()):
            continue
        where = f"{page.relative_to(root)}:{index + 2}: excerpt of {marker.group(1)}"
        source = root / marker.group(1)
        if not source.is_file():
            findings.append(f"{where}: no such file")
            continue
        wanted = []
        for body_line in lines[index + 2:]:
            if body_line.strip().startswith("```"):
                break
            if body_line.strip() and body_line.strip() != "...":
                wanted.append(body_line.strip())
        available = iter(l.strip() for l in source.read_text(encoding="utf-8").splitlines())
        for wanted_line in wanted:
            if not any(wanted_line == have for have in available):
                findings.append(f"{where}: line not in the source (in this order): {wanted_line}")
                break
    return findings


def command_blocks(page):
    """Yields (line number, marker, commands) per sh/bash block; a command is a list of words."""
    lines = page.read_text(encoding="utf-8").splitlines()
    index = 0
    while index < len(lines):
        match = FENCE.match(lines[index].strip())
        if not match:
            index += 1
            continue
        fence, language = match.group(1), match.group(2)
        previous = lines[index - 1].strip() if index > 0 else ""
        marker = MARKER.match(previous)
        start = index + 1
        index += 1
        body = []
        while index < len(lines) and not lines[index].strip().startswith(fence[0] * 3):
            body.append(lines[index])
            index += 1
        index += 1
        if language not in ("sh", "bash", "shell", "console"):
            continue
        commands = []
        joined = "\n".join(body).replace("\\\n", " ")
        for offset, line in enumerate(joined.splitlines()):
            line = line.strip()
            if line.startswith("$ "):
                line = line[2:]
            try:
                words = shlex.split(line, comments=True)
            except ValueError as error:
                commands.append((start + offset, None, f"unparsable: {error}"))
                continue
            if words and PROGRAM.match(words[0]):
                commands.append((start + offset, words[1:], line))
        if commands:
            yield start, marker, commands


def check_commands(root, clothlab, folders=("docs/guide",)):
    findings = []
    build = Path(clothlab).resolve().parent.parent
    for page in pages(root, folders):
        with tempfile.TemporaryDirectory(prefix="doc-test-") as scratch:
            for name in ("configs", "examples", "assets"):
                os.symlink(root / name, Path(scratch) / name)
            os.symlink(build, Path(scratch) / "build")
            for start, marker, commands in command_blocks(page):
                if marker and marker.group(1).startswith("skip"):
                    print(f"{page.relative_to(root)}:{start}: skipped ({marker.group(1)})")
                    continue
                dry_run = bool(marker) and marker.group(1) == "dry-run"
                expected = int(marker.group(2)) if marker and marker.group(2) else 0
                for number, words, line in commands:
                    where = f"{page.relative_to(root)}:{number}: {line}"
                    if words is None:
                        findings.append(f"{where}: {line}")
                        continue
                    words = [os.path.expandvars(word.replace("$PWD", scratch)) for word in words]
                    if dry_run and words[:1] != ["view"]:
                        words.append("--dry-run")
                    try:
                        done = subprocess.run([clothlab] + words, cwd=scratch, capture_output=True,
                                              text=True, timeout=TIMEOUT_S)
                    except subprocess.TimeoutExpired:
                        findings.append(f"{where}: still running after {TIMEOUT_S} s; mark its "
                                        "block <!-- doc-test: dry-run -->")
                        continue
                    if done.returncode != expected:
                        error = (done.stderr.strip().splitlines() or ["(no output)"])[-1]
                        findings.append(f"{where}: exit {done.returncode}, expected {expected}: "
                                        f"{error}")
                    else:
                        print(f"ok {'(dry run) ' if dry_run else ''}{where}")
    return findings


def selftest(clothlab):
    with tempfile.TemporaryDirectory(prefix="doc-test-fixture-") as folder:
        root = Path(folder)
        for name in ("configs", "examples", "lab"):
            (root / name).mkdir()
        (root / "lab" / "notes.md").write_text("# Notes\n", encoding="utf-8")
        (root / "examples" / "step.cpp").write_text("void step() {\n  a();\n  b();\n}\n",
                                                    encoding="utf-8")
        (root / "docs" / "guide").mkdir(parents=True)
        (root / "README.md").write_text(
            "# Fixture\n\n## A heading, with `code`\n\n"
            "[good](docs/guide/page.md#the-page) [anchor](#a-heading-with-code)\n"
            "[missing](docs/nowhere.md) [bad anchor](docs/guide/page.md#no-such-heading)\n"
            "[notebook](lab/notes.md)\n\n"
            "<!-- doc-test: excerpt of examples/step.cpp -->\n```cpp\nvoid step() {\n  a();\n"
            "  ...\n}\n```\n\n"
            "<!-- doc-test: excerpt of examples/step.cpp -->\n```cpp\n  b();\n  a();\n```\n"
            "`[inline code](not/a/link.md)`\n", encoding="utf-8")
        (root / "docs" / "guide" / "page.md").write_text(
            "# The page\n\n```sh\nbuild/bin/clothlab --help\n"
            "build/bin/clothlab --integrator=no-such-integrator --scenario=flag\n```\n\n"
            "<!-- doc-test: dry-run -->\n```sh\nbuild/bin/clothlab --scenario=flag\n```\n",
            encoding="utf-8")
        links = check_links(root)
        commands = check_commands(root, clothlab)
    expected_links = ["docs/nowhere.md", "#no-such-heading", "lab/notes.md", "line not in the source"]
    ok = (len(links) == 4 and all(any(e in f for f in links) for e in expected_links)
          and len(commands) == 1 and "no-such-integrator" in commands[0])
    for finding in links + commands:
        print("fixture finding:", finding)
    if not ok:
        print("FAIL: the checks did not find exactly the fixture's five faults")
    return 0 if ok else 1


def main(argv):
    if len(argv) >= 3 and argv[1] == "links":
        findings = check_links(Path(argv[2]).resolve())
    elif len(argv) >= 4 and argv[1] == "commands":
        findings = check_commands(Path(argv[2]).resolve(), str(Path(argv[3]).resolve()))
    elif len(argv) >= 3 and argv[1] == "selftest":
        return selftest(str(Path(argv[2]).resolve()))
    else:
        print(__doc__, file=sys.stderr)
        return 2
    for finding in findings:
        print(finding)
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
