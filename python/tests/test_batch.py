"""hydrolux.batch on a LocalCluster on 127.0.0.1: the same bytes as the single-process CLI, resume
from the manifest, a worker killed mid-run, a corrupt frame, the Lee atlas, and usage errors."""
import argparse
import json
import os
import shutil
import signal
import subprocess
import sys

import numpy as np
import pytest

import hydrolux as h
from hydrolux.batch import _common, lee_atlas
from hydrolux.batch import rain as batch_rain
from hydrolux.batch.__main__ import main

FRAMES = 16
SIZE = (192, 108)


@pytest.fixture(scope="module")
def frames(tmp_path_factory):
    """A short sequence: the built-in scene with the camera panning down a little each frame."""
    d = tmp_path_factory.mktemp("frames")
    for k in range(FRAMES):
        h.write_image(str(d / f"f_{k:03d}.png"), h.builtin_scene(*SIZE, pitch_deg=2 - 0.25 * k))
    return d


@pytest.fixture(scope="module")
def cli_out(frames, tmp_path_factory, cli):
    """The single-process reference: hydrolux rain --input-dir over the whole sequence."""
    d = tmp_path_factory.mktemp("cli")
    cli("rain", "--input-dir", frames, "--output-dir", d / "rainy", "--mask-dir", d / "masks", "--seed", 4,
        "--rain-rate-mmh", 25, "--wind-mps", 2, "--frame-index", 10, "-q")
    return d


def batch_args(frames, out, **kw):
    a = argparse.Namespace(input_dir=str(frames), output_dir=str(out), mask_dir=None, depth_dir=None,
                           depth_scale_m=None, video=None, output=None, crf=None, frame_index=10,
                           chunk_frames=3, workers=2, threads_per_worker=1, scheduler=None, quiet=True)
    for p in batch_rain.params():  # every other declared parameter as the parser leaves it
        if not hasattr(a, p["name"]):
            setattr(a, p["name"], batch_rain.parser_default(p))
    a.seed, a.rain_rate_mmh, a.wind_mps = 4, 25.0, 2.0
    for k, v in kw.items():
        setattr(a, k, v)
    return a


def manifest_records(folder):
    lines = (folder / _common.MANIFEST).read_text().splitlines()
    return json.loads(lines[0]), [json.loads(line) for line in lines[1:]]


def assert_same_bytes(a, b, names):
    for n in names:
        assert (a / n).read_bytes() == (b / n).read_bytes(), n


def temporaries(folder):
    return [n for n in os.listdir(folder) if ".tmp-" in n]


def test_two_workers_give_the_single_process_bytes_and_resume(frames, cli_out, tmp_path):
    out, masks = tmp_path / "rainy", tmp_path / "masks"
    assert batch_rain.run(batch_args(frames, out, mask_dir=str(masks))) == 0
    names = sorted(os.listdir(cli_out / "rainy"))
    assert len(names) == FRAMES
    assert_same_bytes(cli_out / "rainy", out, names)
    assert_same_bytes(cli_out / "masks", masks, names)
    header, records = manifest_records(out)
    assert header["job"] == "rain" and sorted(r["output"] for r in records) == names
    assert [r["frame_index"] for r in sorted(records, key=lambda r: r["output"])] == list(range(10, 10 + FRAMES))
    assert not temporaries(out)
    # A re-run does nothing: every frame is in the manifest and unchanged.
    stamps = {n: os.stat(out / n).st_mtime_ns for n in names}
    done = []
    assert batch_rain.run(batch_args(frames, out, mask_dir=str(masks)),
                          after_result=lambda n, c: done.append(n)) == 0
    assert done == [] and {n: os.stat(out / n).st_mtime_ns for n in names} == stamps
    # Other parameters: a new manifest, everything redone, other bytes.
    assert batch_rain.run(batch_args(frames, out, seed=5)) == 0
    header, records = manifest_records(out)
    assert header["params"]["options"]["seed"] == 5 and len(records) == FRAMES
    assert (out / names[0]).read_bytes() != (cli_out / "rainy" / names[0]).read_bytes()


def test_a_worker_killed_mid_run_loses_nothing(frames, cli_out, tmp_path):
    out = tmp_path / "rainy"
    killed = []

    def kill_one(done, client):
        if killed:
            return
        # The worker with the most tasks still to do dies outright (no clean-up of its own).
        processing = client.processing()
        addr = max(processing, key=lambda w: len(processing[w]))
        pid = client.run(os.getpid, workers=[addr])[addr]
        os.kill(pid, signal.SIGKILL)
        killed.append((addr, len(processing[addr])))

    assert batch_rain.run(batch_args(frames, out, chunk_frames=1), after_result=kill_one) == 0
    assert killed and killed[0][1] > 0  # it had tasks when it died
    names = sorted(os.listdir(cli_out / "rainy"))
    assert sorted(n for n in os.listdir(out) if not n.startswith("hydrolux-manifest")) == names
    assert_same_bytes(cli_out / "rainy", out, names)
    _, records = manifest_records(out)
    assert sorted(r["output"] for r in records) == names  # each once
    assert not temporaries(out)


