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
import math
import os
import sys
import warnings
from typing import Any, Dict, List, Optional

from . import _common
from ._common import UsageError, printable

# What a task holds per pixel of its frame, measured on a worker (docs/batch.md, "Memory"): a 1080p frame
# raised a worker's peak by 208 MB (the frame as float RGB in and out, its mask, the 8-bit copy, the
# encoded file), ~100 bytes a pixel.
TASK_BYTES_PER_PIXEL = 100
FRAME_EXTENSIONS = {".png", ".jpg", ".jpeg", ".exr", ".tif", ".tiff", ".hdr", ".ppm", ".pfm"}

# The rain command's options, with the CLI's ranges and units (tools/hydrolux/cmd_rain.cpp):
# (flag, Python name, type, default or None, help, lo, hi, unit).
OPTIONS = [
    ("--rate-mmh", "rate_mmh", float, 25.0, "Rain rate, mm/h [0, 500]", 0, 500, "mm/h"),
    ("--wind-mps", "wind_mps", float, 0.0, "Horizontal wind speed, m/s [0, 50]", 0, 50, "m/s"),
    ("--wind-dir-deg", "wind_dir_deg", float, 90.0, "Where the wind blows to: 0 away from the camera, 90 to its right",
     -360, 360, "deg"),
    ("--exposure-s", "exposure_s", float, 0.008, "Exposure time, s (at most 1 / fps)", 1e-6, 1, "s"),
    ("--focal-mm", "focal_mm", float, None, "Focal length, mm [1, 2000] (default 35)", 1, 2000, "mm"),
    ("--fov-deg", "fov_deg", float, None, "Horizontal field of view, degrees [1, 170] (instead of --focal-mm)", 1, 170,
     "deg"),
    ("--sensor-width-mm", "sensor_width_mm", float, None, "Sensor width, mm [1, 100] (default 36)", 1, 100, "mm"),
    ("--pixel-pitch-um", "pixel_pitch_um", float, None, "Pixel pitch, um (instead of --sensor-width-mm)", 0.1, 1000,
     "um"),
    ("--f-number", "f_number", float, 0.0, "Aperture f-number for defocus of near drops; 0 = pinhole", 0, 64, ""),
    ("--focus-m", "focus_m", float, 10.0, "Focus distance, m (with --f-number)", 0.01, 1e4, "m"),
    ("--fps", "fps", float, None, "Frame rate of --input-dir frames: frame k is exposed from k / fps (default 25)",
     0.01, 1000, "1/s"),
    ("--camera-height-m", "camera_height_m", float, 1.7, "Camera height above the ground plane, m", 0, 1000, "m"),
    ("--pitch-deg", "pitch_deg", float, 0.0, "Camera pitch above the horizon, degrees [-80, 80]", -80, 80, "deg"),
    ("--near-m", "near_m", float, 0.5, "No drop nearer than this, m", 0.05, 100, "m"),
    ("--far-m", "far_m", float, 100.0, "No drop drawn beyond this, m (farther rain is unresolved)", 0.1, 1e4, "m"),
    ("--min-radius-mm", "min_radius_mm", float, 0.1, "Smaller drops count only as unresolved rain, mm", 0.04, 2.9,
     "mm"),
    ("--max-radius-mm", "max_radius_mm", float, 2.9, "Largest drop radius, mm", 0.04, 2.9, "mm"),
    ("--min-alpha", "min_alpha", float, 0.01, "A drop is drawn while its streak's peak coverage reaches this", 1e-5,
     0.5, ""),
    ("--extent-m", "extent_m", float, 1000.0, "Depth of the rain where the scene has none (sky), m", 0, 1e5, "m"),
    ("--backdrop-m", "backdrop_m", float, 100.0, "The ground plane's backdrop distance, m", 1, 1e5, "m"),
    ("--oscillation", "oscillation", float, 0.0, "Relative amplitude of the drops' shape oscillation [0, 0.5]", 0, 0.5,
     ""),
    ("--seed", "seed", int, 1, "Random seed: the same seed gives the same rain, bytes for bytes", 0, None, ""),
]
FLAG_OF = {name: flag for flag, name, *_ in OPTIONS}
FLAG_OF.update({"camera_height_m": "--camera-height-m", "width": "the frames' width", "height": "the frames' height"})


def max_seed() -> int:
    """The largest seed, hydrolux::rain::kMaxSeed (2^53: every seed a double holds exactly), from the library."""
    return int(_common.native("_core").kMaxSeed)


