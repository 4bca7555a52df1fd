"""The notebook-style example reproduces Table 3 and draws one decay."""

import subprocess
import sys

from conftest import REPO


def test_table3_notebook_runs(tmp_path):
    run = subprocess.run(
        [sys.executable, str(REPO / "python" / "examples" / "table3.py"), str(tmp_path)],
        cwd=REPO, capture_output=True, text=True,
    )
    assert run.returncode == 0, run.stderr
    assert "Table 3:" in run.stdout
    k_row = next(line for line in run.stdout.splitlines() if line.startswith("| K (N/mm)"))
    assert abs(float(k_row.split("|")[4]) / 3.9275 - 1) < 1e-5, k_row
    assert (tmp_path / "decay.png").stat().st_size > 10_000
