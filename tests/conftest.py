import os
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))

CHECKOUT_OUTPUTS = Path(__file__).resolve().parents[1] / "outputs"


def _outputs_listing(root: Path = CHECKOUT_OUTPUTS) -> dict:
    """{relative path: mtime_ns (files) or None (folders)} of everything under ``root``
    but ``.gitkeep``."""
    found = {}
    for folder, dirs, files in os.walk(root):
        for name in dirs + files:
            p = Path(folder) / name
            rel = p.relative_to(root).as_posix()
            if rel == ".gitkeep":
                continue
            try:
                found[rel] = None if name in dirs else p.lstat().st_mtime_ns
            except FileNotFoundError:
                pass
    return found


@pytest.fixture(scope="session", autouse=True)
def checkout_outputs_untouched():
    """The suite never writes into the checkout's outputs/: a command's default output
    (outputs/<name>/) must be sent to tmp_path (--out/--json, or monkeypatch.chdir)."""
    before = _outputs_listing()
    yield
    after = _outputs_listing()
    changed = sorted(k for k in before.keys() | after.keys() if before.get(k, "-") != after.get(k, "-"))
    if changed:
        more = f" and {len(changed) - 8} more" if len(changed) > 8 else ""
        pytest.fail(f"the tests wrote into the checkout's {CHECKOUT_OUTPUTS}: {', '.join(changed[:8])}{more} "
                    "(give the command --out/--json under tmp_path or monkeypatch.chdir(tmp_path))", pytrace=False)


@pytest.fixture(scope="session", autouse=True)
def record_set_cache(tmp_path_factory):
    """One folder of matched record sets for the session (pipeline/record_cache.py): the tests
    share the sets they match, as a user's runs do, and never write into the user's own cache.
    Set in the environment, so the commands the tests start use it too."""
    from statue2model.pipeline.record_cache import ENV

    before = os.environ.get(ENV)
    os.environ[ENV] = str(tmp_path_factory.mktemp("record_sets"))
    yield
    if before is None:
        os.environ.pop(ENV, None)
    else:
        os.environ[ENV] = before


@pytest.fixture(scope="module")
def chromium() -> str:
    """The headless Chromium the report tests use: skipped without one, a failure under CI."""
    from statue2model.report.browser import DEBIAN_PACKAGE, ENV_VAR, find_chromium

    exe = find_chromium()
    if exe is None:
        msg = (f"no headless Chromium on PATH: install the Debian package {DEBIAN_PACKAGE} "
               f"(.ci/install does) or set {ENV_VAR}")
        if os.environ.get("CI"):
            pytest.fail(msg)
        pytest.skip(msg)
    return exe
