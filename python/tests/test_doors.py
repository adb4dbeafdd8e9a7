"""The same request through every door (issue 37's "Done means"): the CLI, the Python package and the
batch jobs give the same answer, or the same one-line refusal naming the same range, for what the
issue found each door handling its own way: drops flattened below the plane-section method's axis
ratio, a lens whose circle of confusion is wider than the sensor, and a good lens-drops frame."""
import json
import subprocess
import sys

import numpy as np
import pytest

import hydrolux as h


def batch(*args):
    return subprocess.run([sys.executable, "-m", "hydrolux.batch", *map(str, args)], capture_output=True,
                          text=True)


def one_line(err):
    assert "Traceback" not in err, err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1, err
    return lines[0]


# The refusal's own words, the same in every door (each door prefixes its program and flag or keyword).
FLAT = "axis_ratio = 0.75 is outside [0.77, 1]"
WIDE = "is no wider than the sensor (6.17 mm); or 0, a pinhole"


def test_drops_below_the_methods_axis_ratio_are_refused_alike(tmp_path, cli):
    p = cli("lee", "-q", "--theory", "airy", "--shape", "spheroid:0.75", "-o", tmp_path / "t.exr", check=False)
    assert p.returncode == 2
    assert FLAT in one_line(p.stderr)
    with pytest.raises(ValueError, match=r"axis_ratio = 0\.75 is outside \[0\.77, 1\]"):
        h.lee(theory="airy", shape="spheroid:0.75")
    spec = tmp_path / "atlas.json"
    spec.write_text(json.dumps({"defaults": {"size": "4x8", "wavelengths-nm": "380:780:4"},
                                "tables": [{"name": "flat", "theory": "airy", "shape": "spheroid:0.75"}]}))
    p = batch("lee-atlas", "--spec", spec, "--output-dir", tmp_path / "atlas", "-q")
    assert p.returncode == 2, p.stderr
    assert FLAT in one_line(p.stderr)
    assert not (tmp_path / "t.exr").exists() and not (tmp_path / "atlas" / "flat.exr").exists()


LENS = ["--f-number", "0.3", "--focus-m", "0.01", "--glass-distance-m", "10"]


def test_a_circle_of_confusion_wider_than_the_sensor_is_refused_alike(tmp_path, cli):
    frames = tmp_path / "frames"
    frames.mkdir()
    h.write_image(str(frames / "f0.png"), h.builtin_scene(64, 48))
    p = cli("lens-drops", "-q", "--image", frames / "f0.png", "-o", tmp_path / "o.png", *LENS, check=False)
    assert p.returncode == 2
    cli_line = line = one_line(p.stderr)
    assert WIDE in line and "--f-number 0.3 is outside the valid range [1.45721, 64]" in line, line
    assert "with --focus-m = 0.01 and --glass-distance-m = 10" in line, line
    with pytest.raises(ValueError, match=r"f_number = 0\.3 is outside \[1\.45.*no wider than the sensor"):
        h.lens_drops(h.builtin_scene(64, 48), f_number=0.3, focus_m=0.01, glass_distance_m=10)
    p = batch("lens-drops", "--input-dir", frames, "--output-dir", tmp_path / "out", "-q", *LENS)
    assert p.returncode == 2, p.stderr
    # The batch says it in the CLI's words: the library's error spells each parameter it names (the one
    # refused, and those its range follows from) by the door's flags, no text rewritten.
    assert one_line(p.stderr).replace("hydrolux.batch lens-drops:", "hydrolux lens-drops:") == cli_line
    assert not (tmp_path / "o.png").exists() and not (tmp_path / "out").exists()


def test_a_good_lens_drops_frame_is_the_same_in_every_door(tmp_path, cli):
    frames = tmp_path / "frames"
    frames.mkdir()
    clean = h.builtin_scene(96, 64)
    h.write_image(str(frames / "f0.exr"), clean)
    cli("lens-drops", "-q", "--image", frames / "f0.exr", "-o", tmp_path / "cli.exr", "--seed", "4")
    assert batch("lens-drops", "--input-dir", frames, "--output-dir", tmp_path / "out", "--seed", "4",
                 "-q").returncode == 0
    from_cli = h.read_image(str(tmp_path / "cli.exr"))
    from_batch = h.read_image(str(tmp_path / "out" / "f0.exr"))
    from_python = h.lens_drops(h.read_image(str(frames / "f0.exr")), seed=4).image
    np.testing.assert_array_equal(from_batch, from_cli)
    np.testing.assert_array_equal(np.asarray(from_python, dtype=np.float32), from_cli[..., :from_python.shape[2]])
