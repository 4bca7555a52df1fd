"""Records as labs store them, against the tools labs use: pyuff writes UFF datasets 58
and 58b that coil reads (every abscissa and ordinate equal to what pyuff itself reads
back), coil writes UFF that pyuff reads back (58b bit for bit, ASCII to 13 significant
digits), and SciPy's ``savemat`` writes MAT-files (v5, compressed or not, any numeric
type) that coil reads bit for bit."""

import numpy as np
import pytest
import pyuff
import scipy.io

import coil


def _decay(n=500, dt=1e-3):
    t = np.arange(n) * dt
    y = np.exp(-3.0 * t) * np.sin(2 * np.pi * 7.3 * t) * 4.2 + 1e-3 * np.cos(91 * t)
    return t, y


def _pyuff_dataset(t, y, *, binary, node=10, direction=3, even=True, unit="m/s^2", single=False):
    """A dataset 58 dict as pyuff writes it (every key its writer asks for)."""
    return dict(
        binary=binary,
        id1="decay",
        id2="accelerometer",
        id3="NONE",
        id4="NONE",
        id5="NONE",
        func_type=1,
        ver_num=0,
        load_case_id=0,
        rsp_ent_name="pt",
        ref_ent_name="NONE",
        rsp_node=node,
        rsp_dir=direction,
        ref_node=0,
        ref_dir=0,
        ord_data_type=2 if single else 4,
        num_pts=len(y),
        abscissa_spacing=1 if even else 0,
        abscissa_min=t[0],
        abscissa_inc=t[1] - t[0],
        ordinate_spec_data_type=12,
        ordinate_len_unit_exp=1,
        ordinate_force_unit_exp=0,
        ordinate_temp_unit_exp=0,
        ordinate_axis_lab="acceleration",
        ordinate_axis_units_lab=unit,
        abscissa_spec_data_type=17,
        abscissa_len_unit_exp=0,
        abscissa_force_unit_exp=0,
        abscissa_temp_unit_exp=0,
        abscissa_axis_lab="time",
        abscissa_axis_units_lab="s",
        orddenom_spec_data_type=0,
        orddenom_len_unit_exp=0,
        orddenom_force_unit_exp=0,
        orddenom_temp_unit_exp=0,
        orddenom_axis_lab="NONE",
        orddenom_axis_units_lab="NONE",
        z_axis_spec_data_type=0,
        z_axis_len_unit_exp=0,
        z_axis_force_unit_exp=0,
        z_axis_temp_unit_exp=0,
        z_axis_axis_lab="NONE",
        z_axis_axis_units_lab="NONE",
        z_axis_value=0,
        data=y,
        x=t,
        type=58,
    )


@pytest.mark.parametrize("binary", [0, 1])
@pytest.mark.parametrize("even", [True, False])
def test_pyuff_writes_coil_reads(tmp_path, binary, even):
    t, y = _decay()
    datasets = [
        _pyuff_dataset(t, y, binary=binary, node=10, even=even),
        _pyuff_dataset(t, 0.5 * y, binary=binary, node=11, even=even, unit="g"),
    ]
    # pyuff 2.5.8 writes 58b whole only one dataset at a time in mode "add" (in mode
    # "overwrite" it keeps the last of several, or only a `-1` line for one), and does
    # not read back the 58b files it writes: in binary, one file per dataset, and the
    # reference is what pyuff was given (58b stores the doubles themselves) on the
    # abscissa it writes (start + i step, or the x values).
    groups = [[d] for d in datasets] if binary else [datasets]
    for k, group in enumerate(groups):
        path = tmp_path / f"decay{k}.uff"
        pyuff.UFF(str(path)).write_sets(group, mode="add" if binary else "overwrite")
        if binary:
            step = t[1] - t[0]
            back = [{"x": d["x"] if not even else t[0] + np.arange(len(t)) * step,
                     "data": d["data"]} for d in group]
        else:
            back = pyuff.UFF(str(path)).read_sets()
        assert len(back) == len(group)
        for index, (d, b) in enumerate(zip(group, back)):
            scale = 9.80665 if d["ordinate_axis_units_lab"] == "g" else 1.0
            for channel in [str(index + 1), f"{d['rsp_node']}:3"]:
                r = coil.read_record(path, channel=channel)
                assert r["quantity"] == "acceleration"
                assert np.array_equal(r["time_s"], b["x"]), channel
                assert np.array_equal(r["values"], b["data"] * scale), channel


