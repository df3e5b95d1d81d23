"""The documentation runs: every example in docs/*.md is executed, the README stays a front page.

Conventions of the pages:

* A fenced ```python block is executed; the blocks of one page share one namespace, in
  order, in a fresh temporary working directory (holding a link ``meshes`` to the bundled
  scans), so relative outputs land there and never in the checkout.
* A fenced ```console block is a shell session: each line ``$ statue2model ARGS`` (a
  trailing ``\\`` continues it) runs as ``[sys.executable, "-m", "statue2model", *ARGS]`` in
  the same directory and must exit 0; the lines after it, up to the next ``$``, are output
  that must appear in what it printed (whitespace runs compared as one space; a line ``...``
  stands for anything). A console block holds statue2model commands only.
* ```bash, ```text, ```toml blocks are shown, not run (set-up, cluster recipes, formats).
* ``<!-- test: slow -->`` in a page marks its test slow (left out by ``-m "not slow"``);
  ``<!-- test: needs MODULE -->`` skips it when MODULE (an optional extra) does not import.
"""
from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
README = ROOT / "README.md"
PAGES = sorted(DOCS.glob("*.md"))
README_LIMIT = 8192                      # bytes: the README is a front page, the reference is in docs/
COMMAND_TIMEOUT = 600                    # s, one statue2model command of an example

FENCE = re.compile(r"^```([A-Za-z0-9_+-]*)[^\n]*\n(.*?)^```[ \t]*$", re.DOTALL | re.MULTILINE)
MARK = re.compile(r"<!--\s*test:\s*(slow|needs\s+[A-Za-z0-9_.]+)\s*-->")


def blocks(text: str) -> list[tuple[str, str, int]]:
    """(language, body, line number of the opening fence) of every fenced block."""
    return [(m.group(1).lower(), m.group(2), text.count("\n", 0, m.start()) + 1) for m in FENCE.finditer(text)]


def console_steps(body: str) -> list[tuple[str, list[str]]]:
    """[(command line, expected output lines)] of a console block."""
    steps: list[tuple[str, list[str]]] = []
    lines = body.splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("$ "):
            cmd = line[2:]
            while cmd.endswith("\\") and i + 1 < len(lines):
                i += 1
                cmd = cmd[:-1] + " " + lines[i].strip()
            steps.append((cmd.strip(), []))
        elif line.strip() and line.strip() != "...":
            assert steps, f"console output before any '$ ' command: {line!r}"
            steps[-1][1].append(line)
        i += 1
    return steps


def _squash(text: str) -> str:
    return " ".join(text.split())


def run_console(body: str, where: str, cwd: Path) -> None:
    env = dict(os.environ, MPLBACKEND="Agg")
    for cmd, expected in console_steps(body):
        args = shlex.split(cmd, comments=True)
        assert args and args[0] == "statue2model", f"{where}: a console block runs statue2model only, not {cmd!r}"
        proc = subprocess.run([sys.executable, "-m", "statue2model", *args[1:]], cwd=cwd, env=env,
                              capture_output=True, text=True, timeout=COMMAND_TIMEOUT, check=False)
        out = proc.stdout + proc.stderr
        assert proc.returncode == 0, f"{where}: `{cmd}` exited {proc.returncode}:\n{out[-3000:]}"
        shown = _squash(out)
        for line in expected:
            assert _squash(line) in shown, f"{where}: `{cmd}` did not print {line.strip()!r}; it printed:\n{out[-3000:]}"


def run_page(page: Path, cwd: Path) -> int:
    """Execute the page's python and console blocks in ``cwd``; the number run."""
    (cwd / "meshes").symlink_to(ROOT / "meshes", target_is_directory=True)
    namespace: dict = {"__name__": f"docs_{page.stem}"}
    n = 0
    for lang, body, line in blocks(page.read_text(encoding="utf-8")):
        where = f"{page.relative_to(ROOT)}:{line}"
        if lang == "python":
            exec(compile(body, where, "exec"), namespace)  # noqa: S102 - the page's own example
        elif lang == "console":
            run_console(body, where, cwd)
        else:
            continue
        n += 1
    return n


def _page_param(page: Path):
    marks = []
    for m in MARK.finditer(page.read_text(encoding="utf-8")):
        if m.group(1) == "slow":
            marks.append(pytest.mark.slow)
    return pytest.param(page, id=page.stem, marks=marks)


