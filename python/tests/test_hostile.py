"""What a hostile caller tries (issue 23): no call may crash the interpreter, and every bad argument is a
one-line TypeError or ValueError naming the argument, its value (short: never an array's contents) and
what is valid."""
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

import hydrolux as h


# ---- memory: an allocation that fails is MemoryError, never a crash --------------------------------

# Runs `call` in a fresh interpreter whose address space (RLIMIT_AS) is capped at what it has mapped
# after the setup plus `headroom_mb`: a copy larger than that cannot be made. The inputs are broadcast
# views, which cost no memory however large they look.
_LIMITED = """
import resource, sys
import numpy as np
import hydrolux as h
h._image_module()  # OpenImageIO's libraries mapped before the limit
{setup}
def mapped():
    with open("/proc/self/status") as f:
        return next(int(l.split()[1]) * 1024 for l in f if l.startswith("VmSize:"))
resource.setrlimit(resource.RLIMIT_AS, (mapped() + {headroom_mb} * 2**20, resource.getrlimit(resource.RLIMIT_AS)[1]))
try:
    {call}
    print("no error")
except MemoryError as e:
    print("MemoryError")
"""


@pytest.mark.parametrize("setup, call", [
    # A float64 view whose float32 copy (8.1 GB) cannot be made: was SIGSEGV (a null array read).
    ("big = np.broadcast_to(np.zeros(3), (26000, 26000, 3))", "h.write_image('/nonexistent/x.exr', big)"),
    # (rain over a 16000^2 view used to be here: the renderer's memory check now refuses that size before
    # any copy, a ValueError naming what would fit: test_frame_calls_refuse_what_cannot_fit_as_the_cli_does.)
    ("big = np.broadcast_to(np.zeros(3), (16000, 32000, 3))", "h.drop_render(env=big, size=8)"),
    ("big = np.broadcast_to(np.zeros(3), (26000, 26000, 3))", "h.drop_undistort(big, (10, 10), 5)"),
    # A non-contiguous float64 view whose contiguous copy (8 GB) cannot be made: was a TypeError.
    ("big = np.broadcast_to(np.full(1, 30.0), (10**9,))", "h.fresnel(big)"),
    ("big = np.broadcast_to(np.full(1, 3.0), (10**9,))", "h.mie(1.333, big, angles_deg=None)"),
])
def test_an_allocation_that_fails_is_a_memory_error(setup, call):
    code = _LIMITED.format(setup=setup, call=call, headroom_mb=1024)
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=os.environ.copy())
    assert (p.returncode, p.stdout.strip()) == (0, "MemoryError"), p.stderr[-2000:]


# ---- whole numbers: the CLI's ranges and words ------------------------------------------------------

_IMG = np.zeros((64, 64, 3), np.float32)
_MAX_SEED = 2 ** 53  # hydrolux::rain::kMaxSeed, the CLI's --seed range


