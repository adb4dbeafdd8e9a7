"""hydrolux.batch against hostile conditions (issue 23): a full disk, odd and truncated videos, bad
addresses and numbers, more workers than the machine holds, outputs that are inputs through links, and
folder entries that are not files. Every failure must be one line on stderr (never a traceback) with
the CLI's exit codes, and leave nothing behind."""
import argparse
import json
import os
import resource
import shutil
import subprocess
import sys

import pytest

from hydrolux.batch import _common
from hydrolux.batch import rain as batch_rain
from hydrolux.batch.__main__ import main

FRAMES = 16


def ffmpeg(*args):
    subprocess.run(["ffmpeg", "-loglevel", "error", "-y", *map(str, args)], check=True)


@pytest.fixture(scope="module")
def frames(tmp_path_factory):
    """16 small frames (ffmpeg's test pattern, 64x36): small PNGs, each ~400 bytes."""
    d = tmp_path_factory.mktemp("frames")
    ffmpeg("-f", "lavfi", "-i", "testsrc=size=64x36:rate=25", "-frames:v", FRAMES, "-start_number", 0,
           d / "f_%03d.png")
    return d


def batch(*args, limit_file_bytes=None):
    """python3 -m hydrolux.batch, as a user runs it (a traceback would reach this stderr)."""
    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit_file_bytes, limit_file_bytes))

    return subprocess.run([sys.executable, "-m", "hydrolux.batch", *map(str, args)], capture_output=True, text=True,
                          preexec_fn=limit if limit_file_bytes else None)


def one_line(err):
    assert "Traceback" not in err, err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1, err
    return lines[0]


def listing(folder):
    return sorted(os.listdir(folder)) if os.path.exists(folder) else []


# ---- 1. no traceback, ever ------------------------------------------------------------------------

def test_a_full_disk_while_appending_the_manifest_is_one_line_and_leaves_it_whole(frames, tmp_path):
    # A file-size limit (EFBIG, as a full disk's ENOSPC) that the frames (~1.6 kB) stay under and the
    # manifest (a header and ~700 bytes a frame, ~12 kB in all) runs into after a few frames.
    out = tmp_path / "rainy"
    p = batch("rain", "--input-dir", frames, "--output-dir", out, "--workers", 1, "--chunk-frames", 2, "-q",
              limit_file_bytes=4000)
    assert p.returncode == 1, p.stderr
    line = one_line(p.stderr)
    manifest = out / _common.MANIFEST
    assert line == f"hydrolux.batch rain: {manifest}: {os.strerror(27)}"  # EFBIG: File too large
    # The failed append was taken back: whole lines only, each a record, none torn.
    data = manifest.read_bytes()
    assert 0 < len(data) <= 4000 and data.endswith(b"\n")
    lines = data.decode().splitlines()
    assert json.loads(lines[0])["job"] == "rain"
    records = [json.loads(line) for line in lines[1:]]
    assert 0 < len(records) < FRAMES
    assert not [n for n in os.listdir(out) if ".tmp-" in n]
    # Space again: the re-run goes on from the manifest and finishes.
    p = batch("rain", "--input-dir", frames, "--output-dir", out, "--workers", 1, "-q")
    assert p.returncode == 0, p.stderr
    assert sorted(json.loads(line)["output"] for line in manifest.read_text().splitlines()[1:]) == \
        [f"f_{k:03d}.png" for k in range(FRAMES)]