def parse_numbers(a: argparse.Namespace) -> None:
    """Every numeric option parsed as the CLI parses it (the library's parsers) and checked against the CLI's
    range, in place, before any work: one UsageError naming the flag, the value and the range."""
    for flag, name, typ, _default, _text, lo, hi, unit in OPTIONS:
        value = getattr(a, name, None)
        if value is None:
            continue
        if typ is int:
            setattr(a, name, _common.integer_flag(flag, value, lo, max_seed() if hi is None else hi, unit))
        else:
            setattr(a, name, _common.number_flag(flag, value, lo, hi, unit))
    a.frame_index = _common.integer_flag("--frame-index", a.frame_index, 0, 1_000_000_000)
    a.chunk_frames = _common.integer_flag("--chunk-frames", a.chunk_frames, 0, 100000, extra=" (0: automatic)")
    # --crf and --depth-scale-m: given where nothing uses them, refused (as the CLI refuses them), not ignored.
    a.crf_given, a.depth_scale_given = a.crf is not None, a.depth_scale_m is not None
    a.crf = _common.integer_flag("--crf", 18 if a.crf is None else a.crf, 0, 51)
    a.depth_scale_m = _common.number_flag("--depth-scale-m", 0.001 if a.depth_scale_m is None else a.depth_scale_m,
                                          1e-6, 1e3, "m")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--input-dir", help="A folder of frames in name order: one rain field across them")
    p.add_argument("--output-dir", help="Folder for the rainy frames (created; never the input folder)")
    p.add_argument("--video", help="Input video (MP4, MOV, MKV, ...) instead of --input-dir; frame rate and count kept")
    p.add_argument("-o", "--output", help="Output video with --video (.mp4, .mov or .mkv), H.264")
    # Numbers are taken as text and parsed by the library's parsers in run(), as the CLI parses them.
    p.add_argument("--crf", default=None, help="H.264 quality of the output video (0 lossless .. 51; --video only) [18]")
    p.add_argument("--mask-dir", help="Folder for the rain's coverage masks (same names as the frames)")
    p.add_argument("--depth-dir", help="Depth maps for --input-dir: each frame's stem as .exr (metres) or .png "
                                       "(16-bit codes x --depth-scale-m); without, a ground plane")
    p.add_argument("--depth-scale-m", default=None, help="Metres per code of a PNG depth map of --depth-dir [0.001]")
    for flag, name, typ, default, text, lo, hi, unit in OPTIONS:
        valid = f"[{lo}, {hi if hi is not None else '2^53'}]" if typ is int else f"[{lo:g}, {hi:g}]"
        p.add_argument(flag, dest=name, default=default,
                       help=text + ("" if valid in text else f"; valid {valid}{' ' + unit if unit else ''}")
                       + (f" [{default:g}]" if isinstance(default, (int, float)) else ""))
    p.add_argument("--frame-index", default=0, help="Index of the first frame in the rain field's time [0]")
    p.add_argument("--no-unresolved", action="store_true",
                   help="Leave out the unresolved rain's extinction and airlight (streaks only)")
    p.add_argument("--chunk-frames", default=0,
                   help="Frames per task (0: about 4 tasks per worker, at most 32 frames each; 8 for video)")


def _options(a: argparse.Namespace) -> Dict[str, Any]:
    opts = {name: getattr(a, name) for _, name, *_ in OPTIONS if getattr(a, name) is not None}
    if a.fov_deg is not None and a.focal_mm is not None:
        raise UsageError("--fov-deg: give --focal-mm or --fov-deg, not both")
    if a.pixel_pitch_um is not None and a.sensor_width_mm is not None:
        raise UsageError("--pixel-pitch-um: give --sensor-width-mm or --pixel-pitch-um, not both")
    opts["unresolved"] = not a.no_unresolved
    return opts


def _flag_error(e: ValueError) -> UsageError:
    """The library's message, with the Python argument named as the batch flag."""
    import re

    text = str(e)
    # Every setting the message names, the one refused and those its range follows from ("beyond near_m").
    for name in sorted(FLAG_OF, key=len, reverse=True):
        text = re.sub(r"(?<![\w-])" + re.escape(name) + r"(?![\w-])", FLAG_OF[name], text)
    return UsageError(text)


