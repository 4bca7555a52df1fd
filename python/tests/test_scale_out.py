"""Split invariance: a tolerance study run serially, as 4 shards of the coil-tune binary
merged, and on a Dask LocalCluster of 3 worker processes gives the same table, byte for
byte; the summary's percentiles are numpy's."""

import subprocess

import numpy as np
import pandas as pd
from dask.distributed import Client, LocalCluster

import coil
from conftest import CASE, TABLE4

SETTINGS = dict(samples=2, seed=11, paper_material=True, elements_per_coil=8)
FLAGS = ["--paper-material", "--elements-per-coil", "8", "--samples", "2", "--seed", "11"]


def test_serial_shards_and_dask_give_the_same_bits(tmp_path, coil_tune):
    serial, summary = coil.tolerance(CASE, TABLE4, out=tmp_path / "serial", plots=False, **SETTINGS)
    assert len(serial) == 6 * 3
    # The samples differ from each other and from the nominal spring.
    assert serial["stiffness_n_mm"].nunique() == 18

    for i in range(1, 5):
        subprocess.run(
            [coil_tune, "tolerance", str(CASE), "--variants", str(TABLE4), *FLAGS,
             "--shard", f"{i}/4", "--out", str(tmp_path / "parts"), "-q"],
            check=True, capture_output=True,
        )
    subprocess.run(
        [coil_tune, "merge", str(tmp_path / "parts"), "--out", str(tmp_path / "merged"), "--no-plots"],
        check=True, capture_output=True,
    )

    with LocalCluster(n_workers=3, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 3
        on_dask, _ = coil.tolerance(CASE, TABLE4, out=tmp_path / "dask", plots=False,
                                    client=client, **SETTINGS)
        sweep_dask = coil.sweep(CASE, TABLE4, out=tmp_path / "sweep_dask", paper_material=True,
                                elements_per_coil=8, check=False, client=client)
    sweep_serial = coil.sweep(CASE, TABLE4, out=tmp_path / "sweep_serial", paper_material=True,
                              elements_per_coil=8, check=False)

    table = (tmp_path / "serial" / "tolerance.csv").read_bytes()
    assert table == (tmp_path / "merged" / "tolerance.csv").read_bytes()
    assert table == (tmp_path / "dask" / "tolerance.csv").read_bytes()
    summary_file = (tmp_path / "serial" / "tolerance_summary.json").read_bytes()
    assert summary_file == (tmp_path / "merged" / "tolerance_summary.json").read_bytes()
    pd.testing.assert_frame_equal(serial, on_dask, check_exact=True)
    pd.testing.assert_frame_equal(sweep_serial, sweep_dask, check_exact=True)
    assert (tmp_path / "sweep_serial" / "sweep.csv").read_bytes() == \
        (tmp_path / "sweep_dask" / "sweep.csv").read_bytes()

    # The summary against numpy's percentiles of the same table.
    for spring in summary["springs"]:
        drawn = serial[(serial["spring"] == spring["spring"]) & (serial["sample"] > 0)]
        for column in ["stiffness_n_mm", "damping_ratio"]:
            ours = spring[column]["percentiles"]
            ps = [1.0, 5.0, 25.0, 50.0, 75.0, 95.0, 99.0]
            expected = np.percentile(drawn[column].to_numpy(), ps)
            got = [ours[f"p{p:g}"] for p in ps]
            np.testing.assert_allclose(got, expected, rtol=1e-13)
            assert spring[column]["std"] == np.std(drawn[column].to_numpy(), ddof=1) or \
                abs(spring[column]["std"] / np.std(drawn[column].to_numpy(), ddof=1) - 1) < 1e-12


def test_merge_refuses_a_missing_shard(tmp_path):
    study = coil.tolerance_study(CASE, TABLE4, out=tmp_path, samples=2, paper_material=True,
                                 elements_per_coil=8)
    coil.run_shard(study, "1/3", tmp_path / "p")
    coil.run_shard(study, "3/3", tmp_path / "p")
    try:
        coil.merge([tmp_path / "p"], tmp_path / "m")
    except coil.CoilError as error:
        assert "shard 2/3 missing" in str(error)
    else:
        raise AssertionError("merge accepted a missing shard")