@pytest.mark.skipif(os.geteuid() != 0 or not shutil.which("unshare"), reason="a private tmpfs needs root")
def test_a_manifest_append_on_a_really_full_disk_leaves_it_as_it_was(tmp_path):
    # A 64 KiB tmpfs in a private mount namespace, filled: the append writes what fits (a short write),
    # then ENOSPC. The journal must be as it was, and the error a RunFailure naming the path.
    mnt = tmp_path / "mnt"
    mnt.mkdir()
    script = f"""
import errno, os, sys
from hydrolux.batch import _common
m = _common.Manifest({str(mnt)!r}, "rain", {{"p": 1}})
m.add({{"output": "a.png", "x": 1}})
before = open(m.path, "rb").read()
with open({str(mnt / "filler")!r}, "wb", buffering=0) as f:
    try:
        while True:
            f.write(b"x" * 512)
    except OSError as e:
        assert e.errno == errno.ENOSPC
try:
    m.add({{"output": "b.png", "pad": "y" * 20000}})
except _common.RunFailure as e:
    print("failure:", e)
after = open(m.path, "rb").read()
print("unchanged" if after == before else f"changed: {{len(before)}} -> {{len(after)}} bytes")
"""
    p = subprocess.run(["unshare", "-m", "sh", "-c", 'mount -t tmpfs -o size=64k tmpfs "$1" && exec "$2" -c "$3"',
                        "sh", str(mnt), sys.executable, script], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert f"failure: {mnt / _common.MANIFEST}: {os.strerror(28)}" in p.stdout, p.stdout
    assert "unchanged" in p.stdout.splitlines()[-1], p.stdout


def test_an_odd_size_video_is_refused_before_any_work(tmp_path):
    src = tmp_path / "odd.mp4"
    ffmpeg("-f", "lavfi", "-i", "testsrc=size=161x91:rate=25", "-frames:v", 10, "-pix_fmt", "yuv444p", src)
    out = tmp_path / "out" / "rainy.mp4"
    out.parent.mkdir()
    p = batch("rain", "--video", src, "-o", out, "--workers", 1)
    assert p.returncode == 2
    assert one_line(p.stderr) == (f"hydrolux.batch rain: -o {out}: 161 x 91 pixels: H.264 with 4:2:0 chroma needs "
                                  "an even width and height")
    assert listing(out.parent) == []  # no staging folder, no output


def test_a_truncated_video_is_one_line_naming_it_and_leaves_no_staging(tmp_path, cli):
    full = tmp_path / "full.mp4"
    ffmpeg("-f", "lavfi", "-i", "testsrc=size=320x180:rate=25", "-frames:v", 100, "-pix_fmt", "yuv420p",
           "-movflags", "+faststart", full)
    src = tmp_path / "cut.mp4"
    data = full.read_bytes()
    src.write_bytes(data[: len(data) // 2])  # the index whole at the front, half the frames' data
    ref = cli("rain", "--video", src, "-o", tmp_path / "cli.mp4", "-q", check=False)
    out = tmp_path / "out" / "rainy.mp4"
    out.parent.mkdir()
    p = batch("rain", "--video", src, "-o", out, "--workers", 1, "--chunk-frames", 10, "-q")
    assert p.returncode == ref.returncode == 2, p.stderr
    line = one_line(p.stderr)
    assert line.startswith(f"hydrolux.batch rain: --video {src}: cannot decode"), line
    assert line.split(": ", 2)[2] == ref.stderr.strip().split(": ", 2)[2]  # the CLI's reason
    assert listing(out.parent) == []  # the staging folder and its chunks are gone


def test_a_scheduler_address_dask_cannot_parse_is_one_line(frames, tmp_path):
    p = batch("rain", "--input-dir", frames, "--output-dir", tmp_path / "o", "--scheduler", "x y")
    assert p.returncode == 2
    assert one_line(p.stderr).startswith("hydrolux.batch rain: --scheduler x y: cannot connect")
    assert not (tmp_path / "o").exists()


def test_any_unexpected_exception_is_one_line_with_its_type_and_ctrl_c_is_130(frames, tmp_path, monkeypatch,
                                                                            capfd):
    argv = ["rain", "--input-dir", str(frames), "--output-dir", str(tmp_path / "o"), "-q"]

    def boom(a, after_result=None):
        raise RuntimeError("something the job did not expect\nsecond line")

    monkeypatch.setattr(batch_rain, "run_folder", boom)
    assert main(argv) == 1
    assert one_line(capfd.readouterr().err) == \
        "hydrolux.batch rain: internal error: RuntimeError: something the job did not expect\\nsecond line"

    def full(a, after_result=None):
        raise OSError(28, os.strerror(28), "/some/where")

    monkeypatch.setattr(batch_rain, "run_folder", full)
    assert main(argv) == 1
    assert one_line(capfd.readouterr().err) == f"hydrolux.batch rain: /some/where: {os.strerror(28)}"

    def interrupted(a, after_result=None):
        raise KeyboardInterrupt

    monkeypatch.setattr(batch_rain, "run_folder", interrupted)
    assert main(argv) == 130
    assert "interrupted" in capfd.readouterr().err


# ---- 2. bounded work ------------------------------------------------------------------------------

def test_more_workers_than_the_cores_or_the_memory_are_refused_before_any_cluster(frames, tmp_path, monkeypatch,
                                                                                  capfd):
    cores = _common.usable_cores()
    monkeypatch.setattr(_common, "available_memory", lambda: 1 << 40)  # the cores bound, whatever the memory here
    out = tmp_path / "o"
    argv = ["rain", "--input-dir", str(frames), "--output-dir", str(out), "-q"]
    for extra, text in ((["--workers", "1000"], f"--workers: 1000 is outside the valid range [1, {cores}] here"),
                        (["--workers", str(cores + 1)],
                         f"--workers: {cores + 1} is outside the valid range [1, {cores}] here"),
                        (["--threads-per-worker", str(cores + 1)],
                         f"--threads-per-worker: {cores + 1} is outside the valid range [1, {cores}] here"),
                        (["--workers", "0"], "--workers: 0 is outside the valid range [1, "),
                        (["--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], "--workers: sizes the local cluster")):
        assert main(argv + extra) == 2, extra
        line = one_line(capfd.readouterr().err)
        assert line.startswith("hydrolux.batch rain: " + text), line
    # The memory: with 300 MiB available a second worker of ~200 MiB does not fit, whatever the cores.
    monkeypatch.setattr(_common, "available_memory", lambda: 300 << 20)
    monkeypatch.setattr(_common, "usable_cores", lambda: 64)
    assert main(argv + ["--workers", "2"]) == 2
    line = one_line(capfd.readouterr().err)
    assert "--workers: 2 is outside the valid range [1, 1] here" in line and "300 MiB of memory available" in line
    # Not even one worker fits: refused too, not run into the allocator.
    monkeypatch.setattr(_common, "available_memory", lambda: 100 << 20)
    assert main(argv) == 2
    line = one_line(capfd.readouterr().err)
    assert "--workers: even one worker running 1 task(s) at a time needs about" in line, line
    assert not out.exists()


# ---- 3. numbers as the CLI parses them ------------------------------------------------------------

CLI_CASES = [("--seed", "1.5"), ("--seed", "-1"), ("--seed", "9007199254740993"), ("--seed", "1e20"),
             ("--seed", "x"), ("--rain-rate-mmh", "1_0"), ("--rain-rate-mmh", " 10 "), ("--rain-rate-mmh", "infinity"),
             ("--rain-rate-mmh", "nan"), ("--rain-rate-mmh", "600"), ("--rain-rate-mmh", "0x10"), ("--rain-rate-mmh", "1e400"),
             ("--wind-mps", "-1"), ("--fov-deg", "171"), ("--frame-index", "-1"), ("--frame-index", "2.5"),
             ("--crf", "52"), ("--crf", "1_8"), ("--depth-scale-m", "0"), ("--min-alpha", "1"),
             ("--pitch-deg", "+81")]


@pytest.mark.parametrize("flag,value", CLI_CASES)
def test_numbers_are_refused_with_the_cli_message(flag, value, frames, tmp_path, cli, capfd):
    ref = cli("rain", "--image", "builtin", "--size", "64x36", "-o", tmp_path / "cli.png", flag, value, "-q",
              check=False)
    assert ref.returncode == 2
    expected = ref.stderr.strip().removeprefix("hydrolux rain: ").removesuffix(" (see hydrolux rain --help)")
    out = tmp_path / "o"
    assert main(["rain", "--input-dir", str(frames), "--output-dir", str(out), flag, value, "-q"]) == 2
    assert one_line(capfd.readouterr().err) == "hydrolux.batch rain: " + expected
    assert not out.exists()


def test_numbers_the_cli_accepts_are_accepted(frames):
    a = argparse.Namespace(input_dir=str(frames), output_dir="o", seed="1e3", rain_rate_mmh="+25", wind_mps=".5",
                           frame_index="1e2", chunk_frames="4", crf="1.8e1", depth_scale_m="1e-3")
    for p in batch_rain.params():
        if not hasattr(a, p["name"]):
            setattr(a, p["name"], batch_rain.parser_default(p))
    batch_rain.parse_numbers(a)
    assert (a.seed, a.rain_rate_mmh, a.wind_mps, a.frame_index, a.chunk_frames, a.crf, a.depth_scale_m) == \
        (1000, 25.0, 0.5, 100, 4, 18, 0.001)
    assert type(a.seed) is int and type(a.rain_rate_mmh) is float
    for flag, value, text in (("--chunk-frames", "2.5", "--chunk-frames: 2.5 is not a whole number; valid range "
                                                        "[0, 100000] (0: automatic)"),
                              ("--workers", "1_0", "--workers: '1_0' is not a whole number; valid range [1, "),
                              ("--threads-per-worker", " 1", "--threads-per-worker: ' 1' is not a whole number")):
        with pytest.raises(_common.UsageError) as e:
            if flag == "--chunk-frames":
                a.chunk_frames = value
                batch_rain.parse_numbers(a)
            else:
                _common.local_cluster_size(value if flag == "--workers" else None,
                                           value if flag != "--workers" else None)
        assert str(e.value).startswith(text), str(e.value)


# ---- 4. never over an input, member by member -----------------------------------------------------

def test_an_output_that_is_an_input_through_a_link_is_refused_before_any_work(frames, tmp_path, capfd):
    src = tmp_path / "frames"
    shutil.copytree(frames, src)
    before = {n: (src / n).read_bytes() for n in os.listdir(src)}
    depth = tmp_path / "depth"
    depth.mkdir()
    for n in before:
        shutil.copy(src / n, depth / n)  # any readable image will do: the check comes before the reading
    cases = []
    # --output-dir holding a symbolic link to an input frame, under the name the frame is written as.
    o1 = tmp_path / "o1"
    o1.mkdir()
    (o1 / "f_003.png").symlink_to(src / "f_003.png")
    cases.append((["--output-dir", o1], f"--output-dir {o1}/f_003.png: is the same file as the input "
                                        f"--input-dir {src}/f_003.png; refusing to overwrite an input"))
    # --mask-dir whose member is a hard link to a depth map.
    o2, m2 = tmp_path / "o2", tmp_path / "m2"
    m2.mkdir()
    os.link(depth / "f_005.png", m2 / "f_005.png")
    cases.append((["--output-dir", o2, "--mask-dir", m2, "--depth-dir", depth],
                  f"--mask-dir {m2}/f_005.png: is the same file as the input --depth-dir {depth}/f_005.png"))
    # The manifest, a link to an input frame (its rewrite would replace the frame).
    o3 = tmp_path / "o3"
    o3.mkdir()
    (o3 / _common.MANIFEST).symlink_to(src / "f_000.png")
    cases.append((["--output-dir", o3], f"--output-dir {o3}/{_common.MANIFEST}: is the same file as the input"))
    # A mask that is a frame output of the same run (two outputs on one file).
    o4, m4 = tmp_path / "o4", tmp_path / "m4"
    o4.mkdir()
    m4.mkdir()
    (o4 / "f_001.png").write_bytes(b"old")
    (m4 / "f_001.png").symlink_to(o4 / "f_001.png")
    cases.append((["--output-dir", o4, "--mask-dir", m4], f"--mask-dir {m4}/f_001.png: is the same file as the "
                                                          f"output --output-dir {o4}/f_001.png"))
    for extra, text in cases:
        assert main(["rain", "--input-dir", str(src), *map(str, extra), "--workers", "1", "-q"]) == 2, extra
        assert one_line(capfd.readouterr().err) .startswith("hydrolux.batch rain: " + text)
    assert {n: (src / n).read_bytes() for n in os.listdir(src)} == before
    assert listing(o1) == ["f_003.png"] and listing(o3) == [_common.MANIFEST] and not o2.exists()
    assert (o4 / "f_001.png").read_bytes() == b"old"


def test_a_video_output_that_is_the_input_through_a_link_is_refused(tmp_path, capfd):
    src = tmp_path / "in.mp4"
    ffmpeg("-f", "lavfi", "-i", "testsrc=size=64x36:rate=25", "-frames:v", 5, "-pix_fmt", "yuv420p", src)
    before = src.read_bytes()
    link = tmp_path / "link.mp4"
    link.symlink_to(src)
    assert main(["rain", "--video", str(src), "-o", str(link), "--workers", "1", "-q"]) == 2
    assert "is the input video" in one_line(capfd.readouterr().err)
    # A staged chunk that is the input video through a hard link.
    out = tmp_path / "out.mp4"
    staging = tmp_path / ".out.mp4.chunks"
    staging.mkdir()
    os.link(src, staging / "chunk_000000000.rgb")
    assert main(["rain", "--video", str(src), "-o", str(out), "--workers", "1", "-q"]) == 2
    assert "chunk_000000000.rgb: is the same file as the input --video" in one_line(capfd.readouterr().err)
    assert src.read_bytes() == before and not out.exists()


def test_a_lee_atlas_table_that_is_its_spec_is_refused(tmp_path, capfd):
    out = tmp_path / "atlas"
    out.mkdir()
    spec = out / "corona.json"  # the table "corona" writes corona.json beside corona.exr
    spec.write_text(json.dumps({"tables": [{"name": "corona", "table": "corona"}]}))
    assert main(["lee-atlas", "--spec", str(spec), "--output-dir", str(out), "--workers", "1", "-q"]) == 2
    assert one_line(capfd.readouterr().err).startswith(
        f"hydrolux.batch lee-atlas: --output-dir {out}/corona.json: is the same file as the input --spec")
    assert listing(out) == ["corona.json"]


# ---- 5. entries that are not files are named, not dropped silently --------------------------------

def test_fifos_and_dangling_links_in_the_input_folder_are_listed_and_skipped(frames, tmp_path):
    src = tmp_path / "frames"
    src.mkdir()
    for k in range(3):
        shutil.copy(frames / f"f_{k:03d}.png", src / f"f_{k:03d}.png")
    os.mkfifo(src / "a.png")
    (src / "b.png").symlink_to(tmp_path / "nowhere.png")
    (src / "c.txt").symlink_to(tmp_path / "nowhere.txt")  # not an image name: not a frame, not listed
    out = tmp_path / "o"
    p = batch("rain", "--input-dir", src, "--output-dir", out, "--workers", 1, "-q")
    assert p.returncode == 0, p.stderr
    assert one_line(p.stderr) == (f"hydrolux.batch rain: warning: --input-dir {src}: skipped 2 entries that are not "
                                  "regular files: a.png (FIFO), b.png (dangling link)")
    assert sorted(n for n in os.listdir(out) if n.endswith(".png")) == ["f_000.png", "f_001.png", "f_002.png"]


# ---- the same words and the same range as the CLI where a setting follows from others -----------

def test_a_setting_out_of_its_derived_range_names_the_flags(frames, tmp_path, capfd):
    """--fov-deg 1 used to be blamed on --focal-mm (the focal length it implies), and --far-m's range
    named the library's near_m; and --crf or --depth-scale-m given where nothing uses them was ignored."""
    out = tmp_path / "o"
    argv = ["rain", "--input-dir", str(frames), "--output-dir", str(out), "--workers", "1", "-q"]
    for extra, text in ((["--fov-deg", "1"], "--fov-deg 1 is outside the valid range [1.0313, 170] deg of a 36 mm "
                                             "wide sensor (focal lengths 1-2000 mm)"),
                        (["--near-m", "5", "--far-m", "2"], "--far-m 2 is outside the valid range [5.005, 10000] m "
                                                            "(beyond --near-m)"),
                        (["--crf", "20"], "--crf 20: sets the H.264 quality of --video's output; pictures have none"),
                        (["--depth-scale-m", "0.01"], "--depth-scale-m 0.01: scales the codes of PNG depth maps; "
                                                      "none is given")):
        assert main(argv + extra) == 2, extra
        line = one_line(capfd.readouterr().err)
        assert text in line, line
        assert "focal_mm" not in line and "--focal-mm" not in line and "near_m" not in line, line
    assert not out.exists()


def test_a_time_lapse_video_is_processed(tmp_path, capfd):
    """A 0.5 frames/s video was refused as "--fps = 0.5", a flag not given: its rate is in the range now."""
    src, out = tmp_path / "slow.mp4", tmp_path / "slow_out.mp4"
    ffmpeg("-f", "lavfi", "-i", "testsrc=size=64x36:rate=0.5", "-t", 6, "-pix_fmt", "yuv420p", src)
    assert main(["rain", "--video", str(src), "-o", str(out), "--workers", "1", "-q"]) == 0, capfd.readouterr().err
    assert out.stat().st_size > 0
