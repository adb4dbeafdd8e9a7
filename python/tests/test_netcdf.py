"""NetCDF files and xarray Datasets (issue 28): ``hydrolux lee -o t.nc`` and ``hydrolux mie -o p.nc``
write what ``to_xarray()`` builds in memory (one description in the library), xarray and ncdump read
them, CF attributes are there, and bad input is refused with one line and no file."""
import json
import math
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import hydrolux

xr = pytest.importorskip("xarray")
CLI = os.environ.get("HYDROLUX_CLI") or hydrolux._cli.cli_path()


def run(*args, cwd=None):
    return subprocess.run([CLI, *args], capture_output=True, text=True, cwd=cwd)


def without_history(ds):
    ds = ds.copy()
    ds.attrs = {k: v for k, v in ds.attrs.items() if k != "history"}
    return ds


def test_lee_file_is_the_tables_xarray_form(tmp_path):
    path = tmp_path / "corona.nc"
    p = run("lee", "--table", "corona", "--size", "6x10", "--wavelengths-nm", "380:780:6", "--stokes", "-q", "-o",
            str(path))
    assert p.returncode == 0, p.stderr
    assert sorted(os.listdir(tmp_path)) == ["corona.nc"]  # one file: no PNG or JSON beside it
    t = hydrolux.lee(table="corona", size=(6, 10), wavelengths_nm=(380, 780), wavelengths=6, stokes=True)
    with xr.open_dataset(path) as f:
        on_disk = f.load()
    memory = t.to_xarray()
    xr.testing.assert_identical(without_history(on_disk), without_history(memory))
    # The values are the table's, and the CF attributes are there.
    np.testing.assert_array_equal(on_disk.rgb.values, t.rgb)
    np.testing.assert_array_equal(on_disk.display.values, t.display)
    np.testing.assert_array_equal(on_disk.dolp.values, t.dolp)
    np.testing.assert_array_equal(on_disk.radius.values, t.radius_um)
    assert on_disk.attrs["Conventions"] == "CF-1.8"
    assert on_disk.rgb.attrs["units"] == "sr-1" and on_disk.scattering_angle.attrs["units"] == "degree"
    assert on_disk.wavelength.attrs["standard_name"] == "radiation_wavelength"
    assert all("long_name" in on_disk[v].attrs for v in on_disk.variables)
    assert on_disk.attrs["history"].endswith(f"hydrolux lee --table corona --size 6x10 --wavelengths-nm 380:780:6 "
                                             f"--stokes -q -o {path}")
    assert f"hydrolux {hydrolux.__version__}" in on_disk.attrs["history"]
    assert memory.attrs["history"].endswith("hydrolux.lee(table='corona', size=(6, 10), wavelengths=6, stokes=True)")
    # ncdump reads it too.
    if shutil.which("ncdump"):
        d = subprocess.run(["ncdump", "-h", str(path)], capture_output=True, text=True)
        assert d.returncode == 0 and ':Conventions = "CF-1.8"' in d.stdout and "double rgb(scattering_angle, radius, " \
            "channel)" in d.stdout
    # xarray's own writer round-trips the in-memory form.
    again = tmp_path / "again.nc"
    memory.to_netcdf(again)
    with xr.open_dataset(again) as f:
        xr.testing.assert_identical(f.load(), memory)


def test_mie_file_phase_function_integrates_to_one(tmp_path):
    path = tmp_path / "phase.nc"
    p = run("mie", "--radius-um", "2", "--wavelength-nm", "550", "--angles-deg", "0:180:18001", "--mueller", "-q",
            "-o", str(path))
    assert p.returncode == 0, p.stderr
    with xr.open_dataset(path) as f:
        ds = f.load()
    assert ds.attrs["wavelength_nm"] == 550 and ds.attrs["medium"] == "water"
    assert ds.radius.values.tolist() == [2.0] and ds.radius.attrs["units"] == "um"
    # The same numbers as the Python call with the same m and x.
    m = complex(ds.attrs["m_real"], ds.attrs["m_imag"])
    r = hydrolux.mie(m, ds.size_parameter.values, angles_deg=ds.scattering_angle.values, mueller=True)
    mem = r.to_xarray()
    for v in ("qext", "qsca", "g", "s1_real", "s2_imag", "s11", "s34", "phase_function"):
        np.testing.assert_allclose(ds[v].values, mem[v].values, rtol=1e-12, atol=0, err_msg=v)
    # Integral over the sphere by Simpson's rule on 18,001 angles (x = 22.9: the forward peak, ~1/x rad
    # wide, spans ~250 samples): 1 within 1e-6.
    theta = np.radians(ds.scattering_angle.values)
    f = ds.phase_function.values[0] * np.sin(theta) * 2 * math.pi
    h = theta[1] - theta[0]
    w = np.ones_like(f)
    w[1:-1:2], w[2:-1:2] = 4, 2
    assert abs(h / 3 * np.sum(w * f) - 1) < 1e-6
    assert ds.phase_function.attrs["units"] == "sr-1"


