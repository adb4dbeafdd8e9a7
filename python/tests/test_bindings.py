"""Every binding of the hydrolux package: dtypes and shapes, the same numbers as the CLI for the same
inputs (bit for bit: both call the same library code, and the CLI's JSON prints doubles in their
shortest round-trip form), invariants, and bad inputs raising ValueError that names the argument."""
import argparse
import inspect
import json
import os
import signal
import subprocess
import sys
import threading

import numpy as np
import pytest

import hydrolux as h


# ---- interface optics -----------------------------------------------------------------------------

def test_fresnel_matches_cli_and_shapes(cli):
    theta = np.array([[0.0, 30.0], [60.0, 89.0]])
    r = h.fresnel(theta, n1=1.0, n2=1.333)
    for k in ("rs", "rp", "r", "t", "theta_t_deg"):
        assert r[k].shape == (2, 2) and r[k].dtype == np.float64
    assert r["tir"].dtype == np.bool_
    for i, th in enumerate(theta.ravel()):
        j = cli("fresnel", "--theta-deg", th, "--n2", 1.333, "--json", json_out=True)
        for k in ("rs", "rp", "r", "t", "theta_t_deg"):
            assert r[k].ravel()[i] == j[k]
    # Energy: R + T = 1 for a dielectric (exactly as computed, T = 1 - R).
    np.testing.assert_allclose(r["r"] + r["t"], 1.0, rtol=0, atol=1e-15)


def test_fresnel_conductor_and_tir(cli):
    r = h.fresnel([10.0, 70.0], n1=1.333, n2=1.0)
    assert not r["tir"][0] and r["tir"][1] and np.isnan(r["theta_t_deg"][1]) and r["r"][1] == 1.0
    c = h.fresnel(45.0, n2=0.2, k2=3.4)
    j = cli("fresnel", "--theta-deg", 45, "--n2", 0.2, "--k2", 3.4, "--json", json_out=True)
    assert c["r"] == j["r"] and np.isnan(c["t"]) and j["t"] is None


def test_media_and_index_match_cli(cli):
    names = [m["medium"] for m in h.media()]
    assert "water" in names and "air" in names
    w = np.array([400.0, 589.3, 700.0])
    n = h.refractive_index("water", w, temperature_c=10)
    assert n.dtype == np.complex128 and n.shape == (3,)
    for i, nm in enumerate(w):
        j = cli("ior", "--medium", "water", "--wavelength-nm", nm, "--temperature-c", 10, "--json", json_out=True)
        assert (n[i].real, n[i].imag) == (j["n"], j["k"])


# ---- Mie ------------------------------------------------------------------------------------------

def test_mie_matches_cli_bit_for_bit(cli):
    m = 1.333 + 1e-8j
    xs = np.array([0.5, 10.0, 1234.5])
    r = h.mie(m, xs, angles_deg="0:180:7")
    assert r.qext.shape == (3,) and r.qext.dtype == np.float64 and r.n_terms.dtype == np.int32
    assert r.s1.shape == (3, 7) and r.s1.dtype == np.complex128
    for i, x in enumerate(xs):
        j = cli("mie", "--m", "1.333+1e-8i", "--x", x, "--angles-deg", "0:180:7", "--json", json_out=True)
        for k in ("qext", "qsca", "qabs", "qback", "g"):
            assert getattr(r, k)[i] == j[k], k
        assert r.n_terms[i] == j["n_terms"]
        np.testing.assert_array_equal(r.s1[i], [complex(*v) for v in j["s1"]])
        np.testing.assert_array_equal(r.s2[i], [complex(*v) for v in j["s2"]])


