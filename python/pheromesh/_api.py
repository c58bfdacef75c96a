"""sim, sweep, run and replay: the verbs of the `pheromesh` program, from Python."""

from __future__ import annotations

import contextlib
import fcntl
import itertools
import json
import os
import re
import subprocess
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Dict, Iterable, Iterator, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from ._errors import ScenarioError
from ._loader import native as _native
from ._result import Result, load
from ._scenario import Scenario, Value, _text_of

__all__ = ["sim", "sweep", "run", "replay", "program"]

ScenarioLike = Union[Scenario, str, os.PathLike]


# Metrics a run leaves out when it never got there (censored at its last
# tick; docs/outputs.md): a column of NaN, never an unknown name.
_CENSORED = {"ticks_to_coverage_50", "ticks_to_coverage_90", "ticks_to_all_targets", "leader_arrival_tick"}


def _scenario(s: ScenarioLike) -> Scenario:
    return s if isinstance(s, Scenario) else Scenario.load(s)


def _flag_overrides(call: str, **fields: Optional[int]) -> List[Tuple[str, str, str]]:
    paths = {"seed": "run.seed", "ticks": "run.ticks", "uavs": "swarm.uavs"}
    return [(paths[k], str(v), f"{call}({k}={v})") for k, v in fields.items() if v is not None]


def sim(scenario: ScenarioLike, *, seed: Optional[int] = None, ticks: Optional[int] = None,
        uavs: Optional[int] = None, faults: Optional[str] = None, tracks: bool = False,
        record: Optional[Union[str, os.PathLike]] = None, out: Optional[Union[str, os.PathLike]] = None,
        fields_every: Optional[int] = None) -> Result:
    """Runs the scenario on the in-process simulator, as ``pheromesh sim``.

    Args:
        scenario: a :class:`Scenario`, a scenario file or a shipped name.
        seed, ticks, uavs: ``run.seed``, ``run.ticks``, ``swarm.uavs`` for this
            run (``--seed``, ``--ticks``, ``--uavs``); None keeps the scenario's.
        faults: a fault schedule in ticks, added to the scenario's own, as
            ``--faults`` (docs/faults.md), e.g. ``"kill uav:1 @20t"``.
        tracks: also keep every UAV's position of every tick (``Result.tracks``).
        record: write a console recording there (``--record``; ``pheromesh
            replay FILE`` or :func:`replay` shows it).
        out: also write the files ``pheromesh sim --out`` writes there
            (metrics.json, series.csv, final_field.txt/.csv, tracks.csv).
        fields_every: also keep every layer every ``k`` ticks (ticks k, 2k, ...):
            ``Result.fields_over_time[layer]`` is a float32 array of shape
            (ticks // k, rows, cols) and ``Result.fields_ticks`` says the tick
            of each frame.

    The same scenario and seed give the same numbers as ``pheromesh sim``
    (and as a lockstep ``pheromesh run``). Raises :class:`ScenarioError`
    for a bad scenario or set, ValueError for a bad fault schedule.
    """
    every = 0
    if fields_every is not None:
        if isinstance(fields_every, bool) or not isinstance(fields_every, int) or fields_every < 1:
            raise ValueError(f"sim(fields_every={fields_every!r}): a whole number of ticks >= 1")
        every = fields_every
    s = _scenario(scenario)
    config = s._config(_flag_overrides("sim", seed=seed, ticks=ticks, uavs=uavs))
    raw = _native().simulate(config, faults or "", bool(tracks), os.fspath(record) if record else "",
                             os.fspath(out) if out else "", every)
    tr = raw["tracks"]
    if tr is not None:
        tr["role"] = np.array(tr["role"], dtype=object)
    return Result(metrics=json.loads(raw["metrics_json"]), series=dict(raw["series"]), fields=dict(raw["fields"]),
                  tracks=dict(tr) if tr is not None else None, source="sim", notes=list(raw["notes"]),
                  scalars=dict(raw["scalars"]),
                  fields_over_time=dict(raw["fields_over_time"]) if every else None,
                  fields_ticks=raw["fields_ticks"] if every else None)


