"""hydrolux.lens_drops (docs/lens-drops.md): the CLI's declared parameters as keywords, the same
bytes for a seed, the mask 0 away from the drops, and ranges refused as ValueErrors naming the
keyword."""
import numpy as np
import pytest

import hydrolux


@pytest.fixture(scope="module")
def clean():
    return hydrolux.builtin_scene(160, 120)


def test_shapes_determinism_and_mask(clean):
    out, mask = hydrolux.lens_drops(clean, seed=5, coverage=0.2)
    assert out.shape == clean.shape and out.dtype == np.float32
    assert mask.shape == (120, 160, 1)
    assert 0 <= mask.min() and mask.max() <= 1
    assert 0.1 < mask.mean() < 0.5
    again = hydrolux.lens_drops(clean, seed=5, coverage=0.2)
    assert (again.image == out).all() and (again.mask == mask).all()
    other = hydrolux.lens_drops(clean, seed=6, coverage=0.2)
    assert not (other.mask == mask).all()
    clear = mask[..., 0] == 0
    assert clear.any()
    assert (out[clear] == clean[clear]).all()


def test_pinhole_mask_is_one_inside_large_drops(clean):
    _, mask = hydrolux.lens_drops(clean, seed=1, drops=5, min_radius_mm=4, max_radius_mm=5, f_number=0)
    assert np.isclose(mask.max(), 1, atol=1e-5)


@pytest.mark.parametrize("kw,name", [
    ({"contact_angle_deg": 95}, "contact_angle_deg"),
    ({"samples": 0}, "samples"),
    ({"glass_distance_m": float("nan")}, "glass_distance_m"),
    ({"min_radius_mm": 3, "max_radius_mm": 1}, "max_radius_mm"),
    ({"drops": 4, "coverage": 0.1}, "coverage"),
])
def test_bad_keywords_are_value_errors_naming_them(clean, kw, name):
    with pytest.raises(ValueError, match=name):
        hydrolux.lens_drops(clean, **kw)


def test_unknown_keyword_is_a_type_error(clean):
    with pytest.raises(TypeError, match="unknown lens_drops option"):
        hydrolux.lens_drops(clean, rain_rate_mmh=3)


def test_batch_lens_drops_matches_the_cli(tmp_path, batch_matches_cli):
    """python3 -m hydrolux.batch lens-drops writes the CLI's bytes (frame k with seed + k), in chunks."""
    from hydrolux.batch.__main__ import main

    out = batch_matches_cli("lens-drops", "--seed", 41, "--drops", 20)
    assert (out / "f0.png").read_bytes() != (out / "f1.png").read_bytes()  # each frame its own drops
    assert main(["lens-drops", "--input-dir", str(tmp_path / "frames"), "--output-dir", str(tmp_path / "x"),
                 "--contact-angle-deg", "200", "-q"]) == 2
    assert not (tmp_path / "x").exists()
