"""python3 -m hydrolux.batch rain: rain over a folder of frames or a video on a Dask cluster.

The frames (a video as numbered images, or any set of photographs) are one sequence in name order,
as ``hydrolux rain --input-dir``: frame k is frame index ``--frame-index + k`` of one rain field, so
the drops move on from frame to frame. The sequence is cut into chunks of consecutive frames, one
task each; every worker builds the field once (the same for the same options and seed) and renders
any frame alone from its index, so chunk boundaries leave no trace: the output is byte for byte
that of the single-process CLI. Each frame is written atomically (hydrolux's safe output path) and
recorded in the manifest as it completes; a re-run skips recorded frames whose input is unchanged.

A video (``--video in.mp4 -o out.mp4``, as ``hydrolux rain --video``) is cut the same way: each task
decodes its chunk of frames (decoding from the start and dropping the frames before it), renders
them and writes them as raw 8-bit RGB into a staging folder beside the output
(``.<output>.chunks/``, which holds this job's manifest); once every chunk is there, the client
encodes them in order with the CLI's encoder, so the video is byte for byte the CLI's. Staging
takes width x height x 3 bytes per frame; the chunks are removed once the video is in place.
"""
from __future__ import annotations

import argparse
import functools
import os
import sys
import warnings
from typing import Any, Dict, List, Optional

from . import _common, _folder
from ._common import UsageError
from ._folder import TASK_BYTES_PER_PIXEL  # what a task holds per pixel of its frame

# The rain job's parameters are the library's declared ones (src/rain/params.cpp), read through
# _core.params("rain") on first use: each one's flag, range, unit, default and help come from there, as
# the CLI's and the Python functions' do. The flags the table declares an effect for only in some runs
# (only_with, not_with: --fps, --crf, --depth-scale-m) are refused where unused, as the CLI refuses them,
# so they stay None until parse_numbers notes whether they were given.
# What the library's messages name that is no flag.
_NAMED = {"width": "the frames' width", "height": "the frames' height"}


@functools.lru_cache(maxsize=None)
def params() -> tuple:
    """The rain job's declared parameters, the library's one table (``_core.params("rain")``): dicts of
    name, flag, group ("rain", "camera", "files"), kind ("real", "integer", "flag"), unit, lo, hi,
    range, help, excludes, default and default_text.

    Example:

    >>> from hydrolux.batch import rain
    >>> p = {p["name"]: p for p in rain.params()}
    >>> p["rain_rate_mmh"]["flag"], p["rain_rate_mmh"]["range"], p["seed"]["hi"] == 2 ** 53
    ('--rain-rate-mmh', '[0, 500] mm/h', True)
    """
    return tuple(_common.native("_core").params("rain"))


def parser_default(p: dict) -> Any:
    """What the parser leaves for the parameter ``p`` when its flag is not given: its default, or None
    where the flag's absence counts (a parameter another replaces, as --fov-deg replaces --focal-mm; one
    refused where unused). :func:`parse_numbers` fills in the files' defaults (--crf, --depth-scale-m).

    Example:

    >>> from hydrolux.batch import rain
    >>> [rain.parser_default(p) for p in rain.params() if p["name"] in ("rain_rate_mmh", "focal_mm", "crf")]
    [25.0, None, None]
    """
    replaced = any(q["excludes"] == p["name"] for q in params())
    return None if replaced or p["name"] in _common.conditional(params()) else p["default"]