def test_a_corrupt_frame_is_reported_and_the_others_go_on(frames, cli_out, tmp_path, capfd):
    src = tmp_path / "frames"
    shutil.copytree(frames, src)
    good = (src / "f_005.png").read_bytes()
    (src / "f_005.png").write_bytes(good[:200])  # truncated
    out = tmp_path / "rainy"
    a = batch_args(src, out)
    a.quiet = False
    assert batch_rain.run(a) == 1
    err = capfd.readouterr().err
    assert "f_005.png:" in err and "1 failed: f_005.png" in err
    names = sorted(os.listdir(cli_out / "rainy"))
    written = sorted(n for n in os.listdir(out) if not n.startswith("hydrolux-manifest"))
    assert written == [n for n in names if n != "f_005.png"]
    assert_same_bytes(cli_out / "rainy", out, written)
    assert "f_005.png" not in {r["output"] for r in manifest_records(out)[1]}
    # Repaired, a re-run renders that frame alone, with its place in the sequence.
    (src / "f_005.png").write_bytes(good)
    done = []
    assert batch_rain.run(batch_args(src, out), after_result=lambda n, c: done.append(n)) == 0
    assert len(done) == 1
    assert_same_bytes(cli_out / "rainy", out, names)


def test_usage_errors_are_one_line_exit_2(frames, tmp_path, capfd):
    cases = [
        (["rain", "--input-dir", str(frames), "--output-dir", str(tmp_path / "o"), "--rain-rate-mmh", "600"],
         "--rain-rate-mmh: 600 is outside the valid range [0, 500] mm/h"),
        (["rain", "--input-dir", str(frames), "--output-dir", str(frames)], "is the input folder"),
        (["rain", "--input-dir", str(tmp_path / "none"), "--output-dir", str(tmp_path / "o")], "not a folder"),
        (["rain", "--input-dir", str(frames), "--output-dir", str(tmp_path / "o"), "--workers", "0"],
         "--workers: 0 is outside the valid range [1, "),
        (["rain", "--input-dir", str(frames), "--output-dir", str(tmp_path / "o"), "--seed", "1.5"],
         "--seed: 1.5 is not a whole number; valid range [0, 9007199254740992]"),
        (["lee-atlas", "--spec", str(tmp_path / "none.json"), "--output-dir", str(tmp_path / "o")], "no such file"),
    ]
    for argv, text in cases:
        assert main(argv + ["-q"]) == 2, argv
        err = capfd.readouterr().err.strip()
        assert text in err and "\n" not in err, err
    assert not (tmp_path / "o").exists() or not os.listdir(tmp_path / "o")


def test_lee_atlas_sweeps_reports_a_bad_table_and_resumes(cli, tmp_path, capfd):
    spec = {"defaults": {"size": "6x12", "sampling": 0.25},
            "tables": [{"name": "bow-s{size-spread}", "table": "rainbow", "radius-um": "100:400",
                        "sweep": {"size-spread": [0.05, 0.2]}},
                       {"name": "corona", "table": "corona", "limb_darkening": True},
                       {"name": "bad", "table": "rainbow", "radius-um": "0.01:1"}]}
    path = tmp_path / "atlas.json"
    path.write_text(json.dumps(spec))
    out = tmp_path / "atlas"
    a = argparse.Namespace(spec=str(path), output_dir=str(out), threads_per_table=1, workers=2, threads_per_worker=1,
                           scheduler=None, quiet=False)
    assert lee_atlas.run(a) == 2  # the one failure is a table the CLI refuses for its options (its exit 2)
    err = capfd.readouterr().err
    assert "bad: " in err and "--radius-um" in err
    names = ["bow-s0.05", "bow-s0.2", "corona"]
    for n in names:
        for ext in (".exr", ".png", ".json"):
            assert (out / (n + ext)).is_file()
    assert not (out / "bad.exr").exists() and not temporaries(out)
    # The same table by hand: the same bytes.
    cli("lee", "-o", tmp_path / "by_hand.exr", "-q", "--threads", 1, "--size", "6x12", "--sampling", 0.25,
        "--table", "rainbow", "--radius-um", "100:400", "--size-spread", 0.2)
    assert (tmp_path / "by_hand.exr").read_bytes() == (out / "bow-s0.2.exr").read_bytes()
    assert (tmp_path / "by_hand.png").read_bytes() == (out / "bow-s0.2.png").read_bytes()
    assert sorted(r["output"] for r in manifest_records(out)[1]) == names
    # Re-run: only the bad table is tried again.
    done = []
    a.quiet = True
    assert lee_atlas.run(a, after_result=lambda n, c: done.append(n)) == 2
    assert len(done) == 1


