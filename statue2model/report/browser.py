"""Open a report in headless Chromium: check that its figures load, take a screenshot.

:func:`check_figures` loads the page from disk, lets its ``load`` handler run
(see :mod:`statue2model.report.html`: it writes ``data-figures-total``,
``data-figures-loaded`` and ``data-figures-broken`` on ``<body>``), dumps the DOM
and reads those attributes back. The command line is::

    <chromium> --headless --no-sandbox --disable-gpu --no-first-run --no-default-browser-check
               --disable-extensions --user-data-dir=<fresh temp dir>
               --virtual-time-budget=10000 --dump-dom file:///abs/path/report.html

``--no-sandbox`` is needed when running as root in a container (Chromium refuses to
start otherwise) and where user namespaces are unavailable; the page is our own
file and its Content-Security-Policy allows no network access. ``--headless`` is
needed by the full ``chromium`` and accepted by ``chromium-headless-shell``.
``--virtual-time-budget`` makes Chromium wait (in virtual time, which runs ahead
when the page is idle, so it costs no real time) until the load handler has run.

:func:`check_layout` loads the page in a window as wide as an A4 page (794 px) and reads what the
load handler measured (``data-page-width``, ``data-page-scroll-width``, ``data-overflowing``);
:func:`print_pdf` prints it with ``--print-to-pdf`` (the page's own print style: A4 and its margins).

The browser is found by :func:`find_chromium`: the environment variable
``STATUE2MODEL_CHROMIUM`` (a path or a command name) first, then
``chromium-headless-shell``, ``chromium``, ``chromium-browser``, ``google-chrome``
on ``PATH``. On Debian: ``apt-get install chromium-headless-shell``.

Example
-------
Without a browser the check is replaced by its expected result.

>>> from statue2model.report.browser import FigureCheck, check_figures, find_chromium
>>> from statue2model.report.html import render_report
>>> import tempfile, pathlib
>>> out = render_report({"title": "empty", "sections": []}, pathlib.Path(tempfile.mkdtemp()) / "r.html")
>>> check = check_figures(out) if find_chromium() else FigureCheck(0, 0, ())
>>> check
FigureCheck(total=0, loaded=0, broken=(), missing=0)
>>> check.ok
True
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from html.parser import HTMLParser
from pathlib import Path

from ..io.files import atomic_write

ENV_VAR = "STATUE2MODEL_CHROMIUM"
CANDIDATES = ("chromium-headless-shell", "chromium", "chromium-browser", "google-chrome")
DEBIAN_PACKAGE = "chromium-headless-shell"

_BASE_FLAGS = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--no-first-run",
    "--no-default-browser-check",
    "--disable-extensions",
)


@dataclass(frozen=True)
class FigureCheck:
    """What the browser saw: ``<img>`` elements, those that decoded, alt texts of the others.

    ``missing`` counts figures whose file was absent when the report was rendered
    (they have no ``<img>``; the page shows a note instead).
    """

    total: int
    loaded: int
    broken: tuple[str, ...]
    missing: int = 0

    @property
    def ok(self) -> bool:
        """Every figure is in the page and displayed."""
        return self.loaded == self.total and not self.broken and self.missing == 0


def find_chromium() -> str | None:
    """Path of a Chromium executable, or None.

    ``STATUE2MODEL_CHROMIUM`` wins when set; if it names nothing executable this is
    a ``RuntimeError`` (a misconfiguration should not silently fall back).
    """
    env = os.environ.get(ENV_VAR, "").strip()
    if env:
        found = shutil.which(env)
        if found is None:
            raise RuntimeError(f"{ENV_VAR}={env!r} is not an executable file or a command on PATH")
        return found
    for name in CANDIDATES:
        found = shutil.which(name)
        if found:
            return found
    return None


def _browser(browser: str | None) -> str:
    exe = browser or find_chromium()
    if exe is None:
        raise RuntimeError(
            f"no headless Chromium found (tried {', '.join(CANDIDATES)} on PATH); "
            f"install the Debian package {DEBIAN_PACKAGE} or set {ENV_VAR}"
        )
    return exe


def _run(exe: str, args: list[str], html_path: Path, timeout: float) -> subprocess.CompletedProcess:
    if not html_path.is_file():
        raise RuntimeError(f"no such report file: {html_path}")
    with tempfile.TemporaryDirectory(prefix="statue2model-chromium-") as profile:
        cmd = [exe, *_BASE_FLAGS, f"--user-data-dir={profile}", *args, html_path.resolve().as_uri()]
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, check=False)
        except subprocess.TimeoutExpired:
            raise RuntimeError(f"{Path(exe).name} did not finish within {timeout:g} s on {html_path.name}") from None
        except OSError as exc:
            raise RuntimeError(f"cannot run {exe}: {exc.strerror or exc}") from None
    if proc.returncode != 0:
        raise RuntimeError(
            f"{Path(exe).name} exited with status {proc.returncode} on {html_path.name}: {_last_error(proc.stderr)}"
        )
    return proc


def _last_error(stderr: str) -> str:
    """The most telling line of Chromium's stderr (it logs harmless dbus noise in containers)."""
    lines = [ln.strip() for ln in stderr.splitlines() if ln.strip()]
    useful = [ln for ln in lines if "dbus" not in ln and "bluez" not in ln.lower()]
    return (useful or lines or ["(no message)"])[-1][:300]


