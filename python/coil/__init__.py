"""coil from Python: helical-spring beam models, the paper's calibration, sweeps on Dask.

A thin layer over coil's Rust library crates (the native module ``coil._coil``): every
function calls one library function and returns its result as plain dicts, numpy arrays
and pandas tables, with the same names and units as the JSON and CSV files the ``coil-*``
binaries write. Every failure raises :class:`CoilError` with the library's message (file,
line, field and what was expected; under 1 KB, control characters escaped), including a
path that does not exist, an argument out of range and a bug inside coil. The limits are
the command line's (docs/files.md). Ctrl-C stops any call within a second and leaves its
output folder as it was.

The pipeline::

    deck = coil.spring(youngs_modulus_mpa=193837.8, analyses=["static", "modal"])
    result = coil.solve(deck)                       # results.json as a dict
    cal = coil.calibrate("cases/160ect", out="out/cal")
    table = coil.sweep("cases/160ect", "cases/160ect/table4.json", out="out/sweep",
                       calibration="out/cal/calibration.json", client=client)

Every random draw of a study is a function of its seed and the task's number, and each
task runs sequentially inside the solver, so a study's table is the same bit for bit
whether it runs here, split into shards (:func:`run_shard`, :func:`merge`, or
``coil-tune ... --shard I/N``) or on a Dask cluster (``client=``). See docs/python.md and
docs/scale-out.md.
"""

import json as _json
import os as _os

import numpy as _np

from . import _coil

__all__ = [
    "CoilError",
    "spring",
    "read_deck",
    "solve",
    "decrement",
    "plot_history",
    "calibrate",
    "sweep_study",
    "tolerance_study",
    "run_study",
    "sweep",
    "tolerance",
    "run_shard",
    "merge",
    "diagnose",
    "simulate",
    "frc",
    "catenary",
    "check",
    "design",
    "damping",
    "read_record",
    "write_uff",
]


def __dir__():
    """The API (``__all__``), not the modules the package imports."""
    return sorted(__all__)


CoilError = _coil.CoilError


def _call(function, *args):
    """Calls ``_coil.function``: an argument the native layer cannot take (a number out
    of its type's range, a path that is not text, a string where a list goes) raises
    CoilError like every other failure, not TypeError or OverflowError."""
    try:
        return function(*args)
    except CoilError:
        raise
    except (TypeError, ValueError, OverflowError, UnicodeError) as e:
        raise CoilError(f"{function.__name__}: {type(e).__name__}: {e}") from None


def _path(value, what):
    """A path argument as the native layer takes it."""
    if isinstance(value, (str, bytes, _os.PathLike)):
        return _os.fsdecode(value) if isinstance(value, bytes) else _os.fspath(value)
    raise CoilError(f"{what}: {type(value).__name__}; expected a path (str or _os.PathLike)")


def _paths(values, what):
    """A list of paths; a single string is refused (it is not a list of its characters)."""
    if isinstance(values, (str, bytes, _os.PathLike)):
        raise CoilError(f"{what}: a single path {_os.fsdecode(values)!r}; expected a list of paths, e.g. [path]")
    try:
        return [_path(v, what) for v in values]
    except TypeError:
        raise CoilError(f"{what}: {type(values).__name__}; expected a list of paths") from None


def _arrays(value):
    """Lists of numbers -> numpy arrays, recursively (dicts keep their names)."""
    if isinstance(value, dict):
        return {k: _arrays(v) for k, v in value.items()}
    if isinstance(value, list):
        if value and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in value):
            return _np.asarray(value, dtype=float)
        return [_arrays(x) for x in value]
    return value


