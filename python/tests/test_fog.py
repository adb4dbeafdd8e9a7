"""hydrolux.fog (rain/fog.hpp; docs/fog.md): the transmittance exp(-beta d) per pixel for a known
depth map, the airlight at infinite depth, the Mie route, the same floats twice, and bad keywords as
ValueErrors naming them."""
import math

import numpy as np
import pytest

import hydrolux


def _frame(h=40, w=64):
    rng = np.random.default_rng(3)
    return rng.uniform(0.05, 0.5, size=(h, w, 3)).astype(np.float32)


def test_transmittance_per_pixel_and_airlight():
    img = _frame()
    h, w = img.shape[:2]
    depth = np.fromfunction(lambda y, x: 5 + 2.5 * x + 3 * y, (h, w)).astype(np.float32)
    depth[:4] = np.inf  # sky
    out, mask, stats = hydrolux.fog(img, depth, visibility_m=180, glow=False)
    beta = 3.912023005428146 / 180
    assert stats["beta_per_m"] == pytest.approx(beta, rel=1e-12)
    # The default camera: 35 mm on a 36 mm sensor, the principal point at the centre.
    f = 35 / 36 * w
    ys, xs = np.mgrid[0:h, 0:w]
    px, py = xs + 0.5 - w / 2, h / 2 - (ys + 0.5)
    cos = f / np.sqrt(px * px + py * py + f * f)
    t = np.where(np.isfinite(depth), np.exp(-beta * np.where(np.isfinite(depth), depth, 0) / cos), 0.0)
    np.testing.assert_allclose(mask[..., 0], 1 - t, atol=1e-6)
    sky = np.array(stats["sky_rgb"])
    np.testing.assert_allclose(out, img * t[..., None] + sky * (1 - t[..., None]), atol=2e-6)
    np.testing.assert_allclose(out[:4], np.broadcast_to(sky, out[:4].shape), atol=1e-6)  # infinite depth: the sky


def test_mie_route_and_determinism():
    img = _frame()
    a = hydrolux.fog(img, lwc_g_m3=0.37, mode_radius_um=10, size_alpha=3)
    b = hydrolux.fog(img, lwc_g_m3=0.37, mode_radius_um=10, size_alpha=3)
    assert (a.image == b.image).all() and (a.mask == b.mask).all()
    # Shettle & Fenn's heavy advection fog: ~20 drops per cm^3, visibility ~130 m.
    assert a.stats["number_per_cm3"] == pytest.approx(20, rel=0.15)
    assert a.stats["visibility_m"] == pytest.approx(130, rel=0.15)
    assert math.isnan(hydrolux.fog(img, visibility_m=100).stats["lwc_g_m3"])


@pytest.mark.parametrize("kw,name", [
    (dict(), "visibility_m"),
    (dict(visibility_m=0.5), "visibility_m"),
    (dict(visibility_m=float("nan")), "visibility_m"),
    (dict(visibility_m=100, lwc_g_m3=0.1), "lwc_g_m3"),
    (dict(lwc_g_m3=10), "lwc_g_m3"),
    (dict(visibility_m=100, mode_radius_um=100), "mode_radius_um"),
    (dict(visibility_m=100, size_alpha=0), "size_alpha"),
    (dict(visibility_m=100, fov_deg=200), "fov_deg"),
])
def test_bad_keywords_name_themselves(kw, name):
    with pytest.raises(ValueError, match=name):
        hydrolux.fog(_frame(), **kw)


def test_bad_arrays():
    with pytest.raises(ValueError, match="depth"):
        hydrolux.fog(_frame(), np.ones((3, 3), np.float32), visibility_m=100)
    bad = _frame()
    bad[2, 3, 1] = np.nan
    with pytest.raises(ValueError, match="image"):
        hydrolux.fog(bad, visibility_m=100)
    with pytest.raises(TypeError, match="nope"):
        hydrolux.fog(_frame(), visibility_m=100, nope=1)


def test_sky_rgb_given():
    img = _frame()
    out, mask, stats = hydrolux.fog(img, None, (0.3, 0.2, 0.1), visibility_m=100, glow=False)
    assert stats["sky_rgb"] == (0.3, 0.2, 0.1)
    with pytest.raises(ValueError, match="sky_rgb"):
        hydrolux.fog(img, None, (1, 2), visibility_m=100)
    with pytest.raises(ValueError, match="sky_rgb"):
        hydrolux.fog(img, None, (1, -2, 0), visibility_m=100)


def test_batch_fog_matches_the_cli(tmp_path, batch_matches_cli):
    """python3 -m hydrolux.batch fog writes the CLI's bytes (one sky from the first frame for all)."""
    from hydrolux.batch.__main__ import main

    batch_matches_cli("fog", "--visibility-m", 90)
    assert main(["fog", "--input-dir", str(tmp_path / "frames"), "--output-dir", str(tmp_path / "x"),
                 "--visibility-m", "0.5", "-q"]) == 2
    assert not (tmp_path / "x").exists()


def test_rain_with_fog_is_one_pass_and_without_rain_the_fog_alone():
    """hydrolux.rain(..., visibility_m=V): fog and rain in one veil (docs/fog.md, "With rain"); at
    0 mm/h it is hydrolux.fog on the same depth (float compositing: 1e-5)."""
    img = _frame()
    h, w = img.shape[:2]
    depth = np.full((h, w), 60, np.float32)
    r = hydrolux.rain(img, depth, rain_rate_mmh=0, visibility_m=150, glow=False)
    f, _, _ = hydrolux.fog(img, depth, visibility_m=150, glow=False)
    np.testing.assert_allclose(r.image, f, atol=1e-5)
    assert r.stats["fog"]["visibility_m"] == pytest.approx(150)
    wet = hydrolux.rain(img, depth, rain_rate_mmh=25, visibility_m=150, glow=False)
    assert wet.stats["drops_in_view"] > 0 and "fog" in wet.stats
    assert "fog" not in hydrolux.rain(img, depth, rain_rate_mmh=25).stats


def test_rain_fog_setting_without_fog_is_refused():
    with pytest.raises(ValueError, match="mode_radius_um"):
        hydrolux.rain(_frame(), rain_rate_mmh=5, mode_radius_um=4)
