"""Shared fixtures: the real meshes of ../shared/data (or $MESHSMITH_DATA), skipped when absent."""
import os
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


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