def spring(**fields):
    """The deck text of a helical spring (``coil-mesh``'s spec fields, docs/mesher.md).

    Fields not given take the paper's spring with handbook steel: ``coils=14``,
    ``mean_diameter_mm=24``, ``wire_diameter_mm=3``, ``pitch_mm=6.2``,
    ``elements_per_coil=24``, ``youngs_modulus_mpa=206000``, ``analyses=["static"]``, ...

    >>> deck = coil.spring(youngs_modulus_mpa=193837.8, analyses=["static", "modal"], modes=3)
    >>> "TITLE, helical spring" in deck.splitlines()
    True
    >>> coil.spring(wire_diameter_mm=-3)
    Traceback (most recent call last):
    coil.CoilError: wire_diameter_mm = -3: expected a positive wire diameter smaller than the mean diameter
    """
    return _call(_coil.mesh, _json.dumps(fields))


def _deck(deck):
    """(text, path): a path-like, or a string of one line, is a file's path (a missing file
    is an error naming it, never deck text); a string with several lines is the deck."""
    if isinstance(deck, (_os.PathLike, bytes)) or (isinstance(deck, str) and "\n" not in deck):
        return None, _path(deck, "deck")
    if isinstance(deck, str):
        return deck, None
    raise CoilError(f"deck: {type(deck).__name__}; expected a deck's text or its path")


def read_deck(deck):
    """Reads and checks a deck (a path or the deck's text): title and counts.

    >>> info = coil.read_deck(coil.spring(elements_per_coil=8))
    >>> info["elements"], info["load_cases"]
    (112, 1)
    >>> coil.read_deck("TITLE x\\nNOSUCHCARD 1\\n")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    coil.CoilError: <deck text>:2:...
    """
    return _json.loads(_call(_coil.read_deck, *_deck(deck)))


def solve(deck, out=None, allow_large=False):
    """Runs a deck's load cases as ``coil-solve`` does; results.json as a dict.

    ``deck`` is a path or the deck's text; ``out`` a folder for the files (results.json,
    .vtu, histories; written as one set), a temporary one when None. A transient above
    ``coil-solve``'s limit (docs/files.md) is refused unless ``allow_large=True`` (its
    ``--allow-large``). Ctrl-C stops the run within a second and leaves ``out`` as it was. Each transient case carries a
    ``history`` dict of numpy arrays (``time_s`` and every column by its name); numbers
    in lists become numpy arrays.

    >>> deck = coil.spring(youngs_modulus_mpa=193837.8, mass_kg=5.243161,
    ...                    analyses=["static", "modal"], modes=3)
    >>> r = coil.solve(deck)
    >>> round(r["load_cases"][0]["stiffness_n_mm"], 4)
    3.9275
    >>> [case["kind"] for case in r["load_cases"]]
    ['static', 'modal']
    """
    text, path = _deck(deck)
    out = None if out is None else _path(out, "out")
    return _arrays(_json.loads(_call(_coil.solve, text, path, out, allow_large)))


def decrement(time_s, values, every=10, lowpass_hz=None):
    """The paper's logarithmic decrement of a decay record (``coil-post decrement``).

    Returns zeta_mean (the paper's estimator), zeta_fit, period_s, the spans and crests.

    >>> t = np.arange(0, 6, 0.002)
    >>> x = np.exp(-0.002 * 2 * np.pi * t / 0.23) * np.cos(2 * np.pi * t / 0.23)
    >>> d = coil.decrement(t, x)
    >>> round(d["zeta_mean"], 5), round(d["period_s"], 4)
    (0.002, 0.23)
    """
    return _arrays(_json.loads(_call(_coil.decrement,
        _np.asarray(time_s, dtype=float).tolist(),
        _np.asarray(values, dtype=float).tolist(),
        every,
        lowpass_hz,
    )))


def plot_history(time_s, values, path, column="node1_uz_accel_m_s2", label=None):
    """Draws a time history into ``path`` (.png or .svg) with coil's own renderer (the
    figures of ``coil-post plot``); the unit comes from the column's name.

    >>> t = np.linspace(0, 1, 101)
    >>> coil.plot_history(t, np.sin(2 * np.pi * t), tmp / "sine.png")
    >>> (tmp / "sine.png").stat().st_size > 1000
    True
    """
    _call(
        _coil.plot_history,
        _np.asarray(time_s, dtype=float).tolist(),
        _np.asarray(values, dtype=float).tolist(),
        label or column,
        column,
        _path(path, "path"),
    )


