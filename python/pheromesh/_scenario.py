"""pheromesh.Scenario: a scenario file (or shipped name) and the fields set on it."""

from __future__ import annotations

import os
from typing import Any, List, Optional, Tuple, Union

from ._loader import native as _native
from ._errors import ScenarioError

__all__ = ["Scenario", "Value", "shipped_scenarios"]

Value = Union[bool, int, float, str]


def _text_of(value: Value) -> str:
    # As `--set PATH=VALUE` would be typed: the core parses it for the field's type.
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value)  # the shortest text that reads back as the same double
    if isinstance(value, str):
        return value
    raise TypeError(f"a scenario field takes a bool, int, float or str, not {type(value).__name__}")


def shipped_scenarios() -> List[str]:
    """The names of the scenarios shipped with pheromesh (``Scenario.load`` takes them)."""
    return list(_native().shipped_scenarios())


class Scenario:
    """A scenario: a textproto file (docs/scenario-format.md) plus overrides.

    >>> s = pheromesh.Scenario.load("small-test").set("shao.aco.alpha", 2)
    >>> s.validate().uavs
    4

    :meth:`set` changes a field as ``pheromesh --set PATH=VALUE`` does (the
    same code: the field is set in the parsed file and the whole scenario is
    validated again as a file is). Sets are kept in order; a later one of the
    same field wins. They are checked by :meth:`validate`, which
    :func:`pheromesh.sim` and friends call, raising
    :class:`pheromesh.ScenarioError` with the file, line and field.
    """

    def __init__(self, path: Union[str, os.PathLike], overrides: Optional[List[Tuple[str, str, str]]] = None) -> None:
        """A scenario of the file ``path`` (no lookup of shipped names: use :meth:`load`)."""
        self._path = os.fspath(path)
        self._overrides: List[Tuple[str, str, str]] = list(overrides or [])
        self._loaded: Any = None

    @classmethod
    def load(cls, path_or_name: Union[str, os.PathLike]) -> "Scenario":
        """Loads and validates a scenario file, or a shipped scenario by name.

        ``path_or_name`` is a file (relative to the current directory), or the
        name of a shipped scenario such as ``"small-test"`` or
        ``"shao2020-50x50"``, as ``pheromesh run NAME`` takes it
        (:func:`pheromesh.shipped_scenarios` lists them). Raises
        :class:`pheromesh.ScenarioError`.
        """
        arg = os.fspath(path_or_name)
        native = _native()
        try:
            path = native.resolve_scenario(arg)
        except native.ScenarioFailure as e:
            raise ScenarioError(str(e), file=arg) from None
        scenario = cls(path)
        scenario.validate()
        return scenario

    def set(self, path: str, value: Value) -> "Scenario":
        """Sets the field ``path`` (as in the textproto, e.g. ``"shao.aco.alpha"``,
        ``"map.targets[2].x"``, ``"policy.shao_search.search"``) to ``value``.

        Returns this scenario, so sets chain. The value is checked by
        :meth:`validate` (and by every run), not here: several fields may
        have to change together.
        """
        if not isinstance(path, str) or not path:
            raise TypeError("Scenario.set: the field path is a non-empty str, e.g. 'shao.aco.alpha'")
        text = _text_of(value)
        self._overrides.append((path, text, f".set({path!r}, {value!r})"))
        self._loaded = None
        return self

    def copy(self) -> "Scenario":
        """A copy with the same file and sets (sets on it leave this one alone)."""
        c = Scenario(self._path, self._overrides)
        c._loaded = self._loaded
        return c

    def validate(self) -> "Scenario":
        """Validates the file with every set applied, as ``pheromesh validate --set ...``.

        Returns this scenario; raises :class:`pheromesh.ScenarioError` naming
        the file, line and field (or the set) of every problem.
        """
        self._config()
        return self

    def _config(self, extra: Optional[List[Tuple[str, str, str]]] = None) -> Any:
        if self._loaded is not None and not extra:
            return self._loaded
        native = _native()
        overrides = self._overrides + list(extra or [])
        try:
            loaded = native.load_scenario(self._path, overrides)
        except native.ScenarioFailure as e:
            raise ScenarioError(str(e), file=self._path, overrides=overrides) from None
        if not extra:
            self._loaded = loaded
        return loaded

    # --- what the validated scenario says --------------------------------------
    @property
    def path(self) -> str:
        """The scenario file."""
        return self._path

    @property
    def overrides(self) -> List[Tuple[str, str]]:
        """The sets, in order, as (path, value text)."""
        return [(p, v) for p, v, _ in self._overrides]

    @property
    def name(self) -> str:
        """The scenario's ``name:``."""
        return str(self._config().name)

    @property
    def uavs(self) -> int:
        """``swarm.uavs``."""
        return int(self._config().uavs)

    @property
    def ticks(self) -> int:
        """``run.ticks``: ticks a run lasts."""
        return int(self._config().ticks)

    @property
    def seed(self) -> int:
        """``run.seed``."""
        return int(self._config().seed)

    @property
    def tick_rate_hz(self) -> float:
        """``run.tick_rate_hz`` [Hz] (realtime runs)."""
        return float(self._config().tick_rate_hz)

    @property
    def shape(self) -> Tuple[int, int]:
        """(rows, cols) = (map.height, map.width) [cell]: the shape of every field array."""
        c = self._config()
        return int(c.height), int(c.width)

    @property
    def policy(self) -> str:
        """The policy's name in the policy table, e.g. ``"shao_search"``, ``"liu"``."""
        return str(self._config().policy)

    @property
    def layers(self) -> List[str]:
        """The policy's pheromone layers, in the order of :attr:`pheromesh.Result.fields`."""
        return list(self._config().layers)

    @property
    def targets(self) -> List[Tuple[int, int]]:
        """(x, y) of every target [cell]."""
        return [tuple(t) for t in self._config().targets]

    @property
    def text(self) -> str:
        """The scenario as text, the sets applied (what ``pheromesh run`` hands its processes)."""
        return str(self._config().text)

    def __repr__(self) -> str:
        sets = "".join(f".set({p!r}, {v!r})" for p, v in self.overrides)
        return f"Scenario({self._path!r}){sets}"