def test_mie_mueller_matches_cli_and_definitions(cli):
    # The Mueller elements (Bohren & Huffman eq. 4.77): the same doubles as hydrolux mie --mueller, the
    # definitions from S1, S2, and one sphere's pure matrix S11^2 = S12^2 + S33^2 + S34^2 (to rounding).
    xs = np.array([[0.5, 10.0], [100.0, 5.213]])
    r = h.mie(1.5 + 0.01j, xs, angles_deg="0:180:19", mueller=True)
    for k in ("s11", "s12", "s33", "s34"):
        assert getattr(r, k).shape == (2, 2, 19) and getattr(r, k).dtype == np.float64, k
    j = cli("mie", "--m", "1.5+0.01i", "--x", 100.0, "--angles-deg", "0:180:19", "--mueller", "--json", json_out=True)
    for k in ("s11", "s12", "s33", "s34"):
        np.testing.assert_array_equal(getattr(r, k)[1, 0], j[k])
    i1, i2, c = np.abs(r.s1) ** 2, np.abs(r.s2) ** 2, r.s2 * np.conj(r.s1)
    np.testing.assert_allclose(r.s11, (i2 + i1) / 2, rtol=1e-14)
    for got, want in ((r.s12, (i2 - i1) / 2), (r.s33, c.real), (r.s34, c.imag)):
        assert np.all(np.abs(got - want) <= 1e-14 * r.s11)
    np.testing.assert_allclose(r.s12 ** 2 + r.s33 ** 2 + r.s34 ** 2, r.s11 ** 2, rtol=1e-13)
    plain = h.mie(1.5 + 0.01j, xs, angles_deg="0:180:19")
    assert plain.s11 is None and plain.s34 is None
    np.testing.assert_array_equal(plain.s1, r.s1)
    with pytest.raises(ValueError, match="mueller"):
        h.mie(1.5, 1.0, angles_deg=None, mueller=True)
    with pytest.raises(TypeError, match="mueller"):
        h.mie(1.5, 1.0, mueller="yes")


def test_mie_efficiencies_only_matches_cli_no_angles(cli):
    xs = np.geomspace(1e-3, 1e4, 9).reshape(3, 3)
    r = h.mie(1.5 + 0.01j, xs, angles_deg=None)
    assert r.s1 is None and r.qext.shape == (3, 3)
    j = cli("mie", "--m", "1.5+0.01i", "--x", xs[1, 2], "--no-angles", "--json", json_out=True)
    assert r.qext[1, 2] == j["qext"] and r.qback[1, 2] == j["qback"] and r.g[1, 2] == j["g"]
    # The optical theorem: Qext = (4 / x^2) Re S(0), on the amplitudes' path.
    a = h.mie(1.5 + 0.01j, [3.0, 30.0], angles_deg=[0.0])
    np.testing.assert_allclose(a.qext, 4 / np.array([3.0, 30.0]) ** 2 * a.s1[:, 0].real, rtol=1e-12)


def test_sphere_matches_cli_physical_form(cli):
    m, x = h.sphere([10.0, 250.0], 589.3, temperature_c=20)
    assert isinstance(m, complex) and x.shape == (2,)
    j = cli("mie", "--radius-um", 250, "--wavelength-nm", 589.3, "--temperature-c", 20, "--no-angles", "--json",
            json_out=True)
    assert x[1] == j["x"] and (m.real, m.imag) == tuple(j["m"])


def test_size_distributions_and_bulk_optics():
    d = h.SizeDistribution.gamma(10e-6, 0.2, 1e8)
    r, w = d.quadrature(32)
    assert r.dtype == np.float64 and r.shape == w.shape == (32,)
    # The quadrature integrates the distribution's moments (Gauss: exact for the gamma weight).
    for k in (0, 1, 2, 3):
        np.testing.assert_allclose(np.sum(w * r ** k), d.moment(k), rtol=1e-10)
    assert d.number_concentration == pytest.approx(1e8) and d.mean_radius == pytest.approx(10e-6)
    # sigma_r / <r> = 0.2 by construction.
    assert np.sqrt(d.radius_variance) / d.mean_radius == pytest.approx(0.2, rel=1e-12)
    assert d.parameters["alpha"] > 0 and d.parameters["beta"] > 0
    # Over 1-100 um (every drop but a fraction far below 1e-12), Gauss-Legendre in ln r converges:
    # 3.5% short with 16 nodes, 2e-6 with 32, 4e-15 with 64.
    rr, ww = d.quadrature(64, r_min_m=1e-6, r_max_m=1e-4, log_spaced=True)
    assert rr.min() >= 1e-6 and rr.max() <= 1e-4
    np.testing.assert_allclose(np.sum(ww), 1e8, rtol=1e-12)
    with pytest.raises(ValueError, match="give both"):
        d.quadrature(8, r_min_m=1e-6)
    assert d.number_density(np.array([[5e-6, 1e-5]])).shape == (1, 2)
    mp = h.SizeDistribution.marshall_palmer(10.0)
    assert mp.kind == "marshall_palmer" and mp.effective_radius > 0
    assert h.SizeDistribution.log_normal(1e-6, 0.3).kind == "log_normal"
    assert h.SizeDistribution.monodisperse(1e-6).moment(2) == pytest.approx(1e-12)
    # Bulk optics against the written-out sum over the same quadrature.
    b = h.bulk_optics(1.333, 550.0, d, nodes=32)
    x = 2 * np.pi * r / 550e-9
    q = h.mie(1.333, x, angles_deg=None)
    np.testing.assert_allclose(b["extinction_per_m"], np.sum(w * np.pi * r ** 2 * q.qext), rtol=1e-12)
    np.testing.assert_allclose(b["g"], np.sum(w * np.pi * r ** 2 * q.qsca * q.g) /
                               np.sum(w * np.pi * r ** 2 * q.qsca), rtol=1e-12)