@pytest.mark.parametrize("call, error, message", [
    # Huge, fractional, boolean and textual values of every whole-number argument.
    (lambda: h.rain(_IMG, frame_index=10 ** 30), ValueError,
     "frame_index: 1000000000000000000000000000000 is outside the valid range [0, 1000000000]"),
    (lambda: h.RainRenderer(64, 64).render(_IMG, frame_index=2.5), ValueError,
     "frame_index: 2.5 is not a whole number; valid range [0, 1000000000]"),
    (lambda: h.rain(_IMG, seed=2 ** 64), ValueError,
     "seed: 18446744073709551616 is outside the valid range [0, 9007199254740992]"),
    (lambda: h.rain(_IMG, seed=_MAX_SEED + 1), ValueError,
     "seed: 9007199254740993 is outside the valid range [0, 9007199254740992]"),
    (lambda: h.rain(_IMG, seed=-1), ValueError, "seed: -1 is outside the valid range [0, 9007199254740992]"),
    (lambda: h.rain(_IMG, seed=1.5), ValueError, "seed: 1.5 is not a whole number; valid range [0, 9007199254740992]"),
    (lambda: h.rain(_IMG, seed=True), TypeError, "seed: expected a whole number in [0, 9007199254740992], got True"),
    (lambda: h.lee(seed=2 ** 64), ValueError,
     "seed: 18446744073709551616 is outside the valid range [0, 9007199254740992]"),
    (lambda: h.lee(size="8x16"), TypeError, "size: expected (W, H), each a whole number in [1, 16384] px, got '8x16'"),
    (lambda: h.lee(size=(8.5, 16)), ValueError,
     "size[0]: 8.5 is not a whole number; valid range [1, 16384] px"),
    (lambda: h.lee(size=(8, 10 ** 38)), ValueError,
     "size[1]: 100000000000000000000000000000000000000 is outside the valid range [1, 16384] px"),
    (lambda: h.lee(wavelengths=None), TypeError, "wavelengths: expected a whole number in [0, 2000], got None"),
    (lambda: h.lee(threads=-1), ValueError, "threads: -1 is outside the valid range [0, 1024]"),
    (lambda: h.RainRenderer(160.7, 90), ValueError, "width: 160.7 is not a whole number; valid range [16, 16384] px"),
    (lambda: h.RainRenderer(160, "90"), TypeError, "height: expected a whole number in [16, 16384] px, got '90'"),
    (lambda: h.builtin_scene(10 ** 5000, 90), ValueError,
     "width: a whole number of 5001 digits is outside the valid range [16, 16384] px"),
    (lambda: h.drop_render(size=True), TypeError, "size: expected a whole number in [8, 16384] px, got True"),
    (lambda: h.drop_render(samples=np.int64(65)), ValueError, "samples: 65 is outside the valid range [1, 64]"),
    (lambda: h.drop_undistort(_IMG, (4, 4), 3, size=(32.5, 24)), ValueError,
     "size[0] (width): 32.5 is not a whole number; valid range [1, 16384] px"),
    (lambda: h.mie(1.333, 1.0, threads=2 ** 70), ValueError,
     "threads: 1180591620717411303424 is outside the valid range [0, 1024]"),
    (lambda: h.bulk_optics(1.333, 550.0, h.SizeDistribution.gamma(1e-5, 0.1), threads=2000), ValueError,
     "threads: 2000 is outside the valid range [0, 1024]"),
    (lambda: h.SizeDistribution.gamma(1e-5, 0.1).quadrature(8.5), ValueError,
     "nodes: 8.5 is not a whole number; valid range [1, 4096]"),
    (lambda: h.set_threads(float("nan")), ValueError, "threads: nan is not a whole number; valid range [0, 1024]"),
    (lambda: h.write_image("/tmp/never.png", _IMG, bits=12), ValueError, "bits: 12 is not 8 or 16"),
    # Numbers, strings, flags and pairs: named, never the "Unable to cast" of the binding layer.
    (lambda: h.bulk_optics(1.333, np.array([500.0, 600.0]), h.SizeDistribution.gamma(1e-5, 0.1)), TypeError,
     "wavelength_nm: expected a number, got an array of shape (2,) and dtype float64"),
    (lambda: h.mie(np.array([1.3, 1.4]), 1.0), TypeError,
     "m: expected one complex number such as 1.333+1e-8j, got an array of shape (2,) and dtype float64"),
    (lambda: h.lee(table=None), TypeError, "table: expected a string (rainbow, corona or glory), got None"),
    (lambda: h.lee(theory="debye:x"), ValueError, "theory 'debye:x': the order must be a whole number; valid:"),
    (lambda: h.rain(_IMG, rain_rate_mmh="heavy"), TypeError, "rain_rate_mmh: expected a number, got 'heavy'"),
    (lambda: h.RainRenderer(64, 64, rain_rate_mmh=[3]), TypeError, "rain_rate_mmh: expected a number, got a list"),
    (lambda: h.rain(_IMG, unresolved="no"), TypeError, "unresolved: expected True or False, got 'no'"),
    (lambda: h.rain(_IMG, with_layer=np.ones(4)), TypeError,
     "with_layer: expected True or False, got an array of shape (4,) and dtype float64"),
    (lambda: h.fresnel("abc"), TypeError, "theta_deg: expected a number or an array of numbers, got 'abc'"),
    (lambda: h.fresnel(np.ones(3, complex)), TypeError,
     "theta_deg: expected real numbers, got an array of shape (3,) and dtype complex128"),
    (lambda: h.lee(radius_um=(1, "x")), TypeError, "radius_um[1]: expected a number, got 'x'"),
    (lambda: h.drop_undistort(_IMG, "ab", 3), TypeError, "drop_center: expected (x, y) in pixels, got 'ab'"),
    (lambda: h.write_image(None, _IMG), TypeError, "path: expected a file path (str, bytes or pathlib.Path), got None"),
])
def test_bad_arguments_are_named_in_one_line(call, error, message):
    with pytest.raises(error) as e:
        call()
    text = str(e.value)
    assert message in text
    assert "\n" not in text and "Unable to cast" not in text and len(text) < 300


