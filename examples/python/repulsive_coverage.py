"""Repulsive coverage, written in Python: the algorithm of the C++ plugin
examples/repulsive_coverage/src/repulsive_coverage.cpp, step for step, so that
a run of either on the same seed gives the same field byte for byte
(tests/integration/test_policy_python.cpp checks it).

Every UAV marks the cell it is over with a repulsive pheromone and steps to the
neighbouring cell that holds the least of it, so the swarm spreads over the map
and keeps away from where it (or another UAV) has just been. The mark
evaporates and diffuses (pheromesh's declared layers keep it), so an old trail
fades. Deterministic: no random numbers, ties broken by a fixed order.

A scenario names it (repulsive-coverage-python.textproto beside this file):

    policy { python { module: "repulsive_coverage" class: "RepulsiveCoverage"
                      config { key: "mark" number: 10 } } }
"""

import math

import pheromesh

SEARCHER = 0  # role


class RepulsiveCoverage(pheromesh.UavPolicy):
    name = "repulsive_coverage_py"
    # The scenario's `config { key: ... }`, with their defaults (a float or an
    # int reads `number:`, a str `text:`, a bool `flag:`).
    parameters = {
        "mark": 10.0,  # pheromone a UAV leaves on its cell each tick
        "sensor_radius": 2.0,  # [cell] targets within this are found
        "evaporation": 0.01,
        "diffusion": 0.1,
        "max": 1000.0,
        # "stay": a UAV whose every neighbour is blocked stays put; "error": it raises.
        "when_blocked": "stay",
        # A tick at which every UAV raises (0: never), to show how an exception is reported.
        "fail_at_tick": 0,
    }

    @classmethod
    def traits(cls, config):
        # Errors here are reported at the scenario's `class:` line.
        if not 0.0 <= config["mark"] <= config["max"]:
            raise ValueError(f"mark must be in [0, max] (got {config['mark']})")
        if config["when_blocked"] not in ("stay", "error"):
            raise ValueError(f"when_blocked must be \"stay\" or \"error\" (got {config['when_blocked']!r})")
        if config["fail_at_tick"] < 0:
            raise ValueError("fail_at_tick must be >= 0")
        layer = pheromesh.Layer("repulsion", evaporation=config["evaporation"],
                                diffusion=config["diffusion"], max=config["max"])
        # view_radius 2: the 8 neighbours, with a margin; max_step: one cell,
        # diagonals included (sqrt 2).
        return pheromesh.Traits([layer], sensor_radius=config["sensor_radius"], view_radius=2.0, max_step=1.5)

    @classmethod
    def field_summary(cls, config, field):
        # The final field's numbers for metrics.json "field", as the C++ plugin's.
        total = 0.0
        marked = 0.0
        for y in range(field.height):
            for x in range(field.width):
                v = field.value(0, x, y)
                total += v
                marked += 1.0 if v > 0.0 else 0.0
        return {"repulsion_total": total, "cells_marked": marked}

    def __init__(self, config, uav):
        super().__init__(config, uav)
        self.x, self.y = uav.start
        self.heading = 0  # east

    def step(self, view, actions):
        c = self.config
        if c["fail_at_tick"] and view.tick == c["fail_at_tick"]:
            raise RuntimeError(f"repulsive_coverage_py: uav {self.uav.id} was told to fail at tick {view.tick} "
                               "(config fail_at_tick)")
        bx, by = self.x, self.y
        if view.tick > 0:
            self.move(view)
        # Mark where we are, and report the targets in sensor range.
        actions.deposit(0, self.x, self.y, c["mark"])
        for t in self.uav.sense(self.x, self.y, c["sensor_radius"]):
            actions.detect(t)
        actions.set_state(self.x, self.y, vx=self.x - bx, vy=self.y - by, heading=self.heading, role=SEARCHER)

    def move(self, view):
        # The free neighbour with the least repulsion; ties go to straight on,
        # then to the lowest heading number. A neighbour whose tile has not
        # arrived is not a candidate.
        uav = self.uav
        best = math.inf
        best_turn = -1
        for turn in range(8):
            h = pheromesh.rotate(self.heading, turn)
            dx, dy = pheromesh.step_of(h)
            nx, ny = self.x + dx, self.y + dy
            if not uav.in_map(nx, ny) or uav.is_obstacle(nx, ny):
                continue
            v = view.value(0, nx, ny)
            if v is None:
                continue
            if v < best or (v == best and best_turn != 0 and h < pheromesh.rotate(self.heading, best_turn)):
                best = v
                best_turn = turn
        if best_turn < 0:
            if self.config["when_blocked"] == "error":
                raise RuntimeError(f"repulsive_coverage_py: uav {uav.id} at ({self.x}, {self.y}) has no free "
                                   "neighbour it can read")
            return
        self.heading = pheromesh.rotate(self.heading, best_turn)
        dx, dy = pheromesh.step_of(self.heading)
        self.x += dx
        self.y += dy