# ---- Lee ------------------------------------------------------------------------------------------

def test_lee_profile_matches_cli(cli):
    t = h.lee(radius_um=200, size=(1, 48), angle_deg=(130, 145), sampling=0.5)
    assert t.rgb.shape == (48, 1, 3) and t.xyz.dtype == np.float64 and t.display.dtype == np.float32
    assert t.radius_um.shape == (1,) and t.angle_deg.shape == (48,) and t.cos_angle.shape == (48,)
    j = cli("lee", "--radius-um", 200, "--size", "1x48", "--angle-deg", "130:145", "--sampling", 0.5, "--json",
            json_out=True)
    np.testing.assert_array_equal(t.angle_deg, j["angle_deg"])
    np.testing.assert_array_equal(t.xyz[:, 0, :], np.array(j["xyz"]))
    np.testing.assert_array_equal(t.rgb[:, 0, :], np.array(j["rgb"]))
    # The primary bow: the luminance peaks near 138 degrees for 200 um drops.
    assert 136 < t.angle_deg[np.argmax(t.xyz[:, 0, 1])] < 141


def test_lee_table_axes():
    t = h.lee(table="corona", size=(8, 16), wavelengths=8)
    assert t.rgb.shape == (16, 8, 3) and np.all(np.diff(t.radius_um) > 0) and t.angle_deg[0] == 0
    assert t.wavelengths_nm.shape == (8,) and t.info["theory"] == "mie"
    assert t.info["drop_shape"] == {"name": "sphere"}


def _flat_bow(position_deg, **kw):
    return h.lee(theory="airy", shape="spheroid:0.95", position_deg=position_deg, radius_um=500,
                 angle_deg=(130, 150), size=(1, 81), wavelengths=8, **kw)


def test_lee_flattened_drops_shift_the_top_of_the_bow_not_its_feet():
    """Oblate drops (docs/non-spherical.md): at the top of the bow (position 0) the plane section is
    the flattened one and the primary's minimum deviation moves towards the antisolar point, a
    larger scattering angle; at the side (position 90, sun on the horizon) the section is the
    drop's circular equator and the bow stays where the sphere's is."""
    top, side = _flat_bow(0), _flat_bow(90)
    sphere = h.lee(theory="airy", radius_um=500, angle_deg=(130, 150), size=(1, 81), wavelengths=8)
    peak = {n: t.angle_deg[np.argmax(t.xyz[:, 0, 1])] for n, t in (("top", top), ("side", side), ("sphere", sphere))}
    assert peak["top"] > peak["side"] + 2, peak
    assert abs(peak["side"] - peak["sphere"]) <= 0.25, peak
    d = top.info["drop_shape"]
    assert d["name"] == "spheroid:0.95" and d["position_deg"] == 0 and d["sun_elevation_deg"] == 0
    assert d["canting_deg"] == 0 and d["axis_ratio"].shape == (1,) and d["axis_ratio"][0] == 0.95
    assert sphere.info["drop_shape"] == {"name": "sphere"}


