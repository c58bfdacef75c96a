"""pheromesh.ScenarioError: a scenario the core refused, with where and what."""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

__all__ = ["ScenarioError", "ScenarioIssue"]

# "FILE:LINE:COL: text" as the core writes every error at a line of a file.
_AT_LINE = re.compile(r"^(?P<file>.+?):(?P<line>\d+):(?P<column>\d+): (?P<text>.*)$")
# "field 'map.obstacles[2].w': ..." (the core's semantic errors) or protobuf's
# 'no field named "foo"' (an unknown field in the file).
_FIELD = re.compile(r"field '(?P<a>[^']+)'|no field named \"(?P<b>[^\"]+)\"")


@dataclass(frozen=True)
class ScenarioIssue:
    """One thing wrong with a scenario.

    ``file``/``line``/``column`` locate it in the scenario file (``line`` is
    None when an override given with :meth:`pheromesh.Scenario.set` caused it,
    or the message names no line); ``field`` is the field's path in the
    textproto (``"shao.aco.alpha"``) when the message names one; ``text`` is
    the core's message for this issue.
    """

    file: Optional[str]
    line: Optional[int]
    column: Optional[int]
    field: Optional[str]
    text: str


class ScenarioError(ValueError):
    """A scenario that does not load or does not validate.

    ``str(error)`` is the core's message (the same as ``pheromesh validate``
    prints). ``error.issues`` holds every issue it names; ``error.file``,
    ``error.line``, ``error.column`` and ``error.field`` are those of the
    first one.
    """

    issues: List[ScenarioIssue]

    def __init__(self, message: str, file: Optional[str] = None,
                 overrides: Sequence[Tuple[str, str, str]] = ()) -> None:
        super().__init__(message)
        self.issues = _parse(message, file, overrides)
        first = self.issues[0] if self.issues else ScenarioIssue(file, None, None, None, message)
        self.file: Optional[str] = first.file
        self.line: Optional[int] = first.line
        self.column: Optional[int] = first.column
        self.field: Optional[str] = first.field


def _parse(message: str, file: Optional[str], overrides: Sequence[Tuple[str, str, str]]) -> List[ScenarioIssue]:
    issues: List[ScenarioIssue] = []
    for raw in message.splitlines():
        if not raw.strip() or raw.startswith("("):  # "(f.textproto as changed by ...)"
            continue
        m = _AT_LINE.match(raw)
        if m:
            f = _FIELD.search(m.group("text"))
            issues.append(ScenarioIssue(m.group("file"), int(m.group("line")), int(m.group("column")),
                                        (f.group("a") or f.group("b")) if f else None, m.group("text")))
            continue
        # An override's error starts with its source: the field is the one it set.
        for path, _value, source in reversed(overrides):
            if raw.startswith(source + ":"):
                f = _FIELD.search(raw)
                issues.append(ScenarioIssue(file, None, None, f.group("a") if f and f.group("a") else path,
                                            raw[len(source) + 1:].strip()))
                break
        else:
            f = _FIELD.search(raw)
            issues.append(ScenarioIssue(file, None, None, (f.group("a") or f.group("b")) if f else None, raw))
    return issues
