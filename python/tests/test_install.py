"""scripts/install-python into a fresh virtual environment made with Debian's tools (python3-venv):
the package imports there without PYTHONPATH, from another folder, with the CLI beside it."""
import os
import subprocess
import sys

ROOT = os.environ.get("HYDROLUX_SOURCE_DIR") or os.path.join(os.path.dirname(__file__), "..", "..")


def test_install_into_a_venv(tmp_path, cli):
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", str(venv)], check=True)
    build = os.path.dirname(os.path.dirname(os.path.abspath(cli.path)))
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "HYDROLUX_CLI")}
    env["BUILD_DIR"] = build
    p = subprocess.run([os.path.join(ROOT, "scripts", "install-python"), str(venv)], capture_output=True, text=True,
                       env=env)
    assert p.returncode == 0, p.stderr
    code = ("import hydrolux, hydrolux.batch.lee_atlas as la, os\n"
            "print(hydrolux.__file__)\n"
            "print(la.cli_path())\n"
            "print(hydrolux.mie(1.333, [1.0, 10.0], angles_deg=None).qext.shape)\n")
    out = subprocess.run([str(venv / "bin" / "python3"), "-c", code], capture_output=True, text=True, env=env,
                         cwd=str(tmp_path), check=True).stdout.splitlines()
    assert out[0].startswith(str(venv)) and out[1].startswith(str(venv)) and out[2] == "(2,)"
    v = subprocess.run([str(venv / "bin" / "hydrolux"), "--version"], capture_output=True, text=True, env=env)
    assert v.returncode == 0 and v.stdout.strip()
    # A second install replaces the first in place.
    assert subprocess.run([os.path.join(ROOT, "scripts", "install-python"), str(venv)], capture_output=True,
                          env=env).returncode == 0
    platlib = os.path.dirname(os.path.dirname(out[0]))  # .../site-packages/hydrolux/__init__.py
    assert not [n for n in os.listdir(platlib) if n.startswith(".hydrolux")]  # no staging left


def test_install_refuses_what_is_not_a_python(tmp_path):
    p = subprocess.run([os.path.join(ROOT, "scripts", "install-python"), str(tmp_path / "nothing")],
                       capture_output=True, text=True)
    assert p.returncode == 2 and "not a virtual environment" in p.stderr