def test_command_line_entry_point(frames, tmp_path):
    out = tmp_path / "o"
    env = dict(os.environ)
    p = subprocess.run([sys.executable, "-m", "hydrolux.batch", "rain", "--input-dir", str(frames), "--output-dir",
                        str(out), "--workers", "1", "--seed", "4"], capture_output=True, text=True, env=env)
    assert p.returncode == 0, p.stderr
    assert "tasks" in p.stderr and "ETA" in p.stderr and f"{FRAMES} of {FRAMES} frames" in p.stderr
    assert len([n for n in os.listdir(out) if n.endswith(".png")]) == FRAMES


def test_video_in_chunks_is_the_cli_video_and_resumes(cli, tmp_path):
    src = tmp_path / "in.mp4"
    subprocess.run(["ffmpeg", "-loglevel", "error", "-y", "-f", "lavfi", "-i", "testsrc=size=160x96:rate=25",
                    "-frames:v", "23", "-pix_fmt", "yuv420p", str(src)], check=True)
    cli("rain", "--video", src, "-o", tmp_path / "cli.mp4", "--seed", 4, "--wind-mps", 3, "--frame-index", 7, "-q")
    out = tmp_path / "out" / "rainy.mp4"
    out.parent.mkdir()

    def args():
        a = batch_args(None, None, chunk_frames=5, frame_index=7, wind_mps=3.0)
        a.input_dir = a.output_dir = None
        a.video, a.output = str(src), str(out)
        return a

    # Interrupted after two chunks (a crash of the client): nothing is in place yet.
    def stop(done, client):
        if done == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        batch_rain.run(args(), after_result=stop)
    assert not out.exists()
    # Resumed with another chunk size elsewhere: the staged chunks do not fit, everything is redone.
    other = out.parent / "other.mp4"

    def args7():
        a = args()
        a.output, a.chunk_frames = str(other), 7
        return a

    a5 = args()
    a5.output = str(other)
    with pytest.raises(KeyboardInterrupt):
        batch_rain.run(a5, after_result=stop)
    done7 = []
    assert batch_rain.run(args7(), after_result=lambda n, c: done7.append(n)) == 0
    assert len(done7) == 4  # 23 frames in chunks of 7
    assert other.read_bytes() == (tmp_path / "cli.mp4").read_bytes()
    # The re-run does the other three chunks and encodes: the CLI's bytes.
    done = []
    assert batch_rain.run(args(), after_result=lambda n, c: done.append(n)) == 0
    assert len(done) == 3
    assert out.read_bytes() == (tmp_path / "cli.mp4").read_bytes()
    staging = out.parent / ".rainy.mp4.chunks"
    assert not [n for n in os.listdir(staging) if n.endswith(".rgb") or ".tmp-" in n]
    # And once more: nothing to do.
    done.clear()
    assert batch_rain.run(args(), after_result=lambda n, c: done.append(n)) == 0 and done == []


def test_an_existing_cluster_through_scheduler(frames, cli_out, tmp_path):
    import time
    sched_file = tmp_path / "scheduler.json"
    env = dict(os.environ)
    procs = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port",
                               "0", "--no-dashboard", "--scheduler-file", str(sched_file)],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)]
    try:
        for _ in range(600):  # until the scheduler has written its address (a guard, not a time limit)
            if sched_file.exists() and sched_file.stat().st_size > 0:
                break
            time.sleep(0.05)
        address = json.loads(sched_file.read_text())["address"]
        procs.append(subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address, "--nworkers", "2",
                                       "--nthreads", "1", "--no-dashboard"],
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env))
        from distributed import Client
        with Client(address) as c:
            c.wait_for_workers(2)
        out = tmp_path / "rainy"
        assert main(["rain", "--scheduler", address, "--input-dir", str(frames), "--output-dir", str(out),
                     "--seed", "4", "--rain-rate-mmh", "25", "--wind-mps", "2", "--frame-index", "10", "-q"]) == 0
        names = sorted(os.listdir(cli_out / "rainy"))
        assert_same_bytes(cli_out / "rainy", out, names)
    finally:
        for p in reversed(procs):
            p.terminate()
            p.wait()


def test_an_unreachable_scheduler_is_a_usage_error_and_writes_nothing(frames, tmp_path, capfd):
    import socket
    with socket.socket() as s:  # a port nobody listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    out = tmp_path / "rainy"
    assert main(["rain", "--scheduler", f"tcp://127.0.0.1:{port}", "--input-dir", str(frames), "--output-dir",
                 str(out), "-q"]) == 2
    assert "cannot connect" in capfd.readouterr().err
    assert not out.exists()