def _not_regular(path: str) -> Optional[str]:
    """What a folder entry is when it is not a regular file (following a symbolic link), else None."""
    import stat

    try:
        st = os.stat(path)
    except FileNotFoundError:
        return "dangling link" if os.path.islink(path) else "vanished"
    except OSError as e:
        return f"unreadable: {e.strerror}"
    mode = st.st_mode
    if stat.S_ISREG(mode):
        return None
    for test, what in ((stat.S_ISDIR, "folder"), (stat.S_ISFIFO, "FIFO"), (stat.S_ISSOCK, "socket"),
                       (stat.S_ISCHR, "character device"), (stat.S_ISBLK, "block device")):
        if test(mode):
            return what
    return "not a regular file"


def list_frames(input_dir: str, shown_dir: Optional[str] = None) -> List[str]:
    """The frames of input_dir in name order: its regular files with an image extension (not hidden). An
    entry with such a name that is not a regular file (a FIFO, a device, a folder, a dangling link) is
    skipped, and the skipped ones are listed in one warning line on stderr."""
    shown = shown_dir if shown_dir is not None else input_dir
    if not os.path.isdir(input_dir):
        raise UsageError(f"--input-dir {shown}: not a folder")
    try:
        entries = sorted(os.listdir(input_dir))
    except OSError as e:
        raise UsageError(f"--input-dir {shown}: {e.strerror}") from None
    names, skipped = [], []
    for n in entries:
        if n.startswith(".") or os.path.splitext(n)[1].lower() not in FRAME_EXTENSIONS:
            continue
        what = _not_regular(os.path.join(input_dir, n))
        if what is None:
            names.append(n)
        else:
            skipped.append(f"{n} ({what})")
    if skipped:
        listed = ", ".join(skipped[:10]) + (f" and {len(skipped) - 10} more" if len(skipped) > 10 else "")
        sys.stderr.write(printable(f"hydrolux.batch rain: warning: --input-dir {shown_dir or input_dir}: skipped "
                                   f"{len(skipped)} " + ("entry that is not a regular file" if len(skipped) == 1 else
                                                         "entries that are not regular files") + f": {listed}") + "\n")
        sys.stderr.flush()
    if not names:
        raise UsageError(f"--input-dir {shown}: no image files (png, jpg, exr, tif, hdr, ppm, pfm)")
    return names


def output_names(input_dir: str, frames: List[str]) -> List[str]:
    """Each frame's output name, as the CLI names it: its stem as .exr (EXR input) or .png."""
    seen: Dict[str, str] = {}
    out = []
    for f in frames:
        stem, ext = os.path.splitext(f)
        name = stem + (".exr" if ext.lower() == ".exr" else ".png")
        if name in seen:
            raise UsageError(f"--input-dir {input_dir}: {seen[name]} and {f} would both be written as {name}")
        seen[name] = f
        out.append(name)
    return out


def depth_maps(depth_dir: str, frames: List[str]) -> List[str]:
    """Each frame's depth map in depth_dir, its stem as .exr or .png, found before any work (the CLI's
    rule)."""
    if not os.path.isdir(depth_dir):
        raise UsageError(f"--depth-dir {depth_dir}: not a folder")
    out = []
    for f in frames:
        stem = os.path.splitext(f)[0]
        found = next((stem + e for e in (".exr", ".png") if os.path.isfile(os.path.join(depth_dir, stem + e))), None)
        if found is None:
            raise UsageError(f"--depth-dir {depth_dir}: no depth map for {f} ({stem}.exr or {stem}.png)")
        out.append(found)
    return out


# ---- on the workers -------------------------------------------------------------------------------

_RENDERERS: Dict[str, Any] = {}


def _renderer(job: Dict[str, Any], ground: bool):
    """The worker process's renderer for this job: the field is built once per process and kept for
    every task of the same options, frame size and scene (ground plane or depth maps)."""
    import json

    import hydrolux

    if job["threads"]:
        hydrolux.set_threads(job["threads"])
    key = json.dumps([job["options"], job["width"], job["height"], ground], sort_keys=True)
    renderer = _RENDERERS.get(key)
    if renderer is None:
        _RENDERERS.clear()
        renderer = _RENDERERS[key] = hydrolux.RainRenderer(job["width"], job["height"], ground, **job["options"])
    return renderer


