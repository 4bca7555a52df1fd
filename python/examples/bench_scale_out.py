"""Benchmark: throughput of a tolerance sweep of the Table 4 springs, serial, on Dask and
in shards of the coil-tune binary (a benchmark, not a test; run from the repository's
root after `pip install ./python` and `cargo build --release -p coil-tune`):

    python python/examples/bench_scale_out.py [SAMPLES_PER_SPRING] [WORKERS]

SAMPLES_PER_SPRING = 333 gives 6 x 334 = 2004 tasks. Every configuration uses one thread
per process (RAYON_NUM_THREADS=1), so "serial" is one core, and "2 Dask workers" and
"2 shards" are two processes. Prints tasks per second and checks that the three tables
are the same bytes.
"""

import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

os.environ["RAYON_NUM_THREADS"] = "1"

import coil  # noqa: E402
from dask.distributed import Client, LocalCluster  # noqa: E402


def main():
    samples = int(sys.argv[1]) if len(sys.argv) > 1 else 333
    workers = int(sys.argv[2]) if len(sys.argv) > 2 else 2
    case, variants = "cases/160ect", "cases/160ect/table4.json"
    exe = os.environ.get("COIL_TUNE", "target/release/coil-tune")
    out = Path(tempfile.mkdtemp(prefix="coil-bench-"))
    flags = ["--paper-material", "--samples", str(samples), "--seed", "2026"]

    study = coil.tolerance_study(case, variants, out, samples=samples, seed=2026, paper_material=True)
    tasks = json.loads(coil._coil.study_info(study))["tasks"]
    print(f"{tasks} tasks; {os.cpu_count()} cores; load average {os.getloadavg()[0]:.1f}")


    def report(name, seconds, extra=""):
        print(f"{name:34} {seconds:8.1f} s {tasks / seconds:7.2f} tasks/s {extra}")


    t0, c0 = time.perf_counter(), time.process_time()
    serial = coil.run_study(study)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    report("serial (1 process, 1 thread)", wall,
           f"per task {1e3 * wall / tasks:.1f} ms wall, {1e3 * cpu / tasks:.1f} ms CPU")
    coil._write(study, serial, out / "serial", False)

    t0 = time.perf_counter()
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        startup = time.perf_counter() - t0
        t1 = time.perf_counter()
        on_dask = coil.run_study(study, client)
        run = time.perf_counter() - t1
    report(f"Dask, {workers} workers (run)", run, f"cluster start-up {startup:.1f} s")
    coil._write(study, on_dask, out / "dask", False)

    t0, r0 = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
    procs = [subprocess.Popen([exe, "tolerance", case, "--variants", variants, *flags,
                               "--shard", f"{i}/{workers}", "--out", str(out / "parts"), "-q"],
                              stdout=subprocess.DEVNULL) for i in range(1, workers + 1)]
    assert all(p.wait() == 0 for p in procs)
    shards = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    shard_cpu = (r1.ru_utime + r1.ru_stime) - (r0.ru_utime + r0.ru_stime)
    t1 = time.perf_counter()
    subprocess.run([exe, "merge", str(out / "parts"), "--out", str(out / "merged"), "--no-plots"],
                   check=True, stdout=subprocess.DEVNULL)
    merge = time.perf_counter() - t1
    report(f"{workers} shards of coil-tune + merge", shards + merge,
           f"merge {merge:.2f} s, shards' CPU {1e3 * shard_cpu / tasks:.1f} ms per task")

    same = [(out / d / "tolerance.csv").read_bytes() for d in ["serial", "dask", "merged"]]
    print("tables identical:", same[0] == same[1] == same[2])


if __name__ == "__main__":  # Dask's worker processes import this file
    main()
