"""python3 -m hydrolux.batch lee-atlas: an atlas of Lee tables on a Dask cluster.

The spec is a JSON file naming the tables, each with ``hydrolux lee``'s options (flag names without
the dashes; ``size_spread`` and ``size-spread`` alike), defaults shared by all, and sweeps that make
one table per combination::

    {"defaults": {"size": "128x256"},
     "tables": [
       {"name": "rainbow-s{size-spread}-t{temperature-c}", "table": "rainbow",
        "sweep": {"size-spread": [0.05, 0.1, 0.2], "temperature-c": [0, 20]}},
       {"name": "corona-10um", "table": "corona", "radius-um": "5:20", "limb-darkening": true}]}

Each table is one task: ``hydrolux lee`` itself, writing <name>.exr, .png and .json atomically into
the output folder (the same files and bytes as the CLI run by hand), or with ``--format netcdf`` one
<name>.nc (NetCDF-4 with CF attributes). Tables are recorded in the manifest as they complete; a re-run
skips those whose options and files are unchanged. The atlas's layout (each spec entry, its sweeps and
its tables in sweep order) is written to hydrolux-atlas.json at the end of each run, and
:func:`open_atlas` opens a NetCDF atlas's entry from it as one xarray Dataset
(Dask-backed, the tables joined exactly: one grid) with a dimension per swept option.

A spec is read as the CLI reads an input (a regular file of at most SPEC_MAX_BYTES) and makes at most
MAX_TABLES tables; a table named hydrolux-manifest... or hydrolux-atlas... is refused (reserved).
"""
from __future__ import annotations

import argparse
import functools
import itertools
import json
import os
import re
import subprocess
import sys
from typing import Any, Dict, List, Optional

from . import _common
from ._common import UsageError, clip

# The atlas's layout for open_atlas: its entries, their sweeps and tables (written by each run). Version 2:
# the manifest records each table's sweep label and its files' SHA-256 (version 1 recorded sizes only).
INDEX = "hydrolux-atlas.json"
INDEX_VERSION = 2
# Each --format's files of a table, by extension.
FORMATS = {"exr": (".exr", ".png", ".json"), "netcdf": (".nc",)}
# Options the batch sets itself.
RESERVED = {"o", "output", "json", "q", "quiet", "threads", "h", "help"}
# A table's name: its files are <name>.exr, .png, .json or <name>.nc.
NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._+-]{0,99}$")
NAME_MAX_CHARS = 100
# Names of the batch's own files in the output folder (the manifest, its lock, the atlas's index): a table
# whose name begins so is refused as reserved.
RESERVED_NAMES = ("hydrolux-manifest", "hydrolux-atlas")
# The most tables one spec makes (each entry's product of its sweeps' lengths, summed over the entries):
# a day of the largest tables on a 2-core machine is a few hundred; 10,000 is an atlas of many machines.
MAX_TABLES = 10_000
# The largest spec read (--spec): a spec is a few kilobytes of JSON; a file over this is refused before
# it is read, as the CLI refuses an oversized input.
SPEC_MAX_BYTES = 4 << 20
# The most characters of one table's options as hydrolux lee's arguments (its task's command line and its
# manifest record): far beyond any table's (a list of 400 wavelengths is ~2,000), well within a command line.
MAX_ARGS_CHARS = 16_384
# The largest hydrolux-atlas.json open_atlas reads (a spec's sweeps and 10,000 names are well under 4 MiB).
INDEX_MAX_BYTES = 16 << 20
# zlib's deflate (the NetCDF-4 files' compression) shrinks data at most about 1032:1: a table file that
# declares more bytes of values than that times its size on disk did not come from hydrolux lee.
_DEFLATE_MAX_RATIO = 1032


@functools.lru_cache(maxsize=None)
def params() -> tuple:
    """The lee job's declared parameters, the library's one table (``_core.params("lee")``, as
    ``hydrolux lee``'s flags and :func:`hydrolux.lee`'s keywords): dicts of name, flag, group, kind,
    unit, lo, hi, range, help, excludes, default and default_text. A spec's option of a declared
    name is given as its flag; --threads-per-table takes the range of ``threads``.

    Example:

    >>> from hydrolux.batch import lee_atlas
    >>> p = {p["name"]: p for p in lee_atlas.params()}
    >>> p["size_spread"]["flag"], p["size_spread"]["range"], p["threads"]["range"]
    ('--size-spread', '[0, 0.5]', '[0, 1024]')
    """
    return tuple(_common.native("_core").params("lee"))


