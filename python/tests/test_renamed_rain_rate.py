"""Issue 38: the rain rate has one name in every door, ``rain_rate_mmh`` (``--rain-rate-mmh``), and one range,
[0, 500] mm/h where a job takes no rain, [0.01, 500] mm/h where a size distribution needs a positive rate.
The names of earlier releases (``rate_mmh`` of hydrolux.rain and RainRenderer, ``rain_rate_mm_per_h`` of
SizeDistribution.marshall_palmer, the batch's ``--rate-mmh``) are taken for one release, each with a
DeprecationWarning naming the new keyword; the old and the new name together are a TypeError naming both."""
import pickle
import warnings

import numpy as np
import pytest

import hydrolux as h
from hydrolux.batch import rain as batch_rain
from hydrolux.batch.__main__ import main


def test_one_name_in_the_signatures_and_the_table():
    p = {q["name"]: q for q in h._core.params("rain")}
    assert "rate_mmh" not in p
    assert p["rain_rate_mmh"]["flag"] == "--rain-rate-mmh" and p["rain_rate_mmh"]["deprecated"] == "rate_mmh"
    assert p["rain_rate_mmh"]["range"] == "[0, 500] mm/h"
    sky = {q["name"]: q for q in h._core.params("sky")}
    assert sky["rain_rate_mmh"]["range"] == "[0, 500] mm/h" and sky["rain_rate_mmh"]["deprecated"] is None
    import inspect
    assert "rain_rate_mmh" in inspect.signature(h.rain).parameters
    assert "rate_mmh" not in inspect.signature(h.rain).parameters
    assert "rain_rate_mmh" in inspect.signature(h.SizeDistribution.marshall_palmer).parameters


def test_rain_old_keyword_warns_and_gives_the_same_result():
    scene = h.builtin_scene(64, 48)
    now = h.rain(scene, rain_rate_mmh=40, wind_mps=3, seed=4)
    with pytest.warns(DeprecationWarning, match="rate_mmh is deprecated.*give rain_rate_mmh") as caught:
        old = h.rain(scene, rate_mmh=40, wind_mps=3, seed=4)
    assert len([w for w in caught if issubclass(w.category, DeprecationWarning)]) == 1
    assert caught[0].filename == __file__  # said at the caller's line
    assert (old.image == now.image).all() and (old.mask == now.mask).all()
    assert old.stats == now.stats


def test_renderer_old_keyword_warns_and_pickles_with_the_new_name():
    scene = h.builtin_scene(64, 48)
    with pytest.warns(DeprecationWarning, match="give rain_rate_mmh") as caught:
        r = h.RainRenderer(64, 48, rate_mmh=25, seed=4)
    assert caught[0].filename == __file__
    new = h.RainRenderer(64, 48, rain_rate_mmh=25, seed=4)
    assert (r.render(scene, frame_index=2).image == new.render(scene, frame_index=2).image).all()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the copy is made from the new name: no warning again
        copy = pickle.loads(pickle.dumps(r))
    assert (copy.render(scene, frame_index=2).image == new.render(scene, frame_index=2).image).all()


def test_rain_old_and_new_keyword_together_is_a_type_error():
    scene = h.builtin_scene(32, 24)
    with pytest.raises(TypeError, match="rate_mmh: give rain_rate_mmh or rate_mmh"):
        h.rain(scene, rate_mmh=5, rain_rate_mmh=5)
    with pytest.raises(TypeError, match="rain_rate_mmh or rate_mmh"):
        h.RainRenderer(32, 24, rate_mmh=5, rain_rate_mmh=6)


def test_rain_old_keyword_has_the_new_range():
    with pytest.warns(DeprecationWarning), pytest.raises(ValueError, match=r"rain_rate_mmh = 600 is outside \[0, 500\]"):
        h.rain(h.builtin_scene(32, 24), rate_mmh=600)


def test_marshall_palmer_old_keyword_warns_and_gives_the_same_distribution():
    now = h.SizeDistribution.marshall_palmer(rain_rate_mmh=12.5)
    with pytest.warns(DeprecationWarning, match="rain_rate_mm_per_h is deprecated.*give rain_rate_mmh") as caught:
        old = h.SizeDistribution.marshall_palmer(rain_rate_mm_per_h=12.5)
    assert caught[0].filename == __file__
    assert old.number_concentration == now.number_concentration and old.mean_radius == now.mean_radius
    assert h.SizeDistribution.marshall_palmer(12.5).number_concentration == now.number_concentration
    with pytest.raises(TypeError, match="rain_rate_mm_per_h: give rain_rate_mmh or rain_rate_mm_per_h"):
        h.SizeDistribution.marshall_palmer(12.5, rain_rate_mm_per_h=12.5)
    with pytest.raises(TypeError, match="unexpected keyword argument 'rate'"):
        h.SizeDistribution.marshall_palmer(rate=12.5)


def test_marshall_palmer_takes_the_one_range():
    assert h.SizeDistribution.marshall_palmer(500).number_concentration > 0
    assert h.SizeDistribution.marshall_palmer(0.005).number_concentration > 0
    for rate in (600, 1000, 0, -1):
        with pytest.raises(ValueError, match=r"rain_rate_mmh = .* is outside .*500"):
            h.SizeDistribution.marshall_palmer(rate)


def test_batch_old_flag_warns_once_and_sets_the_rate(capfd):
    import argparse
    p = argparse.ArgumentParser()
    batch_rain.add_arguments(p)
    assert "--rate-mmh" not in p.format_help() and "--rain-rate-mmh" in p.format_help()
    a = p.parse_args(["--rate-mmh", "7.5"])
    batch_rain.parse_numbers(a)
    assert a.rain_rate_mmh == 7.5
    err = capfd.readouterr().err
    assert err == ("hydrolux.batch rain: warning: --rate-mmh is deprecated and will be removed in the next release: "
                   "give --rain-rate-mmh (the same value in mm/h)\n"), err
    b = p.parse_args(["--rain-rate-mmh", "7.5"])
    batch_rain.parse_numbers(b)
    assert capfd.readouterr().err == ""
    assert batch_rain._options(a) == batch_rain._options(b)


def test_batch_old_and_new_flag_together_exit_2(tmp_path, capfd):
    frames = tmp_path / "frames"
    frames.mkdir()
    assert main(["rain", "--input-dir", str(frames), "--output-dir", str(tmp_path / "o"), "--rate-mmh", "5",
                 "--rain-rate-mmh", "5", "-q"]) == 2
    err = capfd.readouterr().err.strip()
    assert "--rate-mmh" in err and "--rain-rate-mmh" in err and "\n" not in err, err


def test_batch_job_options_with_the_old_name_warn():
    job_options = {"rate_mmh": 25.0, "seed": 4}  # a job written before the rename
    with pytest.warns(DeprecationWarning, match="give rain_rate_mmh"):
        old = h.RainRenderer(48, 32, True, **job_options)
    new = h.RainRenderer(48, 32, True, rain_rate_mmh=25.0, seed=4)
    scene = h.builtin_scene(48, 32)
    assert np.array_equal(old.render(scene).image, new.render(scene).image)
