# %% [markdown]
# # Table 3 of the paper from Python
#
# A notebook as a plain script (cells marked `# %%`: Jupyter, VS Code and Spyder run
# them one by one). Run from the repository's root:
#
#     python python/examples/table3.py [OUT_FOLDER]
#
# It calibrates the paper's spring (cases/160ect) through the three loops of the paper's
# Figure 6, prints Table 3 beside the paper's values, then runs one decay of the
# validated model, measures it with the paper's decrement and draws it (decay.png).

# %%
import sys
from pathlib import Path

import numpy as np

import coil

out = Path(sys.argv[1] if len(sys.argv) > 1 else "out/python-table3")
case = Path("cases/160ect")

# %% [markdown]
# ## Loops 1-3: E to K, the weight to T, Rayleigh alpha and beta to zeta

# %%
cal = coil.calibrate(case, out=out / "calibration")
s = cal["state"]
targets = cal["targets"]
chosen = cal["damping"]["chosen"]
checked = chosen["direct"] or {"zeta_mean": chosen["zeta"], "period_s": chosen["period_s"]}
rows = [
    ("K (N/mm)", targets["stiffness_n_mm"], 3.927506, cal["stiffness"]["iterations"][-1]["result"]),
    ("zeta", targets["damping_ratio"], 0.001747, checked["zeta_mean"]),
    ("T (s)", targets["period_s"], 0.23, checked["period_s"]),
    ("E (MPa)", None, 190708.0, s["youngs_modulus_mpa"]),
    ("alpha (1/s)", None, 0.8, s["alpha"]),
    ("beta (s)", None, 0.00012, s["beta"]),
]
print("Table 3:")
print(f"| {'':12} | {'experiment':>10} | {'paper FE':>10} | {'coil':>12} |")
for name, experiment, paper, ours in rows:
    e = "" if experiment is None else f"{experiment:.6g}"
    print(f"| {name:12} | {e:>10} | {paper:>10.6g} | {ours:>12.7g} |")

# %% [markdown]
# ## One decay of the validated model, measured as the paper did

# %%
deck = coil.spring(
    youngs_modulus_mpa=s["youngs_modulus_mpa"],
    mass_kg=s["mass_kg"],
    alpha=s["alpha"],
    beta=s["beta"],
    analyses=["transient"],
    dt_s=0.002,
    duration_s=6.0,
    initial_velocity_m_s=0.1,
)
run = coil.solve(deck, out=out / "decay")
history = run["load_cases"][0]["history"]
t, a = history["time_s"], history["node1_uz_accel_m_s2"]
d = coil.decrement(t, a, every=10, lowpass_hz=30.0)
print(f"decay: zeta = {d['zeta_mean']:.6f} (target {targets['damping_ratio']}), T = {d['period_s']:.6f} s")
assert abs(d["zeta_mean"] / targets["damping_ratio"] - 1) < 0.01

# %%
coil.plot_history(t, a, out / "decay.png", column="node1_uz_accel_m_s2",
                  label="validated model: weight's acceleration")
print(f"figure: {out / 'decay.png'}")
