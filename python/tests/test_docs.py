"""Every public function of coil has an example in its docstring, and the examples run
(they are the API reference, docs/python.md)."""

import doctest
import json
import os

import numpy as np
import pytest

import coil
from conftest import CASE, REPO, TABLE4


@pytest.mark.parametrize("name", [n for n in coil.__all__ if n != "CoilError"])
def test_every_function_has_an_example_that_runs(name, tmp_path, monkeypatch):
    monkeypatch.chdir(REPO)
    function = getattr(coil, name)
    assert ">>>" in (function.__doc__ or ""), f"{name} has no example"
    assert "+SKIP" not in function.__doc__, f"{name} skips its example"
    globs = {
        "coil": coil, "np": np, "json": json, "os": os, "_coil": coil._coil,
        "case": CASE, "table4": TABLE4, "tmp": tmp_path, "repo": REPO,
    }
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    for test in doctest.DocTestFinder().find(function, name, globs=globs):
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.attempted > 0
    assert result.failed == 0, f"{name}: {result.failed} of {result.attempted} examples failed"


def test_errors_carry_the_file_and_line(tmp_path):
    case = tmp_path / "case.json"
    case.write_text('{\n  "name": "x",\n  "mass_kg": "heavy"\n}\n')
    with pytest.raises(coil.CoilError) as error:
        coil.calibrate(case, out=tmp_path / "out")
    message = str(error.value)
    assert f"{case}:" in message and "expected" in message, message
    assert not (tmp_path / "out" / "calibration.json").exists()


def test_reference_is_generated_from_the_docstrings():
    import importlib.util

    spec = importlib.util.spec_from_file_location("docgen", REPO / "python" / "docgen.py")
    docgen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(docgen)
    assert (REPO / "docs" / "python.md").read_text() == docgen.render(), \
        "docs/python.md is stale: run python python/docgen.py"
