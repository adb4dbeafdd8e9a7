"""hydrolux.sky: the CLI's sky (hydrolux sky) into arrays, with its checks, polariser and drop shapes.

The frames are small and the tables coarse (sampling 0.25, 10 um droplets: a fogbow), so that each
render takes about a second; the scene is the CLI's either way."""
import math

import numpy as np
import pytest

import hydrolux
from hydrolux._sky import sky

# A small frame looking at the bow: the sun behind the camera, 10 um droplets, the tables coarse.
SCENE = dict(radius_um=10, sampling=0.25, sun_elevation_deg=20, view_azimuth_deg=0, view_elevation_deg=15,
             fov_deg=100)
SIZE = (48, 32)
FLAGS = ["--sampling", "0.25", "--sun-elevation-deg", "20", "--view-azimuth-deg", "0",
         "--view-elevation-deg", "15", "--fov-deg", "100", "--size", "48x32", "-q"]
RADIUS = ["--radius-um", "10"]


def cli_frame(cli, tmp_path, *flags, name="frame.exr"):
    out = tmp_path / name
    cli("sky", *FLAGS, *RADIUS, *flags, "-o", out)
    return hydrolux.read_image(str(out))


def test_agrees_with_the_cli_exactly(cli, tmp_path):
    # The same tables, compositor and floats: the CLI's EXR (float32, lossless) holds the very values.
    frame = sky(SIZE, **SCENE)
    assert frame.image.shape == (32, 48, 3) and frame.image.dtype == np.float32
    assert np.array_equal(frame.image, cli_frame(cli, tmp_path))
    # Something is drawn: the sky's luminance is thousands of cd/m^2 and varies over the frame.
    assert frame.image.min() > 0 and frame.image.max() > 1000
    assert frame.stats["shape"] == "sphere" and frame.stats["positions"] == 1
    # The display values are the PNG's exposure of the same frame.
    assert frame.display.shape == frame.image.shape and 0 <= frame.display.min() and frame.display.max() <= 1


def test_polariser_agrees_with_the_cli(cli, tmp_path):
    frame = sky(SIZE, polarizer_deg=90, **SCENE)
    assert np.array_equal(frame.image, cli_frame(cli, tmp_path, "--polarizer-deg", "90"))


def test_polariser_follows_the_stokes_images():
    # A filter at A passes (I + Q cos 2A + U sin 2A) / 2 of the Stokes images, in each pixel's basis.
    iqu = sky(SIZE, stokes=True, **SCENE)
    assert iqu.image.shape == (32, 48, 9) and iqu.display is None
    i, q, u = iqu.image[..., 0:3], iqu.image[..., 3:6], iqu.image[..., 6:9]
    frames = {}
    for a in (0, 45, 90):
        frames[a] = sky(SIZE, polarizer_deg=a, **SCENE).image
        expect = (i + q * math.cos(math.radians(2 * a)) + u * math.sin(math.radians(2 * a))) / 2
        # float32 sums of values up to ~1e4 cd/m^2: a relative 1e-5 of the frame's peak.
        assert np.allclose(frames[a], expect, rtol=0, atol=1e-5 * float(i.max())), a
    # Crossed filters add up to the unfiltered light, and the sky is polarised: they differ.
    assert np.allclose(frames[0] + frames[90], i, rtol=0, atol=2e-5 * float(i.max()))
    assert np.abs(frames[0] - frames[90]).max() > 0.01 * float(i.max())


def test_drop_shapes():
    frame = sky((24, 16), shape="spheroid:0.9", radius_um=150, sampling=0.25, secondary=False, sun_elevation_deg=20,
                fov_deg=100, view_azimuth_deg=0, view_elevation_deg=15)
    assert frame.stats["shape"] == "spheroid:0.9" and frame.stats["positions"] == 19
    # The profiles state their error; above 1% a note names the sampling that would meet it.
    err = frame.stats["profile_error"]
    assert err is not None and 0 < err < 1
    if err > 0.01:
        assert len(frame.stats["notes"]) == 1 and "give sampling " in frame.stats["notes"][0]
    else:
        assert frame.stats["notes"] == []
    assert frame.stats["sampling"] == {"multiplier": 0.25, "automatic": False, "first_pass": None}
    assert np.isfinite(frame.image).all() and frame.image.min() > 0
    # Without a sampling the profiles choose theirs (1 here, under 1%: no second pass), as the CLI's do.
    chosen = sky((8, 8), radius_um=10)
    assert chosen.stats["sampling"] == {"multiplier": 1.0, "automatic": True, "first_pass": None}
    assert chosen.stats["profile_error"] < 0.01 and chosen.stats["notes"] == []
    with pytest.raises(ValueError, match=r"^shape 'egg': expected sphere, spheroid:Q"):
        sky((24, 16), shape="egg", **SCENE)
    with pytest.raises(ValueError, match=r"^shape beard-chuang: .* at most 89 degrees up \(sun_elevation_deg 90;"):
        sky((24, 16), shape="beard-chuang", sun_elevation_deg=90)


