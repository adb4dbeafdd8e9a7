"""hydrolux.batch against hostile inputs, third round (issue 37): input files that never end or block
(/dev/zero, a FIFO) or are too large, specs that ask for a billion tables or a gigabyte name, NetCDF
atlases whose tables do not fit one grid or are not the files the batch wrote (replaced, relabelled,
corrupt, declaring a huge dimension), tampered atlas indexes, paths that are not UTF-8, and a folder of
frames of two sizes. Every refusal is one line (a ValueError for open_atlas; exit code 2 for the
batch), never a traceback, a TypeError/KeyError or a silent mislabel."""
import argparse
import hashlib
import json
import os
import resource
import shutil
import subprocess
import sys

import numpy as np
import pytest

import hydrolux as h
from hydrolux.batch import _common, lee_atlas
from hydrolux.batch.__main__ import main


def batch(*args, memory_bytes=None):
    """python3 -m hydrolux.batch, as a user runs it (arguments may be bytes: paths that are not UTF-8);
    ``memory_bytes``: an address-space limit, so that a job that reads without end fails fast."""
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (memory_bytes, memory_bytes))

    return subprocess.run([sys.executable, "-m", "hydrolux.batch",
                           *(a if isinstance(a, bytes) else str(a) for a in args)],
                          capture_output=True, text=True, errors="backslashreplace",
                          preexec_fn=limit if memory_bytes else None)


def one_line(err):
    assert "Traceback" not in err, err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1, err
    return lines[0]


def write_spec(path, spec):
    path.write_text(json.dumps(spec))
    return path


def atlas_args(spec, out, fmt="netcdf"):
    return argparse.Namespace(spec=str(spec), output_dir=str(out), threads_per_table=1, workers=1,
                              threads_per_worker=None, scheduler=None, quiet=True, format=fmt)


# ---- 1. every input file gets the CLI's checks -----------------------------------------------------

def test_a_spec_that_never_ends_or_blocks_is_refused_in_the_cli_words(tmp_path, capfd):
    # /dev/zero used to be read until the memory was gone (here: an address-space limit, so that the old
    # code fails in a second instead of taking the machine).
    p = batch("lee-atlas", "--spec", "/dev/zero", "--output-dir", tmp_path / "o", memory_bytes=4 << 30)
    assert p.returncode == 2, p.stderr
    assert one_line(p.stderr) == ("hydrolux.batch lee-atlas: --spec /dev/zero: a character device, not a regular "
                                  "file; give a file")
    # A FIFO used to block the open for ever; a folder; a missing file.
    fifo = tmp_path / "spec.fifo"
    os.mkfifo(fifo)
    for spec, text in ((fifo, "a named pipe (FIFO), not a regular file; give a file"),
                       (tmp_path, "a folder, not a regular file; give a file"),
                       (tmp_path / "none.json", "no such file")):
        assert main(["lee-atlas", "--spec", str(spec), "--output-dir", str(tmp_path / "o"), "-q"]) == 2
        assert one_line(capfd.readouterr().err) == f"hydrolux.batch lee-atlas: --spec {spec}: {text}"
    assert not (tmp_path / "o").exists()


def test_a_spec_over_the_size_limit_is_refused_with_the_limit(tmp_path, capfd):
    limit = 4 << 20  # lee_atlas.SPEC_MAX_BYTES
    big = tmp_path / "big.json"
    with open(big, "wb") as f:  # sparse: nothing is written, and nothing may be read
        f.truncate(limit + 1)
    assert main(["lee-atlas", "--spec", str(big), "--output-dir", str(tmp_path / "o"), "-q"]) == 2
    assert one_line(capfd.readouterr().err) == (
        f"hydrolux.batch lee-atlas: --spec {big}: the file has {limit + 1} bytes, more than the limit of {limit} bytes")
    assert lee_atlas.SPEC_MAX_BYTES == limit


def test_a_spec_nested_too_deep_is_one_line(tmp_path, capfd):
    spec = tmp_path / "deep.json"
    spec.write_text("[" * 100000 + "]" * 100000)
    assert main(["lee-atlas", "--spec", str(spec), "--output-dir", str(tmp_path / "o"), "-q"]) == 2
    assert one_line(capfd.readouterr().err) == \
        f"hydrolux.batch lee-atlas: --spec {spec}: not a JSON file: nested too deep"


