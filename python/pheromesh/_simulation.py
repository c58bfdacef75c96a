"""pheromesh.Simulation: a run of the in-process simulator, a tick at a time.

The stepping is the core's (``core::Simulator``: advance, add_faults, finish);
this module only wraps it, keeps the collectors' values and hands the
numbers over as NumPy arrays.
"""

from __future__ import annotations

import json
import numbers
import os
from typing import Any, Callable, Dict, List, Mapping, Optional, Union

import numpy as np

from ._api import _flag_overrides, _scenario
from ._loader import native as _native
from ._result import Result

__all__ = ["Simulation"]


def _target_text(targets: Union[str, List[str], tuple]) -> str:
    """The grammar's TARGETS (docs/faults.md): "uav:2", "uav:0-3,place:1", or a list of them."""
    if isinstance(targets, str):
        text = targets
    elif isinstance(targets, (list, tuple)) and targets and all(isinstance(t, str) for t in targets):
        text = ",".join(targets)
    else:
        raise TypeError(f"targets are a name such as 'uav:2' or 'place:0-1', or a list of them, not {targets!r}")
    if not text.strip() or "@" in text or ";" in text:
        raise ValueError(f"targets {text!r}: give names only (e.g. 'uav:2'); the tick is the next one, or at=")
    return text.replace(" ", "")