def calibrate(case, out, elements_per_coil=24, method="modal", check=True):
    """Loops 1-3 of the paper's Figure 6 on a case (``coil-tune calibrate``).

    Writes the loops' files into ``out`` and returns calibration.json's content; the
    validated values are in ``["state"]``.

    >>> cal = coil.calibrate(case, out=tmp / "cal", elements_per_coil=8, check=False)
    >>> round(cal["stiffness"]["iterations"][-1]["result"], 4)
    3.9275
    """
    return _json.loads(_call(_coil.calibrate, _path(case, "case"), _path(out, "out"),
                            elements_per_coil, method, check))


def sweep_study(case, variants, out, calibration=None, paper_material=False,
                elements_per_coil=24, method="modal", check=True):
    """The study of ``coil-tune sweep`` (Table 4) as JSON text, for :func:`run_study`,
    :func:`run_shard` or a cluster. The material: ``calibration`` (a calibration.json),
    ``paper_material=True`` (the paper's Table 2), or a calibration run into ``out``.

    >>> s = coil.sweep_study(case, table4, out=tmp, paper_material=True, elements_per_coil=8)
    >>> json.loads(s)["study"], len(json.loads(s)["variants"])
    ('sweep', 6)
    """
    return _call(
        _coil.sweep_study,
        _path(case, "case"), _path(variants, "variants"), _path(out, "out"),
        None if calibration is None else _path(calibration, "calibration"),
        paper_material, elements_per_coil, method, check,
    )


def tolerance_study(case, variants, out, samples=100, seed=1, wire_tol=0.03, grade=2,
                    coil_diameter_tol=None, coils_tol=0.25, youngs_modulus_tol=0.02,
                    mass_tol=0.001, calibration=None, paper_material=False,
                    elements_per_coil=24, method="modal"):
    """The study of ``coil-tune tolerance`` as JSON text: each spring of ``variants``
    sampled ``samples`` times (plus the nominal spring, sample 0) within the tolerances
    (wire diameter +-mm, EN 15800 coil-diameter ``grade`` or ``coil_diameter_tol`` +-mm,
    coils, relative E and mass; docs/scale-out.md cites the sources).

    >>> s = coil.tolerance_study(case, table4, out=tmp, samples=3, paper_material=True,
    ...                          elements_per_coil=8)
    >>> json.loads(_coil.study_info(s))["tasks"]
    24
    """
    return _call(
        _coil.tolerance_study,
        _path(case, "case"), _path(variants, "variants"), _path(out, "out"), samples, seed,
        wire_tol, grade, coil_diameter_tol, coils_tol, youngs_modulus_tol, mass_tol,
        None if calibration is None else _path(calibration, "calibration"),
        paper_material, elements_per_coil, method,
    )


def _run_chunk(study, tasks):
    """Runs some tasks of a study (on a Dask worker): [(task, row), ...]."""
    return list(zip(tasks, _json.loads(_call(_coil.run_tasks, study, list(tasks)))))


