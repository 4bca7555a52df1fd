"""Hostile and careless calls: every failure is CoilError (never PanicException, TypeError
or an abort), the command line's limits hold, and Ctrl-C stops a long call within a
second, leaving its output folder as it was."""

import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import coil

from conftest import CASE, REPO, TABLE4


def refused(call, *expected):
    with pytest.raises(coil.CoilError) as e:
        call()
    message = str(e.value)
    assert len(message.encode()) < 1024, len(message)
    assert "\x1b" not in message
    for text in expected:
        assert text in message, message
    return message


def test_text_that_reaches_a_deck_is_one_printable_line():
    refused(lambda: coil.spring(title="x\nEND OPTION"), "title", "one printable line")
    refused(lambda: coil.spring(title="\x1b[2J"), "title")
    refused(lambda: coil.spring(title="t" * 201), "title")
    assert "TITLE, spring 3, rig B" in coil.spring(title="spring 3, rig B")


def test_paths_missing_or_not_utf8_are_coil_errors(tmp_path):
    refused(lambda: coil.solve("no/such/deck.dat"), "no such deck file")
    refused(lambda: coil.read_deck(tmp_path / "missing.dat"), "no such deck file")
    refused(lambda: coil.read_deck(os.fsdecode(b"/tmp/\xff\xfe.dat")), "no such deck file")
    refused(lambda: coil.read_deck(b"/tmp/\xff\xfe.dat"), "no such deck file")
    refused(lambda: coil.calibrate(os.fsdecode(b"/nonexistent/\xff"), tmp_path / "o"))
    refused(lambda: coil.read_deck(42), "expected a deck's text or its path")


def test_a_string_where_a_list_goes_is_an_error(tmp_path):
    refused(lambda: coil.merge(str(tmp_path), tmp_path / "m"), "expected a list of paths")
    refused(lambda: coil.merge(tmp_path, tmp_path / "m"), "expected a list of paths")
    refused(lambda: coil.merge(42, tmp_path / "m"), "expected a list of paths")


def test_plot_history_validates(tmp_path):
    t = np.linspace(0, 1, 11)
    refused(lambda: coil.plot_history(t, np.full(11, np.nan), tmp_path / "a.png"))
    refused(lambda: coil.plot_history(t, np.zeros(5), tmp_path / "b.png"))
    refused(lambda: coil.plot_history(t[::-1], np.zeros(11), tmp_path / "c.png"))
    refused(lambda: coil.plot_history(t, np.zeros(11), tmp_path / "d.png", label="a\nb"))
    assert not any(tmp_path.iterdir())


def test_limits_equal_the_command_lines(tmp_path):
    refused(lambda: coil.diagnose(REPO / "cases/measured/friction_g1", tmp_path / "d", modes=51),
            "expected 0 to 50")
    refused(lambda: coil.diagnose(REPO / "cases/measured/friction_g1", tmp_path / "d", modes=1000))
    refused(lambda: coil.diagnose(REPO / "cases/measured/friction_g1", tmp_path / "d", modes=-1))
    for samples, expected in [(0, "at least 2"), (1, "at least 2"), (2**63, "at most"), (2**64, "")]:
        refused(lambda: coil.tolerance_study(CASE, TABLE4, tmp_path / "t", samples=samples,
                                             paper_material=True), expected)
    long = coil.spring(analyses=["transient"], dt_s=1e-6, duration_s=50.0)
    refused(lambda: coil.solve(long), "allow")


def test_tampered_studies_and_rows_are_refused(tmp_path):
    study = coil.tolerance_study(CASE, TABLE4, out=tmp_path, samples=2, paper_material=True,
                                 elements_per_coil=6)
    bad = study.replace('"samples":2', '"samples":1000000000000')
    refused(lambda: coil.run_study(bad), "at most 10000000 tasks")
    refused(lambda: coil.run_shard(study.replace('"samples":2', '"samples":1'), "1/2", tmp_path),
            "at least 2")
    import json
    nan_rows = json.dumps([[0, "#1", 0] + [float("nan")] * 9])
    refused(lambda: coil._coil.write_table(study, nan_rows, str(tmp_path / "w"), False), "rows")
    short = json.dumps([[0, "#1", 0] + [1.0] * 9])
    refused(lambda: coil._coil.write_table(study, short, str(tmp_path / "w"), False),
            "the study has")


