"""hydrolux.phase against hydrolux phase: one job (scatter/phase_job.hpp), so the same numbers (the
CLI's --csv digits, compared as text), the same metadata, the Mueller identity of one sphere and its
failure for a size average, and bad arguments named in the error."""
import numpy as np
import pytest

import hydrolux

COLUMNS = ("i1", "i2", "phase", "s11", "s12", "s33", "s34")


def cli_csv(cli, *args):
    """The rows of hydrolux phase --csv: the header and, per angle, the angle (float) and the other
    columns as the CLI printed them (text)."""
    lines = cli("phase", "-q", "--csv", *args).stdout.splitlines()
    rows = [line.split(",") for line in lines[1:]]
    return lines[0], [float(r[0]) for r in rows], [r[1:] for r in rows]


def assert_same_as_cli(cli, result, cli_args, mueller):
    header, angles, rows = cli_csv(cli, *cli_args)
    assert header == "theta_deg,i1,i2,i" + (",s11,s12,s33,s34" if mueller else "")
    assert result.angles_deg.tolist() == angles  # the CLI's parser: the same angles, bit for bit
    columns = COLUMNS if mueller else COLUMNS[:3]
    ours = [[f"{getattr(result, c)[k]:.10e}" for c in columns] for k in range(len(angles))]
    assert ours == rows


@pytest.mark.parametrize("mueller", [False, True])
def test_one_drop_is_the_cli(cli, mueller):
    p = hydrolux.phase(10, 550, angles_deg="0:180:37", mueller=mueller)
    assert_same_as_cli(cli, p, ["--radius-um", "10", "--wavelength-nm", "550", "--angles-deg", "0:180:37"] +
                       (["--mueller"] if mueller else []), mueller)
    assert p.phase.dtype == np.float64 and p.phase.shape == (37,)
    assert (p.s11 is None) == (not mueller) and (p.pol is None) == (not mueller)
    if mueller:
        np.testing.assert_array_equal(p.pol, -p.s12 / p.s11)
        np.testing.assert_array_equal(p.s11, p.phase)


def test_gamma_distribution_is_the_cli(cli):
    args = dict(size_distribution="gamma:0.1", nodes=8, angles_deg="0:180:19", mueller=True)
    p = hydrolux.phase(20, 550, **args)
    assert_same_as_cli(cli, p, ["--radius-um", "20", "--wavelength-nm", "550", "--size-distribution", "gamma:0.1",
                                "--nodes", "8", "--angles-deg", "0:180:19", "--mueller"], True)
    assert p.info["radii"] == 8 and p.info["x"] is None
    assert p.info["radius_um"].shape == (8,) and p.info["weight"].shape == (8,)


def test_theories_temperature_and_array_angles_are_the_cli(cli):
    angles = np.array([137.0, 138.0, 139.0, 140.0])
    p = hydrolux.phase(200, 550, theory="debye:2", angles_deg=angles, temperature_c=20, threads=1)
    assert_same_as_cli(cli, p, ["--radius-um", "200", "--wavelength-nm", "550", "--theory", "debye:2",
                                "--angles-deg", "137,138,139,140", "--temperature-c", "20", "--threads", "1"], False)
    rain = hydrolux.phase(None, 650, theory="airy", size_distribution="marshall-palmer:5", nodes=3,
                          angles_deg="130:145:4")
    assert_same_as_cli(cli, rain, ["--wavelength-nm", "650", "--theory", "airy", "--size-distribution",
                                   "marshall-palmer:5", "--nodes", "3", "--angles-deg", "130:145:4"], False)


def test_info_is_what_the_cli_header_states(cli):
    p = hydrolux.phase(200, 550, theory="airy", angles_deg=[138])
    header = cli("phase", "--radius-um", "200", "--wavelength-nm", "550", "--theory", "airy",
                 "--angles-deg", "138").stdout.splitlines()
    m, x = p.info["m"], p.info["x"]
    assert header[0] == (f"# theory {p.info['theory']}, {p.info['drops']}, wavelength 550 nm: "
                         f"m = {m.real:.6g}{m.imag:+.3g}i, x = {x:.6g}")
    assert p.info["theory"] == "airy:2" and p.info["drops"] == "radius 200 um"
    assert [f"# {n}" for n in p.info["notes"]] == header[1:2]
    assert header[1].startswith("# Airy theory approximates order 2")


def test_mueller_identity_holds_for_one_sphere_only():
    one = hydrolux.phase(10, 550, angles_deg="0:180:91", mueller=True)
    lhs, rhs = one.s11 ** 2, one.s12 ** 2 + one.s33 ** 2 + one.s34 ** 2
    np.testing.assert_allclose(rhs, lhs, rtol=1e-12)
    avg = hydrolux.phase(10, 550, size_distribution="gamma:0.2", nodes=16, angles_deg="0:180:91", mueller=True)
    lhs, rhs = avg.s11 ** 2, avg.s12 ** 2 + avg.s33 ** 2 + avg.s34 ** 2
    inner = slice(1, -1)  # at 0 and 180 degrees S1 = +-S2 for every size: no depolarisation there
    assert np.all(rhs[inner] < lhs[inner] * (1 - 1e-9))
    np.testing.assert_allclose(rhs[[0, -1]], lhs[[0, -1]], rtol=1e-12)
    assert np.all(np.abs(avg.pol) <= 1)