def test_pyuff_single_precision_and_errors(tmp_path):
    t, y = _decay(n=61)
    path = tmp_path / "single.uff"
    pyuff.UFF(str(path)).write_sets(
        [_pyuff_dataset(t, y, binary=0, single=True)], mode="overwrite", force_double=False
    )
    back = pyuff.UFF(str(path)).read_sets()
    r = coil.read_record(path)
    assert np.array_equal(r["values"], back["data"])
    with pytest.raises(coil.CoilError, match="mismatched units"):
        coil.read_record(path, unit="g")
    with pytest.raises(coil.CoilError, match="no dataset 58 matches the channel `7`"):
        coil.read_record(path, channel="7")


@pytest.mark.parametrize("binary", [False, True])
def test_coil_writes_pyuff_reads(tmp_path, binary):
    t, y = _decay(n=333, dt=1e-4)
    path = tmp_path / "out.uff"
    coil.write_uff(
        path,
        [
            {"name": "node10_uz_accel_m_s2", "node": 10, "direction": 3, "quantity": "acceleration",
             "unit": "m/s^2", "start_s": 0.0, "step_s": 1e-4, "values": y},
            {"name": "node10_uz_disp_m", "node": 10, "direction": 3, "quantity": "displacement",
             "unit": "m", "start_s": 0.0, "step_s": 1e-4, "values": -y / 1e3},
        ],
        binary=binary,
    )
    sets = pyuff.UFF(str(path)).read_sets()
    assert len(sets) == 2
    for s, values in zip(sets, [y, -y / 1e3]):
        assert s["func_type"] == 1 and s["rsp_node"] == 10 and s["rsp_dir"] == 3
        assert np.array_equal(s["x"], np.arange(len(y)) * 1e-4)
        if binary:
            assert np.array_equal(s["data"], values)
        else:
            assert np.max(np.abs(s["data"] - values) / np.abs(values).max()) <= 5e-13


@pytest.mark.parametrize("compress", [False, True])
@pytest.mark.parametrize("dtype", ["float64", "float32", "int16"])
@pytest.mark.parametrize("oned_as", ["row", "column"])
def test_savemat_writes_coil_reads(tmp_path, compress, dtype, oned_as):
    t, y = _decay(n=257)
    values = (y * 1000).astype(dtype)
    path = tmp_path / "decay.mat"
    scipy.io.savemat(
        path,
        {"t": t, "acc": values, "label": "impact hammer, run 4", "grid": np.ones((3, 4))},
        do_compression=compress,
        oned_as=oned_as,
    )
    r = coil.read_record(path, channel="acc", time="t", unit="mm/s^2")
    assert np.array_equal(r["time_s"], t)
    assert np.array_equal(r["values"], values.astype(float) * 1e-3)
    assert r["format"].startswith("MAT-file level 5")
    with pytest.raises(coil.CoilError, match="variable `label`.*not a numeric vector"):
        coil.read_record(path, channel="label", time="t", unit="g")
    with pytest.raises(coil.CoilError, match="variable `grid`.*not a numeric vector"):
        coil.read_record(path, channel="grid", time="t", unit="g")
    with pytest.raises(coil.CoilError, match="states no unit"):
        coil.read_record(path, channel="acc", time="t")


def test_mat_v73_is_refused_with_advice(tmp_path):
    header = b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Fri Nov 27 2026 HDF5 schema 1.00 ."
    path = tmp_path / "v73.mat"
    path.write_bytes(header.ljust(512, b" ") + b"\x89HDF\r\n\x1a\n" + bytes(64))
    with pytest.raises(coil.CoilError, match="-v7"):
        coil.read_record(path, channel="acc", time="t")