def _flag(key: str) -> str:
    """The flag of a spec's option: a declared parameter's own, else the key with dashes."""
    declared = {p["name"]: p["flag"] for p in params()}
    return declared.get(key.replace("-", "_"), "--" + key.replace("_", "-"))


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The lee-atlas job's own options (--spec, --output-dir, --threads-per-table) on the parser ``p``;
    ``python3 -m hydrolux.batch`` adds the cluster's (--workers, --threads-per-worker, --scheduler, -q).

    Example:

    >>> import argparse
    >>> from hydrolux.batch import lee_atlas
    >>> p = argparse.ArgumentParser(prog="lee-atlas")
    >>> lee_atlas.add_arguments(p)
    >>> a = p.parse_args(["--spec", "atlas.json", "--output-dir", "atlas"])
    >>> a.spec, a.output_dir, a.threads_per_table
    ('atlas.json', 'atlas', 0)
    """
    p.add_argument("--spec", required=True, help="The atlas: a JSON file of tables (see the module's help)")
    p.add_argument("--output-dir", required=True, help="Folder for the tables (created)")
    p.add_argument("--threads-per-table", default=0,
                   help="Threads of each table's computation (0: the cores / the local workers)")
    p.add_argument("--format", default="exr", choices=sorted(FORMATS),
                   help="Files of each table: exr (<name>.exr, .png, .json, as hydrolux lee -o name.exr) or "
                        "netcdf (<name>.nc, NetCDF-4 with CF attributes; open the atlas with open_atlas)")


def cli_path() -> str:
    """The hydrolux executable beside this package (``hydrolux._cli.cli_path``): $HYDROLUX_CLI, the
    package's bin/ (an installed copy), or the build tree's bin/.

    Example:

    >>> import os
    >>> from hydrolux.batch import lee_atlas
    >>> os.access(lee_atlas.cli_path(), os.X_OK)
    True
    """
    from .. import _cli
    return _cli.cli_path()


def _flag_args(options: Dict[str, Any], where: str) -> List[str]:
    args: List[str] = []
    chars = 0
    for key in sorted(options):
        flag = key.replace("_", "-")
        if flag in RESERVED:
            raise UsageError(f"--spec {where}: '{clip(key)}' is set by the batch itself")
        value = options[key]
        if value is True:
            args.append(_flag(key))
        elif value is False or value is None:
            continue
        elif isinstance(value, (int, float, str)):
            args += [_flag(key), str(value)]
        else:
            raise UsageError(f"--spec {where}: '{clip(key)}' must be a number, a string or true/false")
        chars += sum(len(x) + 1 for x in args[-2:])
        if chars > MAX_ARGS_CHARS:
            raise UsageError(f"--spec {where}: the options make more than {MAX_ARGS_CHARS} characters of "
                             f"hydrolux lee arguments (at '{clip(key)}'); the limit is {MAX_ARGS_CHARS}")
    return args


def _scalar(value) -> bool:
    return isinstance(value, (int, float, str)) and (not isinstance(value, float) or value == value)


def _table_name(pattern: str, fields: Dict[str, Any], where: str) -> str:
    """The name ``pattern`` makes with the options ``fields``: str.format's syntax, each field an option's
    name ({size-spread}, {temperature_c:.0f}), checked while it is made so that no pattern or value can
    make a name larger than NAME_MAX_CHARS (a width of 10^9 in a format spec, a value of megabytes)."""
    import string

    def refuse(why: str):
        raise UsageError(f"--spec {where}: name '{clip(pattern)}': {why}")

    out: List[str] = []
    length = 0
    try:
        parts = list(string.Formatter().parse(pattern))
    except ValueError as e:
        refuse(f"not a name pattern ({e})")
    for literal, field, spec, conversion in parts:
        pieces = [literal]
        if field is not None:
            if field not in fields:
                refuse(f"no option '{clip(field)}' to fill it" if field else "a field without an option's name")
            if spec and ("{" in spec or any(int(n) > NAME_MAX_CHARS for n in re.findall(r"[0-9]+", spec))):
                refuse(f"the format '{clip(spec)}' of {{{clip(field)}}} makes a name longer than "
                       f"{NAME_MAX_CHARS} characters")
            value = fields[field]
            if len(value if isinstance(value, str) else repr(value)) > NAME_MAX_CHARS + 32:
                piece = None  # longer than any name, whatever its format
            else:
                try:
                    value = {"r": repr, "s": str, "a": ascii}[conversion](value) if conversion else value
                    piece = format(value, spec or "")
                except (ValueError, TypeError, KeyError) as e:
                    refuse(f"{{{clip(field)}}} cannot be formatted: {clip(str(e))}")
            if piece is None or len(piece) > NAME_MAX_CHARS:
                refuse(f"{{{clip(field)}}} is '{clip(fields[field])}', longer than a name of at most "
                       f"{NAME_MAX_CHARS} characters")
            pieces.append(piece)
        for piece in pieces:
            length += len(piece)
            if length > NAME_MAX_CHARS:
                refuse(f"makes a name longer than {NAME_MAX_CHARS} characters ('{clip(''.join(out) + piece)}')")
            out.append(piece)
    name = "".join(out)
    if name.startswith(RESERVED_NAMES):
        raise UsageError(f"--spec {where}: name '{clip(name)}': reserved for the batch's own files "
                         f"({_common.MANIFEST}, {_common.LOCK}, {INDEX}); names may not begin with "
                         f"{' or '.join(RESERVED_NAMES)}")
    if not NAME.match(name):
        raise UsageError(f"--spec {where}: name '{clip(name)}': use letters, digits, '.', '_', '+', '-' "
                         f"(at most {NAME_MAX_CHARS}, beginning with a letter or digit)")
    return name


def expand(spec_path: str) -> List[Dict[str, Any]]:
    """The tables of a spec, sweeps expanded: [{"name": ..., "args": [flags...]}, ...].

    Example:

    >>> import json, os, tempfile
    >>> from hydrolux.batch import lee_atlas
    >>> folder = tempfile.mkdtemp()
    >>> spec = os.path.join(folder, "atlas.json")
    >>> with open(spec, "w") as f:
    ...     json.dump({"defaults": {"size": "4x8", "wavelengths-nm": "380:780:4"},
    ...                "tables": [{"name": "rainbow-s{size-spread}", "table": "rainbow",
    ...                            "sweep": {"size-spread": [0.05, 0.2]}}]}, f)
    >>> for t in lee_atlas.expand(spec):
    ...     print(t["name"], " ".join(t["args"]), t["sweep"])
    rainbow-s0.05 --size 4x8 --size-spread 0.05 --table rainbow --wavelengths-nm 380:780:4 {'size-spread': 0.05}
    rainbow-s0.2 --size 4x8 --size-spread 0.2 --table rainbow --wavelengths-nm 380:780:4 {'size-spread': 0.2}

    Each table also names its ``entry`` (the spec entry's name pattern) and that entry's whole
    ``sweeps`` (option -> values), for :func:`open_atlas`.
    """
    # Read as the CLI reads an input: a regular file of at most SPEC_MAX_BYTES (never /dev/zero or a FIFO).
    data = _common.read_input(spec_path, "--spec", SPEC_MAX_BYTES)
    try:
        spec = json.loads(data)
    except (ValueError, RecursionError) as e:  # RecursionError: JSON nested thousands deep
        reason = str(e) if isinstance(e, ValueError) else "nested too deep"
        raise UsageError(f"--spec {spec_path}: not a JSON file: {clip(reason, 200)}") from None
    if not isinstance(spec, dict) or not isinstance(spec.get("tables"), list) or not spec["tables"]:
        raise UsageError(f"--spec {spec_path}: expected an object with a non-empty list \"tables\"")
    defaults = spec.get("defaults", {})
    if not isinstance(defaults, dict):
        raise UsageError(f"--spec {spec_path}: \"defaults\" must be an object of options")
    # The entries' shapes and the count of tables first, before any is expanded: a spec of a few lines can
    # ask for 10^9 tables (sweeps of 1,000 values over three options).
    total = 0
    largest = (0, 0)
    for i, entry in enumerate(spec["tables"]):
        where = f"{spec_path} tables[{i}]"
        if not isinstance(entry, dict) or not isinstance(entry.get("name"), str):
            raise UsageError(f"--spec {where}: each table is an object with a \"name\"")
        sweep = entry.get("sweep", {})
        if not isinstance(sweep, dict) or any(not isinstance(v, list) or not v for v in sweep.values()):
            raise UsageError(f"--spec {where}: \"sweep\" maps options to non-empty lists of values")
        for key, values in sweep.items():
            bad = next((v for v in values if not _scalar(v)), None)
            if bad is not None:
                raise UsageError(f"--spec {where}: \"sweep\" '{clip(key)}': {clip(json.dumps(bad))} is not a "
                                 "number, a string or true/false")
        count = 1
        for values in sweep.values():
            count *= len(values)
        total += count
        largest = max(largest, (count, i))
    if total > MAX_TABLES:
        raise UsageError(f"--spec {spec_path}: makes {total} tables (tables[{largest[1]}] alone {largest[0]}: the "
                         f"product of its sweeps' lengths), more than the limit of {MAX_TABLES} in one atlas")
    out: List[Dict[str, Any]] = []
    names = set()
    for i, entry in enumerate(spec["tables"]):
        where = f"{spec_path} tables[{i}]"
        sweep = entry.get("sweep", {})
        base = {**defaults, **{k: v for k, v in entry.items() if k not in ("name", "sweep")}}
        keys = list(sweep)
        for combo in itertools.product(*(sweep[k] for k in keys)):
            opts = {**base, **dict(zip(keys, combo))}
            fields = {k.replace("_", "-"): v for k, v in opts.items()}
            fields.update({k.replace("-", "_"): v for k, v in opts.items()})
            name = _table_name(entry["name"], fields, where)
            if name in names:
                raise UsageError(f"--spec {where}: two tables are named '{name}'")
            names.add(name)
            out.append({"name": name, "args": _flag_args(opts, where), "entry": entry["name"],
                        "sweep": dict(zip(keys, combo)), "sweeps": {k: list(sweep[k]) for k in keys}})
    return out


# ---- on the workers -------------------------------------------------------------------------------

def make_table(out_dir: str, name: str, args: List[str], threads: int, fmt: str = "exr") -> Dict[str, Any]:
    """A task: one table by the hydrolux CLI in ``fmt`` (a key of FORMATS); its error line if it fails.

    Example:

    >>> import tempfile
    >>> from hydrolux.batch import lee_atlas
    >>> folder = tempfile.mkdtemp()
    >>> rec = lee_atlas.make_table(folder, "bow", ["--size", "4x8", "--wavelengths-nm", "380:780:4"], 1)
    >>> sorted(rec["files"])   # bow.exr, bow.png, bow.json and their sizes
    ['.exr', '.json', '.png']
    >>> print(lee_atlas.make_table(folder, "bad", ["--size", "0x8"], 1)["error"])
    hydrolux lee: --size: '0x8' is not WxH, each ...
    """
    exts = FORMATS[fmt]
    target = os.path.join(out_dir, name + exts[0])
    cmd = [cli_path(), "lee", "-o", target, "-q", "--threads", str(threads)] + args
    # The CLI's message names the folder as its bytes: a name that is not UTF-8 is kept as surrogate escapes.
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, encoding="utf-8",
                       errors="surrogateescape")
    rec: Dict[str, Any] = {"output": name, "args": args}
    if p.returncode != 0:
        lines = [line for line in p.stderr.strip().splitlines() if line.strip()]
        rec["error"] = clip(lines[-1], 2000) if lines else f"hydrolux lee exited with {p.returncode}"
        rec["bad_request"] = p.returncode == 2  # the CLI's usage error: the table's options, not the machine
        return rec
    # Each file's size and content hash: a re-run and open_atlas know the files the batch wrote from any
    # other of the same size.
    rec["files"], rec["sha256"] = {}, {}
    for ext in exts:
        d = _common.file_digest(os.path.join(out_dir, name + ext))
        if d is None:
            rec.pop("files"), rec.pop("sha256")
            rec["error"] = f"{os.path.join(out_dir, name + ext)}: hydrolux lee wrote no regular file there"
            return rec
        rec["files"][ext], rec["sha256"][ext] = d["size"], d["sha256"]
    return rec


# ---- on the client --------------------------------------------------------------------------------

def _is_done(rec, out_dir: str, name: str, args: List[str], exts: tuple) -> bool:
    """Whether the table's record says it was made with these options and each of its files is still the
    one written: the same size and the same SHA-256 (a file replaced by another of the same size is
    redone). A record without hashes (an older batch's) is redone."""
    if not rec or "error" in rec or rec.get("args") != args:
        return False
    files, hashes = rec.get("files"), rec.get("sha256")
    if not isinstance(files, dict) or not isinstance(hashes, dict) or sorted(files) != sorted(exts) or \
            sorted(hashes) != sorted(exts):
        return False
    for ext in exts:
        path = os.path.join(out_dir, name + ext)
        st = _common.file_stamp(path)
        if st is None or st["size"] != files[ext]:
            return False
        d = _common.file_digest(path)
        if d is None or d["sha256"] != hashes[ext]:
            return False
    return True


def _write_index(out_dir: str, tables: List[Dict[str, Any]], fmt: str) -> None:
    """hydrolux-atlas.json: each spec entry (its name pattern), its sweeps (option -> values, the spec's
    order) and its tables' names in the order of the sweeps' product, written atomically."""
    entries: Dict[str, Dict[str, Any]] = {}
    for t in tables:
        e = entries.setdefault(t["entry"], {"entry": t["entry"], "sweeps": t["sweeps"], "tables": []})
        e["tables"].append(t["name"])
    index = {"format": "hydrolux-lee-atlas", "format_version": INDEX_VERSION, "files": fmt,
             "entries": list(entries.values())}
    _common.native("_core").write_file(_common.fs(os.path.join(out_dir, INDEX)),
                                       (json.dumps(index, indent=1) + "\n").encode(), "--output-dir")


def run(a: argparse.Namespace, after_result=None) -> int:
    """The job: every table of ``a.spec`` not done yet, one task each, on the cluster; 0 when all are
    in ``a.output_dir``, 1 when some failed (each said on stderr). ``after_result``: for the tests.

    Example (a local cluster of one worker; ``python3 -m hydrolux.batch lee-atlas`` does the same):

    >>> import argparse, json, os, tempfile
    >>> from hydrolux.batch import lee_atlas
    >>> folder = tempfile.mkdtemp()
    >>> spec = os.path.join(folder, "atlas.json")
    >>> with open(spec, "w") as f:   # one table, its flags its own (no defaults, no sweep)
    ...     json.dump({"tables": [{"name": "glory", "table": "glory", "size": "4x8", "wavelengths-nm": "380:780:4"}]}, f)
    >>> p = argparse.ArgumentParser()
    >>> lee_atlas.add_arguments(p)
    >>> a = p.parse_args(["--spec", spec, "--output-dir", os.path.join(folder, "atlas")])
    >>> a.workers, a.threads_per_worker, a.scheduler, a.quiet = 1, None, None, True   # the cluster's options
    >>> lee_atlas.run(a)
    0
    >>> sorted(os.listdir(os.path.join(folder, "atlas")))
    ['glory.exr', 'glory.json', 'glory.png', 'hydrolux-atlas.json', 'hydrolux-manifest.jsonl', 'hydrolux-manifest.lock']
    """
    lee_threads = {p["name"]: p for p in params()}["threads"]  # hydrolux lee --threads' range
    a.threads_per_table = _common.integer_flag("--threads-per-table", a.threads_per_table, int(lee_threads["lo"]),
                                               int(lee_threads["hi"]), extra=" (0: the cores / the local workers)")
    fmt = getattr(a, "format", "exr")
    if fmt not in FORMATS:
        raise UsageError(f"--format {fmt}: expected one of {', '.join(sorted(FORMATS))}")
    exts = FORMATS[fmt]
    tables = expand(a.spec)
    out_dir = os.path.abspath(a.output_dir)
    if os.path.exists(out_dir) and not os.path.isdir(out_dir):
        raise UsageError(f"--output-dir {out_dir}: exists and is not a folder")
    # Member by member: no table file, manifest or lock that is (through a link) the spec, nor another output.
    _common.check_members([("--spec", os.path.abspath(a.spec))],
                          [("--output-dir", os.path.join(out_dir, n))
                           for n in [_common.MANIFEST, _common.LOCK, INDEX]
                           + [t["name"] + e for t in tables for e in exts]])
    # The local cluster's size within the cores and the memory, then the cluster: an unreachable scheduler
    # leaves no output folder behind.
    a.workers, a.threads_per_worker = _common.local_cluster_size(a.workers, a.threads_per_worker, 0, a.scheduler)
    client, cluster = _common.open_client(a.scheduler, a.workers, a.threads_per_worker, a.quiet)
    manifest = None
    failed: List[str] = []
    bad_requests = 0  # failures that are the CLI's usage errors (exit 2): the spec asked for what cannot be
    try:
        _common.make_folder("--output-dir", out_dir)
        manifest = _common.Manifest(out_dir, "lee-atlas", {} if fmt == "exr" else {"format": fmt})
        todo = []
        for t in tables:
            rec = manifest.records.get(t["name"])
            if not _is_done(rec, out_dir, t["name"], t["args"], exts):
                todo.append(t)
            elif rec.get("entry") != t["entry"] or rec.get("sweep") != t["sweep"]:
                manifest.add({**rec, "entry": t["entry"], "sweep": t["sweep"]})  # the same table, labelled anew
        cores = _common.usable_cores()
        threads = a.threads_per_table or (0 if a.scheduler else max(1, cores // max(1, a.workers)))
        progress = _common.Progress("batch lee-atlas", len(todo), "tables", a.quiet)
        if not a.quiet:
            link = _common.dashboard_link(client)
            where = a.scheduler or f"a local cluster of {a.workers} worker(s)"
            print(f"batch lee-atlas: {len(tables)} tables ({len(tables) - len(todo)} done before) on {where}"
                  + (f"; dashboard {link}" if link else ""), file=sys.stderr)

        def on_result(task, rec):
            if isinstance(rec, Exception):
                failed.append(task[1])
                progress.message(f"batch lee-atlas: {task[1]}: {type(rec).__name__}: {rec}")
            elif "error" in rec:
                nonlocal bad_requests
                failed.append(rec["output"])
                bad_requests += 1 if rec.get("bad_request") else 0
                progress.message(f"batch lee-atlas: {rec['output']}: {rec['error']}")
            else:  # recorded with its label in the sweep, for open_atlas to check against the index
                t = by_name[rec["output"]]
                manifest.add({**rec, "entry": t["entry"], "sweep": t["sweep"]})

        by_name = {t["name"]: t for t in todo}
        tasks = [(out_dir, t["name"], t["args"], threads, fmt) for t in todo]
        _common.run_tasks(client, tasks, make_table, on_result,
                          progress, lambda r: 0 if isinstance(r, Exception) or "error" in r else 1, after_result)
        progress.finish()
        _write_index(out_dir, tables, fmt)
    finally:
        _common.close_client(client, cluster)
        if manifest is not None:
            _common.remove_stale_temporaries(out_dir, [t["name"] + e for t in tables for e in exts] + [INDEX])
            manifest.close()
    if not a.quiet:
        print(_common.printable(f"batch lee-atlas: {len(tables) - len(failed)} of {len(tables)} tables in {out_dir}"
                                + (f"; {len(failed)} failed: {', '.join(failed[:5])}" if failed else "")),
              file=sys.stderr)
    # As the CLI: 2 when every failure was a table's bad options (the same request refused alike in every
    # door), 1 when any table failed for another reason.
    return 0 if not failed else 2 if bad_requests == len(failed) else 1


# ---- reading an atlas back ------------------------------------------------------------------------

def open_atlas(output_dir: str, entry: Optional[str] = None):
    """A NetCDF atlas (``--format netcdf``) as one :class:`xarray.Dataset`: the tables of one spec entry
    opened together as ``xarray.open_mfdataset`` would (Dask-backed: values are read when computed), with a
    dimension per swept option (its name with underscores, coordinates the swept values, units from the
    option's declaration). ``entry``: the entry's name pattern, e.g. "rainbow-s{size-spread}"; may be
    left out when the atlas has one entry. ValueError naming what is wrong, on one line: not a NetCDF
    atlas, an index that is not as the batch writes it, an entry that is not there, tables of the sweep
    not (yet) made, a table whose file is not the one written (its SHA-256 is recorded in the manifest)
    or not recorded under the label the index gives it, a file that cannot be read as NetCDF, declares
    more values than it can hold or states a swept setting other than its label's, and tables of
    different grids (a sweep of --radius-um, --axis, --table or --size: joined, they would be mostly NaN).

    Example:

    >>> import argparse, json, os, tempfile
    >>> from hydrolux.batch import lee_atlas
    >>> folder = tempfile.mkdtemp()
    >>> spec = os.path.join(folder, "atlas.json")
    >>> with open(spec, "w") as f:
    ...     json.dump({"defaults": {"size": "4x8", "wavelengths-nm": "380:780:4"},
    ...                "tables": [{"name": "bow-s{size-spread}-t{temperature-c}", "table": "rainbow",
    ...                            "sweep": {"size-spread": [0.05, 0.2], "temperature-c": [0, 20]}}]}, f)
    >>> p = argparse.ArgumentParser()
    >>> lee_atlas.add_arguments(p)
    >>> a = p.parse_args(["--spec", spec, "--output-dir", os.path.join(folder, "atlas"), "--format", "netcdf"])
    >>> a.workers, a.threads_per_worker, a.scheduler, a.quiet = 1, None, None, True
    >>> lee_atlas.run(a)
    0
    >>> ds = lee_atlas.open_atlas(os.path.join(folder, "atlas"))
    >>> ds.rgb.dims
    ('size_spread', 'temperature_c', 'scattering_angle', 'radius', 'channel')
    >>> ds.size_spread.values, ds.temperature_c.attrs["units"]
    (array([0.05, 0.2 ]), 'C')
    >>> float(ds.rgb.sel(size_spread=0.2, temperature_c=20, channel="G").max()) > 0
    True
    """
    from .. import _xarray

    xr = _xarray.xarray()
    out_dir = os.path.abspath(output_dir)
    index_entries = _read_index(out_dir)
    entries = [e["entry"] for e in index_entries]
    if entry is None:
        if len(entries) != 1:
            raise ValueError(f"entry: the atlas has {len(entries)} entries; name one of: "
                             f"{', '.join(clip(e) for e in entries[:20])}{', ...' if len(entries) > 20 else ''}")
        entry = entries[0]
    if not isinstance(entry, str) or entry not in entries:
        raise ValueError(f"entry '{clip(entry)}': not in the atlas; its entries: "
                         f"{', '.join(clip(e) for e in entries[:20])}{', ...' if len(entries) > 20 else ''}")
    chosen = index_entries[entries.index(entry)]
    sweeps: Dict[str, list] = chosen["sweeps"]
    keys = list(sweeps)
    names: List[str] = chosen["tables"]
    labels = [dict(zip(keys, combo)) for combo in itertools.product(*(sweeps[k] for k in keys))]
    records = _read_records(out_dir)
    # Each table: made (recorded without an error), recorded with the label the index gives its place in the
    # sweep (a swapped or edited index is refused, not mislabelled), and its file the one written (its size
    # and SHA-256 as recorded).
    missing = [n for n in names if not _made(records.get(n))]
    if missing:
        raise ValueError(f"entry '{clip(entry)}': {len(missing)} of its {len(names)} tables are not made "
                         f"({', '.join(missing[:3])}{', ...' if len(missing) > 3 else ''}): run the batch again")
    files = [os.path.join(out_dir, name + ".nc") for name in names]
    for name, label, path in zip(names, labels, files):
        rec = records[name]
        where = f"entry '{clip(entry)}': table '{name}' ({path})"
        if not isinstance(rec.get("sha256"), dict) or not isinstance(rec["sha256"].get(".nc"), str):
            raise ValueError(f"{where}: recorded without a content hash (by an older hydrolux.batch): run the "
                             "batch again")
        if rec.get("entry") != entry or rec.get("sweep") != label:
            raise ValueError(f"{where}: the index places it at {_label_text(label)}, the manifest records it as "
                             f"{_label_text(rec.get('sweep'))} of entry '{clip(rec.get('entry'))}': "
                             f"{INDEX} or {_common.MANIFEST} was changed; run the batch again")
        d = _common.file_digest(path)
        if d is None:
            raise ValueError(f"{where}: missing or not a regular file: run the batch again")
        if d["size"] != rec["files"][".nc"] or d["sha256"] != rec["sha256"][".nc"]:
            raise ValueError(f"{where}: not the file the batch wrote (its size or SHA-256 differs from the "
                             "manifest's): run the batch again to remake it")
    # The files themselves, before xarray loads anything: readable as NetCDF, declaring no more values than
    # such a file can hold (a dimension of 2^31 - 1 would make xarray load its coordinate, 16 GiB), and
    # stating the settings that their label in the sweep says.
    fds: List[int] = []
    datasets = []
    try:
        opened = [_netcdf_path(entry, name, path, fds) for name, path in zip(names, files)]
        for name, label, path, nc_path in zip(names, labels, files, opened):
            _check_table_file(entry, name, path, label, nc_path)
        for name, path, nc_path in zip(names, files, opened):
            try:
                datasets.append(xr.open_dataset(nc_path, chunks={}))
            except Exception as e:  # noqa: BLE001 - xarray's and the NetCDF library's many errors, as one line
                raise ValueError(f"entry '{clip(entry)}': table '{name}' ({path}): cannot be read: "
                                 f"{_first_line(e)}") from None
        if not keys:  # a copy (the same lazy values) that closes the file and any descriptor kept for it
            ds = datasets[0].copy()
            ds.set_close(functools.partial(_close_all, datasets, fds))
            return ds
        # One grid for every table: a sweep that changes it (the radii, the angle axis, the table kind, the
        # size) would leave the joined Dataset mostly NaN.
        _check_one_grid(entry, keys, sweeps, names, datasets)

        def nest(flat: list, dims: List[int]) -> list:
            if len(dims) == 1:
                return flat
            step = len(flat) // dims[0]
            return [nest(flat[i * step:(i + 1) * step], dims[1:]) for i in range(dims[0])]

        dims = [k.replace("-", "_") for k in keys]
        try:
            ds = xr.combine_nested(nest(datasets, [len(sweeps[k]) for k in keys]), concat_dim=dims, data_vars="all",
                                   coords="different", compat="no_conflicts", join="exact",
                                   combine_attrs="drop_conflicts")
        except Exception as e:  # noqa: BLE001 - what the checks above did not foresee, still one line
            raise ValueError(f"entry '{clip(entry)}': its tables cannot be put together: {_first_line(e)}") from None
    except BaseException:
        _close_all(datasets, fds)
        raise
    ds.set_close(functools.partial(_close_all, datasets, fds))
    declared = {p["name"]: p for p in params()}
    coords = {}
    for key, dim in zip(keys, dims):
        attrs = {"long_name": f"swept option {_flag(key)} of hydrolux lee"}
        if dim in declared and declared[dim]["unit"]:
            attrs["units"] = declared[dim]["unit"]
        coords[dim] = xr.Variable((dim,), list(sweeps[key]), attrs=attrs)
    ds = ds.assign_coords(coords).transpose(*dims, ...)
    ds.attrs["history"] = _xarray.history(f"hydrolux.batch.lee_atlas.open_atlas({output_dir!r}) of the tables "
                                          f"that hydrolux.batch lee-atlas made ({len(files)} hydrolux lee runs)")
    return ds


def _close_all(datasets: list, fds: List[int]) -> None:
    for d in datasets:
        d.close()
    while fds:
        os.close(fds.pop())


def _netcdf_path(entry: str, name: str, path: str, fds: List[int]) -> str:
    """The path the NetCDF library opens ``path`` by: the path itself, or where it is not UTF-8 (a folder
    named with byte 0xff; the library takes UTF-8 paths only) /proc/self/fd/N of a descriptor kept open
    in ``fds`` until the Dataset is closed (such a Dataset is read in this process, not by a distributed
    cluster's workers)."""
    try:
        path.encode("utf-8")
        return path
    except UnicodeEncodeError:
        pass
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC | os.O_NOCTTY)
    except OSError as e:
        raise ValueError(f"entry '{clip(entry)}': table '{name}' ({path}): cannot open: {e.strerror or e}") from None
    fds.append(fd)
    proc = f"/proc/self/fd/{fd}"
    if not os.path.exists(proc):
        raise ValueError(f"entry '{clip(entry)}': table '{name}' ({path}): the NetCDF library takes UTF-8 paths "
                         "only, and this system has no /proc/self/fd to open it by")
    return proc


def _first_line(e: BaseException) -> str:
    lines = [line.strip() for line in str(e).splitlines() if line.strip()]
    return clip(lines[0] if lines else type(e).__name__, 300)


def _label_text(label) -> str:
    if not isinstance(label, dict):
        return clip(json.dumps(label) if _jsonable(label) else repr(label))
    return clip(", ".join(f"{_flag(k)} {v}" for k, v in label.items()) or "(no sweep)", 200)


def _jsonable(value) -> bool:
    try:
        json.dumps(value)
        return True
    except (TypeError, ValueError):
        return False


def _read_index(out_dir: str) -> List[Dict[str, Any]]:
    """hydrolux-atlas.json's entries, each checked to be as run() writes it; a ValueError naming what is not
    (a tampered or truncated index is never read as a silently different layout)."""
    path = os.path.join(out_dir, INDEX)
    if not os.path.lexists(path):
        raise ValueError(f"{out_dir}: no {INDEX} (not an atlas written by hydrolux.batch lee-atlas)")
    data = _common.read_input(path, "", INDEX_MAX_BYTES, error=ValueError)
    try:
        index = json.loads(data)
    except (ValueError, RecursionError) as e:
        raise ValueError(f"{path}: not an atlas index: not JSON ({_first_line(e)})") from None

    def bad(what: str):
        raise ValueError(f"{path}: not an atlas index as hydrolux.batch lee-atlas writes it: {what}")

    if not isinstance(index, dict) or index.get("format") != "hydrolux-lee-atlas":
        bad('no "format": "hydrolux-lee-atlas"')
    if index.get("format_version") != INDEX_VERSION:
        if isinstance(index.get("format_version"), int) and index["format_version"] < INDEX_VERSION:
            raise ValueError(f"{path}: written by an older hydrolux.batch (format_version "
                             f"{index['format_version']}, without its tables' hashes): run the batch again")
        bad(f'"format_version" is {clip(json.dumps(index.get("format_version")))}, not {INDEX_VERSION}')
    files = index.get("files")
    if files != "netcdf":
        if isinstance(files, str) and files in FORMATS:
            raise ValueError(f"{out_dir}: the atlas's tables are {files} files; open_atlas reads a NetCDF atlas "
                             "(make it with --format netcdf)")
        bad(f'"files" is {clip(json.dumps(files))}, not one of {", ".join(sorted(FORMATS))}')
    entries = index.get("entries")
    if not isinstance(entries, list) or not entries:
        bad('"entries" is not a non-empty list')
    seen_entries, seen_names = set(), set()
    for i, e in enumerate(entries):
        if not isinstance(e, dict):
            bad(f"entries[{i}] is not an object")
        for key, kind, words in (("entry", str, "a name pattern"), ("sweeps", dict, "an object of option -> values"),
                                 ("tables", list, "a list of table names")):
            if not isinstance(e.get(key), kind):
                bad(f'entries[{i}] "{key}" is {clip(json.dumps(e.get(key)))}, not {words}')
        if e["entry"] in seen_entries:
            bad(f"two entries are named '{clip(e['entry'])}'")
        seen_entries.add(e["entry"])
        count = 1
        for key, values in e["sweeps"].items():
            if not isinstance(values, list) or not values or not all(_scalar(v) for v in values):
                bad(f'entries[{i}] "sweeps" "{clip(key)}" is {clip(json.dumps(values))}, not a non-empty list of '
                    "numbers, strings or true/false")
            count *= len(values)
        if count > MAX_TABLES or len(e["tables"]) != count:
            bad(f'entries[{i}] "tables" holds {len(e["tables"])} names where its sweeps make {count} tables')
        for t in e["tables"]:
            if not isinstance(t, str) or not NAME.match(t) or t.startswith(RESERVED_NAMES):
                bad(f'entries[{i}] "tables": {clip(json.dumps(t))} is not a table name')
            if t in seen_names:
                bad(f'entries[{i}] "tables": \'{t}\' is listed twice')
            seen_names.add(t)
    return entries


def _read_records(out_dir: str) -> Dict[str, dict]:
    """The manifest's records by output name (a torn last line dropped); ValueError where the manifest is
    not a lee-atlas run's."""
    path = os.path.join(out_dir, _common.MANIFEST)
    if not os.path.lexists(path):
        return {}
    lines = _common.read_input(path, "", _common.MANIFEST_MAX_BYTES, error=ValueError).split(b"\n")
    try:
        header = json.loads(lines[0])
    except (ValueError, RecursionError):
        header = None
    if not isinstance(header, dict) or header.get("manifest") != "hydrolux.batch" or header.get("job") != "lee-atlas":
        raise ValueError(f"{path}: not the manifest of a hydrolux.batch lee-atlas run")
    records = {}
    for line in lines[1:]:
        try:
            rec = json.loads(line)
        except (ValueError, RecursionError):
            continue  # a torn last line
        if isinstance(rec, dict) and isinstance(rec.get("output"), str):
            records[rec["output"]] = rec
    return records


def _made(rec) -> bool:
    return isinstance(rec, dict) and "error" not in rec and isinstance(rec.get("files"), dict) and \
        isinstance(rec["files"].get(".nc"), int)


# The global attributes of a table file that state a swept option's value, where the attribute's name is not
# the option's own with underscores (which is looked up first).
_LABEL_ATTRIBUTES = {"sun-disk-deg": "sun_disk_diameter_deg", "sun_disk_deg": "sun_disk_diameter_deg",
                     "axis": "angle_axis", "medium": "drop_medium", "shape": "drop_shape"}


def _same_value(label, attr) -> bool:
    """Whether a swept value (as the spec gives it: a number, a string, true) is what the file states."""
    import numpy as np

    if isinstance(attr, np.ndarray):
        if attr.size != 1:
            return False
        attr = attr.reshape(-1)[0]
    if isinstance(attr, np.generic):
        attr = attr.item()
    if isinstance(label, bool) or isinstance(attr, bool):
        truth = {"true": True, "1": True, "yes": True, "false": False, "0": False, "no": False}
        a = truth.get(str(attr).lower()) if not isinstance(attr, bool) else attr
        b = truth.get(str(label).lower()) if not isinstance(label, bool) else label
        return a is not None and a == b
    def same_number(a, b) -> Optional[bool]:
        try:
            x, y = float(a), float(b)
        except (TypeError, ValueError, OverflowError):
            return None
        return x == y or abs(x - y) <= 1e-9 * max(abs(x), abs(y))

    same = same_number(label, attr)
    if same is not None:
        return same
    if not isinstance(label, str) or not isinstance(attr, str):
        return False
    # A setting as the CLI states it: "airy" as "airy:2" (its default order), "spheroid:0.90" as
    # "spheroid:0.9": the same name, then each part given the same (as a number where it is one).
    given, stated = label.split(":"), attr.split(":")
    if given[0] != stated[0] or len(given) > len(stated):
        return False
    return all(g == t or same_number(g, t) for g, t in zip(given[1:], stated[1:]))


def _check_table_file(entry: str, name: str, path: str, label: Dict[str, Any], nc_path: str) -> None:
    """A table file read by the NetCDF library alone (no values loaded): ValueError naming the table and
    its file where it cannot be read, declares more values than its bytes can hold, or states a swept
    setting other than its label's."""
    where = f"entry '{clip(entry)}': table '{name}' ({path})"
    try:
        import netCDF4
    except ImportError:  # pragma: no cover - python3-netcdf4 is what xarray opens the atlas with
        return
    try:
        size = os.stat(nc_path).st_size
        with netCDF4.Dataset(nc_path, "r") as nc:
            dims = {d: len(v) for d, v in nc.dimensions.items()}
            declared = 0
            biggest = None
            for v in nc.variables.values():
                n = 1
                for d in v.dimensions:
                    n *= dims.get(d, 1)
                declared += n * max(1, getattr(v.dtype, "itemsize", 8))
                if biggest is None or n > biggest[0]:
                    biggest = (n, v.name, v.dimensions)
            attrs = {a: nc.getncattr(a) for a in nc.ncattrs()}
    except Exception as e:  # noqa: BLE001 - the NetCDF library's errors (text, empty or truncated files)
        raise ValueError(f"{where}: cannot be read as NetCDF: {_first_line(e)}") from None
    if declared > _DEFLATE_MAX_RATIO * max(size, 1):
        shape = " x ".join(f"{d} {dims.get(d, 1)}" for d in biggest[2]) if biggest else ""
        raise ValueError(f"{where}: declares {declared} bytes of values (variable '{clip(biggest[1])}': {shape}) "
                         f"in a file of {size} bytes, more than its compression can hold "
                         f"({_DEFLATE_MAX_RATIO}:1): not a table hydrolux lee wrote")
    for key, value in label.items():
        attr = _LABEL_ATTRIBUTES.get(key, key.replace("-", "_"))
        if attr in attrs and not _same_value(value, attrs[attr]):
            raise ValueError(f"{where}: states {attr} = {clip(str(attrs[attr]))} where its label in the sweep says "
                             f"{_flag(key)} {clip(str(value))}: not the table of its label; run the batch again")


def _check_one_grid(entry: str, keys: List[str], sweeps: Dict[str, list], names: List[str], datasets: list) -> None:
    """ValueError naming the entry, the swept option and the coordinate where two tables that differ in one
    swept option have different grids (dimensions' sizes, dimension coordinates) or variables."""
    import numpy as np

    shape = [len(sweeps[k]) for k in keys]

    def grid_difference(a, b, na: str, nb: str) -> Optional[str]:
        for d in sorted(set(a.sizes) | set(b.sizes)):
            if a.sizes.get(d) != b.sizes.get(d):
                return (f"dimension '{d}' is {a.sizes.get(d, 'absent')} long in '{na}' and "
                        f"{b.sizes.get(d, 'absent')} in '{nb}'")
        for d in sorted(a.sizes):
            ca, cb = d in a.coords, d in b.coords
            if ca != cb:
                return f"coordinate '{d}' is in '{na if ca else nb}' only"
            if ca and not np.array_equal(a[d].values, b[d].values):
                va, vb = a[d].values, b[d].values
                i = next((k for k in range(len(va)) if not (va[k] == vb[k])), 0)
                return (f"coordinate '{d}' differs ('{na}' has {clip(str(va[i]), 30)} at {d}[{i}], '{nb}' "
                        f"{clip(str(vb[i]), 30)})")
        va, vb = set(a.data_vars), set(b.data_vars)
        if va != vb:
            extra = sorted(va - vb)
            return (f"variable '{extra[0]}' is in '{na}' and not in '{nb}'" if extra else
                    f"variable '{sorted(vb - va)[0]}' is in '{nb}' and not in '{na}'")
        return None

    for flat in range(len(datasets)):
        pos = np.unravel_index(flat, shape)
        for j, key in enumerate(keys):  # against the table that differs from it in this one option
            if pos[j] == 0:
                continue
            other = list(pos)
            other[j] = 0
            o = int(np.ravel_multi_index(other, shape))
            why = grid_difference(datasets[o], datasets[flat], names[o], names[flat])
            if why:
                raise ValueError(f"entry '{clip(entry)}': the sweep of {_flag(key)} changes the tables' grid: {why}; "
                                 "open_atlas puts together tables of one grid (sweep such an option in entries of "
                                 "their own, or open the tables one by one with xarray.open_dataset)")