def parse_numbers(a: argparse.Namespace) -> None:
    """Every numeric option parsed as the CLI parses it (the library's parsers) and checked against its
    declared range, in place, before any work: one UsageError naming the flag, the value and the range.

    Example:

    >>> import argparse
    >>> from hydrolux.batch import rain
    >>> p = argparse.ArgumentParser()
    >>> rain.add_arguments(p)
    >>> a = p.parse_args(["--rain-rate-mmh", "1e1", "--seed", "7", "--frame-index", "2e3"])
    >>> rain.parse_numbers(a)
    >>> a.rain_rate_mmh, a.seed, a.frame_index, a.crf
    (10.0, 7, 2000, 18)
    >>> rain.parse_numbers(p.parse_args(["--rain-rate-mmh", "600"]))
    Traceback (most recent call last):
    ...
    hydrolux.batch._common.UsageError: --rain-rate-mmh...600...
    """
    # A flag's text is a string; a value not given is its default (a number) or None.
    _common.take_deprecated_flags(a, params(), lambda q: isinstance(getattr(a, q["name"], None), str), "batch rain")
    conditional = _common.conditional(params())
    for p in params():
        name = p["name"]
        if p["kind"] in ("flag", "path"):
            continue
        value = getattr(a, name, None)
        if name in conditional:
            setattr(a, name + "_given", value is not None)
        if value is None and p["group"] == "files":  # the job's own settings, not the renderer's: always set
            value = p["default"]
        if value is None:
            continue
        if p["kind"] == "integer":
            setattr(a, name, _common.integer_flag(p["flag"], value, int(p["lo"]), int(p["hi"]), p["unit"]))
        else:
            setattr(a, name, _common.number_flag(p["flag"], value, p["lo"], p["hi"], p["unit"]))
    a.chunk_frames = _common.integer_flag("--chunk-frames", a.chunk_frames, 0, 100000, extra=" (0: automatic)")


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The rain job's own options on the parser ``p``, numbers kept as text for :func:`parse_numbers`;
    ``python3 -m hydrolux.batch`` adds the cluster's (--workers, --threads-per-worker, --scheduler, -q).

    Example:

    >>> import argparse
    >>> from hydrolux.batch import rain
    >>> p = argparse.ArgumentParser(prog="rain")
    >>> rain.add_arguments(p)
    >>> a = p.parse_args(["--input-dir", "frames", "--output-dir", "rainy", "--wind-mps", "3", "--no-unresolved"])
    >>> a.input_dir, a.rain_rate_mmh, a.wind_mps, a.unresolved
    ('frames', 25.0, '3', False)
    """
    _folder.add_path_arguments(p, params(), _folder.FOLDER_PATHS + ("video", "output"))
    # The declared parameters. Numbers are taken as text and parsed by the library's parsers in run(), as the
    # CLI parses them; a flag parameter's flag turns its default around (--no-unresolved).
    for q in params():
        text = q["help"].replace("%", "%%")  # argparse formats help with %
        if q["kind"] == "path":
            continue
        if q["kind"] == "flag":
            p.add_argument(q["flag"], dest=q["name"], action="store_const", const=not q["default"],
                           default=q["default"], help=text)
        else:
            p.add_argument(q["flag"], dest=q["name"], default=parser_default(q),
                           help=f"{text}; valid {q['range']}" + (f" [{q['default_text']}]" if q["default_text"] else ""))
            _common.add_deprecated_flag(p, q)  # --rate-mmh for --rain-rate-mmh, for one release
    p.add_argument("--chunk-frames", default=0,
                   help="Frames per task (0: about 4 tasks per worker, at most 32 frames each; 8 for video)")


def _options(a: argparse.Namespace) -> Dict[str, Any]:
    """The renderer's options (the declared parameters but the files'), those given or defaulted."""
    return _folder._options(a, RAIN)


def _flag_error(e: ValueError) -> UsageError:
    """The library's message, with the Python argument named as the batch flag."""
    return _folder.flag_error(e, RAIN, _NAMED)