def run_study(study, client=None, chunks=None):
    """Runs every task of a study: the table as a pandas DataFrame, in task order.

    Without ``client`` the tasks run in this process's thread pool. With a
    ``dask.distributed.Client`` they are split round robin into ``chunks`` groups
    (default 4 per worker), mapped over the cluster and gathered; the table is the same
    bit for bit.

    >>> s = coil.tolerance_study(case, table4, out=tmp, samples=2, paper_material=True,
    ...                          elements_per_coil=8)
    >>> t = coil.run_study(s)
    >>> list(t.columns[:3]), len(t)
    (['task', 'spring', 'sample'], 18)
    """
    import pandas as pd

    info = _json.loads(_call(_coil.study_info, study))
    n = info["tasks"]
    if client is None:
        rows = _json.loads(_call(_coil.run_tasks, study, list(range(n))))
    else:
        workers = max(1, len(client.scheduler_info()["workers"]))
        k = max(1, min(n, chunks or 4 * workers))
        groups = [list(range(c, n, k)) for c in range(k)]
        futures = client.map(_run_chunk, [study] * k, groups, pure=False)
        rows = [None] * n
        for part in client.gather(futures):
            for task, row in part:
                rows[task] = row
    return pd.DataFrame(rows, columns=info["columns"])


def _write(study, table, out, plots):
    rows = _json.dumps([[None if isinstance(v, float) and v != v else v for v in row]
                       for row in table.itertuples(index=False, name=None)])
    return _json.loads(_call(_coil.write_table, study, rows, _path(out, "out"), plots))


def sweep(case, variants, out, calibration=None, paper_material=False, elements_per_coil=24,
          method="modal", check=True, client=None):
    """K and zeta of spring variants with the validated material (``coil-tune sweep``):
    a DataFrame with sweep.csv's columns; writes ``out/sweep.csv`` as the binary does.
    ``client``: a ``dask.distributed.Client`` to run the variants on. (At 8 elements per
    coil, as here, the helix is too stiff by 11 %: the paper's material was calibrated
    at about 17.)

    >>> t = coil.sweep(case, table4, out=tmp, paper_material=True, elements_per_coil=8,
    ...                check=False)
    >>> t[["name", "stiffness_n_mm"]].round(2).values.tolist()[:2]
    [['#1', 2.76], ['#2', 8.08]]
    """
    study = sweep_study(case, variants, out, calibration, paper_material,
                        elements_per_coil, method, check)
    table = run_study(study, client)
    _write(study, table, out, plots=False)
    return table


def tolerance(case, variants, out, samples=100, seed=1, client=None, plots=True, **options):
    """K and zeta distributions of the variants as manufactured (``coil-tune
    tolerance``): returns (the table as a DataFrame, the summary dict), and writes
    tolerance.csv, tolerance_summary.json, tolerance.md and tolerance.png into ``out``.
    ``options`` are :func:`tolerance_study`'s; ``client`` a Dask client.

    >>> t, s = coil.tolerance(case, table4, out=tmp, samples=4, seed=3, paper_material=True,
    ...                       elements_per_coil=8, plots=False)
    >>> len(t), [x["samples"] for x in s["springs"]]
    (30, [4, 4, 4, 4, 4, 4])
    """
    study = tolerance_study(case, variants, out, samples, seed, **options)
    table = run_study(study, client)
    return table, _write(study, table, out, plots)


def run_shard(study, shard, out):
    """Runs shard ``"I/N"`` of a study and writes ``out/part-IIII-of-NNNN.csv`` (as
    ``coil-tune ... --shard I/N``); returns its path.

    >>> s = coil.tolerance_study(case, table4, out=tmp, samples=2, paper_material=True,
    ...                          elements_per_coil=8)
    >>> os.path.basename(coil.run_shard(s, "2/3", tmp / "parts"))
    'part-0002-of-0003.csv'
    """
    return _call(_coil.run_shard, study, shard, _path(out, "out"))


def merge(parts, out, plots=True):
    """Joins part files (or folders of them) into the table a single run writes (as
    ``coil-tune merge``); refuses missing, repeated or foreign shards. Returns the
    table's path.

    >>> s = coil.tolerance_study(case, table4, out=tmp, samples=2, paper_material=True,
    ...                          elements_per_coil=8)
    >>> _ = coil.run_shard(s, "1/2", tmp / "p")
    >>> coil.merge([tmp / "p"], tmp / "m")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    coil.CoilError: shard 2/2 missing ...
    >>> _ = coil.run_shard(s, "2/2", tmp / "p")
    >>> os.path.basename(coil.merge([tmp / "p"], tmp / "m", plots=False))
    'tolerance.csv'
    """
    return _call(_coil.merge, _paths(parts, "parts"), _path(out, "out"), plots)