def test_lee_drop_shape_profile_matches_cli(cli):
    kw = dict(theory="airy", shape="beard-chuang", radius_um=800, angle_deg=(132, 148), size=(1, 33), wavelengths=8,
              sun_elevation_deg=20, position_deg=30, canting_deg=5)
    t = h.lee(**kw)
    j = cli("lee", "--theory", "airy", "--shape", "beard-chuang", "--radius-um", 800, "--angle-deg", "132:148",
            "--size", "1x33", "--wavelengths-nm", "380:780:8", "--sun-elevation-deg", 20, "--position-deg", 30,
            "--canting-deg", 5, "--json", "-q", json_out=True)
    np.testing.assert_array_equal(t.angle_deg, j["angle_deg"])
    np.testing.assert_allclose(t.xyz[:, 0, :], np.array(j["xyz"]), rtol=1e-12, atol=0)
    np.testing.assert_allclose(t.rgb[:, 0, :], np.array(j["rgb"]), rtol=1e-12, atol=0)
    np.testing.assert_allclose(t.xyz[:, 0, 1], np.array(j["luminance"]), rtol=1e-12, atol=0)
    d, jd = t.info["drop_shape"], j["drop_shape"]
    assert d["name"] == jd["name"] == "beard-chuang"
    for k in ("sun_elevation_deg", "position_deg", "canting_deg"):
        assert d[k] == jd[k] == kw[k]
    np.testing.assert_allclose(d["axis_ratio"], jd["axis_ratio"], rtol=1e-12, atol=0)
    assert 0.7 < d["axis_ratio"][0] < 0.99  # an 800 um falling drop is flattened by a few percent
    # Another position angle gives another profile: the options reach the library.
    assert not np.array_equal(t.xyz, h.lee(**{**kw, "position_deg": 90}).xyz)


@pytest.mark.parametrize("kw, names", [
    (dict(shape="egg"), "shape 'egg'"),
    (dict(shape="spheroid:0.2"), "shape 'spheroid:0.2'"),
    (dict(shape="spheroid:0.5", theory="airy"), "shape 'spheroid:0.5'"),
    (dict(shape="beard-chuang"), "shape beard-chuang"),  # the default theory, mie
    (dict(shape="spheroid:0.9", table="corona"), "shape spheroid:0.9"),
    (dict(position_deg=200), "position_deg = 200 is outside [0, 180]"),
    (dict(sun_elevation_deg=90), "sun_elevation_deg = 90 is outside [0, 89]"),
    (dict(canting_deg=-1), "canting_deg = -1 is outside [0, 30]"),
])
def test_lee_bad_drop_shape_options_raise_value_error_naming_them(kw, names):
    with pytest.raises(ValueError) as e:
        h.lee(**kw)
    assert names in str(e.value)


def test_lee_stokes_matches_cli_and_leaves_intensity_alone(cli):
    """stokes=True adds the Stokes Q (scattering-plane basis, > 0 tangential) and dolp = Q_Y / I_Y;
    I is bit for bit the same; the CLI's --stokes profile gives the same numbers."""
    kw = dict(radius_um=500, size=(1, 41), angle_deg=(134, 144), wavelengths=8)
    t, plain = h.lee(stokes=True, **kw), h.lee(**kw)
    assert plain.q_xyz is None and plain.dolp is None
    np.testing.assert_array_equal(t.xyz, plain.xyz)
    assert t.q_xyz.shape == (41, 1, 3) and t.dolp.shape == (41, 1)
    assert np.all(np.abs(t.q_xyz) <= t.xyz * (1 + 1e-12))
    np.testing.assert_allclose(t.dolp, t.q_xyz[..., 1] / t.xyz[..., 1], rtol=1e-12)
    # The primary bow is polarised tangentially: Q > 0 and dolp about 0.9 at its peak.
    peak = np.argmax(t.xyz[:, 0, 1])
    assert 0.85 < t.dolp[peak, 0] < 0.93
    j = cli("lee", "--radius-um", 500, "--size", "1x41", "--angle-deg", "134:144", "--wavelengths-nm", "380:780:8",
            "--stokes", "--json", "-q", json_out=True)
    np.testing.assert_array_equal(t.q_xyz[:, 0, :], np.array(j["q_xyz"]))
    np.testing.assert_array_equal(t.dolp[:, 0], np.array(j["dolp"]))
    assert "tangential" in j["stokes"]["sign"]
    with pytest.raises(TypeError, match="stokes: expected True or False"):
        h.lee(stokes=1, **kw)


