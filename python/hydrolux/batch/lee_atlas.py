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
the output folder (the same files and bytes as the CLI run by hand). Tables are recorded in the
manifest as they complete; a re-run skips those whose options and files are unchanged.
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
from typing import Any, Dict, List

from . import _common
from ._common import UsageError

# Options the batch sets itself.
RESERVED = {"o", "output", "json", "q", "quiet", "threads", "h", "help"}
NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._+-]{0,99}$")


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
    for key in sorted(options):
        flag = key.replace("_", "-")
        if flag in RESERVED:
            raise UsageError(f"--spec {where}: '{key}' is set by the batch itself")
        value = options[key]
        if value is True:
            args.append(_flag(key))
        elif value is False or value is None:
            continue
        elif isinstance(value, (int, float, str)):
            args += [_flag(key), str(value)]
        else:
            raise UsageError(f"--spec {where}: '{key}' must be a number, a string or true/false")
    return args


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
    ...     print(t["name"], " ".join(t["args"]))
    rainbow-s0.05 --size 4x8 --size-spread 0.05 --table rainbow --wavelengths-nm 380:780:4
    rainbow-s0.2 --size 4x8 --size-spread 0.2 --table rainbow --wavelengths-nm 380:780:4
    """
    try:
        with open(spec_path, "rb") as f:
            spec = json.loads(f.read())
    except FileNotFoundError:
        raise UsageError(f"--spec {spec_path}: does not exist") from None
    except (ValueError, OSError) as e:
        raise UsageError(f"--spec {spec_path}: not a JSON file: {e}") from None
    if not isinstance(spec, dict) or not isinstance(spec.get("tables"), list) or not spec["tables"]:
        raise UsageError(f"--spec {spec_path}: expected an object with a non-empty list \"tables\"")
    defaults = spec.get("defaults", {})
    if not isinstance(defaults, dict):
        raise UsageError(f"--spec {spec_path}: \"defaults\" must be an object of options")
    out: List[Dict[str, Any]] = []
    names = set()
    for i, entry in enumerate(spec["tables"]):
        where = f"{spec_path} tables[{i}]"
        if not isinstance(entry, dict) or not isinstance(entry.get("name"), str):
            raise UsageError(f"--spec {where}: each table is an object with a \"name\"")
        sweep = entry.get("sweep", {})
        if not isinstance(sweep, dict) or any(not isinstance(v, list) or not v for v in sweep.values()):
            raise UsageError(f"--spec {where}: \"sweep\" maps options to non-empty lists of values")
        base = {**defaults, **{k: v for k, v in entry.items() if k not in ("name", "sweep")}}
        keys = list(sweep)
        for combo in itertools.product(*(sweep[k] for k in keys)):
            opts = {**base, **dict(zip(keys, combo))}
            fields = {k.replace("_", "-"): v for k, v in opts.items()}
            fields.update({k.replace("-", "_"): v for k, v in opts.items()})
            try:
                name = entry["name"].format(**fields)
            except (KeyError, IndexError, ValueError) as e:
                raise UsageError(f"--spec {where}: name '{entry['name']}': no option {e} to fill it") from None
            if not NAME.match(name) or name.startswith("hydrolux-manifest"):
                raise UsageError(f"--spec {where}: name '{name}': use letters, digits, '.', '_', '+', '-' "
                                 "(at most 100)")
            if name in names:
                raise UsageError(f"--spec {where}: two tables are named '{name}'")
            names.add(name)
            out.append({"name": name, "args": _flag_args(opts, where)})
    return out


# ---- on the workers -------------------------------------------------------------------------------

def make_table(out_dir: str, name: str, args: List[str], threads: int) -> Dict[str, Any]:
    """A task: one table by the hydrolux CLI; its error line if it fails.

    Example:

    >>> import tempfile
    >>> from hydrolux.batch import lee_atlas
    >>> folder = tempfile.mkdtemp()
    >>> rec = lee_atlas.make_table(folder, "bow", ["--size", "4x8", "--wavelengths-nm", "380:780:4"], 1)
    >>> sorted(rec["files"])   # bow.exr, bow.png, bow.json and their sizes
    ['.exr', '.json', '.png']
    >>> print(lee_atlas.make_table(folder, "bad", ["--size", "0x8"], 1)["error"])
    hydrolux lee: --size: '0x8' is not WxH ...
    """
    exr = os.path.join(out_dir, name + ".exr")
    cmd = [cli_path(), "lee", "-o", exr, "-q", "--threads", str(threads)] + args
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    rec: Dict[str, Any] = {"output": name, "args": args}
    if p.returncode != 0:
        lines = [line for line in p.stderr.strip().splitlines() if line.strip()]
        rec["error"] = lines[-1] if lines else f"hydrolux lee exited with {p.returncode}"
        return rec
    rec["files"] = {ext: os.path.getsize(os.path.join(out_dir, name + ext)) for ext in (".exr", ".png", ".json")}
    return rec


# ---- on the client --------------------------------------------------------------------------------

def _is_done(rec, out_dir: str, name: str, args: List[str]) -> bool:
    if not rec or "error" in rec or rec.get("args") != args:
        return False
    for ext, size in rec.get("files", {}).items():
        st = _common.file_stamp(os.path.join(out_dir, name + ext))
        if st is None or st["size"] != size:
            return False
    return len(rec.get("files", {})) == 3


def run(a: argparse.Namespace, after_result=None) -> int:
    """The job: every table of ``a.spec`` not done yet, one task each, on the cluster; 0 when all are
    in ``a.output_dir``, 1 when some failed (each said on stderr). ``after_result``: for the tests.

    Example (a local cluster of one worker; ``python3 -m hydrolux.batch lee-atlas`` does the same):

    >>> import json, os, tempfile
    >>> from hydrolux.batch import lee_atlas
    >>> folder = tempfile.mkdtemp()
    >>> spec = os.path.join(folder, "atlas.json")
    >>> with open(spec, "w") as f:
    ...     json.dump({"defaults": {"size": "4x8", "wavelengths-nm": "380:780:4"},
    ...                "tables": [{"name": "rainbow-s{size-spread}", "table": "rainbow",
    ...                            "sweep": {"size-spread": [0.05, 0.2]}}]}, f)
    >>> import argparse
    >>> p = argparse.ArgumentParser()
    >>> lee_atlas.add_arguments(p)
    >>> a = p.parse_args(["--spec", spec, "--output-dir", os.path.join(folder, "atlas")])
    >>> a.workers, a.threads_per_worker, a.scheduler, a.quiet = 1, None, None, True   # the cluster's options
    >>> lee_atlas.run(a)
    0
    >>> sorted(os.listdir(os.path.join(folder, "atlas")))
    ['hydrolux-manifest.jsonl', ..., 'rainbow-s0.05.png', 'rainbow-s0.2.exr', 'rainbow-s0.2.json', 'rainbow-s0.2.png']
    """
    lee_threads = {p["name"]: p for p in params()}["threads"]  # hydrolux lee --threads' range
    a.threads_per_table = _common.integer_flag("--threads-per-table", a.threads_per_table, int(lee_threads["lo"]),
                                               int(lee_threads["hi"]), extra=" (0: the cores / the local workers)")
    tables = expand(a.spec)
    out_dir = os.path.abspath(a.output_dir)
    if os.path.exists(out_dir) and not os.path.isdir(out_dir):
        raise UsageError(f"--output-dir {out_dir}: exists and is not a folder")
    # Member by member: no table file, manifest or lock that is (through a link) the spec, nor another output.
    _common.check_members([("--spec", os.path.abspath(a.spec))],
                          [("--output-dir", os.path.join(out_dir, n))
                           for n in [_common.MANIFEST, _common.LOCK]
                           + [t["name"] + e for t in tables for e in (".exr", ".png", ".json")]])
    # The local cluster's size within the cores and the memory, then the cluster: an unreachable scheduler
    # leaves no output folder behind.
    a.workers, a.threads_per_worker = _common.local_cluster_size(a.workers, a.threads_per_worker, 0, a.scheduler)
    client, cluster = _common.open_client(a.scheduler, a.workers, a.threads_per_worker, a.quiet)
    manifest = None
    failed: List[str] = []
    try:
        _common.make_folder("--output-dir", out_dir)
        manifest = _common.Manifest(out_dir, "lee-atlas", {})
        todo = [t for t in tables if not _is_done(manifest.records.get(t["name"]), out_dir, t["name"], t["args"])]
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
                failed.append(rec["output"])
                progress.message(f"batch lee-atlas: {rec['output']}: {rec['error']}")
            else:
                manifest.add(rec)

        _common.run_tasks(client, [(out_dir, t["name"], t["args"], threads) for t in todo], make_table, on_result,
                          progress, lambda r: 0 if isinstance(r, Exception) or "error" in r else 1, after_result)
        progress.finish()
    finally:
        _common.close_client(client, cluster)
        if manifest is not None:
            _common.remove_stale_temporaries(out_dir, [t["name"] + e for t in tables for e in (".exr", ".png", ".json")])
            manifest.close()
    if not a.quiet:
        print(f"batch lee-atlas: {len(tables) - len(failed)} of {len(tables)} tables in {out_dir}"
              + (f"; {len(failed)} failed: {', '.join(failed[:5])}" if failed else ""), file=sys.stderr)
    return 1 if failed else 0