def diagnose(case, out, elements_per_coil=24, modes=4, plots=True):
    """Diagnoses a measured case (``coil-tune diagnose``, docs/diagnose.md): writes its
    files into ``out`` and returns diagnosis.json's content.

    >>> d = coil.diagnose(repo / "cases/measured/friction_g1", tmp / "diag",
    ...                   elements_per_coil=8, modes=2, plots=False)
    >>> d["cause"], round(d["extended"]["parameters"]["friction_force_n"], 3)
    ('coulomb_friction', 0.011)
    """
    return _json.loads(_call(_coil.diagnose, _path(case, "case"), _path(out, "out"),
                            elements_per_coil, modes, plots))


def simulate(model, record, input, output, init, time="time_s", out=None):
    """Drives a forced diagnosis's model (``model.json`` or ``model_linear.json``) with a
    record's input, from the state fitted to its first ``init`` output samples
    (``coil-tune simulate``, docs/forced.md): a DataFrame with simulated.csv's columns
    ``time_s`` and ``output`` (the output's unit), one row per input sample; writes
    ``out/simulated.csv`` when ``out`` is given. The output column may hold only those
    ``init`` values; nothing after them is read. ``coil.diagnose`` on a case with forced
    records writes the model.

    >>> d = coil.diagnose(repo / "cases/forced/hardening", tmp / "forced", plots=False)
    >>> d["cause"]
    'cubic_stiffness'
    >>> record = repo / "cases/forced/hardening/record_1.csv"
    >>> sim = coil.simulate(tmp / "forced" / "model.json", record, input="force_n",
    ...                     output="displacement_m", init=50)
    >>> len(sim), list(sim.columns)
    (4000, ['time_s', 'output'])
    >>> measured = np.genfromtxt(record, delimiter=",", names=True)["displacement_m"]
    >>> rms = lambda x: float(np.sqrt(np.mean(np.square(x))))
    >>> bool(rms(sim["output"] - measured) < 0.02 * rms(measured))   # the record's 1 % noise
    True
    """
    import pandas as pd

    result = _json.loads(_call(_coil.simulate, _path(model, "model"), _path(record, "record"),
                               input, output, init, time,
                               None if out is None else _path(out, "out")))
    table = pd.DataFrame({"time_s": result["time_s"], "output": result["output"]})
    table.attrs["initial_state"] = result["initial_state"]
    return table


def frc(model, amplitude, from_hz, to_hz, points=400, harmonics=7, out=None):
    """The forced response curve of a forced diagnosis's model under a harmonic input of
    ``amplitude`` (the model's input unit) from ``from_hz`` to ``to_hz`` (``coil-tune
    frc``, docs/forced.md): harmonic balance with ``harmonics`` harmonics continued
    through the folds, each point's stability by Floquet. Returns ``(curve, backbone)``:
    frc.csv's columns ``frequency_hz``, ``amplitude`` (first harmonic of the output, the
    output's unit) and ``stable``, with the folds' frequencies in
    ``curve.attrs["jumps_hz"]``, and backbone.csv's ``frequency_hz``, ``amplitude``,
    ``peak_displacement``; writes both files into ``out`` when it is given.

    >>> _ = coil.diagnose(repo / "cases/forced/hardening", tmp / "forced", plots=False)
    >>> curve, backbone = coil.frc(tmp / "forced" / "model.json", amplitude=1.0,
    ...                            from_hz=3.0, to_hz=8.0, out=tmp / "frc")
    >>> list(curve.columns), sorted(f for f in os.listdir(tmp / "frc") if f.endswith(".csv"))
    (['frequency_hz', 'amplitude', 'stable'], ['backbone.csv', 'frc.csv'])
    >>> round(float(backbone["frequency_hz"][0]), 2)     # sqrt(k / m) / 2 pi at small amplitude
    5.03
    >>> peak = curve.loc[curve["amplitude"].idxmax()]    # the hardening spring lifts the peak
    >>> round(float(peak["frequency_hz"]), 1), bool(peak["stable"])
    (5.3, True)
    """
    import pandas as pd

    result = _json.loads(_call(_coil.frc, _path(model, "model"), float(amplitude),
                               float(from_hz), float(to_hz), points, harmonics,
                               None if out is None else _path(out, "out")))
    curve = pd.DataFrame(result["curve"], columns=["frequency_hz", "amplitude", "stable"])
    curve.attrs["jumps_hz"] = result["jumps_hz"]
    backbone = pd.DataFrame(result["backbone"],
                            columns=["frequency_hz", "amplitude", "peak_displacement"])
    return curve, backbone