def test_a_manifest_over_the_size_limit_is_refused_not_read(tmp_path):
    limit = 256 << 20  # _common.MANIFEST_MAX_BYTES
    with open(tmp_path / _common.MANIFEST, "wb") as f:
        f.truncate(limit + 1)
    with pytest.raises(_common.UsageError) as e:
        _common.Manifest(str(tmp_path), "rain", {"p": 1})
    assert str(e.value) == (f"--output-dir {tmp_path / _common.MANIFEST}: the file has {limit + 1} bytes, more than "
                            f"the limit of {limit} bytes")
    assert os.path.getsize(tmp_path / _common.MANIFEST) == limit + 1  # left as it was
    assert _common.MANIFEST_MAX_BYTES == limit


# ---- 2. a spec's size: the count of tables, the length of what a message quotes -------------------

def test_the_count_of_tables_is_limited(tmp_path):
    limit = 10_000  # lee_atlas.MAX_TABLES
    spec = write_spec(tmp_path / "a.json", {"tables": [
        {"name": "a{seed}", "sweep": {"seed": list(range(limit))}},
        {"name": "b"}]})
    with pytest.raises(_common.UsageError) as e:
        lee_atlas.expand(str(spec))
    assert str(e.value) == (f"--spec {spec}: makes {limit + 1} tables (tables[0] alone {limit}: the product of its "
                            f"sweeps' lengths), more than the limit of {limit} in one atlas")
    # 1.6e9 tables from a spec of a few kilobytes: refused before any is made.
    spec = write_spec(tmp_path / "b.json", {"tables": [
        {"name": "t{seed}-{sampling}-{sun-disk-deg}", "sweep": {"seed": list(range(1000)),
                                                                 "sampling": list(range(1000)),
                                                                 "sun-disk-deg": list(range(1600))}}]})
    with pytest.raises(_common.UsageError, match="makes 1600000000 tables"):
        lee_atlas.expand(str(spec))
    assert lee_atlas.MAX_TABLES == 10_000


@pytest.mark.parametrize("entry,text", [
    ({"name": "x" * 3_000_000}, "name '" + "x" * 60 + "... (3000000 characters)'"),
    ({"name": "t{seed:>100000000}", "seed": 1}, "the format '>100000000' of {seed} makes a name longer than 100"),
    ({"name": "t{seed}", "seed": "y" * 1_000_000}, "{seed} is 'yyyyyyyy"),
    ({"name": "t", "z" * 1_000_000: [1]}, "'zzzzzzzz"),
    ({"name": "t{" + "q" * 1_000_000 + "}"}, "no option 'qqqqqqqq"),
])
def test_values_quoted_in_errors_are_cut_short(tmp_path, entry, text):
    spec = write_spec(tmp_path / "a.json", {"tables": [entry]})
    with pytest.raises(_common.UsageError) as e:
        lee_atlas.expand(str(spec))
    message = str(e.value)
    assert text in message and len(message) < 400 + len(str(spec)), message[:500]
    assert "\n" not in message


def test_reserved_names_are_said_to_be_reserved(tmp_path):
    for name in ("hydrolux-manifest", "hydrolux-atlas"):
        spec = write_spec(tmp_path / "a.json", {"tables": [{"name": name}]})
        with pytest.raises(_common.UsageError) as e:
            lee_atlas.expand(str(spec))
        assert str(e.value).startswith(f"--spec {spec} tables[0]: name '{name}': reserved for the batch's own "
                                       "files"), str(e.value)
        assert "use letters" not in str(e.value)
    spec = write_spec(tmp_path / "a.json", {"tables": [{"name": "bad name"}]})
    with pytest.raises(_common.UsageError, match="name 'bad name': use letters, digits"):
        lee_atlas.expand(str(spec))


# ---- 3. open_atlas: one grid, the files the batch wrote, the labels they state ---------------------