def plan_folder(input_dir: str, output_dir: str, mask_dir: Optional[str] = None,
                depth_dir: Optional[str] = None) -> Dict[str, Any]:
    """The frames of ``input_dir`` as ``hydrolux rain --input-dir`` plans them (the library's one
    definition, ``_core.plan_frame_folder``): ``frames`` in name order, each one's output name in
    ``outputs`` (its stem as .exr for EXR, else .png) and depth map in ``depth_maps`` (its stem as .exr
    or .png in ``depth_dir``), the folders checked (an output or mask folder that is the input folder, the
    depth folder or not a folder; masks in the output folder). Entries with a frame's name that are not
    regular files (a FIFO, a device, a folder, a dangling link) are skipped and listed in one warning line
    on stderr. A UsageError naming the flag otherwise, as the CLI's.

    Example:

    >>> import os, tempfile
    >>> from hydrolux.batch import rain
    >>> folder, depth = tempfile.mkdtemp(), tempfile.mkdtemp()
    >>> for name in ("b.jpg", "a.exr", "notes.txt", ".hidden.png"):
    ...     open(os.path.join(folder, name), "wb").close()
    >>> for name in ("a.exr", "b.png"):
    ...     open(os.path.join(depth, name), "wb").close()
    >>> plan = rain.plan_folder(folder, os.path.join(folder, "rainy"), depth_dir=depth)
    >>> plan["frames"], plan["outputs"], plan["depth_maps"]
    (['a.exr', 'b.jpg'], ['a.exr', 'b.png'], ['a.exr', 'b.png'])
    """
    return _folder.plan_folder(input_dir, output_dir, mask_dir, depth_dir, "batch rain")


# ---- on the workers -------------------------------------------------------------------------------

_RENDERERS: Dict[str, Any] = {}


def _renderer(job: Dict[str, Any], ground: bool):
    """The worker process's renderer for this job: the field is built once per process and kept for
    every task of the same options, frame size and scene (ground plane or depth maps)."""
    import json

    import hydrolux

    key = json.dumps([job["options"], job["width"], job["height"], ground], sort_keys=True)
    renderer = _RENDERERS.get(key)
    if renderer is None:
        _RENDERERS.clear()
        renderer = _RENDERERS[key] = hydrolux.RainRenderer(job["width"], job["height"], ground, **job["options"])
    return renderer


def _render(image, depth, index: int, job: Dict[str, Any]) -> tuple:
    """One frame of the job's rain field: (image, mask, stats)."""
    renderer = _renderer(job, ground=not job["depth_dir"])
    with warnings.catch_warnings():  # negative values: counted in the stats, said once by the client
        warnings.simplefilter("ignore", RuntimeWarning)
        result = renderer.render(image, depth, index)
    return result.image, result.mask, result.stats


def _prepare(first, opts: Dict[str, Any], ground: bool) -> tuple:
    """Every option checked, and the field's size, on the sequence's first frame."""
    import hydrolux

    try:
        field = hydrolux.RainRenderer(first.shape[1], first.shape[0], ground, **opts).field_info()
    except ValueError as e:
        raise _flag_error(e) from None
    return {}, f"; {field['drops']} drops in the field"


RAIN = _folder.FrameJob(name="rain", job="rain", noun="rainy frames", prepare=_prepare, render=_render)


def render_frames(job: Dict[str, Any], frames: List[tuple]) -> List[dict]:
    """A task: renders consecutive frames [(input name, output name, frame index, depth map), ...] and writes
    them. Returns one record per frame; a frame that fails carries "error" and the others go on.

    Example (what a worker runs; ``threads`` 0 leaves the process's threads as they are):

    >>> import hydrolux, os, tempfile
    >>> from hydrolux.batch import rain
    >>> frames, out = tempfile.mkdtemp(), tempfile.mkdtemp()
    >>> hydrolux.write_image(os.path.join(frames, "f0.png"), hydrolux.builtin_scene(64, 48))
    >>> job = {"input_dir": frames, "output_dir": out, "mask_dir": None, "depth_dir": None, "depth_scale_m": None,
    ...        "width": 64, "height": 48, "options": {"rain_rate_mmh": 25.0, "seed": 4}, "threads": 0}
    >>> records = rain.render_frames(job, [("f0.png", "rainy0.png", 0, None), ("gone.png", "gone.png", 1, None)])
    >>> [(r["output"], r.get("error", "ok")) for r in records]
    [('rainy0.png', 'ok'), ('gone.png', '...gone.png...')]
    >>> os.listdir(out)
    ['rainy0.png']
    """
    return _folder.render_frames(job, frames, _render)


# ---- on the client --------------------------------------------------------------------------------

