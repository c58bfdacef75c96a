"""Which Python (docs/python.md, "Which Python"): the wheel a build leaves in
build/python/dist installs into a fresh venv and simulates there; importing
the package where it cannot load says which interpreter it was built for."""

import os
import shutil
import subprocess
import sys
import venv

import pytest

import pheromesh
from conftest import BUILD

PACKAGE_PARENT = BUILD / "python"


def clean_env(**extra):
    """This environment without the test's PYTHONPATH (a user's shell has none)."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PHEROMESH_PROGRAM")}
    env.update(extra)
    return env


def import_in(python, *args, env=None):
    code = f"import sys; sys.path.insert(0, {str(PACKAGE_PARENT)!r}); import pheromesh"
    return subprocess.run([python, *args, "-c", code], capture_output=True, text=True, timeout=120,
                          env=env or clean_env(), check=False)


def test_importing_without_numpy_says_which_python_it_was_built_for_and_how_to_get_numpy():
    # -S: no site-packages, so no NumPy (Debian's is in dist-packages).
    done = import_in(sys.executable, "-S")
    assert done.returncode != 0
    message = done.stderr.strip().splitlines()[-1]
    assert message.startswith("ImportError: pheromesh needs NumPy"), done.stderr
    assert f"It was built for Python {sys.version_info.major}.{sys.version_info.minor} ({sys.executable})" in message
    assert "--system-site-packages" in message


def other_python():
    """An interpreter of another minor version than this one, if the host has one:
    $PHEROMESH_OTHER_PYTHON, else the first python3.N on PATH that runs."""
    candidates = [os.environ.get("PHEROMESH_OTHER_PYTHON", "")]
    candidates += [shutil.which(f"python3.{n}") or "" for n in range(6, 20) if n != sys.version_info.minor]
    for c in filter(None, candidates):
        done = subprocess.run([c, "-c", "import sys; print(sys.version_info[1])"], capture_output=True, text=True,
                              timeout=30, check=False, env=clean_env())
        if done.returncode == 0 and done.stdout.strip() != str(sys.version_info.minor):
            return c
    return None


def test_importing_under_another_python_says_which_one_it_was_built_for():
    other = other_python()
    if other is None:
        pytest.skip("no Python of another minor version on this host (set PHEROMESH_OTHER_PYTHON to one)")
    done = import_in(other)
    assert done.returncode != 0
    message = done.stderr.strip().splitlines()[-1]
    built = f"{sys.version_info.major}.{sys.version_info.minor}"
    assert message.startswith(f"ImportError: pheromesh was built for Python {built} ({sys.executable})"), done.stderr
    assert f"loads only in Python {built}" in message and "-DPython_EXECUTABLE=" in message


def the_wheel():
    tag = f"cp{sys.version_info.major}{sys.version_info.minor}"
    wheels = sorted((BUILD / "python" / "dist").glob(f"pheromesh-{pheromesh.__version__}-{tag}-{tag}-*.whl"))
    assert len(wheels) == 1, f"expected one wheel for {tag} in {BUILD / 'python' / 'dist'}: {wheels}"
    return wheels[0]


def test_the_wheel_installs_into_a_fresh_venv_and_simulates_there_as_the_build_tree_does(tmp_path):
    wheel = the_wheel()
    env_dir = tmp_path / "venv"
    venv.EnvBuilder(system_site_packages=True, with_pip=True).create(env_dir)
    python = str(env_dir / "bin" / "python")
    done = subprocess.run([python, "-m", "pip", "install", "--no-index", "--no-deps", "--quiet", str(wheel)],
                          capture_output=True, text=True, timeout=300, env=clean_env(), check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    code = (
        "import pheromesh, os, sys\n"
        "r = pheromesh.sim('small-test', seed=2, ticks=40)\n"
        "s = pheromesh.Simulation('small-test', seed=2, ticks=40).run()\n"
        "assert s.result().fields['path'].tobytes() == r.fields['path'].tobytes()\n"
        "assert os.path.exists(pheromesh.program())\n"
        "sys.stdout.buffer.write(pheromesh.__file__.encode() + b'\\n' + r.fields['path'].tobytes())\n"
    )
    # From a folder of its own, with no PYTHONPATH: the venv's site-packages only.
    done = subprocess.run([python, "-c", code], capture_output=True, timeout=300, cwd=tmp_path, env=clean_env(),
                          check=False)
    assert done.returncode == 0, done.stderr.decode()
    where, field = done.stdout.split(b"\n", 1)
    assert where.decode().startswith(str(env_dir)), where
    assert field == pheromesh.sim("small-test", seed=2, ticks=40).fields["path"].tobytes()