def test_depth_maps_give_the_cli_bytes_and_are_tracked(frames, cli, cli_out, tmp_path):
    # A wall 3 m away over the left half (EXR metres), open sky elsewhere; PNG codes for the others.
    depth = tmp_path / "depth"
    depth.mkdir()
    w, hh = SIZE
    for k in range(FRAMES):
        z = np.full((hh, w, 1), np.inf, np.float32)
        z[:, : w // 2] = 3.0 + 0.1 * k
        if k % 2:
            h.write_image(str(depth / f"f_{k:03d}.exr"), z)
        else:  # a 16-bit PNG (code 0: no geometry); what its codes mean is the same for both readers
            h.write_image(str(depth / f"f_{k:03d}.png"), np.where(np.isfinite(z), z / 100, 0), bits=16)
    cli("rain", "--input-dir", frames, "--output-dir", tmp_path / "cli", "--depth-dir", depth, "--seed", 4,
        "--rain-rate-mmh", 25, "--wind-mps", 2, "--frame-index", 10, "-q")
    out = tmp_path / "rainy"
    assert batch_rain.run(batch_args(frames, out, depth_dir=str(depth))) == 0
    names = sorted(os.listdir(tmp_path / "cli"))
    assert_same_bytes(tmp_path / "cli", out, names)
    assert (out / names[0]).read_bytes() != (cli_out / "rainy" / names[0]).read_bytes()  # the wall hides rain
    # A changed depth map redoes its frame alone.
    z = h.read_image(str(depth / "f_003.exr"))
    h.write_image(str(depth / "f_003.exr"), z * 0.5)
    done = []
    assert batch_rain.run(batch_args(frames, out, depth_dir=str(depth)), after_result=lambda n, c: done.append(n)) == 0
    assert len(done) == 1


def test_a_frame_added_before_others_shifts_their_index(frames, tmp_path):
    src = tmp_path / "frames"
    shutil.copytree(frames, src)
    out = tmp_path / "rainy"
    assert batch_rain.run(batch_args(src, out, chunk_frames=4)) == 0
    shutil.copy(src / "f_000.png", src / "f_000a.png")  # sorts second: every later frame moves on by one
    done = []
    assert batch_rain.run(batch_args(src, out, chunk_frames=1), after_result=lambda n, c: done.append(n)) == 0
    assert len(done) == FRAMES  # all but f_000.png, and the new one
    records = {r["output"]: r["frame_index"] for r in manifest_records(out)[1]}
    assert records["f_000.png"] == 10 and records["f_000a.png"] == 11 and records["f_015.png"] == 10 + FRAMES


def test_a_torn_manifest_line_is_dropped_not_glued_to_the_next(tmp_path):
    m = _common.Manifest(str(tmp_path), "rain", {"p": 1})
    m.add({"output": "a.png", "x": 1})
    m.close()
    with open(tmp_path / _common.MANIFEST, "ab") as f:
        f.write(b'{"output": "b.p')  # a crash mid-line
    m = _common.Manifest(str(tmp_path), "rain", {"p": 1})
    assert set(m.records) == {"a.png"}
    m.add({"output": "c.png", "x": 3})
    m.close()
    m = _common.Manifest(str(tmp_path), "rain", {"p": 1})
    assert set(m.records) == {"a.png", "c.png"}
    # One run at a time per folder.
    with pytest.raises(_common.UsageError, match="another hydrolux.batch run"):
        _common.Manifest(str(tmp_path), "rain", {"p": 1})
    m.close()


def crash_on_f_005(job, frames):
    """A task that kills its worker whenever its chunk holds f_005.png (a frame that crashes a codec)."""
    if any(f[0] == "f_005.png" for f in frames):
        os._exit(17)
    from hydrolux.batch.rain import render_frames
    return render_frames(job, frames)


def test_a_frame_that_kills_its_worker_is_named_and_the_rest_kept(frames, cli_out, tmp_path, monkeypatch, capfd):
    import cloudpickle
    import dask
    cloudpickle.register_pickle_by_value(sys.modules[__name__])  # the workers cannot import this file
    monkeypatch.setattr(batch_rain, "render_frames", crash_on_f_005)
    out = tmp_path / "rainy"
    a = batch_args(frames, out, chunk_frames=4)
    a.quiet = False
    with dask.config.set({"distributed.scheduler.allowed-failures": 1}):
        assert batch_rain.run(a) == 1
    err = capfd.readouterr().err
    assert "f_005.png: KilledWorker" in err and "1 failed: f_005.png" in err
    names = [n for n in sorted(os.listdir(cli_out / "rainy")) if n != "f_005.png"]
    assert sorted(n for n in os.listdir(out) if n.endswith(".png")) == names
    assert_same_bytes(cli_out / "rainy", out, names)
