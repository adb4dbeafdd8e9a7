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
    ("big = np.broadcast_to(np.zeros(3), (16000, 16000, 3))", "h.rain(big)"),
    ("big = np.broadcast_to(np.zeros(3), (16000, 16000, 3)); r = h.RainRenderer(16000, 16000)", "r.render(big)"),
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
    (lambda: h.lee(size="8x16"), TypeError, "size: expected (columns, rows), two whole numbers, got '8x16'"),
    (lambda: h.lee(size=(8.5, 16)), ValueError,
     "size[0] (columns): 8.5 is not a whole number; valid range [1, 16384]"),
    (lambda: h.lee(size=(8, 10 ** 38)), ValueError,
     "size[1] (rows): 100000000000000000000000000000000000000 is outside the valid range [1, 16384]"),
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
    (lambda: h.rain(_IMG, rate_mmh="heavy"), TypeError, "rate_mmh: expected a number, got 'heavy'"),
    (lambda: h.RainRenderer(64, 64, rate_mmh=[3]), TypeError, "rate_mmh: expected a number, got a list"),
    (lambda: h.rain(_IMG, unresolved="no"), TypeError, "unresolved: expected True or False, got 'no'"),
    (lambda: h.rain(_IMG, with_layer=np.ones(4)), TypeError,
     "with_layer: expected True or False, got an array of shape (4,) and dtype float64"),
    (lambda: h.fresnel("abc"), TypeError, "theta_deg: expected a number or an array of numbers, got 'abc'"),
    (lambda: h.fresnel(np.ones(3, complex)), TypeError,
     "theta_deg: expected real numbers, got an array of shape (3,) and dtype complex128"),
    (lambda: h.lee(radius_um=(1, "x")), TypeError, "radius_um[1]: expected a number, got 'x'"),
    (lambda: h.drop_undistort(_IMG, "ab", 3), TypeError, "drop_center: expected (x, y) in pixels, got 'ab'"),
    (lambda: h.write_image(None, _IMG), TypeError, "path: expected a file path (str or pathlib.Path), got None"),
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