SMALL = {"size": "4x8", "wavelengths-nm": "380:780:4", "sampling": 0.25}
ENTRY = "bow-t{temperature-c}"


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    """A NetCDF atlas with one good entry (temperature) and one entry per sweep that changes the grid."""
    d = tmp_path_factory.mktemp("atlas")
    spec = write_spec(d / "atlas.json", {"defaults": SMALL, "tables": [
        {"name": "bow-t{temperature-c}", "table": "rainbow", "radius-um": "100:400",
         "sweep": {"temperature-c": [10, 20, 30]}},
        {"name": "bow-r{radius-um}", "table": "rainbow", "size": "1x8", "sweep": {"radius-um": [300, 500]}},
        {"name": "bow-a{axis}", "table": "rainbow", "radius-um": "100:400", "sweep": {"axis": ["angle", "cos"]}},
        {"name": "kind-{table}", "radius-um": "5:20", "sweep": {"table": ["corona", "glory"]}},
        {"name": "bow-z{size}", "table": "rainbow", "radius-um": "100:400", "sweep": {"size": ["4x8", "4x16"]}},
        {"name": "bow-st{stokes}", "table": "rainbow", "radius-um": "100:400", "sweep": {"stokes": [False, True]}}]})
    out = d / "atlas"
    assert lee_atlas.run(atlas_args(spec, out)) == 0
    return spec, out


@pytest.fixture
def copy(atlas, tmp_path):
    """A copy of the atlas to tamper with."""
    out = tmp_path / "atlas"
    shutil.copytree(atlas[1], out)
    return out


def test_an_entry_of_one_grid_opens(atlas):
    ds = lee_atlas.open_atlas(str(atlas[1]), "bow-t{temperature-c}")
    assert ds.rgb.dims[0] == "temperature_c" and list(ds.temperature_c.values) == [10, 20, 30]
    assert not np.isnan(ds.rgb.values).any()
    ds.close()


@pytest.mark.parametrize("entry,flag,coordinate", [
    ("bow-r{radius-um}", "--radius-um", "coordinate 'radius' differs"),
    ("bow-a{axis}", "--axis", "coordinate 'scattering_angle' differs"),
    ("kind-{table}", "--table", "coordinate 'scattering_angle' differs"),
    ("bow-z{size}", "--size", "dimension 'scattering_angle' is 8 long in 'bow-z4x8' and 16 in 'bow-z4x16'"),
    ("bow-st{stokes}", "--stokes", "variable 'dolp' is in 'bow-stTrue' and not in 'bow-stFalse'"),
])
def test_a_sweep_that_changes_the_grid_is_refused_not_joined_into_nan(atlas, entry, flag, coordinate):
    # These came back 25-75% NaN from xarray's outer join, without an error.
    with pytest.raises(ValueError) as e:
        lee_atlas.open_atlas(str(atlas[1]), entry)
    message = str(e.value)
    assert message.startswith(f"entry '{entry}': the sweep of {flag} changes the tables' grid: {coordinate}"), message
    assert "\n" not in message


def manifest_lines(out):
    return [json.loads(line) for line in (out / _common.MANIFEST).read_text().splitlines()]


def record_file(out, name, data=None):
    """Makes the manifest agree with the table file as it is now (a hand-edited atlas): its size and hash."""
    path = out / (name + ".nc")
    if data is not None:
        path.write_bytes(data)
    lines = manifest_lines(out)
    for rec in lines[1:]:
        if rec.get("output") == name:
            rec["files"][".nc"] = path.stat().st_size
            rec.setdefault("sha256", {})[".nc"] = hashlib.sha256(path.read_bytes()).hexdigest()
    (out / _common.MANIFEST).write_text("".join(json.dumps(r) + "\n" for r in lines))


