"""Shared fixtures: the real meshes of ../shared/data (or $MESHSMITH_DATA), skipped when absent.

Under scripts/test_wheel.sh, $MESHSMITH_WHEEL_TEST names the wheel under test, and the session
refuses to start unless meshsmith is imported from the wheel's install (meshsmith/ beside
meshsmith.libs/) in the running virtualenv."""
import os
import signal
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
WHEEL_UNDER_TEST = os.environ.get("MESHSMITH_WHEEL_TEST")


def pytest_configure(config) -> None:
    # A suite started from a background job inherits SIGINT ignored: Python then installs no handler,
    # so the Ctrl-C tests' interrupt_main / os.kill do nothing here and in the interpreters they start
    # (an ignored signal stays ignored across exec; a handled one is reset to the default, which a
    # child Python turns into KeyboardInterrupt).
    if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    if WHEEL_UNDER_TEST:
        import meshsmith
        package = Path(meshsmith.__file__).resolve().parent
        venv = Path(sys.prefix).resolve()
        if venv not in package.parents or not (package.parent / "meshsmith.libs").is_dir():
            raise pytest.UsageError(f"testing the wheel {WHEEL_UNDER_TEST}, but meshsmith was imported from "
                                    f"{package}, not from a repaired wheel's install in the virtualenv {venv}")


def shared_data_dir() -> Path | None:
    # A clone sits beside shared/ (CI, /work/main); a git worktree one level deeper (/work/wt/x).
    candidates = [os.environ.get("MESHSMITH_DATA"), REPO.parent / "shared" / "data",
                  REPO.parent.parent / "shared" / "data"]
    for candidate in candidates:
        if candidate and Path(candidate, "README.md").is_file():
            return Path(candidate)
    return None


@pytest.fixture(scope="session")
def data_dir() -> Path:
    directory = shared_data_dir()
    if directory is None:
        pytest.skip("shared test data not found (set MESHSMITH_DATA or place ../shared/data)")
    return directory