class Simulation:
    """A run of the in-process simulator that you advance yourself, as Mesa's
    ``model.step()`` or ARGoS's step: look at the field, the UAVs and the
    metrics between ticks, perturb the run, collect your own measures.

    >>> sim = pheromesh.Simulation("small-test", seed=3, ticks=100)
    >>> sim.step(39)                    # ticks 1..39 (tick 0 ran when it was made)
    >>> sim.fields["path"].max(), sim.uavs["x"]
    >>> sim.kill("uav:1")               # gone from tick 40: as --faults "kill uav:1 @40t"
    >>> sim.run()                       # to the last tick; the run ends there
    >>> sim.result().fields["path"]     # == pheromesh.sim(..., faults="kill uav:1 @40t")

    Making it runs tick 0 (every UAV senses and deposits where it starts), so
    ``tick`` is 0 and ``fields`` already holds the first deposits; each
    ``step()`` runs the next tick. Stepping to the last tick (``ticks``) ends
    the run: the same numbers as ``pheromesh sim --ticks N`` and
    :func:`pheromesh.sim`, byte for byte, with the same faults at the same
    ticks.

    Args:
        scenario: a :class:`Scenario`, a scenario file or a shipped name.
        seed, ticks, uavs: ``run.seed``, ``run.ticks`` (the last tick),
            ``swarm.uavs``, as for :func:`pheromesh.sim`.
        faults: a fault schedule in ticks given before the run starts
            (``--faults``), the only way to a fault at tick 0.
        tracks: keep every UAV's position of every tick (``result().tracks``).
        collect: ``{name: callable}``; each callable is called with this
            Simulation after every tick (tick 0 included) and its value becomes
            column ``name`` of :meth:`frame`, beside the built-in measures.
    """

    def __init__(self, scenario: Any, *, seed: Optional[int] = None, ticks: Optional[int] = None,
                 uavs: Optional[int] = None, faults: Optional[str] = None, tracks: bool = False,
                 collect: Optional[Mapping[str, Callable[["Simulation"], Any]]] = None) -> None:
        self.scenario = _scenario(scenario)
        config = self.scenario._config(_flag_overrides("Simulation", seed=seed, ticks=ticks, uavs=uavs))
        self._collect: Dict[str, Callable[["Simulation"], Any]] = {}
        for name, fn in dict(collect or {}).items():
            if not isinstance(name, str) or not callable(fn):
                raise TypeError(f"collect: {{name: callable}}, e.g. {{'peak': lambda sim: ...}}; got {name!r}: {fn!r}")
            self._collect[name] = fn
        self._collected: Dict[str, List[Any]] = {name: [] for name in self._collect}
        self._layers = list(config.layers)
        self._native = _native().Stepper(config, faults or "", bool(tracks))
        self._fields_cache: Optional[tuple] = None
        self._advance(1)  # tick 0

    # --- time -------------------------------------------------------------------

    @property
    def tick(self) -> int:
        """The last tick run (0 once the Simulation is made)."""
        return int(self._native.tick)

    @property
    def ticks(self) -> int:
        """The run's last tick (``run.ticks``): stepping to it ends the run."""
        return int(self._native.last_tick)

    @property
    def done(self) -> bool:
        """The last tick has run and the run has ended (:meth:`result` is ready)."""
        return bool(self._native.finished)

    def step(self, n: int = 1) -> "Simulation":
        """Runs the next ``n`` ticks; returns this Simulation.

        Raises ValueError when fewer than ``n`` ticks are left (nothing runs).
        """
        if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
            raise ValueError(f"step(n): n is a whole number of ticks >= 1, not {n!r}")
        left = self.ticks - self.tick
        if n > left:
            raise ValueError(f"step({n}): only {left} tick(s) left (the run is at tick {self.tick}, its last is "
                             f"{self.ticks}; Simulation(..., ticks=N) makes a longer run)")
        self._advance(int(n))
        return self

    def run(self, until: Optional[int] = None) -> "Simulation":
        """Runs until tick ``until`` has run (default: the last tick, which ends the run)."""
        target = self.ticks if until is None else until
        if isinstance(target, bool) or not isinstance(target, numbers.Integral) or not self.tick <= target <= self.ticks:
            raise ValueError(f"run(until={until!r}): a tick from {self.tick} (the last run) to {self.ticks} (the last)")
        if target > self.tick:
            self._advance(int(target) - self.tick)
        return self

    def _advance(self, n: int) -> None:
        self._fields_cache = None
        if not self._collect:
            self._native.advance(n)
            return
        for _ in range(n):
            self._native.advance(1)
            self._fields_cache = None
            for name, fn in self._collect.items():
                self._collected[name].append(fn(self))

    # --- what the swarm is doing ------------------------------------------------

    @property
    def fields(self) -> Dict[str, np.ndarray]:
        """The pheromone field after the last tick: layer name -> float32 array
        (rows, cols), indexed ``[y, x]``, read-only. Gathered once per tick from
        the place agents' regions into one buffer per layer (the array owns it;
        later ticks do not change it)."""
        if self._fields_cache is None or self._fields_cache[0] != self.tick:
            self._fields_cache = (self.tick, dict(self._native.fields()))
        return dict(self._fields_cache[1])

    @property
    def uavs(self) -> Dict[str, np.ndarray]:
        """Every UAV after the last tick, as columns (``pd.DataFrame(sim.uavs)``):
        ``uav``, ``x``, ``y`` [cell], ``vx``, ``vy`` [cell/tick], ``heading``
        (0..7, 0 = east), ``role`` (name), ``alive`` (acts in the next tick). A
        killed UAV keeps the position of its last tick; one killed at tick 0
        never flew and has NaN."""
        d = dict(self._native.uavs())
        d["role"] = np.array(d["role"], dtype=object)
        return d

    @property
    def targets(self) -> Dict[str, np.ndarray]:
        """Every target, as columns: ``target``, ``x``, ``y`` [cell] and
        ``found_tick`` (the tick it was first detected, -1 while it is not)."""
        return dict(self._native.targets())

    @property
    def metrics(self) -> Dict[str, Any]:
        """metrics.json so far (its schema; ``ticks`` is the last tick run,
        ``wall_seconds`` the time spent stepping)."""
        return json.loads(self._native.metrics_json())

    @property
    def series(self) -> Dict[str, np.ndarray]:
        """series.csv so far: one row per tick run (``Result.series``)."""
        return dict(self._native.series())

    @property
    def notes(self) -> List[str]:
        """What the simulator said of the faults (events that change no number)."""
        return list(self._native.notes())

    # --- collectors -------------------------------------------------------------

    @property
    def collected(self) -> Dict[str, List[Any]]:
        """The collectors' values so far, one per tick run: ``{name: [...]}``."""
        return {k: list(v) for k, v in self._collected.items()}

    def frame(self) -> Any:
        """The per-tick measures so far as a DataFrame (Mesa's
        ``get_model_vars_dataframe``): one row per tick run, the built-in
        columns of :attr:`series` (tick, coverage, covered_cells,
        targets_found, uavs_reporting, deposits_*) then one per collector.
        A dict of columns when pandas is not importable."""
        table: Dict[str, Any] = dict(self.series)
        for name, values in self._collected.items():
            if name in table:
                raise ValueError(f"collect: {name!r} is a built-in column; name the collector otherwise")
            table[name] = list(values)
        try:
            import pandas as pd  # noqa: PLC0415
        except ImportError:
            return table
        return pd.DataFrame(table)

    # --- perturbations (docs/faults.md, "Faults in the simulator") --------------

    def kill(self, targets: Union[str, List[str]], *, at: Optional[int] = None) -> List[str]:
        """Kills UAVs or place agents from the next tick on (or from tick ``at``):
        ``kill("uav:2")`` between ticks k and k+1 is ``--faults "kill uav:2 @{k+1}t"``.
        ``targets`` as the fault grammar names them ("uav:2", "uav:0-3,place:1").
        Returns the simulator's notes; ValueError names what is wrong (no such
        UAV, already dead, a tick already run)."""
        return self.fault(f"kill {_target_text(targets)} @{self._when(at)}t")

    def stop(self, targets: Union[str, List[str]], *, seconds: float = 1.0, at: Optional[int] = None) -> List[str]:
        """Stops processes (SIGSTOP) for ``seconds`` of wall time from the next
        tick (``stop place:1 @{k+1}t for 1s``). In the simulator, as in a
        lockstep run, a stop changes no number (the run only waits): the note
        returned says so. A stop's length is wall time in the fault grammar,
        never ticks."""
        if isinstance(seconds, bool) or not isinstance(seconds, numbers.Real) or not seconds > 0:
            raise ValueError(f"stop: seconds is a positive number (wall time), not {seconds!r}")
        return self.fault(f"stop {_target_text(targets)} @{self._when(at)}t for {float(seconds):g}s")

    def fault(self, schedule: str) -> List[str]:
        """Adds events in the fault grammar, timed in ticks at the next tick or
        later (``"kill uav:1 @50t; kill place:2 @60t"``), as ``--faults`` would
        have them. Returns the simulator's notes on them."""
        if not isinstance(schedule, str):
            raise TypeError(f"fault: a schedule such as 'kill uav:1 @50t', not {schedule!r}")
        return list(self._native.add_faults(schedule))

    def _when(self, at: Optional[int]) -> int:
        if at is None:
            return self.tick + 1
        if isinstance(at, bool) or not isinstance(at, numbers.Integral):
            raise ValueError(f"at: a tick, not {at!r}")
        return int(at)

    # --- the end ----------------------------------------------------------------

    def result(self, *, out: Optional[Union[str, os.PathLike]] = None) -> Result:
        """The run's :class:`Result`, as :func:`pheromesh.sim` returns it; ``out``
        also writes the files ``pheromesh sim --out`` writes. Only once the last
        tick has run (ValueError before)."""
        if not self.done:
            raise ValueError(f"result(): the run is at tick {self.tick} of {self.ticks}; run() it to the end first")
        raw = self._native.result(os.fspath(out) if out else "")
        tr = raw["tracks"]
        if tr is not None:
            tr = dict(tr)
            tr["role"] = np.array(tr["role"], dtype=object)
        return Result(metrics=json.loads(raw["metrics_json"]), series=dict(raw["series"]),
                      fields=dict(raw["fields"]), tracks=tr, source="sim", notes=list(raw["notes"]),
                      scalars=dict(raw["scalars"]))

    def __repr__(self) -> str:
        return (f"Simulation({self.scenario.name!r}, tick={self.tick}/{self.ticks}, "
                f"layers={self._layers}, done={self.done})")