def test_a_table_replaced_by_another_of_the_same_size_is_refused_and_redone(atlas, copy):
    path = copy / "bow-t20.nc"
    data = path.read_bytes()
    # Another file of the same byte size: the history attribute's text changed, a valid NetCDF file still.
    k = data.index(b"hydrolux")
    tampered = data[:k] + b"HYDROLUX" + data[k + 8:]
    path.write_bytes(tampered)
    with pytest.raises(ValueError) as e:
        lee_atlas.open_atlas(str(copy), ENTRY)
    assert str(e.value) == (f"entry 'bow-t{{temperature-c}}': table 'bow-t20' ({path}): not the file the batch "
                            "wrote (its size or SHA-256 differs from the manifest's): run the batch again to "
                            "remake it")
    # The batch knows it too: a re-run remakes that table alone (it used to report every table done).
    done = []
    assert lee_atlas.run(atlas_args(atlas[0], copy), after_result=lambda n, c: done.append(n)) == 0
    assert len(done) == 1 and path.read_bytes() != tampered
    lee_atlas.open_atlas(str(copy), "bow-t{temperature-c}").close()


def test_a_table_whose_attributes_are_not_its_label_is_refused(copy):
    import xarray as xr
    name = "bow-t10"
    with xr.open_dataset(copy / (name + ".nc")) as ds:
        ds.load()
    assert float(ds.attrs["temperature_c"]) == 10
    ds.attrs["temperature_c"] = 90.0
    ds.to_netcdf(copy / "other.nc")
    record_file(copy, name, (copy / "other.nc").read_bytes())  # the manifest agrees: only the file can tell
    with pytest.raises(ValueError) as e:
        lee_atlas.open_atlas(str(copy), ENTRY)
    assert str(e.value) == (f"entry 'bow-t{{temperature-c}}': table '{name}' ({copy / (name + '.nc')}): states "
                            "temperature_c = 90.0 where its label in the sweep says --temperature-c 10: not the "
                            "table of its label; run the batch again")


def edit_index(out, edit):
    index = json.loads((out / lee_atlas.INDEX).read_text())
    edit(index)
    (out / lee_atlas.INDEX).write_text(json.dumps(index))


def entry_of(index, pattern="bow-t{temperature-c}"):
    return next(e for e in index["entries"] if e["entry"] == pattern)


def swap(index):
    t = entry_of(index)["tables"]
    t[0], t[2] = t[2], t[0]


def relabel(index):
    entry_of(index)["sweeps"]["temperature-c"] = [30, 20, 10]


@pytest.mark.parametrize("edit,text", [
    (swap, "table 'bow-t30' ({out}/bow-t30.nc): the index places it at --temperature-c 10, the manifest records it "
           "as --temperature-c 30 of entry 'bow-t{{temperature-c}}'"),
    (relabel, "table 'bow-t10' ({out}/bow-t10.nc): the index places it at --temperature-c 30"),
    (lambda i: entry_of(i)["sweeps"].update({"temperature-c": "ab"}),
     '"sweeps" "temperature-c" is "ab", not a non-empty list of numbers, strings or true/false'),
    (lambda i: entry_of(i)["sweeps"].update({"temperature-c": [[1], [2], [3]]}), 'is [[1], [2], [3]], not a non-empty'),
    (lambda i: entry_of(i).update({"tables": "bow-t10"}), '"tables" is "bow-t10", not a list of table names'),
    (lambda i: entry_of(i).update({"tables": ["bow-t10", 5, "bow-t30"]}), '"tables": 5 is not a table name'),
    (lambda i: entry_of(i).update({"tables": ["bow-t10", "bow-t20"]}),
     '"tables" holds 2 names where its sweeps make 3'),
    (lambda i: entry_of(i).pop("sweeps"), '"sweeps" is null, not an object of option -> values'),
    (lambda i: entry_of(i).pop("entry"), '"entry" is null, not a name pattern'),
    (lambda i: i.pop("entries"), '"entries" is not a non-empty list'),
    (lambda i: i.update({"entries": [5]}), "entries[0] is not an object"),
    (lambda i: i.update({"files": ["netcdf"]}), '"files" is ["netcdf"], not one of exr, netcdf'),
    (lambda i: i.update({"format_version": "2"}), '"format_version" is "2", not 2'),
    (lambda i: i.update({"format_version": 1}), "written by an older hydrolux.batch (format_version 1"),
])
def test_a_tampered_index_is_a_value_error_naming_the_problem(copy, edit, text):
    edit_index(copy, edit)
    with pytest.raises(ValueError) as e:  # never TypeError or KeyError, never a mislabelled Dataset
        lee_atlas.open_atlas(str(copy), "bow-t{temperature-c}")
    assert type(e.value) is ValueError
    assert text.format(out=copy) in str(e.value), str(e.value)
    assert "\n" not in str(e.value)