def test_lee_automatic_sampling_matches_cli(cli, tmp_path):
    # One radius without a spread and a point sun: about 13% estimated at sampling 1, so without a
    # sampling the table is computed once more at 4 (docs/lee.md, "Automatic sampling"), as the CLI does.
    kw = dict(radius_um=10, size=(1, 64), size_spread=0, sun_disk_deg=0)
    t = h.lee(**kw)
    s = t.info["sampling"]
    assert s["automatic"] and s["multiplier"] == 4
    assert s["first_pass"]["multiplier"] == 1 and s["first_pass"]["luminance_rms"] > 0.01
    assert t.info["error"]["luminance_rms"] < s["first_pass"]["luminance_rms"]
    np.testing.assert_array_equal(t.xyz, h.lee(sampling=4, **kw).xyz)
    given = h.lee(sampling=1, **kw).info["sampling"]
    assert not given["automatic"] and given["multiplier"] == 1 and given["first_pass"] is None
    out = tmp_path / "t.exr"
    cli("lee", "--radius-um", 10, "--size", "1x64", "--size-spread", 0, "--sun-disk-deg", 0, "-o", out, "-q")
    sidecar = json.loads((tmp_path / "t.json").read_text())
    assert sidecar["sampling"]["multiplier"] == 4 and sidecar["sampling"]["automatic"]
    assert sidecar["sampling"]["first_pass"] == s["first_pass"]


def test_lee_signature_defaults_are_the_declared_ones():
    sig = inspect.signature(h.lee).parameters
    assert sig["shape"].default == "sphere"
    for p in h._core.params("lee"):
        assert sig[p["name"]].default == p["default"], p["name"]


# ---- the drop -------------------------------------------------------------------------------------

def test_drop_render_and_undistort_match_cli(cli, tmp_path):
    img = h.drop_render(size=48, samples=2)
    assert img.shape == (48, 48, 4) and img.dtype == np.float32
    exr = tmp_path / "drop.exr"
    cli("drop", "render", "--size", 48, "--samples", 2, "-o", exr, "-q")
    np.testing.assert_array_equal(img, h.read_image(str(exr)))
    u = h.drop_undistort(img, (24, 24), 9.6, fov_deg=50, size=(32, 24))
    assert u.shape == (24, 32, 4) and u.dtype == np.float32
    out = tmp_path / "view.exr"
    cli("drop", "undistort", "--image", exr, "--drop-center", "24,24", "--drop-radius-px", 9.6, "--fov-deg", 50,
        "--size", "32x24", "-o", out, "-q")
    np.testing.assert_array_equal(u, h.read_image(str(out)))


# ---- rain -----------------------------------------------------------------------------------------

def test_rain_matches_cli(cli, tmp_path):
    frame = h.builtin_scene(240, 136)
    assert frame.shape == (136, 240, 3) and frame.dtype == np.float32
    src = tmp_path / "frame.exr"
    h.write_image(str(src), frame)
    r = h.rain(h.read_image(str(src)), seed=7, rain_rate_mmh=40, wind_mps=3, frame_index=5, with_layer=True)
    assert r.image.shape == (136, 240, 3) and r.mask.shape == (136, 240, 1) and r.layer.shape == (136, 240, 4)
    cli("rain", "--image", src, "-o", tmp_path / "out.exr", "--mask-out", tmp_path / "mask.exr",
        "--layer-out", tmp_path / "layer.exr", "--stats-json", tmp_path / "s.json", "--seed", 7, "--rain-rate-mmh", 40,
        "--wind-mps", 3, "--frame-index", 5, "-q")
    np.testing.assert_array_equal(r.image, h.read_image(str(tmp_path / "out.exr")))
    np.testing.assert_array_equal(r.mask, h.read_image(str(tmp_path / "mask.exr")))
    np.testing.assert_array_equal(r.layer, h.read_image(str(tmp_path / "layer.exr")))
    stats = json.loads((tmp_path / "s.json").read_text())["frames"][0]
    assert stats.pop("frame_index", 5) == 5  # the CLI's record names its frame
    for k, v in stats.items():
        assert r.stats[k] == v, k
    assert set(r.stats) == set(stats) and r.stats["negative_values_clamped"] == 0
    assert r.stats["drops_in_view"] > 0
    # image = clear (1 - alpha) + layer, up to float rounding.
    assert np.all((r.mask >= 0) & (r.mask <= 1))