def test_an_image_is_never_printed():
    # A whole-number argument pybind11 could not convert used to list every argument, the image too.
    big = np.arange(64 * 64 * 3, dtype=np.float64).reshape(64, 64, 3)
    for bad in (10 ** 30, 2.5, "1", None, [1]):
        with pytest.raises((TypeError, ValueError)) as e:
            h.RainRenderer(64, 64).render(big, frame_index=bad)
        assert str(e.value).startswith("frame_index: ") and "12287" not in str(e.value) and "\n" not in str(e.value)
    with pytest.raises(ValueError) as e:
        h.rain(np.zeros((64, 64, 3), object))
    assert str(e.value) == ("image: expected a real-valued array (float32 or float64), got an array of shape "
                            "(64, 64, 3) and dtype object")


def test_whole_numbers_in_any_numeric_type_are_taken():
    # What is whole is accepted from any numeric type, as the CLI accepts 1e3: the same rain.
    a = h.rain(_IMG + 0.25, seed=7, frame_index=3)
    b = h.rain(_IMG + 0.25, seed=np.uint64(7), frame_index=3.0)
    np.testing.assert_array_equal(a.image, b.image)
    c = h.rain(_IMG + 0.25, seed=_MAX_SEED)  # the top of the range is in it
    assert c.image.shape == (64, 64, 3)
    assert h.lee(size=(np.int32(1), 8.0), radius_um=100).rgb.shape == (8, 1, 3)


# ---- the rain's input values --------------------------------------------------------------------

@pytest.mark.parametrize("bad, shown", [(np.nan, "NaN"), (np.inf, "+inf"), (-np.inf, "-inf")])
def test_a_non_finite_pixel_is_a_value_error_naming_it(bad, shown):
    img = np.full((64, 64, 3), 0.5, np.float32)
    img[17, 5, 2] = bad
    with pytest.raises(ValueError) as e:
        h.rain(img)
    assert str(e.value).startswith(f"image: pixel (5, 17) channel 2 is {shown}")
    r = h.RainRenderer(64, 64)
    with pytest.raises(ValueError, match=r"^image: pixel \(5, 17\) channel 2"):
        r.render(img.astype(np.float64))


def test_negative_values_are_read_as_zero_with_one_warning():
    img = np.full((64, 64, 3), 0.5, np.float32)
    img[:2, :, 0] = -0.25  # 128 negative red values
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        r = h.rain(img, seed=3)
    assert [str(x.message) for x in w] == ["image: 128 negative values read as 0 (rain needs linear light, >= 0)"]
    assert w[0].category is RuntimeWarning and w[0].filename == __file__  # pointed at the caller
    assert r.stats["negative_values_clamped"] == 128
    # Read as 0: the same frame as with zeros there.
    clean = img.copy()
    clean[:2, :, 0] = 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no warning without negative values
        ref = h.rain(clean, seed=3)
    np.testing.assert_array_equal(r.image, ref.image)
    assert ref.stats["negative_values_clamped"] == 0


# ---- issue 37: files read back as written, the CLI's parsers, memory, Ctrl-C, pickling, colours ----

def _srgb_encode(v):
    return np.where(v <= 0.0031308, v * 12.92, 1.055 * np.power(np.maximum(v, 0), 1 / 2.4) - 0.055)


def _png_chunks(data):
    """(type, body) of each chunk of a PNG's bytes."""
    import struct
    out, pos = [], 8
    while pos + 8 <= len(data):
        n, = struct.unpack(">I", data[pos:pos + 4])
        out.append((data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]))
        pos += 12 + n
    return out