def test_an_index_that_is_not_json_or_not_a_file_is_a_value_error(copy):
    (copy / lee_atlas.INDEX).write_text("[" * 100000)
    with pytest.raises(ValueError, match="not an atlas index: not JSON"):
        lee_atlas.open_atlas(str(copy), ENTRY)
    (copy / lee_atlas.INDEX).unlink()
    os.mkfifo(copy / lee_atlas.INDEX)
    with pytest.raises(ValueError, match=r"a named pipe \(FIFO\), not a regular file"):
        lee_atlas.open_atlas(str(copy), ENTRY)


@pytest.mark.parametrize("content", [b"", b"this is text, not NetCDF\n", "truncated"])
def test_a_corrupt_table_file_is_one_line_naming_the_table_and_its_file(copy, content):
    name = "bow-t20"
    path = copy / (name + ".nc")
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2] if content == "truncated" else content)
    with pytest.raises(ValueError) as e:  # the manifest says it is not the file written
        lee_atlas.open_atlas(str(copy), ENTRY)
    assert str(e.value).startswith(f"entry 'bow-t{{temperature-c}}': table '{name}' ({path}): not the file the batch "
                                   "wrote")
    record_file(copy, name)  # and where the manifest agrees, the file itself says it
    with pytest.raises(ValueError) as e:
        lee_atlas.open_atlas(str(copy), ENTRY)
    message = str(e.value)
    assert message.startswith(f"entry 'bow-t{{temperature-c}}': table '{name}' ({path}): cannot be read as NetCDF: "), \
        message
    assert "\n" not in message


def test_a_table_declaring_a_huge_dimension_is_refused_before_loading(copy):
    import netCDF4
    name = "bow-t20"
    path = copy / (name + ".nc")
    path.unlink()
    with netCDF4.Dataset(path, "w") as nc:  # a 2^31 - 1 long coordinate, never written: a file of a few kB
        nc.createDimension("scattering_angle", 2**31 - 1)
        nc.createVariable("scattering_angle", "f8", ("scattering_angle",))
        nc.temperature_c = 20.0
    assert path.stat().st_size < 100000
    record_file(copy, name)
    with pytest.raises(ValueError) as e:
        lee_atlas.open_atlas(str(copy), ENTRY)
    assert str(e.value).startswith(
        f"entry 'bow-t{{temperature-c}}': table '{name}' ({path}): declares {8 * (2**31 - 1)} bytes of values "
        "(variable 'scattering_angle': scattering_angle 2147483647) in a file of"), str(e.value)


def test_a_manifest_that_is_not_a_lee_atlas_one_is_a_value_error(copy):
    (copy / _common.MANIFEST).write_text('{"manifest": "hydrolux.batch", "job": "rain"}\n')
    with pytest.raises(ValueError, match="not the manifest of a hydrolux.batch lee-atlas run"):
        lee_atlas.open_atlas(str(copy), ENTRY)
    (copy / _common.MANIFEST).write_text('{"manifest": "hydrolux.batch", "job": "lee-atlas", "params": {}}\n'
                                         '{"output": ["x"]}\n{"output": "bow-t10", "files": {".nc": "big"}}\n')
    with pytest.raises(ValueError, match="3 of its 3 tables are not made"):
        lee_atlas.open_atlas(str(copy), ENTRY)


# ---- 4. paths that are not UTF-8 ------------------------------------------------------------------