def test_the_labelled_forms_of_phase_bulk_optics_and_size_distributions():
    p = hydrolux.phase(10, 550, size_distribution="gamma:0.1", nodes=16, angles_deg="0:180:7", mueller=True)
    ds = p.to_xarray()
    np.testing.assert_array_equal(ds.phase.values, p.phase)
    assert ds.quadrature_radius.size == 16 and ds.attrs["theory"] == "mie"
    assert ds.attrs["history"].endswith("hydrolux.phase(radius_um=10, wavelength_nm=550, size_distribution="
                                        "'gamma:0.1', angles_deg='0:180:7', nodes=16, mueller=True)")
    assert "estimated_error" not in ds.phase.attrs and "size_average_tolerance" not in ds.attrs  # a fixed count
    # A size average that chose its radii carries its estimates (docs/mie.md, "Size averages").
    auto = hydrolux.phase(2, 550, size_distribution="gamma:0.1", angles_deg="0:180:7", mueller=True)
    ads = auto.to_xarray()
    for name in ("s11", "s12", "s33", "s34"):
        assert ads[name].attrs["estimated_error"] == auto.info["error"][name]
    assert ads.phase.attrs["estimated_error"] == auto.info["error"]["s11"]
    assert ads.attrs["size_average_tolerance"] == 0.005
    assert ads.attrs["size_average_last_change"] == auto.info["last_change"]
    assert ads.attrs["size_average_shifted_change"] == auto.info["shifted_change"]
    fog = hydrolux.SizeDistribution.gamma(10e-6, 0.2, number_per_m3=1e8)
    b = hydrolux.bulk_optics(1.333, 550, fog, nodes=32)
    bd = b.to_xarray()
    assert float(bd.extinction_coefficient) == b["extinction_per_m"]
    assert bd.single_scattering_albedo.attrs["units"] == "1" and abs(float(bd.single_scattering_albedo) - 1) < 1e-12
    sd = fog.to_xarray(nodes=12)
    assert sd.number_density.attrs["units"] == "m-4" and sd.radius.size == 12
    assert np.all(np.diff(sd.radius.values) > 0)
    with pytest.raises(ValueError, match="radius_m"):
        fog.to_xarray(np.ones((2, 2)) * 1e-5)
    with pytest.raises(ValueError, match="x has shape"):
        hydrolux.mie(1.333, np.ones((2, 2))).to_xarray()


@pytest.mark.parametrize("args, says", [
    (["lee", "--size", "4x8", "-o", "table.txt"], "-o table.txt: give a .exr path"),
    (["lee", "--size", "4x8", "-o", "missing/table.nc"], "missing"),
    (["mie", "--x", "10", "--m", "1.33", "-o", "p.txt"], ".csv, .npy, .json or .nc"),
    (["mie", "--x", "10", "--m", "1.33", "--no-angles", "-o", "p.nc"], "--no-angles computes none"),
    (["lee", "--size", "0x8", "-o", "table.nc"], "--size"),
])
def test_bad_input_is_one_line_exit_2_and_no_file(tmp_path, args, says):
    (tmp_path / "keep.nc").write_bytes(b"mine")
    p = run(*args, cwd=tmp_path)
    assert p.returncode == 2, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and says in lines[0], p.stderr
    assert sorted(os.listdir(tmp_path)) == ["keep.nc"]
    assert (tmp_path / "keep.nc").read_bytes() == b"mine"


def test_a_failed_run_leaves_an_existing_file_as_it_was(tmp_path):
    path = tmp_path / "table.nc"
    path.write_bytes(b"an older table")
    p = run("lee", "--size", "4x8", "--radius-um", "1e9", "-o", str(path))
    assert p.returncode == 2
    assert path.read_bytes() == b"an older table" and os.listdir(tmp_path) == ["table.nc"]