def test_masks_read_back_as_written_through_the_cli_and_python(tmp_path, cli):
    # rain --mask-out writes 16-bit linear codes (gAMA 1.0, no sRGB chunk); read_image used to put them
    # through the sRGB curve (a 0.17 alpha read as 0.02).
    args = ["rain", "-q", "--image", "builtin", "--size", "96x64", "--rain-rate-mmh", "50", "--seed", "3"]
    cli(*args, "-o", tmp_path / "a.png", "--mask-out", tmp_path / "m.png")
    cli(*args, "-o", tmp_path / "b.png", "--mask-out", tmp_path / "m.exr")
    exact = h.read_image(str(tmp_path / "m.exr"))
    png = h.read_image(str(tmp_path / "m.png"))
    assert exact.max() > 0.1
    np.testing.assert_allclose(png, exact, rtol=0, atol=0.5 / 65535 + 1e-7)
    chunks = dict(_png_chunks((tmp_path / "m.png").read_bytes()))
    assert b"sRGB" not in chunks and chunks[b"gAMA"] == (100000).to_bytes(4, "big")
    # The Python doors write the same file: the batch's mask encoder and write_image(linear=True).
    alpha = np.linspace(0, 1, 96 * 64, dtype=np.float32).reshape(64, 96, 1)
    alpha[0, 0, 0] = 0.17
    (tmp_path / "p.png").write_bytes(h._image_module().encode(alpha, "png", 16, True))
    for bits in (8, 16):
        h.write_image(str(tmp_path / f"w{bits}.png"), alpha, bits=bits, linear=True)
    for name, step in (("p.png", 65535), ("w16.png", 65535), ("w8.png", 255)):
        back = h.read_image(str(tmp_path / name))
        np.testing.assert_allclose(back, alpha, rtol=0, atol=0.5 / step + 1e-7, err_msg=name)
        assert abs(back[0, 0, 0] - 0.17) <= 0.5 / step + 1e-7
    with pytest.raises(TypeError, match="^linear: expected True or False"):
        h.write_image(str(tmp_path / "x.png"), alpha, linear="yes")


def test_an_srgb_png_still_decodes_through_the_curve(tmp_path):
    import zlib
    colour = np.full((1, 1, 1), 0.17, np.float32)
    h.write_image(str(tmp_path / "c.png"), colour, bits=16)
    chunks = _png_chunks((tmp_path / "c.png").read_bytes())
    assert b"sRGB" in dict(chunks)
    raw = zlib.decompress(b"".join(body for kind, body in chunks if kind == b"IDAT"))
    assert int.from_bytes(raw[1:3], "big") == round(float(_srgb_encode(0.17)) * 65535)  # the curve's code
    assert abs(h.read_image(str(tmp_path / "c.png"))[0, 0, 0] - 0.17) < 1e-5


def test_mie_angles_are_the_clis_bit_for_bit(tmp_path, cli):
    xr = pytest.importorskip("xarray")
    cli("mie", "--m", "1.333", "--x", "10", "-q", "-o", tmp_path / "p.nc")
    with xr.open_dataset(tmp_path / "p.nc") as f:
        on_disk = f.scattering_angle.values.copy()
    mem = h.mie(1.333, 10.0).to_xarray().scattering_angle.values
    assert on_disk.tobytes() == mem.tobytes()  # numpy's linspace differed in 19 of the 181
    assert h._core.parse_angles("0:180:181").tobytes() == on_disk.tobytes()


@pytest.mark.parametrize("text", ["0:1_80:3", "0:180:0", " 0:180:3", "0:180:3 ", "0:inf:3", "nan", "0:200:3",
                                  "1e400:180:3", "0x10:180:2", "0,,10", "0:180:2.5", "0:180", ""])
def test_mie_refuses_the_angle_texts_the_cli_refuses(text, cli):
    p = cli("mie", "--m", "1.333", "--x", "1", "-q", "--json", "--angles-deg", text, check=False)
    assert p.returncode == 2, (text, p.stdout[:200])
    with pytest.raises(ValueError, match="^angles_deg '") as e:
        h.mie(1.333, 1.0, angles_deg=text)
    assert "\n" not in str(e.value)
    with pytest.raises(ValueError, match="^angles_deg '"):
        h.phase(10, 550, angles_deg=text)