def test_a_declared_parameter_reaches_every_door(cli, tmp_path):
    """radius_classes, declared once (src/rain/params.cpp; docs/parameters.md): the CLI's flag, the
    Python keyword, the batch job's option and the reference all take it, with the same range."""
    from hydrolux.batch import rain as batch_rain
    frame = h.builtin_scene(96, 64)
    src = tmp_path / "frame.exr"
    h.write_image(str(src), frame)
    r = h.rain(h.read_image(str(src)), seed=3, radius_classes=6)
    cli("rain", "--image", src, "-o", tmp_path / "out.exr", "--stats-json", tmp_path / "s.json", "--seed", 3,
        "--radius-classes", 6, "-q")
    np.testing.assert_array_equal(r.image, h.read_image(str(tmp_path / "out.exr")))
    run = json.loads((tmp_path / "s.json").read_text())
    assert run["rain"]["radius_classes"] == 6 and len(run["field"]["classes"]) == 6
    assert not np.array_equal(r.image, h.rain(frame, seed=3).image)  # 6 classes are not the default 24
    assert "radius_classes" in inspect.signature(h.rain).parameters
    bad = cli("rain", "--image", src, "-o", tmp_path / "bad.exr", "--radius-classes", 300, check=False)
    assert bad.returncode == 2 and "--radius-classes" in bad.stderr and "[1, 256]" in bad.stderr
    with pytest.raises(ValueError, match=r"radius_classes: 300 is outside the valid range \[1, 256\]"):
        h.rain(frame, radius_classes=300)
    p = argparse.ArgumentParser()
    batch_rain.add_arguments(p)
    assert p.parse_args(["--radius-classes", "6"]).radius_classes == "6"  # parsed by the library later
    reference = open(os.path.join(os.environ.get("HYDROLUX_SOURCE_DIR", "."), "docs", "reference.md")).read()
    assert "| `--radius-classes` | `radius_classes` | rain |" in reference


def test_rain_renderer_sequence_is_frame_independent():
    frame = h.builtin_scene(160, 96)
    a = h.RainRenderer(160, 96, seed=3)
    seq = [a.render(frame, frame_index=k).image for k in range(3)]
    b = h.RainRenderer(160, 96, seed=3)
    np.testing.assert_array_equal(b.render(frame, frame_index=2).image, seq[2])
    assert not np.array_equal(seq[0], seq[1])  # the drops moved
    assert a.field_info()["drops"] > 0


# ---- images ---------------------------------------------------------------------------------------

def test_image_files_round_trip(tmp_path):
    img = np.random.default_rng(1).random((20, 30, 3), dtype=np.float32)
    h.write_image(str(tmp_path / "a.exr"), img)
    np.testing.assert_array_equal(h.read_image(str(tmp_path / "a.exr")), img)
    h.write_image(str(tmp_path / "a.png"), img, bits=16)
    np.testing.assert_allclose(h.read_image(str(tmp_path / "a.png")), img, atol=2e-4)
    with pytest.raises(OSError):
        h.write_image(str(tmp_path / "missing" / "a.png"), img)
    assert not (tmp_path / "missing").exists()
    with pytest.raises(FileNotFoundError):
        h.read_image(str(tmp_path / "nothing.png"))
    with pytest.raises(OSError, match="must be a .png or .exr"):
        h.write_image(str(tmp_path / "a.bmp"), img)
    assert sorted(os.listdir(tmp_path)) == ["a.exr", "a.png"]  # nothing half-written beside them


# ---- validation -----------------------------------------------------------------------------------

