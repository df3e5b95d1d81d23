"""The documentation runs: every example in docs/*.md is executed, the README stays a front page.

Conventions of the pages:

* A fenced ```python block is executed; the blocks of one page share one namespace, in
  order, in a fresh temporary working directory (holding a link ``meshes`` to the bundled
  scans), so relative outputs land there and never in the checkout.
* A ```python block with an ``if __name__ == "__main__":`` guard is a whole script: it is
  saved in that directory and run as ``python SCRIPT.py`` (a separate process, as a user
  runs it: worker pools started with ``spawn`` import it again), and must exit 0.
* A fenced ```console block is a shell session: each line ``$ statue2model ARGS`` (a
  trailing ``\\`` continues it) runs as ``[sys.executable, "-m", "statue2model", *ARGS]`` in
  the same directory and must exit 0; the lines after it, up to the next ``$``, are output
  that must appear in what it printed (whitespace runs compared as one space; a line ``...``
  stands for anything). A console block holds statue2model commands only.
* ```bash, ```text, ```toml blocks are shown, not run (set-up, cluster recipes, formats);
  each ``statue2model ...`` line of a bash block must parse with the command line's own
  parser (the options and their values exist). The README's example (a bash block) runs in
  full in :func:`test_readme_example_runs` (slow).
* Nothing an example does may land in the checkout: each test compares the checkout's
  untracked and ignored files (caches aside) before and after (:func:`checkout_untouched`).
* ``<!-- test: slow -->`` in a page marks its test slow (left out by ``-m "not slow"``);
  ``<!-- test: needs MODULE -->`` skips it when MODULE (an optional extra) does not import.
"""
from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
README = ROOT / "README.md"
PAGES = sorted(DOCS.glob("*.md"))
README_LIMIT = 8192                      # bytes: the README is a front page, the reference is in docs/
COMMAND_TIMEOUT = 600                    # s, one statue2model command of an example
MAIN_GUARD = re.compile(r"^if __name__ == [\"']__main__[\"']\s*:", re.MULTILINE)

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


def run_script(body: str, where: str, cwd: Path, name: str) -> str:
    """Save a python block as ``cwd/name`` and run it as ``python name`` in ``cwd``; its output.
    It must exit 0."""
    script = cwd / name
    script.write_text(body, encoding="utf-8")
    env = dict(os.environ, MPLBACKEND="Agg")
    proc = subprocess.run([sys.executable, name], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=COMMAND_TIMEOUT, check=False)
    out = proc.stdout + proc.stderr
    assert proc.returncode == 0, f"{where}: the script `python {name}` exited {proc.returncode}:\n{out[-3000:]}"
    return out


def run_page(page: Path, cwd: Path) -> int:
    """Execute the page's python and console blocks in ``cwd``; the number run."""
    (cwd / "meshes").symlink_to(ROOT / "meshes", target_is_directory=True)
    namespace: dict = {"__name__": f"docs_{page.stem}"}
    n = 0
    for lang, body, line in blocks(page.read_text(encoding="utf-8")):
        where = f"{page.relative_to(ROOT)}:{line}"
        if lang == "python" and MAIN_GUARD.search(body):
            run_script(body, where, cwd, f"{page.stem}_{line}.py")
        elif lang == "python":
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


_CACHES = re.compile(r"(^|/)(__pycache__|\.pytest_cache|\.hypothesis|[^/]*\.egg-info)(/|$)")


def checkout_files(root: Path = ROOT) -> set[str] | None:
    """The untracked and ignored files of the git checkout at ``root`` (one by one; the
    virtual environment and the caches of Python, pytest, hypothesis and numba left out), or
    None when ``root`` is not a git checkout (an installed copy: nothing to compare)."""
    try:
        proc = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "--ignored",
                               "--untracked-files=all", "--", ".", ":(exclude).venv"],
                              capture_output=True, text=True, timeout=120, check=False)
    except (OSError, subprocess.TimeoutExpired):
        return None
    if proc.returncode != 0:
        return None
    return {line[3:] for line in proc.stdout.splitlines()
            if line[:2] in ("??", "!!") and not _CACHES.search(line[3:])}


@pytest.fixture
def checkout_untouched():
    """The test must leave no new file in the checkout (its examples run in a temporary folder)."""
    before = checkout_files()
    yield
    if before is None:
        return
    new = sorted(checkout_files() - before)
    assert not new, f"the examples wrote {len(new)} file(s) into the checkout {ROOT}: {new[:20]}"


@pytest.mark.parametrize("page", [_page_param(p) for p in PAGES])
def test_page_examples_run(page: Path, tmp_path, monkeypatch, checkout_untouched):
    """Every python and console block of the page runs (and prints what the page shows)."""
    for m in MARK.finditer(page.read_text(encoding="utf-8")):
        if m.group(1).startswith("needs"):
            pytest.importorskip(m.group(1).split()[1])
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    assert run_page(page, tmp_path) >= 1, f"{page.name} has no runnable example (a python or console block)"


def _readme_example() -> str:
    """The bash block of the README's '## Example' section."""
    section = README.read_text(encoding="utf-8").split("\n## Example", 1)[1].split("\n## ", 1)[0]
    found = [body for lang, body, _ in blocks(section) if lang == "bash"]
    assert found, "README.md: the Example section has no bash block"
    return found[0]


EDIT = re.compile(r"\[(\w+)\]\s+(\w+)\s*=\s*(\"[^\"]*\"|[-+0-9.eE]+)")