def run(a: argparse.Namespace, after_result=None) -> int:
    """The job (``python3 -m hydrolux.batch rain``): the numbers parsed and checked, then
    :func:`run_folder` or :func:`run_video`; 0 when every output is in place, 1 when some failed.

    Example (the mode checked before any work; :func:`run_folder` shows a run):

    >>> import argparse
    >>> from hydrolux.batch import rain
    >>> p = argparse.ArgumentParser()
    >>> rain.add_arguments(p)
    >>> rain.run(p.parse_args(["--input-dir", "frames", "--video", "street.mp4"]))
    Traceback (most recent call last):
    ...
    hydrolux.batch._common.UsageError: give exactly one of --input-dir and --video
    """
    if (a.input_dir is None) == (getattr(a, "video", None) is None):
        raise UsageError("give exactly one of --input-dir and --video")
    parse_numbers(a)
    video = getattr(a, "video", None) is not None
    _common.refuse_unused("rain", a, ["video"] if video else ["depth_dir"] if a.depth_dir else [])
    if video:
        return run_video(a, after_result)
    if getattr(a, "output", None):
        raise UsageError("-o: with --input-dir the frames go to --output-dir")
    if not a.output_dir:
        raise UsageError("--output-dir: give the folder for the rainy frames (with --input-dir)")
    return run_folder(a, after_result)


def run_folder(a: argparse.Namespace, after_result=None) -> int:
    """Rain over the frames of ``a.input_dir`` into ``a.output_dir`` (and their masks into
    ``a.mask_dir``), every input checked before the cluster starts; ``a`` as :func:`run` leaves it.

    Example (a local cluster of one worker):

    >>> import argparse, hydrolux, os, tempfile
    >>> from hydrolux.batch import rain
    >>> frames = tempfile.mkdtemp()
    >>> for k in range(2):
    ...     hydrolux.write_image(os.path.join(frames, f"f{k}.png"), hydrolux.builtin_scene(64, 48))
    >>> p = argparse.ArgumentParser()
    >>> rain.add_arguments(p)
    >>> out, masks = tempfile.mkdtemp(), tempfile.mkdtemp()
    >>> a = p.parse_args(["--input-dir", frames, "--output-dir", out, "--mask-dir", masks, "--seed", "4"])
    >>> a.workers, a.threads_per_worker, a.scheduler, a.quiet = 1, None, None, True   # the cluster's options
    >>> rain.parse_numbers(a)   # run() does this first
    >>> rain.run_folder(a)
    0
    >>> sorted(os.listdir(masks))   # the rain's coverage, 16-bit
    ['f0.png', 'f1.png']
    """
    return _folder.run_folder(a, RAIN, _options(a), after_result, task=render_frames)


# ---- video ----------------------------------------------------------------------------------------

def render_video_chunk(job: Dict[str, Any], start: int, count: int) -> Dict[str, Any]:
    """A task: frames [start, start + count) of the video (count -1: to its end), rendered and
    written as raw 8-bit RGB into the staging folder.

    Example (what a worker runs; a short video made with the ffmpeg command):

    >>> import os, subprocess, tempfile
    >>> from hydrolux.batch import rain
    >>> folder = tempfile.mkdtemp()
    >>> video = os.path.join(folder, "street.mp4")
    >>> _ = subprocess.run(["ffmpeg", "-loglevel", "error", "-f", "lavfi", "-i", "testsrc=size=64x48:rate=25",
    ...                     "-frames:v", "4", "-pix_fmt", "yuv420p", video], check=True)
    >>> job = {"video": video, "video_label": "--video", "staging": folder, "width": 64, "height": 48,
    ...        "options": {"seed": 4, "fps": 25.0}, "frame_index": 0, "threads": 0}
    >>> rec = rain.render_video_chunk(job, 0, 2)
    >>> rec["output"], rec["frames"], rec["size"]   # 2 frames of 64 x 48 x 3 bytes
    ('chunk_000000000.rgb', 2, 18432)
    """
    _core = _common.native("_core")
    _video = _common.native("_video")

    name = f"chunk_{start:09d}.rgb"
    parts, stats = [], []
    if job["threads"]:
        import hydrolux
        hydrolux.set_threads(job["threads"])
    try:  # the video's own problems (truncated, corrupt): a bad input, reported as the CLI reports it
        renderer = _renderer(job, ground=True)
        reader = _video.VideoReader(_common.fs(job["video"]), job["video_label"])
        if reader.skip(start) != start:  # the container promised more frames than it holds
            count = 0
        while count < 0 or len(parts) < count:
            frame = reader.read()
            if frame is None:
                break
            result = renderer.render(frame, None, job["frame_index"] + start + len(parts))
            parts.append(_video.to_srgb8(result.image).tobytes())
            stats.append(result.stats)
    except (ValueError, OSError) as e:
        return {"output": name, "start": start, "error": str(e), "input_error": True}
    data = b"".join(parts)
    try:  # a full disk in the staging folder: the system failed (exit 1)
        _core.write_file(_common.fs(os.path.join(job["staging"], name)), data, "staging")
    except OSError as e:
        return {"output": name, "start": start, "error": str(e), "input_error": False}
    return {"output": name, "start": start, "frames": len(parts), "size": len(data), "stats": stats}