# The child takes Ctrl-C as an interactive Python does, whatever the runner left it: a
# process started in the background by a non-interactive shell inherits SIGINT ignored,
# and Python then installs no handler of its own.
LONG_SOLVE = textwrap.dedent(
    """
    import signal, sys, coil
    signal.signal(signal.SIGINT, signal.default_int_handler)
    deck = coil.spring(analyses=["static", "transient"], dt_s=1e-5, duration_s=200.0,
                       initial_velocity_m_s=0.1, mass_kg=5.0, elements_per_coil=12)
    print("ready", flush=True)
    coil.solve(deck, out=sys.argv[1], allow_large=True)
    """
)


def test_ctrl_c_stops_a_long_solve_within_a_second(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "previous.txt").write_text("previous set\n")
    child = subprocess.Popen([sys.executable, "-c", LONG_SOLVE, str(out)],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "ready"
    time.sleep(1.5)
    assert child.poll() is None, "finished before the signal"
    sent = time.monotonic()
    child.send_signal(signal.SIGINT)
    _, err = child.communicate(timeout=30)
    latency = time.monotonic() - sent
    assert "KeyboardInterrupt" in err, err
    # 1 s is the contract; the margin covers a loaded CI machine's scheduling.
    assert latency < 2.0, latency
    assert sorted(p.name for p in out.iterdir()) == ["previous.txt"]
    assert not [p for p in tmp_path.iterdir() if ".coil-staging" in p.name]


def test_forced_model_calls_refuse_bad_input_and_write_nothing(tmp_path):
    """coil.simulate and coil.frc: the command line's checks, a CoilError naming what is
    wrong, and nothing written into ``out``."""
    coil.diagnose(REPO / "cases/forced/hardening", tmp_path / "forced", plots=False)
    model = tmp_path / "forced" / "model.json"
    record = REPO / "cases/forced/hardening/record_1.csv"
    out = tmp_path / "out"
    refused(lambda: coil.simulate(model, record, input="no_such", output="displacement_m",
                                  init=50, out=out), "no_such")
    refused(lambda: coil.simulate(model, record, input="force_n", output="displacement_m",
                                  init=1, out=out), "at least 2")
    refused(lambda: coil.simulate(model, record, input="force_n", output="displacement_m",
                                  init=10**6, out=out))
    refused(lambda: coil.simulate(model, record, input="force_n", output="displacement_m",
                                  init=-1, out=out))
    refused(lambda: coil.simulate(record, record, input="force_n", output="displacement_m",
                                  init=50, out=out), "model")
    nan = tmp_path / "nan.csv"
    nan.write_text(record.read_text().replace("1.173709696e-1", "NaN", 1))
    refused(lambda: coil.simulate(model, nan, input="force_n", output="displacement_m",
                                  init=50, out=out))
    refused(lambda: coil.frc(model, 1.0, 3.0, 8.0, points=0, out=out), "expected 2 to")
    refused(lambda: coil.frc(model, 1.0, 3.0, 8.0, points=10**6, out=out), "expected 2 to")
    refused(lambda: coil.frc(model, 1.0, 3.0, 8.0, harmonics=0, out=out), "expected 1 to 40")
    refused(lambda: coil.frc(model, 1.0, 3.0, 8.0, harmonics=41, out=out), "expected 1 to 40")
    refused(lambda: coil.frc(model, 1.0, 8.0, 3.0, out=out), "0 < from < to")
    refused(lambda: coil.frc(model, float("nan"), 3.0, 8.0, out=out), "amplitude")
    assert not out.exists()