def test_open_atlas_one_dimension_per_swept_option(tmp_path):
    from hydrolux.batch import lee_atlas

    spec = tmp_path / "atlas.json"
    spec.write_text(json.dumps({
        "defaults": {"size": "3x6", "wavelengths-nm": "380:780:4"},
        "tables": [{"name": "bow-s{size-spread}-t{temperature-c}", "table": "rainbow",
                    "sweep": {"size-spread": [0.05, 0.1, 0.2], "temperature-c": [0, 20]}},
                   {"name": "corona", "table": "corona"}]}))
    out = tmp_path / "atlas"
    p = subprocess.run([sys.executable, "-m", "hydrolux.batch", "lee-atlas", "--spec", str(spec), "--output-dir", str(out), "--format", "netcdf",
                        "--workers", "1", "-q"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    with pytest.raises(ValueError, match="2 entries"):
        lee_atlas.open_atlas(str(out))
    ds = lee_atlas.open_atlas(str(out), "bow-s{size-spread}-t{temperature-c}")
    assert ds.rgb.dims[:2] == ("size_spread", "temperature_c")
    assert ds.size_spread.values.tolist() == [0.05, 0.1, 0.2] and ds.temperature_c.values.tolist() == [0, 20]
    assert ds.size_spread.attrs["long_name"].startswith("swept option --size-spread")
    for s in (0.05, 0.1, 0.2):
        for t in (0, 20):
            with xr.open_dataset(out / f"bow-s{s}-t{t}.nc") as one:
                np.testing.assert_array_equal(one.rgb.values, ds.rgb.sel(size_spread=s, temperature_c=t).values)
    assert lee_atlas.open_atlas(str(out), "corona").rgb.dims == ("scattering_angle", "radius", "channel")
    with pytest.raises(ValueError, match="not in the atlas"):
        lee_atlas.open_atlas(str(out), "nothing")
    # A table gone: named, not silently left out.
    os.remove(out / "bow-s0.1-t20.nc")
    with pytest.raises(ValueError, match="bow-s0.1-t20"):
        lee_atlas.open_atlas(str(out), "bow-s{size-spread}-t{temperature-c}")
    with pytest.raises(ValueError, match="not an atlas"):
        lee_atlas.open_atlas(str(tmp_path))


def test_what_a_table_cannot_resolve_is_said_by_every_door(tmp_path):
    """A table whose rows are wider than the supernumeraries it shows (a point sun leaves 800 um drops'
    fringes 0.27 deg apart; 128 rows over 130-150 deg are 0.16 apart) says so: the CLI warns once per
    note naming its flags, the sidecar, the profile and the NetCDF file keep it in the library's
    names, and Python's info["notes"] in its keywords (atmos::lee_resolution_notes; its numbers are
    checked in tests/atmos/test_lee_notes.cpp). The default rows (1024 over 90-180 deg) say nothing.
    Four wavelengths leave the table's estimated error (its even against its odd wavelengths) far above
    1%: a second note, after the work, names the wavelengths; every door states the error itself."""
    args = ["lee", "-q", "--sun-disk-deg", "0", "--angle-deg", "130:150", "--size", "16x128",
            "--wavelengths-nm", "400:700:4"]
    p = run(*args, "-o", str(tmp_path / "t.exr"))
    assert p.returncode == 0, p.stderr
    warnings = [line for line in p.stderr.splitlines() if "warning" in line]
    assert len(warnings) == 2 and "give --size with at least" in warnings[0] and "--angle-deg" in warnings[0]
    assert "estimated error" in warnings[1] and "--wavelengths-nm than 4" in warnings[1]
    sidecar = json.loads((tmp_path / "t.json").read_text())
    assert len(sidecar["notes"]) == 2 and "give size with at least" in sidecar["notes"][0]
    assert "give more wavelengths than 4" in sidecar["notes"][1]
    error = sidecar["error"]["luminance_rms"]
    assert 0.01 < error < 1
    assert run(*args, "-o", str(tmp_path / "t.nc")).returncode == 0
    with xr.open_dataset(tmp_path / "t.nc") as ds:
        assert ds.attrs["resolution_notes"] == "; ".join(sidecar["notes"])
        assert ds.attrs["error_luminance_rms"] == pytest.approx(error, rel=1e-12)
    t = hydrolux.lee(sun_disk_deg=0, angle_deg=(130, 150), size=(16, 128), wavelengths_nm=(400, 700), wavelengths=4)
    assert t.info["notes"] == sidecar["notes"]
    assert t.info["error"]["luminance_rms"] == pytest.approx(error, rel=1e-12)
    quiet = run("lee", "-q", "--size", "16x1024", "--wavelengths-nm", "400:700:4", "-o", str(tmp_path / "d.exr"))
    assert quiet.returncode == 0
    assert [line for line in quiet.stderr.splitlines() if "warning" in line and "estimated error" not in line] == []
    assert [n for n in json.loads((tmp_path / "d.json").read_text())["notes"] if "estimated error" not in n] == []
