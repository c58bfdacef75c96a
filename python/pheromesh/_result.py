"""pheromesh.Result: what a run leaves (docs/outputs.md), in memory."""

from __future__ import annotations

import csv
import json
import os
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Union

import numpy as np

__all__ = ["Result", "load"]

# series.csv's columns and their types (common/report/include/pheromesh/report/tidy.hpp).
_SERIES_FLOAT = {"coverage"}
_TRACKS_FLOAT = {"x", "y"}
_TRACKS_TEXT = {"role"}


@dataclass
class Result:
    """One run's outputs: the same numbers as the files of ``pheromesh sim`` / ``run``.

    Attributes:
        metrics: metrics.json as a dict.
        series: series.csv as columns, one NumPy array per column, one row per
            tick (``pd.DataFrame(result.series)``).
        fields: the final pheromone field, one float32 array per layer, shaped
            (rows, cols) = (map.height, map.width), indexed ``[y, x]``. From the
            simulator the arrays own the buffer the simulator's values were
            gathered into (no further copy).
        tracks: tracks.csv as columns (tick, uav, x, y, role), or None when
            the run kept no tracks (``tracks=True``).
        source: ``"sim"``, or the folder the outputs were read from.
        notes: what the simulator said about the faults (events that change no
            number).
        scalars: the scalar metrics as ``sweep`` tabulates them (simulator only).
        fields_over_time: with ``sim(..., fields_every=k)``, layer name ->
            float32 array (ticks // k, rows, cols): the field after ticks k,
            2k, ...; else None.
        fields_ticks: the tick of each frame of ``fields_over_time`` (int64), or None.
        domain: the DDS domain ``run(domain=...)`` flew on, or None.
    """

    metrics: Dict[str, Any]
    series: Dict[str, np.ndarray]
    fields: Dict[str, np.ndarray]
    tracks: Optional[Dict[str, np.ndarray]] = None
    source: str = "sim"
    notes: List[str] = field(default_factory=list)
    scalars: Optional[Dict[str, float]] = None
    fields_over_time: Optional[Dict[str, np.ndarray]] = None
    fields_ticks: Optional[np.ndarray] = None
    domain: Optional[int] = None

    @property
    def layers(self) -> List[str]:
        """The field's layer names, in order."""
        return list(self.fields)

    def frame(self) -> Any:
        """``series`` as a pandas DataFrame (needs pandas)."""
        import pandas as pd  # noqa: PLC0415

        return pd.DataFrame(self.series)

    def __repr__(self) -> str:
        m = self.metrics
        return (f"Result(source={self.source!r}, ticks={len(next(iter(self.series.values()), []))}, "
                f"coverage={m.get('coverage')!r}, targets_found={m.get('targets_found')!r}, layers={self.layers})")


def _read_csv(path: str) -> List[List[str]]:
    with open(path, newline="") as f:
        return list(csv.reader(f))


def _columns(rows: List[List[str]], floats: set, texts: set = frozenset()) -> Dict[str, np.ndarray]:
    header, body = rows[0], rows[1:]
    out: Dict[str, np.ndarray] = {}
    for i, name in enumerate(header):
        values = [r[i] for r in body]
        if name in texts:
            out[name] = np.array(values, dtype=object)
        elif name in floats:
            out[name] = np.array([float(v) for v in values], dtype=np.float64)
        else:
            out[name] = np.array([int(v) for v in values], dtype=np.int64)
    return out


def _read_fields(path: str) -> Dict[str, np.ndarray]:
    rows = _read_csv(path)
    if rows[0] != ["layer", "x", "y", "value"]:
        raise ValueError(f"{path}: not a final_field.csv (header {rows[0]})")
    body = rows[1:]
    width = max(int(r[1]) for r in body) + 1 if body else 0
    height = max(int(r[2]) for r in body) + 1 if body else 0
    layers: Dict[str, np.ndarray] = {}
    for name, x, y, value in body:
        a = layers.get(name)
        if a is None:
            a = layers[name] = np.full((height, width), np.nan, dtype=np.float32)
        # Written as the shortest text that reads back as the float32 value.
        a[int(y), int(x)] = np.float32(value)
    return layers


def load(path: Union[str, os.PathLike]) -> Result:
    """A Result from the OUT folder of ``pheromesh sim``, ``pheromesh run`` or
    ``sim(..., out=...)``: metrics.json, series.csv, final_field.csv and,
    when there, tracks.csv (docs/outputs.md)."""
    out = os.fspath(path)
    if not os.path.isdir(out):
        raise FileNotFoundError(f"{out}: not a folder of run outputs (metrics.json, series.csv, final_field.csv)")
    with open(os.path.join(out, "metrics.json")) as f:
        metrics = json.load(f)
    series = _columns(_read_csv(os.path.join(out, "series.csv")), _SERIES_FLOAT)
    fields = _read_fields(os.path.join(out, "final_field.csv"))
    tracks_path = os.path.join(out, "tracks.csv")
    tracks = _columns(_read_csv(tracks_path), _TRACKS_FLOAT, _TRACKS_TEXT) if os.path.exists(tracks_path) else None
    return Result(metrics=metrics, series=series, fields=fields, tracks=tracks, source=out)
