"""Cost of a compound screen (tirefric screen) and how it scales with workers.

    python benchmarks/bench_screen.py [--spec screen_example] [--n-scaling 4] [--no-dask]
                                      [--out bench_screen_out]

1. One worker over the whole spec (fresh output folder): the cost per compound (median of the
   tasks' wall times, and their CPU times), the wall time, the overhead share
   1 - sum(task times) / wall (what the runner, the store and the process cost around the
   tasks).
2. Two local worker processes over the first ``--n-scaling`` compounds and the reference
   (fresh folder): wall time, speed-up against the same tasks' times of run 1, and the
   overhead share 1 - sum(task times) / (workers x wall).
3. A dask.distributed LocalCluster of 4 single-threaded processes over the same tasks (if
   dask.distributed is installed).
4. The estimate for 1000 compounds on 16 workers from the measured per-task cost and
   overhead, and what 100 compounds x 2 roads (the screen's dry and wet road) take here.

Medians and ratios only; the machine may be shared (load average printed).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import time
from pathlib import Path

import numpy as np

from tire_brush.screening import load_screen_spec, run_screen


def _summary(res, workers: int) -> dict:
    recs = [r for r in res.records if r["key"] in res.computed]
    if res.reference["key"] in res.computed:
        recs.append(res.reference)
    task = np.array([r["seconds"]["total_s"] for r in recs])
    cpu = np.array([r["seconds"].get("cpu_s", np.nan) for r in recs])
    comp = [r for r in recs if not r.get("reference")]
    # per worker: the span from its first task's start to its last task's end, less its
    # tasks' own times, is what dispatching cost it (the runner, pickling, the store); the
    # rest of workers x wall is the tail (workers idle at the end: fewer tasks than workers
    # x their length), which a 1000-task screen makes small
    spans: dict[tuple, list] = {}
    for r in recs:
        w = r.get("worker")
        if w:
            spans.setdefault((w["host"], w["pid"]), []).append(r)
    gaps = sum(max(x["worker"]["end_epoch_s"] for x in rs)
               - min(x["worker"]["start_epoch_s"] for x in rs)
               - sum(x["seconds"]["total_s"] for x in rs) for rs in spans.values())
    busy = sum(max(x["worker"]["end_epoch_s"] for x in rs)
               - min(x["worker"]["start_epoch_s"] for x in rs) for rs in spans.values())
    return {"workers": workers, "tasks": len(recs), "wall_s": res.wall_s,
            "dispatch_share": float(gaps / busy) if busy > 0 else float("nan"),
            "worker_processes": len(spans),
            "task_s_sum": float(task.sum()),
            "compound_s_median": float(np.median([r["seconds"]["total_s"] for r in comp])),
            "compound_cpu_s_median": float(np.median([r["seconds"]["cpu_s"] for r in comp])),
            "reference_s": float(res.reference["seconds"]["total_s"])
            if res.reference["key"] in res.computed else None,
            "overhead_share": float(1.0 - task.sum() / (workers * res.wall_s)),
            "cpu_share": float(np.nansum(cpu) / task.sum()),
            "failed": [r["name"] for r in res.failed]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spec", default="screen_example")
    ap.add_argument("--n-scaling", type=int, default=4)
    ap.add_argument("--no-dask", action="store_true")
    ap.add_argument("--out", default="bench_screen_out")
    ap.add_argument("--json", default=None)
    args = ap.parse_args()
    out = Path(args.out)
    if out.exists():
        shutil.rmtree(out)
    spec = load_screen_spec(args.spec)
    print(f"load average {os.getloadavg()}, {os.cpu_count()} cores")
    res1 = run_screen(spec, out / "w1", workers=1, progress=False)
    s1 = _summary(res1, 1)
    print(f"1 worker, {s1['tasks']} tasks: wall {s1['wall_s']:.1f} s, cost per compound "
          f"(median) {s1['compound_s_median']:.1f} s wall / {s1['compound_cpu_s_median']:.1f} "
          f"s CPU, reference {s1['reference_s']:.1f} s, overhead "
          f"{100 * s1['overhead_share']:.2f} %")
    report = {"load_average": os.getloadavg(), "serial": s1}
    # the scaling runs: the first n compounds (and the reference)
    names = [d["name"] for d in spec.compounds()][: args.n_scaling]
    task1 = {r["name"]: r["seconds"]["total_s"] for r in res1.records}
    task1[res1.reference["name"]] = res1.reference["seconds"]["total_s"]
    serial_same = sum(task1[n] for n in names) + res1.reference["seconds"]["total_s"]

    def subset_run(folder: Path, **kw):
        # same settings, only the first n compounds: run the whole spec but pre-seed the
        # store with the records of the others from run 1 (their keys are the same)
        (folder / "compounds").mkdir(parents=True)
        for r in res1.records:
            if r["name"] not in names:
                shutil.copy(out / "w1" / "compounds" / f"{r['key']}.json",
                            folder / "compounds" / f"{r['key']}.json")
        return run_screen(spec, folder, progress=False, write=False, **kw)

    res2 = subset_run(out / "w2", workers=2)
    s2 = _summary(res2, 2)
    s2["speedup_vs_serial_tasks"] = serial_same / s2["wall_s"]
    print(f"2 workers, {s2['tasks']} tasks: wall {s2['wall_s']:.1f} s (the same tasks took "
          f"{serial_same:.1f} s in run 1: speed-up {s2['speedup_vs_serial_tasks']:.2f}), "
          f"median task {s2['compound_s_median']:.1f} s, overhead "
          f"{100 * s2['overhead_share']:.2f} % of 2 workers' time (dispatch "
          f"{100 * s2['dispatch_share']:.2f} %, the rest the run's tail)")
    report["two_workers"] = s2
    per_task = s1["compound_s_median"]
    # per-task overhead: the serial run's share (runner and store around the tasks) and the
    # parallel runs' dispatch share (the gaps between a worker's tasks), whichever is larger;
    # not the tail of a short run (workers idle at its end)
    overhead = max(s1["overhead_share"], s2["dispatch_share"], 0.0)
    if not args.no_dask:
        try:
            from distributed import Client, LocalCluster
        except ImportError:
            print("dask.distributed not installed: LocalCluster run skipped")
        else:
            t0 = time.perf_counter()
            with LocalCluster(n_workers=4, threads_per_worker=1, processes=True,
                              dashboard_address=None) as cluster, Client(cluster) as client:
                start = time.perf_counter() - t0
                res3 = subset_run(out / "dask4", scheduler=client)
            s3 = _summary(res3, 4)
            s3["cluster_start_s"] = start
            s3["speedup_vs_serial_tasks"] = serial_same / s3["wall_s"]
            print(f"dask LocalCluster 4 processes on {os.cpu_count()} cores, {s3['tasks']} "
                  f"tasks: wall {s3['wall_s']:.1f} s (cluster start {start:.1f} s), speed-up "
                  f"{s3['speedup_vs_serial_tasks']:.2f}, median task "
                  f"{s3['compound_s_median']:.1f} s (4 processes share the cores), overhead "
                  f"{100 * s3['overhead_share']:.2f} % of 4 workers' time")
            report["dask_local_4"] = s3
    # 1000 tasks on 16 workers: 62.5 per worker, the tail at most one task
    est = 1000 * per_task / 16 * (1 + overhead) + per_task
    cpu = s1["compound_cpu_s_median"]
    est_cpu = 1000 * cpu / 16 * (1 + overhead) + cpu
    print(f"estimate, 1000 compounds on 16 workers with {per_task:.1f} s per compound and "
          f"{100 * overhead:.2f} % per-task overhead: {est / 60:.0f} min (the tail at most one "
          f"task); at the CPU time per compound {cpu:.1f} s (idle workers): "
          f"{est_cpu / 60:.0f} min")
    print(f"100 compounds x 2 roads here: {100 * per_task / 2 / 60:.0f} min on 2 workers at "
          f"the loaded wall time per compound, {100 * cpu / 2 / 60:.0f} min at its CPU time "
          f"(an idle machine)")
    report["estimate_1000_on_16_s"] = est
    report["estimate_100_on_2_s"] = {"wall": 100 * per_task / 2, "cpu": 100 * cpu / 2}
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
