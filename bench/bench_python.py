#!/usr/bin/env python3
"""The Python package's costs (BENCHMARKS.md, "Python and batch"): a small Mie call through the
binding, the C++ library (bench_mie) and the CLI; batch rain throughput with 1 and 2 workers against
the single-process CLI; Dask's scheduling overhead per task.

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_python.py [--build build] [--frames 48]
"""
import argparse
import json
import os
import shutil
import subprocess
import tempfile
import time
import timeit


def best_per_call(stmt, number, repeat=7):
    return min(timeit.repeat(stmt, number=number, repeat=repeat)) / number


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--build", default="build")
    p.add_argument("--frames", type=int, default=96)
    p.add_argument("--size", default="640x360")
    a = p.parse_args()
    import numpy as np

    import hydrolux as h

    cli = os.path.join(a.build, "bin", "hydrolux")
    print(f"## Small Mie call (x = 1, m = 1.333 + 1e-8i, efficiencies only), {os.cpu_count()} cores")
    cxx = subprocess.run([os.path.join(a.build, "bin", "bench_mie"), "--benchmark_filter=BM_MieEfficiencies/1$",
                          "--benchmark_format=json", "--benchmark_repetitions=5",
                          "--benchmark_report_aggregates_only=true"], capture_output=True, text=True, check=True)
    med = [b for b in json.loads(cxx.stdout)["benchmarks"] if b["name"].endswith("_median")][0]
    t_cxx = med["real_time"] * {"ns": 1e-9, "us": 1e-6, "ms": 1e-3}[med["time_unit"]]
    m = 1.333 + 1e-8j
    t_py = best_per_call(lambda: h.mie(m, 1.0, angles_deg=None), 20000)
    xs = np.ones(100000)
    t_vec = best_per_call(lambda: h.mie(m, xs, angles_deg=None, threads=1), 3) / xs.size
    t_py181 = best_per_call(lambda: h.mie(m, 1.0), 5000)
    runs = []
    for _ in range(30):
        t0 = time.perf_counter()
        subprocess.run([cli, "mie", "--m", "1.333+1e-8i", "--x", "1", "--no-angles"], stdout=subprocess.DEVNULL,
                       check=True)
        runs.append(time.perf_counter() - t0)
    t_cli = min(runs)
    print("| path | time per call | over C++ |")
    print("| --- | --- | --- |")
    print(f"| C++ `mie_efficiencies(m, 1.0)` (bench_mie, median of 5) | {t_cxx * 1e6:.3f} us | 1 |")
    print(f"| Python `hydrolux.mie(m, 1.0, angles_deg=None)` (best of 7 x 20000) | {t_py * 1e6:.2f} us | "
          f"{t_py / t_cxx:.1f}x |")
    print(f"| Python, one call over 100,000 sizes, 1 thread, per size | {t_vec * 1e6:.3f} us | {t_vec / t_cxx:.2f}x |")
    print(f"| Python `hydrolux.mie(m, 1.0)` with the default 181 angles | {t_py181 * 1e6:.2f} us | - |")
    print(f"| CLI `hydrolux mie --m ... --x 1 --no-angles` (process, best of 30) | {t_cli * 1e3:.2f} ms | "
          f"{t_cli / t_cxx:.0f}x |")

    # ---- batch throughput ----
    w, hh = map(int, a.size.split("x"))
    tmp = tempfile.mkdtemp(prefix="hydrolux-bench-")
    try:
        frames = os.path.join(tmp, "frames")
        os.makedirs(frames)
        for k in range(a.frames):
            h.write_image(os.path.join(frames, f"f_{k:04d}.png"), h.builtin_scene(w, hh, pitch_deg=0.05 * k))
        print(f"\n## Batch rain, {a.frames} PNG frames of {w}x{hh}, 25 mm/h, seed 4")
        t0 = time.perf_counter()
        subprocess.run([cli, "rain", "--input-dir", frames, "--output-dir", os.path.join(tmp, "cli"), "--seed", "4",
                        "-q"], check=True)
        t_single = time.perf_counter() - t0
        print("| run | wall (s) | frames/s over the wall | frames/s, steady (first to last task) | fixed cost (s) |")
        print("| --- | --- | --- | --- | --- |")
        print(f"| `hydrolux rain --input-dir` (one process, 2 threads) | {t_single:.2f} | {a.frames / t_single:.1f} | - "
              "| - |")
        for workers in (1, 2):
            out = os.path.join(tmp, f"b{workers}")
            marks = {}

            def hook(done, client, marks=marks):
                marks.setdefault("first", (time.perf_counter(), done))
                marks["last"] = (time.perf_counter(), done)

            from hydrolux.batch import rain as br
            t0 = time.perf_counter()
            ns = argparse.Namespace(input_dir=frames, output_dir=out, mask_dir=None, depth_dir=None,
                                    depth_scale_m=None, frame_index=0, chunk_frames=4, workers=workers,
                                    threads_per_worker=1, scheduler=None, quiet=True, video=None, output=None, crf=None)
            for p in br.params():  # every other declared parameter as the batch's parser leaves it
                if not hasattr(ns, p["name"]):
                    setattr(ns, p["name"], br.parser_default(p))
            ns.seed = 4
            br.run(ns, after_result=hook)
            wall = time.perf_counter() - t0
            same = all(open(os.path.join(tmp, "cli", n), "rb").read() == open(os.path.join(out, n), "rb").read()
                       for n in os.listdir(os.path.join(tmp, "cli")))
            tasks = marks["last"][1] - marks["first"][1]
            steady = tasks * 4 / (marks["last"][0] - marks["first"][0])
            print(f"| batch, LocalCluster {workers} worker(s) x 1 thread, tasks of 4 frames"
                  f"{'' if same else ' (BYTES DIFFER)'} | {wall:.2f} | {a.frames / wall:.1f} | {steady:.1f} | "
                  f"{wall - a.frames / steady:.1f} |")
        # Scheduling overhead: no-op tasks through the same client set-up.
        from hydrolux.batch import _common
        client, cluster = _common.open_client(None, 2, 1, True)
        try:
            client.submit(int, 0).result()
            per = []
            for _ in range(3):
                t0 = time.perf_counter()
                futs = [client.submit(int, i, pure=False) for i in range(1000)]
                client.gather(futs)
                per.append((time.perf_counter() - t0) / 1000)
            print(f"\nDask scheduling overhead (2 workers, 1000 no-op tasks submitted and gathered, best of 3): "
                  f"{min(per) * 1e3:.2f} ms per task")
        finally:
            client.close()
            cluster.close()
        t0 = time.perf_counter()
        client, cluster = _common.open_client(None, 2, 1, True)
        t1 = time.perf_counter()
        client.close()
        cluster.close()
        print(f"LocalCluster of 2 workers: start {t1 - t0:.2f} s, stop {time.perf_counter() - t1:.2f} s")
    finally:
        shutil.rmtree(tmp)



if __name__ == "__main__":
    main()