def catenary(case, out, springs=None, plots=True, damping=None, mass_share=True, reduced=False,
             allow_supercritical=False, speeds=None):
    """A pantograph-catenary case (``coil-tune catenary``, docs/catenary.md): writes
    catenary.json, report.md, the histories and figures into ``out`` and returns the
    statistics as a DataFrame, one row per speed (EN 50318's keys, ``wave_speed_ratio``,
    ``assessment``). With ``springs`` (spring sources: a measured case folder, a variants
    file or ``"table4.json:#2"``, a calibration.json, a SPRING.json, a design.json or one
    of its candidates, ``"design.json:2"``) it runs a spring
    study and returns one row per spring and speed (column ``spring``). ``speeds`` (km/h)
    runs those speeds instead of the case's ``speeds_km_h``.

    >>> cat = {"spans": 2, "span_length_m": 60.0, "system_height_m": 1.2, "presag_mm": 0.0,
    ...        "contact_wire": {"mass_kg_m": 1.35, "tension_n": 20000.0, "ei_n_m2": 195.0},
    ...        "messenger_wire": {"mass_kg_m": 1.07, "tension_n": 16000.0, "ei_n_m2": 131.7},
    ...        "droppers": {"positions_m": [5.0, 10.5, 17.0, 23.5, 30.0, 36.5, 43.0, 49.5, 55.0],
    ...                     "stiffness_n_m": 100000.0, "contact_clamp_mass_kg": 0.195,
    ...                     "messenger_clamp_mass_kg": 0.165},
    ...        "steady_arm": {"stiffness_n_m": 300.0, "mass_kg": 1.0},
    ...        "messenger_support": {"stiffness_n_m": 50000.0, "mass_kg": 0.0},
    ...        "damping": {"ratio": 0.005, "frequencies_hz": [1.0, 20.0]},
    ...        "element_length_m": 1.0}
    >>> panto = {"stages": [{"mass_kg": 7.2, "stiffness_n_m": 4200.0, "damping_n_s_m": 10.0},
    ...                     {"mass_kg": 15.0, "stiffness_n_m": 50.0, "damping_n_s_m": 90.0}],
    ...          "uplift_force_n": 120.0, "contact_stiffness_n_m": 50000.0}
    >>> os.makedirs(tmp / "cat")
    >>> _ = (tmp / "cat" / "case.json").write_text(json.dumps({"catenary": cat, "pantograph": panto,
    ...     "speeds_km_h": [200, 250], "time_step_s": 0.002,
    ...     "window": {"start_m": 30.0, "end_m": 90.0}}))
    >>> table = coil.catenary(tmp / "cat", tmp / "cat_out", plots=False)
    >>> table["speed_km_h"].tolist(), bool((table["mean_n"] > 100).all())
    ([200.0, 250.0], True)
    >>> round(float(table["wave_speed_ratio"][1]), 3)
    0.571
    >>> coil.catenary(tmp / "cat", tmp / "cat_250", plots=False, speeds=[250])["speed_km_h"].tolist()
    [250.0]
    """
    import pandas as pd

    springs = [] if springs is None else _paths(springs, "springs")
    result = _json.loads(_call(_coil.catenary, _path(case, "case"), _path(out, "out"), springs,
                               plots, damping, mass_share, reduced, allow_supercritical,
                               None if speeds is None else [float(v) for v in speeds]))
    rows = []
    entries = result["springs"] if "springs" in result else [{"runs": result["runs"]}]
    for entry in entries:
        for run in entry["runs"]:
            row = {"spring": entry["spring"]} if "spring" in entry else {}
            row.update({k: v for k, v in run.items() if not isinstance(v, (dict, list))})
            row["assessment"] = run["assessment_verdict"]
            rows.append(row)
    return pd.DataFrame(rows)