@pytest.mark.parametrize("kwargs, name", [
    (dict(nodes=0), "nodes"),
    (dict(nodes=5000), "nodes"),
    (dict(threads=-1), "threads"),
    (dict(temperature_c=150), "temperature_c"),
    (dict(temperature_c=20, medium="ice"), "temperature_c"),
    (dict(theory="foo"), "theory"),
    (dict(theory="debye:-1"), "theory"),
    (dict(size_distribution="gamma:2"), "size_distribution"),
    (dict(size_distribution="cauchy:1"), "size_distribution"),
    (dict(radius_um=-1), "radius_um"),
    (dict(radius_um=None, size_distribution="gamma:0.1"), "radius_um"),
    (dict(wavelength_nm=2000), "wavelength_nm"),
    (dict(wavelength_nm=0), "wavelength_nm"),
    (dict(angles_deg=[0, 190]), "angles_deg"),
    (dict(angles_deg="0:190:3"), "angles_deg"),
    (dict(medium="foo"), "medium"),
    (dict(surrounding="const:0"), "surrounding"),
    (dict(theory="airy", medium="const:2.5"), "medium"),
])
def test_bad_values_are_value_errors_naming_the_keyword(kwargs, name):
    args = dict(radius_um=10, wavelength_nm=550, angles_deg=[0, 90])
    args.update(kwargs)
    with pytest.raises(ValueError, match=name) as e:
        hydrolux.phase(**args)
    assert "\n" not in str(e.value)


@pytest.mark.parametrize("kwargs, name", [
    (dict(nodes="8"), "nodes"),
    (dict(tolerance="0.01"), "tolerance"),
    (dict(mueller=1), "mueller"),
    (dict(theory=None), "theory"),
    (dict(radius_um="10"), "radius_um"),
    (dict(wavelength_nm=None), "wavelength_nm"),
    (dict(angles_deg=None), "angles_deg"),
    (dict(temperature_c="20"), "temperature_c"),
])
def test_wrong_types_are_type_errors_naming_the_keyword(kwargs, name):
    args = dict(radius_um=10, wavelength_nm=550, angles_deg=[0, 90])
    args.update(kwargs)
    with pytest.raises(TypeError, match=name):
        hydrolux.phase(**args)


def test_a_size_average_chooses_its_radii_to_the_tolerance_unless_given_a_count():
    """Without ``nodes`` the average refines its radii until two spacings agree to half the tolerance
    and a grid shifted by 0.618 of the last spacing agrees too (the same job as ``hydrolux phase``; its
    accuracy against a finer grid: tests/scatter/test_phase_job.cpp)."""
    auto = hydrolux.phase(2, 550, size_distribution="gamma:0.1", angles_deg=[0, 90, 180])
    assert auto.info["tolerance"] == 0.005 and auto.info["last_change"] < 0.0025
    assert 0 < auto.info["shifted_change"] < 0.0025
    assert auto.info["radii"] == auto.info["radius_um"].size >= 65
    # The estimated error per Mueller element: the last change times at most 4, or the shifted grid's
    # difference where that is larger (docs/mie.md); the loose average's estimate is the larger (the
    # C++ test holds each against a finer grid).
    assert set(auto.info["error"]) == {"s11", "s12", "s33", "s34"}
    bound = max(4 * auto.info["last_change"], auto.info["shifted_change"])
    assert all(0 <= e <= bound for e in auto.info["error"].values())
    assert "radii" not in auto.info["drops"]  # the count is the job's own choice, stated in info["radii"]
    loose = hydrolux.phase(2, 550, size_distribution="gamma:0.1", angles_deg=[0, 90, 180], tolerance=0.05)
    assert loose.info["radii"] <= auto.info["radii"] and loose.info["last_change"] < 0.025
    assert np.allclose(loose.phase, auto.phase, rtol=0.05, atol=0)
    assert max(loose.info["error"].values()) > max(auto.info["error"].values())
    fixed = hydrolux.phase(2, 550, size_distribution="gamma:0.1", angles_deg=[90], nodes=16)
    assert fixed.info["radii"] == 16 and fixed.info["last_change"] is None and fixed.info["tolerance"] is None
    assert fixed.info["error"] is None and fixed.info["shifted_change"] is None
    with pytest.raises(ValueError, match="give nodes or tolerance, not both"):
        hydrolux.phase(2, 550, size_distribution="gamma:0.1", nodes=16, tolerance=0.01)
    with pytest.raises(ValueError, match="tolerance 0.01: size_distribution mono is one radius"):
        hydrolux.phase(2, 550, tolerance=0.01)
