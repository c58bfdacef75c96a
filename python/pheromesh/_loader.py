"""Where the C++ extension comes from (loaded on first use)."""

from __future__ import annotations

from types import ModuleType

__all__ = ["native"]


def native() -> ModuleType:
    """The extension pheromesh._pheromesh: the core, the simulator, scenario loading."""
    from . import _pheromesh  # type: ignore[attr-defined]  # noqa: PLC0415

    return _pheromesh