def _json_file(value, folder):
    """A path as it is; a dict written as a JSON file into ``folder`` (a relative path
    inside the dict would be taken from that folder: give paths absolute)."""
    if isinstance(value, dict):
        import tempfile

        _os.makedirs(folder, exist_ok=True)
        handle, path = tempfile.mkstemp(suffix=".json", dir=folder)
        with _os.fdopen(handle, "w") as f:
            _json.dump(value, f)
        return path
    return _os.fspath(value)


def check(spring, elements_per_coil=24):
    """The EN 13906-1 sheet of a spring beside coil's FE values on the same spring
    (``coil-tune check --json``, docs/spring-design.md): ``spring`` is a SPRING.json path
    or a dict with its keys. Returns the sheet as a dict (``fe`` holds the FE values).

    >>> s = coil.check(repo / "cases/spring-design/helispring.json")
    >>> round(s["rate_n_mm"], 3), round(s["solid_length_mm"], 2), s["buckling_stable"]
    (16.181, 57.79, True)
    >>> s = coil.check(repo / "cases/spring-design/160ect_spring.json")
    >>> round(s["rate_n_mm"], 4), round(s["fe"]["rate_n_mm"], 3)
    (3.8373, 3.806)
    """
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        return _json.loads(_call(_coil.check, _json_file(spring, folder), elements_per_coil))


def design(target, out, objective=None, short_list=None, plots=True):
    """Designs to a target (``coil-tune design``, docs/spring-design.md): ``target`` is a
    TARGET.json path or a dict with its keys (a calibration path in it: absolute, or
    relative to the target file). Writes design.json, report.md, design.png and the
    decks into ``out``; returns (design.json as a dict, its ``candidates`` as a
    DataFrame, best first).

    >>> cal = coil.calibrate(case, out=tmp / "cal")
    >>> target = {"rate_n_mm": 3.9275, "rate_tolerance_percent": 2.0, "weight_kg": 5.3,
    ...           "force_1_n": 40, "force_2_n": 120, "objective": "stress_margin",
    ...           "envelope": {"max_outer_diameter_mm": 27.0, "min_inner_diameter_mm": 21.0,
    ...                        "max_free_length_mm": 100.0, "max_solid_length_mm": 50.0},
    ...           "material": {"calibration": str(tmp / "cal" / "calibration.json")}}
    >>> d, table = coil.design(target, out=tmp / "design", plots=False)
    >>> table[["wire_diameter_mm", "mean_diameter_mm", "active_coils"]].values[0].tolist()
    [3.0, 24.0, 14.0]
    >>> round(float(table["fe_rate_n_mm"][0]), 3), d["candidates"][0]["deck"]
    (3.928, 'decks/candidate_01.dat')
    """
    import tempfile

    import pandas as pd

    with tempfile.TemporaryDirectory() as folder:
        result = _json.loads(_call(_coil.design, _json_file(target, folder), _path(out, "out"),
                                          objective, short_list, plots))
    columns = ["rank", "wire_diameter_mm", "mean_diameter_mm", "active_coils", "total_coils",
               "pitch_mm", "free_length_mm", "rate_n_mm", "fe_rate_n_mm", "spring_mass_kg",
               "stress_margin", "deck"]
    rows = []
    for c in result["candidates"]:
        row = {k: c[k] for k in columns}
        row.update({f"damping_ratio_{law}": z for law, z in c["damping_ratio"].items()})
        rows.append(row)
    return result, pd.DataFrame(rows)


