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
(``xarray.open_mfdataset``, Dask-backed) with a dimension per swept option.
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
from ._common import UsageError

# The atlas's layout for open_atlas: its entries, their sweeps and tables (written by each run).
INDEX = "hydrolux-atlas.json"
# Each --format's files of a table, by extension.
FORMATS = {"exr": (".exr", ".png", ".json"), "netcdf": (".nc",)}
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
    ...     print(t["name"], " ".join(t["args"]), t["sweep"])
    rainbow-s0.05 --size 4x8 --size-spread 0.05 --table rainbow --wavelengths-nm 380:780:4 {'size-spread': 0.05}
    rainbow-s0.2 --size 4x8 --size-spread 0.2 --table rainbow --wavelengths-nm 380:780:4 {'size-spread': 0.2}

    Each table also names its ``entry`` (the spec entry's name pattern) and that entry's whole
    ``sweeps`` (option -> values), for :func:`open_atlas`.
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
    hydrolux lee: --size: '0x8' is not WxH ...
    """
    exts = FORMATS[fmt]
    target = os.path.join(out_dir, name + exts[0])
    cmd = [cli_path(), "lee", "-o", target, "-q", "--threads", str(threads)] + args
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    rec: Dict[str, Any] = {"output": name, "args": args}
    if p.returncode != 0:
        lines = [line for line in p.stderr.strip().splitlines() if line.strip()]
        rec["error"] = lines[-1] if lines else f"hydrolux lee exited with {p.returncode}"
        return rec
    rec["files"] = {ext: os.path.getsize(os.path.join(out_dir, name + ext)) for ext in exts}
    return rec


# ---- on the client --------------------------------------------------------------------------------

def _is_done(rec, out_dir: str, name: str, args: List[str], exts: tuple) -> bool:
    if not rec or "error" in rec or rec.get("args") != args:
        return False
    for ext, size in rec.get("files", {}).items():
        st = _common.file_stamp(os.path.join(out_dir, name + ext))
        if st is None or st["size"] != size:
            return False
    return sorted(rec.get("files", {})) == sorted(exts)


def _write_index(out_dir: str, tables: List[Dict[str, Any]], fmt: str) -> None:
    """hydrolux-atlas.json: each spec entry (its name pattern), its sweeps (option -> values, the spec's
    order) and its tables' names in the order of the sweeps' product, written atomically."""
    entries: Dict[str, Dict[str, Any]] = {}
    for t in tables:
        e = entries.setdefault(t["entry"], {"entry": t["entry"], "sweeps": t["sweeps"], "tables": []})
        e["tables"].append(t["name"])
    index = {"format": "hydrolux-lee-atlas", "format_version": 1, "files": fmt, "entries": list(entries.values())}
    _common.native("_core").write_file(os.path.join(out_dir, INDEX), (json.dumps(index, indent=1) + "\n").encode(),
                                       "--output-dir")


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
    ['hydrolux-atlas.json', 'hydrolux-manifest.jsonl', ..., 'rainbow-s0.2.exr', 'rainbow-s0.2.json', 'rainbow-s0.2.png']
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
    try:
        _common.make_folder("--output-dir", out_dir)
        manifest = _common.Manifest(out_dir, "lee-atlas", {} if fmt == "exr" else {"format": fmt})
        todo = [t for t in tables
                if not _is_done(manifest.records.get(t["name"]), out_dir, t["name"], t["args"], exts)]
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
        print(f"batch lee-atlas: {len(tables) - len(failed)} of {len(tables)} tables in {out_dir}"
              + (f"; {len(failed)} failed: {', '.join(failed[:5])}" if failed else ""), file=sys.stderr)
    return 1 if failed else 0


# ---- reading an atlas back ------------------------------------------------------------------------

def open_atlas(output_dir: str, entry: Optional[str] = None):
    """A NetCDF atlas (``--format netcdf``) as one :class:`xarray.Dataset`: the tables of one spec entry
    opened together with ``xarray.open_mfdataset`` (Dask-backed: values are read when computed), with a
    dimension per swept option (its name with underscores, coordinates the swept values, units from the
    option's declaration). ``entry``: the entry's name pattern, e.g. "rainbow-s{size-spread}"; may be
    left out when the atlas has one entry. ValueError naming what is wrong: not a NetCDF atlas, an entry
    that is not there, or tables of the sweep not (yet) made.

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
    try:
        with open(os.path.join(out_dir, INDEX), "rb") as f:
            index = json.loads(f.read())
        index_entries = index["entries"]
    except FileNotFoundError:
        raise ValueError(f"{out_dir}: no {INDEX} (not an atlas written by hydrolux.batch lee-atlas)") from None
    except (ValueError, KeyError, TypeError) as e:
        raise ValueError(f"{out_dir}: {INDEX} is not an atlas index ({e})") from None
    if index.get("files") != "netcdf":
        raise ValueError(f"{out_dir}: the atlas's tables are {index.get('files')} files; open_atlas reads a NetCDF "
                         "atlas (make it with --format netcdf)")
    entries = [e["entry"] for e in index_entries]
    if entry is None:
        if len(entries) != 1:
            raise ValueError(f"entry: the atlas has {len(entries)} entries; name one of: {', '.join(entries)}")
        entry = entries[0]
    if entry not in entries:
        raise ValueError(f"entry '{entry}': not in the atlas; its entries: {', '.join(entries)}")
    chosen = index_entries[entries.index(entry)]
    sweeps: Dict[str, list] = chosen["sweeps"]
    keys = list(sweeps)
    # The tables the manifest records as made, with their files' sizes still as recorded.
    done = set()
    try:
        with open(os.path.join(out_dir, _common.MANIFEST), "rb") as f:
            for line in f.read().split(b"\n")[1:]:
                try:
                    rec = json.loads(line)
                except ValueError:
                    continue  # a torn last line
                if isinstance(rec, dict) and "error" not in rec and ".nc" in rec.get("files", {}):
                    st = _common.file_stamp(os.path.join(out_dir, rec["output"] + ".nc"))
                    if st is not None and st["size"] == rec["files"][".nc"]:
                        done.add(rec["output"])
    except FileNotFoundError:
        pass
    files = [os.path.join(out_dir, name + ".nc") for name in chosen["tables"]]
    missing = [name for name in chosen["tables"] if name not in done]
    if missing:
        raise ValueError(f"entry '{entry}': {len(missing)} of its {len(files)} tables are not made "
                         f"({', '.join(missing[:3])}{', ...' if len(missing) > 3 else ''}): run the batch again")
    if not keys:
        return xr.open_dataset(files[0])
    # The files as a nested list, one level per swept option (the spec's order), for a nested combine.
    shape = [len(sweeps[k]) for k in keys]

    def nest(flat: list, dims: List[int]) -> list:
        if len(dims) == 1:
            return flat
        step = len(flat) // dims[0]
        return [nest(flat[i * step:(i + 1) * step], dims[1:]) for i in range(dims[0])]

    dims = [k.replace("-", "_") for k in keys]
    ds = xr.open_mfdataset(nest(files, shape), combine="nested", concat_dim=dims, combine_attrs="drop_conflicts")
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