@pytest.mark.slow
def test_readme_example_runs(tmp_path, checkout_untouched):
    """The README's example, as a user runs it, in a fresh folder: its statue2model commands in
    order, with the edits its comment names applied to project.toml in between; every command
    exits 0 and the run writes its report (and used the edited values)."""
    import tomllib

    import tomli_w

    (tmp_path / "meshes").symlink_to(ROOT / "meshes", target_is_directory=True)
    env = dict(os.environ, MPLBACKEND="Agg")
    steps = []
    for line in _readme_example().splitlines():
        if line.startswith("statue2model "):
            steps.append(("run", shlex.split(line, comments=True)))
        elif line.startswith("# edit project.toml"):
            steps.append(("edit", EDIT.findall(line)))
    assert [kind for kind, _ in steps] == ["run", "edit", "run"], steps
    edits = steps[1][1]
    assert {(s, k) for s, k, _ in edits} == {("scan", "density"), ("isolator", "spectrum"), ("building", "floor"),
                                             ("building", "storeys"), ("building", "height")}, edits
    times = []
    for kind, what in steps:
        if kind == "edit":
            path = tmp_path / "project.toml"
            data = tomllib.loads(path.read_text(encoding="utf-8"))
            for sec, key, value in what:
                data[sec][key] = tomllib.loads(f"v = {value}")["v"]
            path.write_text(tomli_w.dumps(data), encoding="utf-8")
            continue
        t0 = time.perf_counter()
        proc = subprocess.run([sys.executable, "-m", "statue2model", *what[1:]], cwd=tmp_path, env=env,
                              capture_output=True, text=True, timeout=COMMAND_TIMEOUT, check=False)
        times.append(time.perf_counter() - t0)
        out = proc.stdout + proc.stderr
        assert proc.returncode == 0, f"README example: `{shlex.join(what)}` exited {proc.returncode}:\n{out[-3000:]}"
    run = steps[-1][1]
    out_dir = tmp_path / run[run.index("--out") + 1]
    assert (out_dir / "report.html").is_file(), f"README example: no {out_dir / 'report.html'}"
    resolved = tomllib.loads((out_dir / "config.toml").read_text(encoding="utf-8"))
    for sec, key, value in edits:
        assert resolved[sec][key] == tomllib.loads(f"v = {value}")["v"], (sec, key, resolved[sec][key])
    print(f"README example: {shlex.join(run)} took {times[-1]:.1f} s")


def test_bash_commands_parse():
    """Every statue2model line of a bash block (shown, not run) is a valid command line: its
    options and their values exist (`statue2model run meshes/ --scheduler ...` parses)."""
    from statue2model.cli import build_parser
    from statue2model.cli.argtypes import join_dash_values

    bad = []
    for doc in [README, *PAGES]:
        for lang, body, line in blocks(doc.read_text(encoding="utf-8")):
            if lang != "bash":
                continue
            text = re.sub(r"\\\n\s*", " ", body)                 # join continued lines
            for cmd in text.splitlines():
                cmd = cmd.strip()
                for prefix in (".venv/bin/statue2model", "statue2model"):
                    if cmd.startswith(prefix + " ") or cmd == prefix:
                        args = shlex.split(cmd.split("&&")[0], comments=True)[1:]
                        try:
                            build_parser().parse_args(join_dash_values(args))
                        except SystemExit:
                            bad.append(f"{doc.name}:{line}: {cmd}")
                        break
    assert not bad, "bash examples that statue2model's parser refuses:\n" + "\n".join(bad)


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
    """The harness itself: output lines are checked, a failing command fails, a script with a
    main guard runs in its own process (and fails when it fails), a new file in a checkout is seen."""
    assert run_script("import os\nif __name__ == '__main__':\n    print(os.getcwd())\n", "self-test", tmp_path,
                      "ok.py").strip() == str(tmp_path)
    with pytest.raises(AssertionError, match="exited 1"):
        run_script("if __name__ == '__main__':\n    raise SystemExit(1)\n", "self-test", tmp_path, "bad.py")
    assert MAIN_GUARD.search('x = 1\n\nif __name__ == "__main__":\n    main()\n')
    assert not MAIN_GUARD.search("print(__name__)\n")
    repo = tmp_path / "repo"
    repo.mkdir()
    if subprocess.run(["git", "init", "-q", str(repo)], capture_output=True, check=False).returncode == 0:
        (repo / ".gitignore").write_text("outputs/\n__pycache__/\n")
        (repo / "__pycache__").mkdir()
        (repo / "__pycache__" / "m.pyc").write_text("")
        before = checkout_files(repo)
        (repo / "outputs").mkdir()
        (repo / "outputs" / "report.html").write_text("")
        (repo / "project.toml").write_text("")
        assert checkout_files(repo) - before == {"outputs/report.html", "project.toml"}
    body = "$ statue2model config --out - \\\n    # a comment\n[scan]\n...\nunits = \"auto\"\n"
    assert console_steps(body) == [("statue2model config --out -  # a comment", ["[scan]", 'units = "auto"'])]
    with pytest.raises(AssertionError, match="did not print"):
        run_console("$ statue2model config --out -\nno such line\n", "self-test", tmp_path)
    with pytest.raises(AssertionError, match="exited 2"):
        run_console("$ statue2model props no_such_scan.stl\n", "self-test", tmp_path)
    with pytest.raises(AssertionError, match="statue2model only"):
        run_console("$ ls\n", "self-test", tmp_path)
