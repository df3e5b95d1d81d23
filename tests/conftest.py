import os
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))


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