def run_video(a: argparse.Namespace, after_result=None) -> int:
    """Rain over the video ``a.video`` into the video ``a.output``, in chunks of ``a.chunk_frames``
    staged beside it; ``a`` as :func:`run` leaves it.

    Example (a local cluster of one worker; a short video made with the ffmpeg command):

    >>> import argparse, os, subprocess, tempfile
    >>> from hydrolux.batch import rain
    >>> folder = tempfile.mkdtemp()
    >>> video = os.path.join(folder, "street.mp4")
    >>> _ = subprocess.run(["ffmpeg", "-loglevel", "error", "-f", "lavfi", "-i", "testsrc=size=64x48:rate=25",
    ...                     "-frames:v", "6", "-pix_fmt", "yuv420p", video], check=True)
    >>> p = argparse.ArgumentParser()
    >>> rain.add_arguments(p)
    >>> a = p.parse_args(["--video", video, "-o", os.path.join(folder, "rainy.mp4"), "--seed", "4",
    ...                   "--chunk-frames", "3"])
    >>> a.workers, a.threads_per_worker, a.scheduler, a.quiet = 1, None, None, True   # the cluster's options
    >>> rain.parse_numbers(a)   # run() does this first
    >>> rain.run_video(a)
    0
    >>> sorted(os.listdir(folder))   # the staging folder holds the manifest
    ['.rainy.mp4.chunks', 'rainy.mp4', 'street.mp4']
    """
    import hydrolux
    _video = _common.native("_video")

    if a.input_dir or a.output_dir or a.mask_dir or a.depth_dir:
        raise UsageError("--video writes one video (-o); --output-dir, --mask-dir and --depth-dir are for "
                         "--input-dir (video frames use the ground plane)")
    if not a.output:
        raise UsageError("-o: give the output video (.mp4, .mov or .mkv)")
    if os.path.splitext(a.output)[1].lower() not in (".mp4", ".mov", ".mkv"):
        raise UsageError(f"-o {a.output}: expected a .mp4, .mov or .mkv file")
    video, output = os.path.abspath(a.video), os.path.abspath(a.output)
    if not os.path.isfile(video):
        raise UsageError(f"--video {a.video}: not a file")
    out_dir = os.path.dirname(output)
    if not os.path.isdir(out_dir):
        raise UsageError(f"-o {a.output}: the folder {out_dir} does not exist")
    if os.path.exists(output) and os.path.samefile(output, video):
        raise UsageError(f"-o {a.output}: is the input video")
    video_label = "--video"  # the bindings' errors read "--video <path>: <reason>"
    try:
        info = _video.VideoReader(_common.fs(video), video_label).info()
    except (ValueError, OSError) as e:
        raise UsageError(str(e)) from None
    if info["width"] % 2 or info["height"] % 2:  # the encoder's rule, before any frame is rendered
        raise UsageError(f"-o {a.output}: {info['width']} x {info['height']} pixels: H.264 with 4:2:0 chroma needs "
                         "an even width and height")
    opts = _options(a)
    opts["fps"] = info["fps"]
    try:
        field = hydrolux.RainRenderer(info["width"], info["height"], True, **opts).field_info()
    except ValueError as e:
        raise _flag_error(e) from None
    expected = info["frame_count"] if info["frame_count"] > 0 else round(info["duration_s"] * info["fps"])
    if expected <= 0:  # the container says nothing: count them
        try:
            expected = _video.VideoReader(_common.fs(video), video_label).skip(1 << 40)
        except (ValueError, OSError) as e:
            raise UsageError(str(e)) from None
    staging = os.path.join(out_dir, f".{os.path.basename(output)}.chunks")
    chunk = a.chunk_frames or 8
    # Member by member: the output video, the staging folder's chunks, manifest and lock are never the input
    # video (through a link), nor one another.
    if os.path.lexists(staging) and not os.path.isdir(staging):
        raise UsageError(f"-o {a.output}: its staging folder {staging} exists and is not a folder")
    starts = list(range(0, max(1, expected), chunk))
    _common.check_members(
        [("--video", video)],
        [("-o", output)] + [("-o", os.path.join(staging, n))
                            for n in [_common.MANIFEST, _common.LOCK] + [f"chunk_{s:09d}.rgb" for s in starts]])
    stamp = _common.file_stamp(video)
    params = {"video": video, "input_size": stamp["size"], "input_mtime_ns": stamp["mtime_ns"],
              "frame_index": a.frame_index, "options": opts, "chunk_frames": chunk}
    # The local cluster's size within the cores and the memory (a task holds its chunk's frames, 3 bytes a
    # pixel, and one frame's buffers), then the cluster: an unreachable scheduler leaves no staging folder behind.
    a.workers, a.threads_per_worker = _common.local_cluster_size(
        a.workers, a.threads_per_worker, (TASK_BYTES_PER_PIXEL + 3 * chunk) * info["width"] * info["height"],
        a.scheduler)
    client, cluster = _common.open_client(a.scheduler, a.workers, a.threads_per_worker, a.quiet)
    manifest = None
    chunk_names: List[str] = []
    finished = interrupted = False
    try:
        _common.make_folder("-o", staging)
        manifest = _common.Manifest(staging, "rain-video", params, label="-o")
        out_name = os.path.basename(output)
        final = manifest.records.get(out_name)
        if final and final.get("crf") == a.crf and _common.file_stamp(output) and \
                _common.file_stamp(output)["size"] == final.get("size"):
            if not a.quiet:
                print(f"batch rain: {output} is done (hydrolux-manifest.jsonl in {staging})", file=sys.stderr)
            finished = True
            return 0
        code = _video_job(a, after_result, client, info, field, expected, staging, manifest, video, video_label,
                          output, out_name, opts, chunk_names)
        finished = code == 0
        return code
    except KeyboardInterrupt:
        interrupted = True  # the staged chunks stay: a re-run goes on from them
        raise
    except _common.RunFailure as e:
        # The system failed (a full disk): the chunks staged so far, this run's and any earlier one's, stay
        # for a re-run to go on from, as after Ctrl-C.
        interrupted = manifest is not None
        raise _common.RunFailure(f"{e}; the chunks staged so far stay in {staging} for a re-run" if interrupted
                                 else str(e)) from None
    finally:
        _common.close_client(client, cluster)
        if manifest is not None:
            _common.remove_stale_temporaries(staging, chunk_names)
            _common.remove_stale_temporaries(out_dir, [os.path.basename(output)])
            manifest.close()
        if not finished and not interrupted:
            # A bad video (truncated, corrupt) leaves nothing behind: the staging folder goes whole (its
            # chunks cannot be used), and so does one this run made but could not start a manifest in.
            _common.remove_staging(staging, r"chunk_[0-9]{9}\.rgb")