def render_frames(job: Dict[str, Any], frames: List[tuple]) -> List[dict]:
    """A task: renders consecutive frames [(input name, output name, frame index, depth map), ...] and writes
    them. Returns one record per frame; a frame that fails carries "error" and the others go on."""
    _core = _common.native("_core")
    _image = _common.native("_image")

    renderer = _renderer(job, ground=not job["depth_dir"])
    records = []
    for src, name, index, depth_name in frames:
        rec: Dict[str, Any] = {"output": name, "input": src, "frame_index": index}
        try:
            path = os.path.join(job["input_dir"], src)
            stamp = _common.file_stamp(path)
            image = _image.read(path)[0]
            h, w = image.shape[:2]
            if (w, h) != (job["width"], job["height"]):
                raise ValueError(f"is {w}x{h}, unlike the first frame ({job['width']}x{job['height']}); "
                                 "one sequence has one size")
            depth = depth_stamp = None
            if depth_name:
                depth_stamp = _common.file_stamp(os.path.join(job["depth_dir"], depth_name))
                depth = _image.read_depth(os.path.join(job["depth_dir"], depth_name), job["depth_scale_m"], w, h,
                                          "--depth-dir")[:, :, 0]
            with warnings.catch_warnings():  # negative values: counted in the stats, said once by the client
                warnings.simplefilter("ignore", RuntimeWarning)
                result = renderer.render(image, depth, index)
            fmt = "exr" if name.endswith(".exr") else "png"
            if job["mask_dir"]:
                _core.write_file(os.path.join(job["mask_dir"], name), _image.encode(result.mask, fmt, 16, True),
                                 "--mask-dir")
            data = _image.encode(result.image, fmt, 8, False)
            _core.write_file(os.path.join(job["output_dir"], name), data, "--output-dir")
            rec.update(input_size=stamp["size"], input_mtime_ns=stamp["mtime_ns"], output_size=len(data),
                       stats=result.stats)
            if depth_name:
                rec["depth"] = depth_stamp
        except Exception as e:  # reported by name; the chunk's other frames go on
            rec["error"] = str(e)
        records.append(rec)
    return records


# ---- on the client --------------------------------------------------------------------------------

def _is_done(rec: Optional[dict], frame_index: int, input_path: str, output_path: str, mask_path: Optional[str],
             depth_path: Optional[str]) -> bool:
    if not rec or "error" in rec or rec.get("frame_index") != frame_index:  # a frame added or removed before it
        return False
    if depth_path and rec.get("depth") != _common.file_stamp(depth_path):
        return False
    stamp = _common.file_stamp(input_path)
    out = _common.file_stamp(output_path)
    if stamp is None or out is None or (mask_path and _common.file_stamp(mask_path) is None):
        return False
    return (stamp["size"], stamp["mtime_ns"]) == (rec.get("input_size"), rec.get("input_mtime_ns")) and \
        out["size"] == rec.get("output_size")


def run(a: argparse.Namespace, after_result=None) -> int:
    if (a.input_dir is None) == (getattr(a, "video", None) is None):
        raise UsageError("give exactly one of --input-dir and --video")
    parse_numbers(a)
    if getattr(a, "video", None) is not None:
        if a.depth_scale_given:
            raise UsageError("--depth-scale-m: scales PNG depth maps, which are for --input-dir")
        return run_video(a, after_result)
    if a.crf_given:
        raise UsageError("--crf: sets the H.264 quality of --video's output; --input-dir writes pictures")
    if a.depth_scale_given and not a.depth_dir:
        raise UsageError("--depth-scale-m: scales PNG maps of --depth-dir; none is given")
    if getattr(a, "output", None):
        raise UsageError("-o: with --input-dir the frames go to --output-dir")
    if not a.output_dir:
        raise UsageError("--output-dir: give the folder for the rainy frames (with --input-dir)")
    return run_folder(a, after_result)


