"""Ctrl-C latency of coil's long Python calls: each call runs in a child interpreter,
SIGINT is sent after ``--after`` seconds, and the time from the signal to the child's
exit is printed (with how the call ended and whether its output folder was left as it
was). Run from the repository root:

    python python/examples/ctrl_c_latency.py [--after 3] [--limit 120]

A call that is still running ``--limit`` seconds after the signal is killed and shown
as "not stopped". Used for the acceptance numbers of the trust work (docs/python.md).
"""

import argparse
import os
import signal
import subprocess
import sys
import tempfile
import textwrap
import time

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))

SETUP = textwrap.dedent(
    """
    import os, sys, time, coil
    repo, out = sys.argv[1], sys.argv[2]
    case = os.path.join(repo, "cases", "160ect")
    table4 = os.path.join(case, "table4.json")
    """
)

CALLS = {
    "solve (long transient)": """
deck = coil.spring(analyses=["static", "transient"], dt_s=1e-5, duration_s=200.0,
                   initial_velocity_m_s=0.1, mass_kg=5.0, elements_per_coil=12)
print("ready", flush=True)
coil.solve(deck, out=out, allow_large=True)
""",
    "calibrate": """
print("ready", flush=True)
coil.calibrate(case, out=out, elements_per_coil=12, method="direct", check=False)
""",
    "tolerance": """
print("ready", flush=True)
coil.tolerance(case, table4, out=out, samples=200, paper_material=True,
               elements_per_coil=12, plots=False)
""",
    "diagnose": """
print("ready", flush=True)
coil.diagnose(os.path.join(repo, "cases/measured/friction_g1"), out, elements_per_coil=12,
              modes=8, plots=False)
""",
}


def measure(name, body, after, limit):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out")
        os.makedirs(out)
        with open(os.path.join(out, "previous.txt"), "w") as f:
            f.write("previous set\n")
        before = sorted(os.listdir(out))
        child = subprocess.Popen(
            [sys.executable, "-c", SETUP + body, REPO, out],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        )
        child.stdout.readline()
        time.sleep(after)
        if child.poll() is not None:
            return f"{name:24s} finished before the signal ({after} s): lower --after"
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        try:
            _, err = child.communicate(timeout=limit)
            latency = time.monotonic() - sent
            ended = "KeyboardInterrupt" if "KeyboardInterrupt" in err else f"exit {child.returncode}"
        except subprocess.TimeoutExpired:
            child.kill()
            child.communicate()
            return f"{name:24s} not stopped {limit} s after SIGINT (killed)"
        after_names = sorted(n for n in os.listdir(out) if not n.startswith(".coil-lock"))
        kept = "output folder as it was" if after_names == before else f"output folder now {after_names}"
        return f"{name:24s} {latency:6.2f} s  {ended}; {kept}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--after", type=float, default=3.0)
    parser.add_argument("--limit", type=float, default=120.0)
    parser.add_argument("calls", nargs="*", default=list(CALLS))
    args = parser.parse_args()
    for name in args.calls:
        print(measure(name, CALLS[name], args.after, args.limit), flush=True)


if __name__ == "__main__":
    main()
