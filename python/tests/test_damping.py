"""coil.damping as coil-tune damping, and the package's namespace.

Two records of the paper's spring at 5.24 and 10.48 kg decaying at one zeta (closed-form
damped cosines at the frequencies sqrt(K / m_eff)) are a loss factor: the law is named
hysteretic with eta = 2 zeta. A record listed twice is refused naming both entries, and
no output is written.
"""

import json

import numpy as np
import pytest

import coil

ZETA = 0.00175


def _record(path, mass_kg):
    # K of the paper's spring (N/m) and a third of its 0.0586 kg wire.
    w = np.sqrt(3927.5 / (mass_kg + 0.0586 / 3.0))
    t = np.arange(8000) * 1e-3
    a = np.exp(-ZETA * w * t) * np.cos(w * np.sqrt(1.0 - ZETA**2) * t)
    path.write_text("time_s,accel_m_s2\n" + "".join(f"{x:.17g},{y:.17g}\n" for x, y in zip(t, a)))


def _case(folder, decay):
    (folder / "case.json").write_text(json.dumps({
        "name": "two masses",
        "spring": {"active_coils": 14.0, "mean_diameter_mm": 24.0, "wire_diameter_mm": 3.0,
                   "pitch_mm": 6.2},
        "material": {"youngs_modulus_mpa": 206000.0, "poisson_ratio": 0.3,
                     "density_kg_m3": 7850.0},
        "mass_kg": 5.24,
        "gravity_m_s2": 0.0,
        "records": {"decay": decay},
    }, indent=2))


def test_two_masses_with_one_zeta_are_hysteretic(tmp_path):
    _record(tmp_path / "a.csv", 5.24)
    _record(tmp_path / "b.csv", 10.48)
    _case(tmp_path, ["a.csv", {"file": "b.csv", "mass_kg": 10.48}])
    d = coil.damping(tmp_path, tmp_path / "out", elements_per_coil=8)
    assert d["law"] == "hysteretic" and d["identifiable"] is True
    assert abs(d["parameters"]["loss_factor"] / (2 * ZETA) - 1) < 1e-3
    assert d["repeat_scatter"]["source"] == "default"
    assert d["repeat_scatter"]["relative"] == 0.03
    assert (tmp_path / "out" / "report.md").is_file()
    assert json.loads((tmp_path / "out" / "damping.json").read_text()) == d


def test_a_record_listed_twice_is_refused(tmp_path):
    _record(tmp_path / "a.csv", 5.24)
    (tmp_path / "copy.csv").write_text((tmp_path / "a.csv").read_text())
    _case(tmp_path, ["a.csv", {"file": "copy.csv", "mass_kg": 10.48}])
    with pytest.raises(coil.CoilError) as error:
        coil.damping(tmp_path, tmp_path / "out", elements_per_coil=8)
    message = str(error.value)
    assert "records.decay[1] (copy.csv)" in message and "records.decay[0]" in message, message
    assert "identical content" in message, message
    assert not (tmp_path / "out").exists()


def test_the_namespace_is_the_api():
    names = dir(coil)
    assert names == sorted(coil.__all__)
    assert {"damping", "diagnose", "solve", "CoilError"} <= set(names)
    assert not {"json", "np", "os"} & set(names)