@pytest.mark.parametrize("job,extra", [("lens-drops", ["--seed", "3"]), ("rain", ["--seed", "3"])])
def test_frame_folders_that_are_not_utf8_are_handled_as_the_cli_handles_them(tmp_path, cli, capfd, job, extra):
    # Folders named with byte 0xff (Python holds it as a surrogate escape, as in sys.argv): rain, fog and
    # lens drops share one planner (_folder.py).
    root = os.fsencode(tmp_path)
    src, out, masks = root + b"/fr\xffames", root + b"/o\xfeut", root + b"/m\xfd"
    os.mkdir(src)
    names = [b"f0.png", b"f\xff1.png"]  # a frame's own name too (the library's plan reaches Python escaped)
    for k, n in enumerate(names):
        h.write_image(src + b"/" + n, h.builtin_scene(48, 32, pitch_deg=k))
    argv = [job, "--input-dir", os.fsdecode(src), "--output-dir", os.fsdecode(out), "--mask-dir", os.fsdecode(masks),
            "--workers", "1", "-q", *extra]
    assert main(argv) == 0  # was 1: "internal error: TypeError: check_files(): incompatible function arguments ..."
    assert capfd.readouterr().err == ""
    cli(job, "--input-dir", os.fsdecode(src), "--output-dir", tmp_path / "cli", "--mask-dir", tmp_path / "cli-m",
        "-q", *extra)
    cli_out, cli_masks = os.fsencode(tmp_path / "cli"), os.fsencode(tmp_path / "cli-m")
    for n in names:
        assert open(out + b"/" + n, "rb").read() == open(cli_out + b"/" + n, "rb").read(), n
        assert open(masks + b"/" + n, "rb").read() == open(cli_masks + b"/" + n, "rb").read(), n


def test_a_lee_atlas_whose_paths_are_not_utf8_is_made_and_opened(tmp_path, capfd):
    root = os.fsencode(tmp_path)
    spec = root + b"/sp\xffec.json"
    with open(spec, "w") as f:
        json.dump({"defaults": SMALL, "tables": [{"name": "bow", "table": "rainbow", "radius-um": "100:400"}]}, f)
    atlas = root + b"/at\xfflas"
    assert main(["lee-atlas", "--spec", os.fsdecode(spec), "--output-dir", os.fsdecode(atlas), "--workers", "1",
                 "--format", "netcdf", "-q"]) == 0, capfd.readouterr().err
    assert sorted(os.listdir(atlas)) == [b"bow.nc", b"hydrolux-atlas.json", b"hydrolux-manifest.jsonl",
                                         b"hydrolux-manifest.lock"]
    ds = lee_atlas.open_atlas(os.fsdecode(atlas))  # the NetCDF library takes UTF-8 paths only: opened by its fd
    assert ds.rgb.shape == (8, 4, 3) and float(ds.rgb.max()) > 0
    ds.close()
    # An error names the file as the CLI does (its bytes escaped), on one line, exit 2.
    p = batch("lee-atlas", "--spec", root + b"/n\xffone.json", "--output-dir", atlas, "-q")
    assert p.returncode == 2
    assert one_line(p.stderr) == f"hydrolux.batch lee-atlas: --spec {tmp_path}/n\\xffone.json: no such file"


# ---- 5. batch lens-drops does what hydrolux lens-drops does with frames of two sizes -------------

def test_lens_drops_over_frames_of_two_sizes_gives_the_cli_bytes(tmp_path, cli):
    src = tmp_path / "frames"
    src.mkdir()
    for k, (w, hh) in enumerate([(64, 48), (80, 40), (64, 48)]):
        h.write_image(str(src / f"f{k}.png"), h.builtin_scene(w, hh, pitch_deg=k))
    cli("lens-drops", "--input-dir", src, "--output-dir", tmp_path / "cli", "--mask-dir", tmp_path / "cli-m",
        "--seed", 5, "-q")
    out, masks = tmp_path / "o", tmp_path / "m"
    assert main(["lens-drops", "--input-dir", str(src), "--output-dir", str(out), "--mask-dir", str(masks),
                 "--seed", "5", "--chunk-frames", "2", "--workers", "1", "-q"]) == 0  # was 1: "f1.png: is 80x40"
    for n in ("f0.png", "f1.png", "f2.png"):
        assert (out / n).read_bytes() == (tmp_path / "cli" / n).read_bytes(), n
        assert (masks / n).read_bytes() == (tmp_path / "cli-m" / n).read_bytes(), n
    assert h.read_image(str(out / "f1.png")).shape[:2] == (40, 80)