class _BodyAttrs(HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.attrs: dict[str, str | None] | None = None

    def handle_starttag(self, tag, attrs):
        if tag == "body" and self.attrs is None:
            self.attrs = dict(attrs)


def parse_figure_attributes(dom: str) -> FigureCheck:
    """Read the ``data-figures-*`` attributes of ``<body>`` from a dumped DOM."""
    parser = _BodyAttrs()
    parser.feed(dom)
    parser.close()
    attrs = parser.attrs
    if attrs is None:
        raise RuntimeError("the browser's DOM dump has no <body>")
    if attrs.get("data-figures-total") is None:
        raise RuntimeError(
            "the page's load handler did not run (no data-figures-total on <body>): "
            "not a statue2model report, or the page did not finish loading"
        )
    try:
        total = int(attrs["data-figures-total"])
        loaded = int(attrs.get("data-figures-loaded") or 0)
        broken = tuple(str(b) for b in json.loads(attrs.get("data-figures-broken") or "[]"))
        missing = int(attrs.get("data-figures-missing") or 0)
    except (ValueError, TypeError) as exc:
        raise RuntimeError(f"unreadable data-figures-* attributes on <body>: {exc}") from None
    return FigureCheck(total=total, loaded=loaded, broken=broken, missing=missing)


def dump_dom(html_path: str | os.PathLike, timeout: float = 30, browser: str | None = None) -> str:
    """The DOM of ``html_path`` after headless Chromium loaded it and ran its scripts."""
    exe = _browser(browser)
    budget_ms = int(max(1.0, min(10.0, timeout / 2)) * 1000)
    return _run(exe, [f"--virtual-time-budget={budget_ms}", "--dump-dom"], Path(html_path), timeout).stdout


def body_attributes(dom: str) -> dict:
    """The attributes of ``<body>`` in a dumped DOM (e.g. data-verdict-height)."""
    parser = _BodyAttrs()
    parser.feed(dom)
    parser.close()
    return dict(parser.attrs or {})


A4_WIDTH_PX = 794
"""The width of an A4 page in CSS pixels (210 mm at 96 dpi): the narrowest window the report is laid out for."""


@dataclass(frozen=True)
class LayoutCheck:
    """How the page fits its window: the window's content width (px), the page's scroll width (px),
    and what sticks out to the right (a table by its caption, another element by tag#id.class)."""

    width: int
    scroll_width: int
    overflowing: tuple[str, ...]

    @property
    def ok(self) -> bool:
        """Nothing needs a horizontal scroll bar."""
        return self.scroll_width <= self.width and not self.overflowing


def parse_layout_attributes(dom: str) -> LayoutCheck:
    """Read the ``data-page-width``, ``data-page-scroll-width`` and ``data-overflowing`` attributes
    of ``<body>`` from a dumped DOM (written by the page's load handler)."""
    attrs = body_attributes(dom)
    if attrs.get("data-page-width") is None:
        raise RuntimeError("the page's load handler did not measure the layout (no data-page-width on <body>)")
    try:
        return LayoutCheck(int(attrs["data-page-width"]), int(attrs.get("data-page-scroll-width") or 0),
                           tuple(str(x) for x in json.loads(attrs.get("data-overflowing") or "[]")))
    except (ValueError, TypeError) as exc:
        raise RuntimeError(f"unreadable layout attributes on <body>: {exc}") from None


def check_layout(
    html_path: str | os.PathLike, width: int = A4_WIDTH_PX, height: int = 1123, timeout: float = 30,
    browser: str | None = None,
) -> LayoutCheck:
    """Load ``html_path`` in a ``width`` x ``height`` window (default: A4 at 96 dpi) and report what
    overflows it horizontally. Raises ``RuntimeError`` as :func:`check_figures` does."""
    exe = _browser(browser)
    budget_ms = int(max(1.0, min(10.0, timeout / 2)) * 1000)
    dom = _run(exe, [f"--window-size={int(width)},{int(height)}", f"--virtual-time-budget={budget_ms}",
                     "--dump-dom"], Path(html_path), timeout).stdout
    return parse_layout_attributes(dom)


def print_pdf(
    html_path: str | os.PathLike, pdf_path: str | os.PathLike, timeout: float = 60, browser: str | None = None
) -> Path:
    """Print ``html_path`` to ``pdf_path`` as the browser's print dialog would (the page's print style:
    A4, its own margins, no browser header or footer). Raises ``RuntimeError`` when no PDF is written."""
    exe = _browser(browser)
    pdf_path = Path(pdf_path)

    def write(tmp: Path) -> None:
        with tempfile.TemporaryDirectory(prefix=".pdf-", dir=tmp.parent) as d:
            out = Path(d) / "report.pdf"
            args = ["--no-pdf-header-footer", "--print-to-pdf-no-header", "--virtual-time-budget=5000",
                    f"--print-to-pdf={out}"]
            _run(exe, args, Path(html_path), timeout)
            if not out.is_file() or not out.read_bytes()[:5] == b"%PDF-":
                raise RuntimeError(f"{Path(exe).name} wrote no PDF of {Path(html_path).name}")
            os.replace(out, tmp)

    return atomic_write(pdf_path, write)


def check_figures(
    html_path: str | os.PathLike, timeout: float = 30, browser: str | None = None
) -> FigureCheck:
    """Load ``html_path`` in headless Chromium and report which figures displayed.

    Raises ``RuntimeError`` (one line) when no browser is found, the browser fails
    or times out, or the page's load handler did not run.
    """
    return parse_figure_attributes(dump_dom(html_path, timeout, browser))


def screenshot(
    html_path: str | os.PathLike,
    png_path: str | os.PathLike,
    width: int = 1200,
    height: int = 2000,
    timeout: float = 30,
    browser: str | None = None,
) -> Path:
    """Save a ``width`` x ``height`` PNG of the top of the page (for a person to look at)."""
    exe = _browser(browser)
    png_path = Path(png_path)

    def write(tmp: Path) -> None:
        # Chromium picks the image format from the extension, so shoot to a .png in a private dir
        with tempfile.TemporaryDirectory(prefix=".shot-", dir=tmp.parent) as d:
            shot = Path(d) / "shot.png"
            args = [f"--window-size={int(width)},{int(height)}", "--hide-scrollbars",
                    "--virtual-time-budget=5000", f"--screenshot={shot}"]
            _run(exe, args, Path(html_path), timeout)
            if not shot.is_file() or shot.stat().st_size == 0:
                raise RuntimeError(f"{Path(exe).name} wrote no screenshot of {Path(html_path).name}")
            os.replace(shot, tmp)

    return atomic_write(png_path, write)