def test_pages_exist():
    expected = {"install", "run", "params", "prototype", "isolator", "dynamics", "crosscheck", "python",
                "benchmarks", "layout"}
    assert expected <= {p.stem for p in PAGES}


@pytest.mark.parametrize("page", [_page_param(p) for p in PAGES])
def test_page_examples_run(page: Path, tmp_path, monkeypatch):
    """Every python and console block of the page runs (and prints what the page shows)."""
    for m in MARK.finditer(page.read_text(encoding="utf-8")):
        if m.group(1).startswith("needs"):
            pytest.importorskip(m.group(1).split()[1])
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    assert run_page(page, tmp_path) >= 1, f"{page.name} has no runnable example (a python or console block)"


def test_readme_is_a_front_page():
    size = len(README.read_bytes())
    assert size <= README_LIMIT, f"README.md is {size} bytes, more than {README_LIMIT}: move reference to docs/"


LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")


@pytest.mark.parametrize("doc", [README, *PAGES], ids=lambda p: p.name)
def test_relative_links_exist(doc: Path):
    links = [u for u in LINK.findall(doc.read_text(encoding="utf-8")) if not re.match(r"[a-z]+:", u)]
    missing = [u for u in links if not (doc.parent / u).exists()]
    assert not missing, f"{doc.name} links to missing files: {missing}"


def test_readme_links_every_page():
    linked = {(README.parent / u).resolve() for u in LINK.findall(README.read_text(encoding="utf-8"))}
    unlinked = [p.name for p in PAGES if p.resolve() not in linked]
    assert not unlinked, f"README.md does not link {unlinked}"


def _subcommands(*args: str) -> set[str]:
    """The sub-commands `statue2model ARGS --help` lists."""
    proc = subprocess.run([sys.executable, "-m", "statue2model", *args, "--help"], capture_output=True, text=True,
                          timeout=120, cwd=ROOT, check=False)
    assert proc.returncode == 0, proc.stderr
    text = proc.stdout.split("positional arguments:", 1)[1].split("options:", 1)[0]
    return set(re.findall(r"^ {4}([a-z][a-z-]*)(?:\s|$)", text, re.MULTILINE))


def _code_text(text: str) -> str:
    """What the page shows as commands: fenced blocks but python, and inline code spans."""
    fenced = "\n".join(body for lang, body, _ in blocks(text) if lang != "python")
    inline = "\n".join(re.findall(r"`([^`]+)`", FENCE.sub("", text)))       # a span may wrap a line
    return fenced + "\n" + inline


def test_named_commands_exist():
    """Every `statue2model CMD` (and `statue2model isolator ACTION`) the README and the docs
    show is a command of `statue2model --help`."""
    commands = _subcommands()
    actions = _subcommands("isolator")
    assert {"run", "props", "slice", "isolator", "crosscheck"} <= commands
    unknown = []
    for doc in [README, *PAGES]:
        code = _code_text(doc.read_text(encoding="utf-8"))
        for cmd, arg in re.findall(r"(?<![\w.-])statue2model[ \t]+([a-z][a-z-]*)(?:[ \t]+([a-z][a-z-]*))?", code):
            if cmd not in commands:
                unknown.append(f"{doc.name}: statue2model {cmd}")
            elif cmd == "isolator" and arg and arg not in actions:
                unknown.append(f"{doc.name}: statue2model isolator {arg}")
    assert not unknown, "commands not in `statue2model --help`: " + ", ".join(sorted(set(unknown)))


def test_console_convention_is_checked(tmp_path):
    """The harness itself: output lines are checked, a failing command fails."""
    body = "$ statue2model config --out - \\\n    # a comment\n[scan]\n...\nunits = \"auto\"\n"
    assert console_steps(body) == [("statue2model config --out -  # a comment", ["[scan]", 'units = "auto"'])]
    with pytest.raises(AssertionError, match="did not print"):
        run_console("$ statue2model config --out -\nno such line\n", "self-test", tmp_path)
    with pytest.raises(AssertionError, match="exited 2"):
        run_console("$ statue2model props no_such_scan.stl\n", "self-test", tmp_path)
    with pytest.raises(AssertionError, match="statue2model only"):
        run_console("$ ls\n", "self-test", tmp_path)