@pytest.mark.parametrize("text", ["0:180:7", "+5:.5e2:3", "0,10,90", "1e1", "180:0:5"])
def test_mie_takes_the_angle_texts_the_cli_takes(text, cli):
    import json
    p = cli("mie", "--m", "1.333", "--x", "1", "-q", "--json", "--angles-deg", text)
    assert h.mie(1.333, 1.0, angles_deg=text).info["angles_deg"].tolist() == json.loads(p.stdout)["angles_deg"]


def test_text_is_not_a_number():
    for bad in (["10"], [1.0, "2"], np.array(["10"]), [b"1"]):
        with pytest.raises(TypeError, match="^x: expected (a number or an array of numbers|real numbers)"):
            h.mie(1.333, bad)
    with pytest.raises(TypeError, match="^theta_deg: expected"):
        h.fresnel(["45"])
    with pytest.raises(ValueError, match=r"^radius_um '1_0:20': expected A:B"):
        h.lee(radius_um="1_0:20", size=(2, 4))
    with pytest.raises(ValueError, match=r"^angle_deg '140:130': expected A:B"):
        h.lee(angle_deg="140:130", size=(2, 4))


# A Lee table too large for the memory this process may take: refused before the work, with the same
# estimate in both doors (the library's check; it ran until killed in Python).
_LEE_LIMITED = """
import resource
import hydrolux as h
def mapped():
    with open("/proc/self/status") as f:
        return next(int(l.split()[1]) * 1024 for l in f if l.startswith("VmSize:"))
resource.setrlimit(resource.RLIMIT_AS, (mapped() + 1024 * 2**20, resource.getrlimit(resource.RLIMIT_AS)[1]))
try:
    h.lee(size=(4096, 4096), wavelengths=2)
    print("no error")
except ValueError as e:
    print(e)
"""


def test_a_lee_table_too_large_is_refused_by_both_doors_with_the_same_numbers(cli):
    import re
    import resource
    p = subprocess.run([sys.executable, "-c", _LEE_LIMITED], capture_output=True, text=True, env=os.environ.copy())
    py = p.stdout.strip()
    assert re.fullmatch(r"size \(4096, 4096\): the rainbow table needs about (\S+ [GM]B) of memory and \S+ [GMk]?B is "
                        r"available; about size=\(\d+, \d+\) would fit", py), (py, p.stderr[-2000:])

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (1536 * 2**20, resource.getrlimit(resource.RLIMIT_AS)[1]))
    c = subprocess.run([cli.path, "lee", "--size", "4096x4096", "--wavelengths-nm", "380:780:2", "-q", "-o",
                        "/nonexistent/t.exr"], capture_output=True, text=True, preexec_fn=limit)
    assert c.returncode == 2, c.stderr
    m = re.search(r"--size 4096x4096: the rainbow table needs about (\S+ [GM]B) of memory and .* available; about "
                  r"--size \d+x\d+ would fit", c.stderr)
    assert m and m.group(1) == re.search(r"needs about (\S+ [GM]B)", py).group(1), c.stderr


# Ctrl-C: the call itself raises KeyboardInterrupt (the profiler sees the C function end in an exception),
# where it used to run to its end and the interrupt came after it had returned.
def _interrupted(function, call):
    import signal
    import threading
    events = []

    def profile(frame, event, arg):
        if arg is function and event.startswith("c_"):
            events.append(event)
            if event == "c_call":
                threading.Timer(0.05, os.kill, (os.getpid(), signal.SIGINT)).start()

    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        sys.setprofile(profile)
        try:
            call()
        except KeyboardInterrupt:
            pass
        finally:
            sys.setprofile(None)
    finally:
        signal.signal(signal.SIGINT, old)
    return events


def test_ctrl_c_stops_lens_drops():
    img = np.full((1000, 1000, 3), 0.5, np.float32)
    assert _interrupted(h._core.lens_drops, lambda: h.lens_drops(img, drops=20000, seed=1)) == ["c_call", "c_exception"]


def test_ctrl_c_stops_fog():
    img = np.full((3000, 4000, 3), 2.0, np.float32)  # every pixel a glow source: the glow's longest search
    img[:1500] = 0.5
    assert _interrupted(h._core.fog, lambda: h.fog(img, visibility_m=100)) == ["c_call", "c_exception"]


