"""hydrolux.detect_rain, hydrolux.remove_rain and hydrolux.eval.score (docs/rain-detection.md): the CLI's
masks from the same frames, the oracle against the composite it inverts, scores counted by hand, and
bad arguments refused."""
import numpy as np
import pytest

import hydrolux


@pytest.fixture(scope="module")
def sequence():
    """Six frames of the built-in street at 160 x 90 with rain of 80 mm/h at 8 ms (streaks only), their
    masks and layers, and the clear frame."""
    clear = hydrolux.builtin_scene(160, 90)
    r = hydrolux.RainRenderer(160, 90, seed=2, rain_rate_mmh=80, unresolved=False)
    out = [r.render(clear, frame_index=k, with_layer=True) for k in range(6)]
    return clear, out


def test_detect_rain_gives_the_clis_masks(tmp_path, cli, sequence):
    clear, out = sequence
    frames = [o.image for o in out]
    (tmp_path / "in").mkdir()
    for k, f in enumerate(frames):
        hydrolux.write_image(str(tmp_path / "in" / f"f{k}.exr"), f)
    d = hydrolux.detect_rain(frames, exposure_s=0.008)
    assert d.masks.shape == (6, 90, 160) and d.masks.dtype == np.uint8
    assert (d.masks <= d.photometric).all() and (d.photometric <= d.candidates).all()
    assert d.masks[0].sum() == 0 and d.masks[-1].sum() == 0
    assert d.candidates.sum() > 0
    cli("detect-rain", "-q", "--exposure-s", 0.008, "--input-dir", tmp_path / "in", "--output-dir", tmp_path / "m")
    for k in range(6):
        m = hydrolux.read_image(str(tmp_path / "m" / f"f{k}.png"))[..., 0]
        assert ((m > 0) == (d.masks[k] > 0)).all(), k
    base = hydrolux.detect_rain(np.stack(frames), method="candidates")
    assert base.photometric is None and (base.masks == d.candidates).all()


def test_remove_rain_oracle_inverts_the_composite(sequence):
    clear, out = sequence
    frames = [o.image for o in out]
    back = hydrolux.remove_rain(frames, layers=[o.layer for o in out], method="oracle")
    assert back.shape == (6, 90, 160, 3)
    # image = clear (1 - alpha) + layer in float32: inverted to float rounding where alpha is below 0.99
    alpha = np.stack([o.layer[..., 3] for o in out])
    ok = alpha < 0.99
    assert np.abs(back - clear[None])[ok].max() < 1e-4
    med = hydrolux.remove_rain(frames, method="median", median_frames=3)
    assert med.shape == back.shape
    gn = hydrolux.remove_rain(frames, masks=hydrolux.detect_rain(frames, exposure_s=0.008).masks)
    assert gn.shape == back.shape


def test_scores_counted_by_hand():
    truth = np.array([[[0.5, 0.05, 0.3, 0.02], [0.0, 0.0, 0.009, 0.0]]], dtype=np.float32)
    pred = np.array([[[1, 1, 0, 1], [1, 0, 0, 0]]], dtype=np.uint8)
    s = hydrolux.eval.score(pred, truth)
    o = s["overall"]
    assert (o["true_positive"], o["false_negative"], o["ignored"], o["false_positive"], o["true_negative"]) == \
        (2, 1, 1, 1, 3)
    assert o["precision"] == pytest.approx(2 / 3) and o["iou"] == pytest.approx(0.5)
    assert len(s["frames"]) == 1
    assert hydrolux.eval.score(pred, truth, rain_alpha=0.4)["overall"]["true_positive"] == 1
    clean = np.zeros((1, 2, 4, 3), np.float32)
    derained = clean.copy()
    derained[0, 0, 0] = 1.0  # 255 codes off in the one rain pixel's three channels... and 0 elsewhere
    s = hydrolux.eval.score(pred, truth, clean, derained)
    assert s["overall"]["psnr_out_mask"] == float("inf")
    assert s["overall"]["psnr_in_mask"] == pytest.approx(10 * np.log10(3))  # 3 pixels in the rain, 1 off


def test_bad_arguments_are_refused():
    frames = [np.zeros((8, 8, 3), np.float32)] * 3
    with pytest.raises(TypeError, match="unknown detect_rain option 'c'"):
        hydrolux.detect_rain(frames, c=3)
    with pytest.raises(ValueError, match="min_change_grey"):
        hydrolux.detect_rain(frames, min_change_grey=0)
    with pytest.raises(ValueError, match="at least 3"):
        hydrolux.detect_rain(frames[:2])
    with pytest.raises(ValueError, match="masks"):
        hydrolux.remove_rain(frames)
    with pytest.raises(ValueError, match="layers"):
        hydrolux.remove_rain(frames, method="oracle")
    with pytest.raises(ValueError, match="channels"):
        hydrolux.remove_rain([frames[0], np.zeros((8, 8, 1), np.float32), frames[0]], method="median")
    nan = np.zeros((8, 8, 3), np.float32)
    nan[2, 3, 1] = np.nan
    with pytest.raises(ValueError, match=r"frames\[1\]: a non-finite value"):
        hydrolux.detect_rain([frames[0], nan, frames[0]])
    with pytest.raises(ValueError, match="derained"):
        hydrolux.eval.score([np.zeros((8, 8))], [np.zeros((8, 8))], clean=frames[:1])
