"""hydrolux.renderer_medium against hydrolux medium: one job (scatter/renderer_export.hpp), so the same
file bytes; the arrays are the file's numbers; the table integrates to 1 over the sphere as Mitsuba's
tabphase integrates it; bad arguments named in the error."""
import numpy as np
import pytest

import hydrolux


@pytest.mark.parametrize("fmt,ext", [("mitsuba3", "xml"), ("pbrt-v4", "pbrt")])
def test_the_text_is_the_clis_file(cli, tmp_path, fmt, ext):
    out = tmp_path / f"fog.{ext}"
    cli("medium", "-q", "--radius-um", "4", "--size-distribution", "gamma:0.2", "--number-per-cm3", "100",
        "--nodes", "16", "--values", "513", "--name", "fog", "-o", out)
    m = hydrolux.renderer_medium(4, "gamma:0.2", number_per_cm3=100, nodes=16, values=513, format=fmt, name="fog")
    assert m.text == out.read_text()
    assert m.info["format"] == fmt


def test_arrays_and_normalisation():
    m = hydrolux.renderer_medium(3, "gamma:0.2", number_per_cm3=50, nodes=16, values=1025)
    assert m.wavelength_nm.tolist() == list(np.arange(360.0, 831.0, 10.0))
    # 2 pi times the trapezoid integral over cos theta (tabphase's interpolation): 1 to rounding.
    mu = np.linspace(-1, 1, len(m.phase))
    assert abs(2 * np.pi * np.sum((m.phase[1:] + m.phase[:-1]) / 2 * np.diff(mu)) - 1) < 1e-12
    np.testing.assert_allclose(m.sigma_t_per_m, m.sigma_s_per_m + m.sigma_a_per_m, rtol=1e-15)
    np.testing.assert_array_equal(m.albedo, m.sigma_s_per_m / m.sigma_t_per_m)
    assert m.info["cut_deg"] == 0 and m.info["l1_error"] > 0
    assert m.info["phase_smoothed"] is False  # rain's alone (its default table: test_claims_renderer_medium.cpp)
    assert abs(m.info["normalisation"] - 1) <= m.info["l1_error"]
    # The spectra's size average states its radii and estimated error (held against a finer rule by
    # tests/scatter/test_renderer_export.cpp); one radius has none.
    assert m.info["spectra_radii"] >= 65 and set(m.info["spectra_error"]) == {"extinction", "g"}
    assert 0 <= m.info["spectra_error"]["extinction"] < 0.005
    one = hydrolux.renderer_medium(3, number_per_cm3=50, values=257)
    assert one.info["spectra_error"] is None and one.info["spectra_radii"] == 0


@pytest.mark.parametrize("kwargs,message", [
    (dict(radius_um=10), "number_per_cm3"),
    (dict(radius_um=10, number_per_cm3=1, lwc_g_m3=1), "lwc_g_m3"),
    (dict(radius_um=10, number_per_cm3=1, format="blender"), "format"),
    (dict(radius_um=10, number_per_cm3=1, values=2), "values"),
    (dict(radius_um=10, number_per_cm3=1, name="a b"), "name"),
    (dict(radius_um=10, number_per_cm3=1, phase_wavelength_nm=900), "phase_wavelength_nm"),
    (dict(radius_um=None, size_distribution="marshall-palmer:5", number_per_cm3=1), "number_per_cm3"),
])
def test_bad_arguments_are_named(kwargs, message):
    with pytest.raises(ValueError, match=message):
        hydrolux.renderer_medium(**kwargs)