def test_cancellable_calls_give_the_same_results():
    img = h.builtin_scene(96, 64)
    a, b = h.lens_drops(img, drops=40, seed=2), h.lens_drops(img, drops=40, seed=2)
    np.testing.assert_array_equal(a.image, b.image)
    f = h.fog(img, visibility_m=150)
    assert f.image.shape == (64, 96, 3) and f.stats["negative_values_clamped"] == 0


def test_distributions_results_and_renderers_pickle():
    import pickle
    for d in (h.SizeDistribution.monodisperse(1e-3, 100), h.SizeDistribution.gamma(1e-5, 0.2, 1e8),
              h.SizeDistribution.log_normal(5e-6, 0.3, 1e9), h.SizeDistribution.marshall_palmer(5.0)):
        e = pickle.loads(pickle.dumps(d))
        assert e.kind == d.kind and e.parameters == d.parameters
        for x, y in zip(d.quadrature(16), e.quadrature(16)):
            assert x.tobytes() == y.tobytes()
    fog = h.SizeDistribution.gamma(1e-5, 0.2, 1e8)
    b = h.bulk_optics(1.333, 550, fog, nodes=16)
    c = pickle.loads(pickle.dumps(b))
    assert c == b and isinstance(c, h.BulkOptics)
    xr = pytest.importorskip("xarray")
    xr.testing.assert_identical(c.to_xarray(), b.to_xarray())
    r = h.RainRenderer(64, 48, rain_rate_mmh=25, wind_mps=3, seed=4)
    s = pickle.loads(pickle.dumps(r))
    scene = h.builtin_scene(64, 48)
    assert s.field_info() == r.field_info()
    np.testing.assert_array_equal(s.render(scene, frame_index=3).image, r.render(scene, frame_index=3).image)


@pytest.mark.parametrize("bad, error, message", [
    ("123", TypeError, "sky_rgb: expected three finite numbers >= 0 (linear R, G, B), e.g. (0.8, 0.8, 0.85), got '123'"),
    ("abc", TypeError, "sky_rgb: expected three finite numbers >= 0"),
    (5, TypeError, "sky_rgb: expected three finite numbers >= 0 (linear R, G, B), e.g. (0.8, 0.8, 0.85), got 5"),
    ({1, 2, 3}, TypeError, "sky_rgb: expected three finite numbers >= 0 (linear R, G, B), e.g. (0.8, 0.8, 0.85), got a set"),
    (True, TypeError, "sky_rgb: expected three finite numbers >= 0 (linear R, G, B), e.g. (0.8, 0.8, 0.85), got True"),
    (np.ones((3, 1)), ValueError, "sky_rgb: expected three finite numbers >= 0 (linear R, G, B), e.g. (0.8, 0.8, "
                                  "0.85), got an array of shape (3, 1) and dtype float64"),
    (np.array(["1", "2", "3"]), TypeError, "sky_rgb: expected three finite numbers >= 0"),
    ((1, 2), ValueError, "sky_rgb: expected three finite numbers >= 0 (linear R, G, B), e.g. (0.8, 0.8, 0.85), got a "
                         "tuple of 2"),
    ((1, "2", 3), TypeError, "sky_rgb[1]: expected a number, got '2'"),
    ((True, 1, 1), TypeError, "sky_rgb[0]: expected a number, got True"),
    ((1, 2, -1), ValueError, "sky_rgb[2] = -1 is not a finite value >= 0"),
    ([1, float("nan"), 1], ValueError, "sky_rgb[1] = nan is not a finite value >= 0"),
])
def test_sky_rgb_is_three_finite_numbers(bad, error, message):
    with pytest.raises(error) as e:
        h.fog(_IMG, visibility_m=100, sky_rgb=bad)
    assert message in str(e.value) and "\n" not in str(e.value)


def test_sky_rgb_takes_a_sequence_or_an_array_of_three():
    ref = h.fog(_IMG + 0.25, visibility_m=100, sky_rgb=(0.5, 0.5, 0.75)).image
    for given in ([0.5, 0.5, 0.75], np.array([0.5, 0.5, 0.75]), np.array([0.5, 0.5, 0.75], np.float32),
                  (np.float64(0.5), 0.5, 0.75)):
        np.testing.assert_array_equal(h.fog(_IMG + 0.25, visibility_m=100, sky_rgb=given).image, ref)