def _video_job(a, after_result, client, info, field, expected, staging, manifest, video, video_label, output,
               out_name, opts, chunk_names) -> int:
    """Renders the chunks not done yet on the cluster, then encodes them all in order. A chunk that fails ends
    the run with one line: a UsageError for the video's own fault (truncated, corrupt: exit 2, as the CLI),
    a RunFailure for the system's (a full disk, a worker lost too often: exit 1)."""
    import numpy as np

    _video = _common.native("_video")

    failed: List[tuple] = []
    chunk = a.chunk_frames or 8
    starts = list(range(0, max(1, expected), chunk))
    chunk_names.extend(f"chunk_{s:09d}.rgb" for s in starts)

    def done_chunk(i):
        rec = manifest.records.get(chunk_names[i])
        st = _common.file_stamp(os.path.join(staging, chunk_names[i]))
        return bool(rec) and st is not None and st["size"] == rec["size"]

    cores = _common.usable_cores()
    job = {"video": video, "video_label": video_label, "staging": staging, "width": info["width"],
           "height": info["height"], "options": opts, "frame_index": a.frame_index,
           "threads": 0 if a.scheduler else max(1, cores // max(1, a.workers * a.threads_per_worker))}
    tasks = [(job, s, chunk if i + 1 < len(starts) else -1) for i, s in enumerate(starts) if not done_chunk(i)]
    progress = _common.Progress("batch rain", len(tasks), "frames", a.quiet)
    if not a.quiet:
        link = _common.dashboard_link(client)
        where = a.scheduler or f"a local cluster of {a.workers} worker(s)"
        print(f"batch rain: {video}: {expected} frames at {info['fps']:g}/s in {len(starts)} chunks of {chunk} "
              f"({len(starts) - len(tasks)} done before) on {where}; {field['drops']} drops in the field"
              + (f"; dashboard {link}" if link else ""), file=sys.stderr)

    def on_result(task, rec):
        if isinstance(rec, Exception):  # the task as a whole: its worker lost too often (KilledWorker)
            failed.append((task[1], False, f"the chunk of frames from {task[1]}: {type(rec).__name__}: {rec}"))
        elif "error" in rec:
            failed.append((task[1], rec["input_error"], rec["error"]))
        else:
            manifest.add(rec)

    def count(r):
        return 0 if isinstance(r, Exception) or "error" in r else r["frames"]

    _common.run_tasks(client, tasks, render_video_chunk, on_result, progress, count, after_result)
    progress.finish()
    if failed:
        # One line: the video's own fault first (the earliest chunk that saw it), else the system's.
        failed.sort(key=lambda f: (not f[1], f[0]))
        start, input_error, text = failed[0]
        raise (UsageError if input_error else _common.RunFailure)(text)
    # Every chunk in order through the CLI's encoder: the same frames give the same bytes.
    if not a.quiet:
        print(f"batch rain: encoding {output}", file=sys.stderr)
    frame_bytes = info["width"] * info["height"] * 3
    frames = 0
    try:
        writer = _video.VideoWriter(_common.fs(output), info, a.crf, "-o")
        for name in chunk_names:
            # Checked as every file the batch reads: a regular file of the size its record says.
            data = _common.read_input(os.path.join(staging, name), "-o", manifest.records[name]["size"],
                                      error=_common.RunFailure)
            for k in range(len(data) // frame_bytes):
                writer.write(np.frombuffer(data, np.uint8, frame_bytes, k * frame_bytes).reshape(
                    info["height"], info["width"], 3))
                frames += 1
        writer.finish()
    except OSError as e:  # a full disk at -o, a staged chunk that cannot be read
        raise _common.RunFailure(_common.os_error_text(e)) from None
    except ValueError as e:  # what the encoder refuses (checked before the work; here for its other rules)
        raise UsageError(str(e)) from None
    manifest.add({"output": out_name, "size": os.path.getsize(output), "crf": a.crf, "frames": frames})
    for name in chunk_names:
        try:
            os.unlink(os.path.join(staging, name))
        except FileNotFoundError:
            pass
    if not a.quiet:
        print(f"batch rain: wrote {output} ({frames} frames)", file=sys.stderr)
    return 0