@pytest.mark.parametrize("call, names", [
    (lambda: h.fresnel(95.0), "theta_deg = 95"),
    (lambda: h.fresnel(10.0, n2=0), "n2 = 0"),
    (lambda: h.refractive_index("water", 100.0), "wavelength_nm"),
    (lambda: h.refractive_index("unobtainium", 500.0), "medium"),
    (lambda: h.mie(1.333, 2e6), "x = 2e+06"),
    (lambda: h.mie(1.333 - 0.1j, 1.0), "m_imag"),
    (lambda: h.mie(1.333, 1.0, angles_deg=[190.0]), "angles_deg = 190"),
    (lambda: h.mie(1.333, 1.0, angles_deg="0:180"), "angles_deg"),
    (lambda: h.SizeDistribution.gamma(-1.0, 0.1), "mean_radius_m"),
    (lambda: h.SizeDistribution.gamma(1e-5, 0.1).quadrature(0), "nodes: 0 is outside the valid range [1, 4096]"),
    (lambda: h.lee(size=(0, 10)), "size[0]: 0 is outside the valid range [1, 16384] px"),
    (lambda: h.lee(table="halo"), "table 'halo'"),
    (lambda: h.lee(theory="magic"), "theory 'magic'"),
    (lambda: h.lee(temperature_c=200), "temperature_c = 200"),
    (lambda: h.drop_render(radius_mm=500), "radius_mm = 500"),
    (lambda: h.drop_render(size=4), "size: 4 is outside the valid range [8, 16384] px"),
    (lambda: h.drop_undistort(np.zeros((8, 8, 3)), (4, 4), 3, fov_deg=200), "fov_deg"),
    (lambda: h.drop_undistort(np.zeros((8, 8, 3)), (4, 4), -3), "drop_radius_px"),
    (lambda: h.rain(np.zeros((64, 64, 3), np.float32), rain_rate_mmh=600), "rain_rate_mmh = 600"),
    (lambda: h.rain(np.zeros((64, 64, 3), np.float32), camera_height_m=-1), "camera_height_m"),
    (lambda: h.rain(np.zeros((64, 64, 3), np.float32), fov_deg=179), "fov_deg = 179"),
    (lambda: h.rain(np.zeros((64, 64), np.float32)), "image"),
    (lambda: h.rain(np.zeros((8, 8, 3), np.float32)), "width: 8 is outside the valid range [16, 16384] px"),
    (lambda: h.RainRenderer(64, 64).render(np.zeros((32, 32, 3)), frame_index=0), "image"),
    (lambda: h.RainRenderer(64, 64).render(np.zeros((64, 64, 3)), frame_index=-1), "frame_index"),
])
def test_bad_inputs_raise_value_error_naming_the_argument(call, names):
    with pytest.raises(ValueError) as e:
        call()
    assert names in str(e.value)


def test_unknown_rain_option_is_a_type_error():
    with pytest.raises(TypeError, match="rate_mm"):
        h.RainRenderer(64, 64, rate_mm=3)


# ---- the GIL and Ctrl-C ---------------------------------------------------------------------------

def test_long_calls_release_the_gil():
    # While a Lee table is computed on another thread, this thread keeps running Python.
    ticks = 0
    done = threading.Event()

    def work():
        h.lee(size=(16, 64), sampling=0.5, threads=1)
        done.set()

    t = threading.Thread(target=work)
    t.start()
    while not done.is_set():
        ticks += 1
        done.wait(0.001)
    t.join()
    assert ticks > 10


def test_ctrl_c_cancels_a_long_call():
    # A table that would take minutes; SIGINT once it has started must end it with KeyboardInterrupt.
    code = ("import sys, hydrolux as h\n"
            "print('started', flush=True)\n"
            "try:\n"
            "    h.lee(size=(512, 1024), sampling=4, threads=1)\n"
            "    print('finished', flush=True)\n"
            "except KeyboardInterrupt:\n"
            "    print('interrupted', flush=True)\n")
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True, env=os.environ.copy())
    assert p.stdout.readline().strip() == "started"
    import time
    time.sleep(0.5)  # inside the call
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=600)  # a guard against a hang, not a time limit on the work
    assert out.strip() == "interrupted"
    assert p.returncode == 0


def test_set_threads_keeps_the_numbers():
    a = h.mie(1.333, [50.0, 500.0], angles_deg="0:180:361")
    h.set_threads(1)
    try:
        b = h.mie(1.333, [50.0, 500.0], angles_deg="0:180:361")
    finally:
        h.set_threads(0)
    np.testing.assert_array_equal(a.s1, b.s1)
    with pytest.raises(ValueError, match="threads"):
        h.set_threads(-1)


def test_package_metadata():
    assert h.__version__ and h.simd_target()
    assert h.mie_terms(100.0) == h.mie(1.333, 100.0, angles_deg=None).n_terms
    assert "theta_deg" in (h.fresnel.__doc__ or "")