def damping(case, out, variants=None, elements_per_coil=24, scatter=0.03):
    """Which damping law? (``coil-tune damping``, docs/damping.md): fits the Rayleigh,
    hysteretic and external-dashpot laws to all decay records of a measured case, judged
    against the repeat scatter of zeta (estimated from repeated tests, else ``scatter``);
    writes damping.json and report.md into ``out`` and returns damping.json's content.
    ``variants`` defaults to a table4.json beside case.json.

    >>> d = coil.damping(repo / "cases/measured/null_g4", tmp / "damping", elements_per_coil=8)
    >>> d["law"], d["identifiable"], d["repeat_scatter"]["source"]
    (None, False, 'default')
    >>> "surge" in d["deciding_test"]["text"]
    True
    """
    return _json.loads(_call(
        _coil.damping, _path(case, "case"), _path(out, "out"),
        None if variants is None else _path(variants, "variants"), elements_per_coil, scatter,
    ))


def read_record(path, channel=None, time=None, quantity=None, unit=None):
    """Reads a measured record as every coil command does (docs/measured-case.md,
    "Records as labs store them"): UFF dataset 58 or 58b, a MATLAB level 5 MAT-file, or
    CSV in any common dialect. ``channel`` is a UFF dataset index (from 1) or
    ``"node:direction"``, a ``.mat`` variable or a CSV column; ``time`` the ``.mat``
    variable of the time stamps; ``quantity`` and ``unit`` what the case states.

    Returns a dict: ``file``, ``format`` (the format or dialect detected), ``channel``,
    ``quantity``, ``unit`` (as stated), and numpy arrays ``time_s`` and ``values`` (SI:
    m, m/s or m/s^2).

    >>> _ = (tmp / "decay.csv").write_text("Zeit [s];Beschl. [g]\\n0,00;1,0\\n0,01;0,5\\n0,02;-0,5\\n")
    >>> r = coil.read_record(tmp / "decay.csv")
    >>> r["format"].startswith("CSV: delimiter ';', decimal comma"), r["quantity"], float(r["values"][0])
    (True, 'acceleration', 9.80665)
    """
    text = _call(_coil.read_record, _path(path, "path"), channel, time, quantity, unit)
    return _arrays(_json.loads(text))


def write_uff(path, datasets, binary=False):
    """Writes evenly sampled histories as UFF dataset 58 (ASCII, or 58b when ``binary``),
    the writer behind ``coil-solve --uff`` and ``coil-tune diagnose --uff``. Each dataset
    is a dict with ``name``, ``node``, ``direction`` (1..6), ``quantity``
    (``"displacement"``, ``"velocity"``, ``"acceleration"``), ``unit``, ``start_s``,
    ``step_s`` and ``values``. ASCII keeps 13 significant digits, 58b every bit.

    >>> d = {"name": "x", "node": 1, "direction": 3, "quantity": "displacement", "unit": "m",
    ...      "start_s": 0.0, "step_s": 0.01, "values": [0.001, 0.002, -0.001]}
    >>> coil.write_uff(tmp / "x.uff", [d], binary=True)
    >>> coil.read_record(tmp / "x.uff")["values"].tolist()
    [0.001, 0.002, -0.001]
    """
    plain = [
        {**d, "values": [float(v) for v in _np.asarray(d["values"], dtype=float)]} for d in datasets
    ]
    _call(_coil.write_uff, _path(path, "path"), _json.dumps(plain), binary)
