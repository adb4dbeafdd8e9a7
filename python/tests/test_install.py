"""The package pip's way (pyproject.toml; setup.py driving the CMake build), with Debian's tools only
(python3-venv with its pip, setuptools, wheel, python3-build; no package index): `pip install
--no-build-isolation .` into a fresh virtual environment, and a wheel from `python3 -m build --wheel
--no-isolation` installed into another. Each imports from another folder (not the build tree), has
CMake's version, finds the CLI it carries and runs the `hydrolux` console script; a second install
replaces the first. HYDROLUX_BUILD_DIR points the build at ctest's own build folder, so nothing is
compiled again."""
import os
import re
import subprocess
import sys
import zipfile

ROOT = os.path.abspath(os.environ.get("HYDROLUX_SOURCE_DIR") or os.path.join(os.path.dirname(__file__), "..", ".."))


def _cmake_version():
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        return re.search(r"project\(hydrolux\s+VERSION\s+([0-9.]+)", f.read()).group(1)


def _env(cli):
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "HYDROLUX_CLI")}
    env["HYDROLUX_BUILD_DIR"] = os.path.dirname(os.path.dirname(os.path.abspath(cli.path)))
    env["PIP_NO_INDEX"] = "1"  # nothing downloaded: numpy comes from Debian through --system-site-packages
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
    return env


def _venv(path):
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(path)], check=True)
    return path


def _pip_install(venv, what, env, cwd):
    p = subprocess.run([str(venv / "bin" / "pip"), "install", "--no-build-isolation", str(what)], capture_output=True,
                       text=True, env=env, cwd=str(cwd))
    assert p.returncode == 0, p.stdout + p.stderr


def _check(venv, env, cwd):
    code = ("import hydrolux, hydrolux.batch.lee_atlas as la\n"
            "print(hydrolux.__file__)\n"
            "print(la.cli_path())\n"
            "print(hydrolux.__version__)\n"
            "print(hydrolux.mie(1.333, [1.0, 10.0], angles_deg=None).qext.shape)\n")
    out = subprocess.run([str(venv / "bin" / "python"), "-c", code], capture_output=True, text=True, env=env,
                         cwd=str(cwd), check=True).stdout.splitlines()
    assert out[0].startswith(str(venv)) and out[1].startswith(str(venv)), out
    assert out[2] == _cmake_version() and out[3] == "(2,)", out
    v = subprocess.run([str(venv / "bin" / "hydrolux"), "--version"], capture_output=True, text=True, env=env,
                       cwd=str(cwd))
    assert v.returncode == 0 and _cmake_version() in v.stdout, v.stdout + v.stderr
    # The console script passes the CLI's usage errors through: exit 2, one line.
    bad = subprocess.run([str(venv / "bin" / "hydrolux"), "mie", "--m", "1.33", "--x", "-1"], capture_output=True,
                         text=True, env=env, cwd=str(cwd))
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1, bad.stderr
    # The CLI finds its NetCDF plugin beside itself in the installed copy.
    nc = subprocess.run([str(venv / "bin" / "hydrolux"), "mie", "--m", "1.33", "--x", "10", "--angles-deg", "0:180:3",
                         "-o", "p.nc"], capture_output=True, text=True, env=env, cwd=str(cwd))
    assert nc.returncode == 0 and (cwd / "p.nc").stat().st_size > 0, nc.stderr
    (cwd / "p.nc").unlink()


def test_pip_install_and_wheel(tmp_path, cli):
    env = _env(cli)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()

    venv = _venv(tmp_path / "pip")
    _pip_install(venv, ROOT, env, elsewhere)
    _check(venv, env, elsewhere)
    _pip_install(venv, ROOT, env, elsewhere)  # again: replaces the first
    _check(venv, env, elsewhere)

    dist = tmp_path / "dist"
    p = subprocess.run([sys.executable, "-m", "build", "--wheel", "--no-isolation", "--outdir", str(dist), ROOT],
                       capture_output=True, text=True, env=env, cwd=str(elsewhere))
    assert p.returncode == 0, p.stdout + p.stderr
    wheels = sorted(dist.glob("hydrolux-*.whl"))
    assert len(wheels) == 1, wheels
    tag = f"cp{sys.version_info.major}{sys.version_info.minor}"
    assert wheels[0].name.startswith(f"hydrolux-{_cmake_version()}-{tag}-{tag}-linux_"), wheels[0].name
    with zipfile.ZipFile(wheels[0]) as z:
        names = set(z.namelist())
        assert {"hydrolux/bin/hydrolux", "hydrolux/bin/libhydrolux_image_plugin.so",
                "hydrolux/bin/libhydrolux_video_plugin.so", "hydrolux/bin/libhydrolux_netcdf_plugin.so",
                "hydrolux/_cli.py", "hydrolux/_xarray.py", "hydrolux/batch/rain.py"} <= names
        assert any(n.startswith("hydrolux/_core.") and n.endswith(".so") for n in names)
        assert (z.getinfo("hydrolux/bin/hydrolux").external_attr >> 16) & 0o111  # executable
    venv2 = _venv(tmp_path / "wheel")
    _pip_install(venv2, wheels[0], env, elsewhere)
    _check(venv2, env, elsewhere)
