"""Why ``import pheromesh`` failed, said in terms of interpreters (docs/python.md, "Which Python")."""

from __future__ import annotations

import importlib.util
import sys


def import_problem(error: BaseException) -> str:
    """A message for an ImportError of the extension or of NumPy: which
    interpreter the package was built for, which one this is, what to do."""
    try:
        from . import _build  # noqa: PLC0415
    except ImportError:
        return f"pheromesh cannot load its extension ({error}); its build information (_build.py) is missing too"
    here = f"Python {sys.version_info.major}.{sys.version_info.minor} ({sys.executable})"
    built = f"Python {_build.PYTHON_VERSION} ({_build.PYTHON_EXECUTABLE})"
    exe = _build.PYTHON_EXECUTABLE
    if f"{sys.version_info.major}.{sys.version_info.minor}" != _build.PYTHON_VERSION:
        return (f"pheromesh was built for {built}, and this is {here}: its extension "
                f"(_pheromesh{_build.EXTENSION_SUFFIX}) loads only in Python {_build.PYTHON_VERSION}. Run it with "
                f"{exe}, or in a venv made from it ({exe} -m venv --system-site-packages DIR), or build "
                f"pheromesh for this Python (cmake -DPython_EXECUTABLE={sys.executable}).")
    if importlib.util.find_spec("numpy") is None:
        return (f"pheromesh needs NumPy, which {here} cannot import. It was built for {built}, where Debian's "
                f"python3-numpy provides it: run it with {exe}, or make the venv with --system-site-packages "
                f"({exe} -m venv --system-site-packages DIR), or install NumPy into this one (pip install numpy).")
    return f"pheromesh cannot load its extension in {here} (built for {built}): {error}"
