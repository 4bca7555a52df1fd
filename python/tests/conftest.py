"""Shared fixtures of coil's Python tests: the repository's paths, the coil-tune binary."""

import os
import pathlib
import shutil

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
CASE = REPO / "cases" / "160ect"
TABLE4 = CASE / "table4.json"


@pytest.fixture(scope="session")
def coil_tune():
    """The coil-tune binary: $COIL_TUNE, else the workspace's release build."""
    exe = os.environ.get("COIL_TUNE") or str(REPO / "target" / "release" / "coil-tune")
    if not os.path.exists(exe):
        exe = shutil.which("coil-tune")
    assert exe, "coil-tune not found: build it (cargo build --release -p coil-tune) or set COIL_TUNE"
    return exe