def sweep(scenario: ScenarioLike, grid: Mapping[str, Sequence[Value]], *, seeds: Iterable[int] = range(1, 11),
          jobs: Optional[int] = None, ticks: Optional[int] = None, uavs: Optional[int] = None,
          metrics: Optional[Sequence[str]] = None) -> Any:
    """Runs the simulator for every combination of ``grid``'s values, times every seed.

    Args:
        grid: field path -> the values to try, e.g. ``{"shao.aco.alpha": [1, 2]}``
            (``pheromesh sweep --set shao.aco.alpha=1,2``).
        seeds: the seeds of every combination.
        jobs: simulations at once (threads; the simulator runs without the GIL);
            None: the host's CPU count.
        ticks, uavs: fixed for every run.
        metrics: the metric columns to keep (flattened names as in runs.csv,
            e.g. ``"coverage"``, ``"targets_found"``, ``"ticks_to_all_targets"``);
            None keeps all. A time a run did not reach (``ticks_to_*``,
            censored at its last tick) is NaN in its row.

    Returns one row per run: every swept path, ``seed``, then the scalar
    metrics as ``pheromesh sweep``'s runs.csv has them (nested names dotted,
    booleans 0/1). A pandas DataFrame when pandas is importable, else a dict
    of columns. Every combination is validated before any run starts.
    """
    base = _scenario(scenario)
    paths = list(grid)
    for p in paths:
        if isinstance(grid[p], (str, bytes)) or not isinstance(grid[p], Iterable):
            raise TypeError(f"sweep: the values of {p!r} are a list, e.g. [1, 2], not {grid[p]!r}")
    combos = list(itertools.product(*(list(grid[p]) for p in paths)))
    seed_list = [int(x) for x in seeds]
    if not seed_list:
        raise ValueError("sweep: no seeds")
    # Load (and so validate) every run's scenario first, under the GIL.
    runs = []
    for combo in combos:
        extra = [(p, _text_of(v), f"sweep({p}={v!r})") for p, v in zip(paths, combo)]
        for seed in seed_list:
            config = base._config(extra + _flag_overrides("sweep", ticks=ticks, uavs=uavs, seed=seed))
            runs.append((combo, seed, config))

    def one(item: Tuple[Tuple[Value, ...], int, Any]) -> Dict[str, float]:
        return dict(_native().simulate(item[2])["scalars"])

    with ThreadPoolExecutor(max_workers=jobs or os.cpu_count() or 1) as pool:
        results = list(pool.map(one, runs))
    names = sorted(set().union(*results)) if metrics is None else list(metrics)
    table: Dict[str, List[Any]] = {p: [] for p in paths}
    table["seed"] = []
    for n in names:
        table.setdefault(n, [])
    if metrics is not None:
        for n in names:
            if n not in _CENSORED and not any(n in scalars for scalars in results):
                raise KeyError(f"sweep: no metric {n!r} (some: {', '.join(sorted(results[0])[:8])}, ...)")
    for (combo, seed, _), scalars in zip(runs, results):
        for p, v in zip(paths, combo):
            table[p].append(v)
        table["seed"].append(seed)
        for n in names:
            # A time a run did not reach (censored) is absent from its metrics: NaN.
            table[n].append(scalars.get(n, float("nan")))
    try:
        import pandas as pd  # noqa: PLC0415
    except ImportError:
        return table
    return pd.DataFrame(table)


def program() -> str:
    """The ``pheromesh`` program :func:`run` and :func:`replay` start: $PHEROMESH_PROGRAM,
    else the one of this build or installation."""
    return os.environ.get("PHEROMESH_PROGRAM") or str(_native().program_path())


def _cli_sets(s: Scenario, extra: List[Tuple[str, str, str]]) -> List[str]:
    args: List[str] = []
    for p, v, _ in list(s._overrides) + extra:
        args += ["--set", f"{p}={v}"]
    return args


# The DDS domains run(domain="auto") chooses from: below 101, where a swarm
# flies in cells (higher domains' well-known ports are ephemeral, and
# `pheromesh run` falls back to flat discovery there).
AUTO_DOMAINS = range(60, 100)


@contextlib.contextmanager
def _claimed_domain() -> Iterator[int]:
    """The first domain of AUTO_DOMAINS no other holder of this host claims,
    held until the block ends: an exclusive flock on
    $TMPDIR/pheromesh-domain-N.lock, released by the kernel if the process
    dies. It keeps pheromesh.run(domain="auto") calls of this host apart;
    DDS programs that do not claim (pheromesh run --domain N) it cannot see."""
    folder = tempfile.gettempdir()
    for domain in AUTO_DOMAINS:
        f = open(os.path.join(folder, f"pheromesh-domain-{domain}.lock"), "a+")  # noqa: SIM115
        try:
            fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            f.close()
            continue
        try:
            yield domain
        finally:
            fcntl.flock(f, fcntl.LOCK_UN)
            f.close()
        return
    raise RuntimeError(f"run(domain='auto'): every domain of {AUTO_DOMAINS.start}..{AUTO_DOMAINS.stop - 1} is "
                       f"claimed by a run of this host; give domain=N")