def refusal(cli, tmp_path, *flags):
    out = tmp_path / "refused.exr"
    radius = [] if "--radius-um" in flags else RADIUS
    p = cli("sky", *FLAGS, *radius, *flags, "-o", out, check=False)
    assert p.returncode == 2 and p.stderr.count("\n") == 1 and not out.exists(), p.stderr
    return p.stderr


def test_refuses_bad_values_with_the_clis_range(cli, tmp_path):
    # A declared value: the same range as the CLI's flag, named by the keyword.
    with pytest.raises(ValueError) as e:
        sky(SIZE, polarizer_deg=181)
    assert str(e.value).startswith("polarizer_deg = 181 is outside [-180, 180] deg")
    assert "[-180, 180] deg" in refusal(cli, tmp_path, "--polarizer-deg", "181")
    # The radius the tables computed here allow (Mie's size parameter limit): the CLI's words and bound.
    with pytest.raises(ValueError) as e:
        sky(SIZE, radius_um=4000, sampling=0.25)
    words = str(e.value)
    assert words.startswith("radius_um 4000 is outside the valid range [")
    assert words.replace("radius_um", "--radius-um").replace("hydrolux sky --lut", "--lut") in \
        refusal(cli, tmp_path, "--radius-um", "4000")
    # The size, span, colour and choices, declared as the CLI's flags, named by their keywords.
    with pytest.raises(ValueError, match=r"^size\[0\]: 0 is outside the valid range \[1, 16384\] px"):
        sky((0, 10))
    with pytest.raises(ValueError, match=r"^curtain_distance_m \(10, 5\): expected \(NEAR, FAR\)"):
        sky(SIZE, curtain_distance_m=(10, 5))
    with pytest.raises(ValueError, match=r"^light_color \(1, 2000, 1\): .* \[0, 1000\]"):
        sky(SIZE, light_color=(1, 2000, 1))
    with pytest.raises(ValueError, match=r"^mode 'dome'"):
        sky(SIZE, mode="dome")
    with pytest.raises(TypeError, match=r"^unknown sky option 'radius'"):
        sky(SIZE, radius=10)
    with pytest.raises(TypeError, match=r"^radius_um: expected a number"):
        sky(SIZE, radius_um="10")


def test_polariser_refusals_in_the_compositors_words(cli, tmp_path):
    # One check for every door (scene::check_polarization): the same sentence, each door's spelling.
    with pytest.raises(ValueError) as e:
        sky(SIZE, stokes=True, polarizer_deg=10, **SCENE)
    assert str(e.value) == ("stokes: the Stokes images are the light before any filter: ask for them or for a "
                            "polariser (polarizer_deg 10), not both")
    assert ("--stokes: the Stokes images are the light before any filter: ask for them or for a polariser "
            "(--polarizer-deg 10), not both") in refusal(cli, tmp_path, "--stokes", "--polarizer-deg", "10")
    with pytest.raises(ValueError, match=r"^stokes: the Stokes images need the physical blend"):
        sky(SIZE, stokes=True, blend="whitepaper", **SCENE)
    # The sky's degree of polarisation without anything that shows it.
    with pytest.raises(ValueError, match=r"^sky_max_dolp 0\.5: sets the sky's polarisation, which only a polariser "
                                         r"or the Stokes images show \(add polarizer_deg or stokes"):
        sky(SIZE, sky_max_dolp=0.5, **SCENE)
    assert "--sky-max-dolp 0.5: sets the sky's polarisation" in refusal(cli, tmp_path, "--sky-max-dolp", "0.5")


def test_signature_names_the_declared_parameters():
    import inspect
    params = inspect.signature(sky).parameters
    for p in hydrolux._core.params("sky"):
        assert p["name"] in params and params[p["name"]].default == p["default"]
    assert "polarizer_deg" in sky.__doc__ and "``stokes``" in sky.__doc__