def test_fog_and_lens_drops_warn_of_negative_light_as_rain_does():
    img = np.full((64, 64, 3), 0.5, np.float32)
    img[:2, :, 0] = -0.25  # 128 negative red values
    for call, job in ((lambda: h.fog(img, visibility_m=100), "fog"), (lambda: h.lens_drops(img, drops=3), "lens_drops")):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            call()
        assert [str(x.message) for x in w] == [f"image: 128 negative values read as 0 ({job} needs linear light, >= 0)"]
        assert w[0].category is RuntimeWarning and w[0].filename == __file__


def test_pol_where_s11_is_zero_is_nan_with_a_warning():
    with pytest.warns(RuntimeWarning, match=r"^pol: NaN at 1 of 2 angles, where S11 = 0") as w:
        p = h.phase(500, 550, theory="airy", angles_deg=[10, 140], mueller=True)  # Airy: near the bow only
    assert len(w) == 1 and w[0].filename == __file__
    assert p.s11[0] == 0 and np.isnan(p.pol[0]) and np.isfinite(p.pol[1])


def test_mie_angles_given_as_an_array_are_checked_as_the_cli_checks_its_text():
    # Repeated or unsorted angles make a result whose rows (and NetCDF coordinate) are not one
    # direction: refused at the call, as --angles-deg refuses "10,10,20", not later at to_xarray().
    for bad in ([10, 10, 20], [0, 90, 45], np.array([180.0, 0.0, 90.0])):
        with pytest.raises(ValueError, match=r"^angles_deg: .*strictly increasing or strictly decreasing"):
            h.mie(1.333, 10.0, angles_deg=bad)
    assert h.mie(1.333, 10.0, angles_deg=[180, 90, 0]).s1.shape == (3,)
    with pytest.raises(ValueError, match=r"N in \[2, 1000000\], or N = 1 with A = B"):
        h.mie(1.333, 10.0, angles_deg="0:180:1")


def test_image_paths_that_are_not_utf8_are_read_and_written(tmp_path):
    # A folder name with byte 0xff (os.listdir gives it as a surrogate escape): write_image and
    # read_image raised TypeError where the CLI reads and writes such paths.
    folder = os.path.join(os.fsencode(str(tmp_path)), b"fr\xffames")
    os.mkdir(folder)
    img = h.builtin_scene(32, 24)
    h.write_image(os.path.join(folder, b"a.exr"), img)  # bytes
    listed = [os.path.join(os.fsdecode(folder), n) for n in os.listdir(os.fsdecode(folder))]  # str, escaped
    assert len(listed) == 1
    np.testing.assert_array_equal(h.read_image(listed[0]), img)
    np.testing.assert_array_equal(h.read_image(os.path.join(folder, b"a.exr")), img)
    with pytest.raises(TypeError, match="path: expected a file path"):
        h.read_image(5)


def test_frame_calls_refuse_what_cannot_fit_as_the_cli_does():
    # fog(), lens_drops() and RainRenderer had no memory check (the CLI's jobs and the batch, which calls
    # them, had none either for fog and lens drops): a frame too large for the memory left ran until the
    # allocator failed. Now the library's estimate refuses it in one line naming what would fit. A
    # 1.2 GB address space stands for a small machine; the 4096^2 frames need 1.2-2.3 GB.
    code = (
        "import resource\n"
        "resource.setrlimit(resource.RLIMIT_AS, (1200 << 20, 1200 << 20))\n"
        "import numpy as np, hydrolux as h\n"
        "img = np.full((4096, 4096, 3), 0.3, np.float32)\n"
        "big = np.broadcast_to(np.zeros(3), (16000, 16000, 3))\n"
        "for call in (lambda: h.lens_drops(img), lambda: h.fog(img, visibility_m=200),\n"
        "             lambda: h.RainRenderer(4096, 4096), lambda: h.rain(big)):\n"
        "    try:\n"
        "        call()\n"
        "        print('ran')\n"
        "    except ValueError as e:\n"
        "        print(e)\n")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert len(lines) == 4, p.stdout
    for line, what in zip(lines, ("image: lens drops over 4096x4096", "image: fog over 4096x4096",
                                  "width, height (4096, 4096): rain over 4096x4096",
                                  "width, height (16000, 16000): rain over 16000x16000")):
        assert line.startswith(what + " needs about") and line.endswith("would fit"), line