def run(scenario: ScenarioLike, *, out: Optional[Union[str, os.PathLike]] = None, clock: str = "lockstep",
        dds: str = "cyclone", seed: Optional[int] = None, ticks: Optional[int] = None, uavs: Optional[int] = None,
        faults: Optional[str] = None, tracks: bool = False, domain: Union[int, str, None] = None,
        args: Sequence[str] = (), timeout: Optional[float] = 600, quiet: bool = True) -> Result:
    """Flies the scenario as real processes (``pheromesh run``): one process per
    UAV and per place agent and a ground station, over DDS on this host.

    Args:
        out: the run's folder (a temporary one when None: the Result holds
            everything read back).
        clock: ``"lockstep"`` (the same numbers as :func:`sim`) or ``"realtime"``.
        dds: ``"cyclone"``, ``"fastdds"`` or ``"mixed"``.
        seed, ticks, uavs, faults, tracks: as for :func:`sim` (faults as ``--faults``:
            in ticks, or in seconds for a realtime run).
        domain: the DDS domain (``--domain``); ``"auto"``: the first of
            60..99 that no other ``run(domain="auto")`` of this host holds,
            held until the run ends (``Result.domain`` says which); None:
            the launcher's default, 0.
        args: more flags of ``pheromesh run``, e.g. ``["--http", "8080"]``.
        timeout: seconds before the launcher is stopped (None: no limit).
        quiet: keep the launcher's output (it is in the exception when the run
            fails); False lets it through to this process's stdout/stderr.

    Returns the Result read from the run's outputs (:func:`load`). Raises
    :class:`ScenarioError` for a bad scenario (checked here first) and
    RuntimeError when the launcher fails.
    """
    if domain is not None and "--domain" in args:
        raise ValueError("run: the domain is given twice (domain= and --domain in args)")
    if domain is not None and domain != "auto" and (isinstance(domain, bool) or not isinstance(domain, int)):
        raise ValueError(f"run(domain={domain!r}): a DDS domain id (0..232) or 'auto'")
    s = _scenario(scenario)
    extra = _flag_overrides("run", seed=seed, ticks=ticks, uavs=uavs)
    s._config(extra)  # refuse a bad scenario before starting anything
    tmp = None
    if out is None:
        tmp = tempfile.TemporaryDirectory(prefix="pheromesh-run-")
        out = tmp.name
    cmd = [program(), "run", s.path, "--out", os.fspath(out), "--clock", clock, "--dds", dds]
    cmd += _cli_sets(s, extra)
    if faults:
        cmd += ["--faults", faults]
    if tracks:
        cmd.append("--tracks")
    cmd += list(args)
    claim = _claimed_domain() if domain == "auto" else contextlib.nullcontext(domain)
    try:
        with claim as chosen:
            if chosen is not None:
                cmd += ["--domain", str(chosen)]
            done = subprocess.run(cmd, stdout=subprocess.PIPE if quiet else None,
                                  stderr=subprocess.STDOUT if quiet else None, text=True, timeout=timeout, check=False)
        if done.returncode != 0:
            raise RuntimeError(f"pheromesh run failed (exit {done.returncode}): {' '.join(cmd)}\n{done.stdout or ''}")
        result = load(out)
    finally:
        if tmp is not None:
            tmp.cleanup()
    if tmp is not None:
        result.source = "run"
    result.domain = chosen
    return result


class replay:  # noqa: N801  (a verb, as the others)
    """Serves a console recording (``sim(record=...)``, ``pheromesh run --http``)
    in the web console with its time slider, as ``pheromesh replay FILE``.

    >>> with pheromesh.replay("out/sim.phrec") as r:
    ...     print(r.url)          # open it in a browser

    ``replay.check(path)`` only reads the recording and returns what
    ``pheromesh replay --check`` says of it.
    """

    def __init__(self, path: Union[str, os.PathLike], *, port: int = 0, bind: str = "127.0.0.1",
                 start_timeout: float = 20) -> None:
        self.path = os.fspath(path)
        self._proc = subprocess.Popen([program(), "replay", self.path, "--http", str(port), "--http-bind", bind],
                                      stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.url: Optional[str] = None
        deadline = time.monotonic() + start_timeout
        lines: List[str] = []
        assert self._proc.stdout is not None
        while time.monotonic() < deadline:
            line = self._proc.stdout.readline()
            if not line:
                break
            lines.append(line)
            m = re.search(r"replay at (\S+)", line)
            if m:
                self.url = m.group(1)
                return
        self.stop()
        raise RuntimeError(f"pheromesh replay {self.path} did not start:\n{''.join(lines)}")

    @staticmethod
    def check(path: Union[str, os.PathLike]) -> str:
        """What the recording holds (``pheromesh replay --check``); RuntimeError if unreadable."""
        done = subprocess.run([program(), "replay", os.fspath(path), "--check"], stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True, timeout=60, check=False)
        if done.returncode != 0:
            raise RuntimeError(f"pheromesh replay --check {os.fspath(path)}: {done.stdout}")
        return done.stdout

    def stop(self) -> None:
        """Stops the console."""
        if self._proc.poll() is None:
            self._proc.terminate()
            try:
                self._proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self._proc.kill()
                self._proc.wait()
        if self._proc.stdout is not None:
            self._proc.stdout.close()

    def __enter__(self) -> "replay":
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()