def run_folder(a: argparse.Namespace, after_result=None) -> int:
    import hydrolux
    _image = _common.native("_image")

    opts = _options(a)
    in_dir, out_dir = os.path.abspath(a.input_dir), os.path.abspath(a.output_dir)
    mask_dir = os.path.abspath(a.mask_dir) if a.mask_dir else None
    frames = list_frames(in_dir, a.input_dir)
    names = output_names(in_dir, frames)
    depth_dir = os.path.abspath(a.depth_dir) if a.depth_dir else None
    depths = depth_maps(depth_dir, frames) if depth_dir else [None] * len(frames)
    exr_depth = next((d for d in depths if d and d.lower().endswith(".exr")), None)
    if a.depth_scale_given and exr_depth:
        raise UsageError(f"--depth-scale-m: scales the codes of a PNG depth map; --depth-dir {depth_dir}: {exr_depth} "
                         "holds metres already")
    for flag, d in (("--output-dir", out_dir), ("--mask-dir", mask_dir)):
        if d and os.path.exists(d):
            if not os.path.isdir(d):
                raise UsageError(f"{flag} {d}: exists and is not a folder")
            if os.path.samefile(d, in_dir):
                raise UsageError(f"{flag} {d}: is the input folder; the frames would replace their inputs")
            if depth_dir and os.path.samefile(d, depth_dir):
                raise UsageError(f"{flag} {d}: is --depth-dir; the outputs could replace depth maps")
    if mask_dir and os.path.exists(mask_dir) and os.path.exists(out_dir) and os.path.samefile(mask_dir, out_dir):
        raise UsageError(f"--mask-dir {mask_dir}: is --output-dir; masks and frames share names")
    # Member by member: no output file (a frame, a mask, the manifest or its lock) that is, through a link, an
    # input frame, a depth map or another output.
    inputs = [("--input-dir", os.path.join(in_dir, f)) for f in frames]
    if depth_dir:
        inputs += [("--depth-dir", os.path.join(depth_dir, d)) for d in depths]
    outputs = [("--output-dir", os.path.join(out_dir, n)) for n in names + [_common.MANIFEST, _common.LOCK]]
    if mask_dir:
        outputs += [("--mask-dir", os.path.join(mask_dir, n)) for n in names]
    _common.check_members(inputs, outputs)
    # The sequence's size from its first readable frame (an unreadable one is reported with the rest).
    size = None
    for f in frames:
        try:
            img = _image.read(os.path.join(in_dir, f))[0]
            size = (img.shape[1], img.shape[0])
            break
        except (ValueError, OSError):
            continue
    if size is None:
        raise UsageError(f"--input-dir {in_dir}: no frame could be read")
    # Every option checked, and the field's size, before any task starts.
    try:
        field = hydrolux.RainRenderer(size[0], size[1], depth_dir is None, **opts).field_info()
    except ValueError as e:
        raise _flag_error(e) from None
    # The local cluster's size within the cores and the memory (a task holds a frame's buffers), then the
    # cluster: an unreachable scheduler leaves no output folder behind.
    a.workers, a.threads_per_worker = _common.local_cluster_size(a.workers, a.threads_per_worker,
                                                                 TASK_BYTES_PER_PIXEL * size[0] * size[1], a.scheduler)
    client, cluster = _common.open_client(a.scheduler, a.workers, a.threads_per_worker, a.quiet)
    manifest = None
    failed: List[str] = []
    try:
        for flag, d in (("--output-dir", out_dir), ("--mask-dir", mask_dir)):
            if d:
                _common.make_folder(flag, d)
        params = {"input_dir": in_dir, "mask_dir": mask_dir, "frame_index": a.frame_index, "options": opts,
                  "size": list(size), "depth_dir": depth_dir, "depth_scale_m": a.depth_scale_m if depth_dir else None}
        manifest = _common.Manifest(out_dir, "rain", params)
        if manifest.restarted and not a.quiet:
            print(f"batch rain: {out_dir} holds a run with other parameters; every frame is redone",
                  file=sys.stderr)
        todo = []
        for k, (src, name) in enumerate(zip(frames, names)):
            if not _is_done(manifest.records.get(name), a.frame_index + k, os.path.join(in_dir, src),
                            os.path.join(out_dir, name),
                            os.path.join(mask_dir, name) if mask_dir else None,
                            os.path.join(depth_dir, depths[k]) if depth_dir else None):
                todo.append((src, name, a.frame_index + k, depths[k]))
        skipped = len(frames) - len(todo)
        workers = max(1, len(client.scheduler_info().get("workers", {})) or a.workers)
        chunk = a.chunk_frames or max(1, min(32, math.ceil(len(todo) / (4 * workers))))
        tasks = [todo[i:i + chunk] for i in range(0, len(todo), chunk)]
        cores = _common.usable_cores()
        job = {"input_dir": in_dir, "output_dir": out_dir, "mask_dir": mask_dir, "width": size[0],
               "height": size[1], "options": opts, "depth_dir": depth_dir, "depth_scale_m": a.depth_scale_m,
               "threads": 0 if a.scheduler else max(1, cores // max(1, a.workers * a.threads_per_worker))}
        progress = _common.Progress("batch rain", len(tasks), "frames", a.quiet)
        if not a.quiet:
            link = _common.dashboard_link(client)
            where = a.scheduler or f"a local cluster of {a.workers} worker(s)"
            print(f"batch rain: {len(frames)} frames ({skipped} done before), {len(tasks)} tasks of up to {chunk} "
                  f"on {where}; {field['drops']} drops in the field" + (f"; dashboard {link}" if link else ""),
                  file=sys.stderr)

        retry: List[tuple] = []
        final_round = False
        negatives = [0, 0]  # negative input values read as 0, and the frames that had them

        def on_result(task, result):
            if isinstance(result, Exception):
                # The task as a whole failed: a frame that kills its worker every time (KilledWorker), or
                # a bystander queued on that worker. Its frames go again alone, one task at a time, so
                # that only the culprit can fail and the others are kept.
                if not final_round:
                    retry.extend(task[1])
                    return
                failed.append(task[1][0][0])
                progress.message(f"batch rain: {task[1][0][0]}: {type(result).__name__}: {result}")
                return
            for rec in result:
                if "error" in rec:
                    failed.append(rec["input"])
                    progress.message(f"batch rain: {rec['input']}: {rec['error']}")
                else:
                    manifest.add(rec)
                    n = rec.get("stats", {}).get("negative_values_clamped", 0)
                    negatives[0] += n
                    negatives[1] += 1 if n else 0

        def count(r):
            return 0 if isinstance(r, Exception) else len(r)

        _common.run_tasks(client, [(job, t) for t in tasks], render_frames, on_result, progress, count, after_result)
        if retry:
            final_round = True
            progress.message(f"batch rain: {len(retry)} frame(s) of failed tasks, again one at a time")
            progress = _common.Progress("batch rain (again)", len(retry), "frames", a.quiet)
            for k, f in enumerate(sorted(retry)):
                _common.run_tasks(client, [(job, [f])], render_frames, on_result, progress, count)
                progress.update(k + 1, k + 1)
        progress.finish()
        if negatives[0]:
            progress.message(f"batch rain: warning: --input-dir {a.input_dir}: {negatives[0]} negative value"
                             f"{'s' if negatives[0] != 1 else ''} in {negatives[1]} frame(s) read as 0 (light cannot "
                             "be negative)")
    finally:
        _common.close_client(client, cluster)
        if manifest is not None:
            for d in (out_dir, mask_dir):
                if d:
                    _common.remove_stale_temporaries(d, names)
            manifest.close()
    if not a.quiet:
        print(f"batch rain: {len(frames) - len(failed)} of {len(frames)} frames in {out_dir}"
              + (f"; {len(failed)} failed: {', '.join(failed[:5])}{' ...' if len(failed) > 5 else ''}"
                 if failed else ""), file=sys.stderr)
    return 1 if failed else 0


# ---- video ----------------------------------------------------------------------------------------

def render_video_chunk(job: Dict[str, Any], start: int, count: int) -> Dict[str, Any]:
    """A task: frames [start, start + count) of the video (count -1: to its end), rendered and
    written as raw 8-bit RGB into the staging folder."""
    _core = _common.native("_core")
    _video = _common.native("_video")

    name = f"chunk_{start:09d}.rgb"
    parts, stats = [], []
    try:  # the video's own problems (truncated, corrupt): a bad input, reported as the CLI reports it
        renderer = _renderer(job, ground=True)
        reader = _video.VideoReader(job["video"], job["video_label"])
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
        _core.write_file(os.path.join(job["staging"], name), data, "staging")
    except OSError as e:
        return {"output": name, "start": start, "error": str(e), "input_error": False}
    return {"output": name, "start": start, "frames": len(parts), "size": len(data), "stats": stats}


def run_video(a: argparse.Namespace, after_result=None) -> int:
    import hydrolux
    _video = _common.native("_video")

    if a.input_dir or a.output_dir or a.mask_dir or a.depth_dir:
        raise UsageError("--video writes one video (-o); --output-dir, --mask-dir and --depth-dir are for "
                         "--input-dir (video frames use the ground plane)")
    if not a.output:
        raise UsageError("-o: give the output video (.mp4, .mov or .mkv)")
    if os.path.splitext(a.output)[1].lower() not in (".mp4", ".mov", ".mkv"):
        raise UsageError(f"-o {a.output}: expected a .mp4, .mov or .mkv file")
    if a.fps is not None:
        raise UsageError("--fps: a video's frame rate is its own")
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
        info = _video.VideoReader(video, video_label).info()
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
            expected = _video.VideoReader(video, video_label).skip(1 << 40)
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
        manifest = _common.Manifest(staging, "rain-video", params)
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
        writer = _video.VideoWriter(output, info, a.crf, "-o")
        for name in chunk_names:
            with open(os.path.join(staging, name), "rb") as f:
                data = f.read()
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
