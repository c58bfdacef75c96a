"""pheromesh in Python: scenarios, simulations, sweeps and swarms of real processes.

    import pheromesh
    s = pheromesh.Scenario.load("shao2020-50x50").set("shao.aco.alpha", 2)
    r = pheromesh.sim(s, seed=3, ticks=200)
    r.metrics["coverage"], r.fields["target"].shape     # dict, (rows, cols) float32
    sim = pheromesh.Simulation(s, seed=3, ticks=200)     # a tick at a time
    sim.step(39); sim.kill("uav:1"); sim.run()          # == faults="kill uav:1 @40t"
    pheromesh.sweep(s, {"shao.aco.alpha": [1, 2]}, seeds=range(1, 6), jobs=2)
    pheromesh.run("small-test", ticks=50)                # real processes, lockstep

docs/python.md has the whole API and how it relates to the `pheromesh` program.
"""

from __future__ import annotations

__version__ = "0.1.0"

# Two ways this package is imported:
#  * in a Python interpreter (a notebook, a script, pytest): it loads its
#    extension pheromesh._pheromesh, which carries the core, and offers the
#    whole API below;
#  * inside a pheromesh process that embeds an interpreter to run a Python
#    policy (pheromesh-uav, pheromesh-place; issue 27 deliverable 3). That
#    process registers the built-in module `_pheromesh_embedded` and already
#    holds the core: loading the extension would put a second copy of the
#    core and of the scenario schema's generated protobuf code in the
#    process, which aborts. There the package only offers the policy API,
#    from `_pheromesh_embedded`.
try:
    import _pheromesh_embedded  # type: ignore[import-not-found]
except ImportError:
    _pheromesh_embedded = None

if _pheromesh_embedded is not None:
    # Inside a pheromesh process: the policy API only (UavPolicy, PlaceModel,
    # the view and action types), exactly as the process registered it.
    from _pheromesh_embedded import *  # type: ignore[import-not-found]  # noqa: F401,F403

    __all__ = [n for n in dir(_pheromesh_embedded) if not n.startswith("_")]
    EMBEDDED = True
else:
    EMBEDDED = False
    try:
        # The extension (fail here, not at the first call), and NumPy, which
        # the API needs: a failure says which Python this copy was built for.
        from . import _pheromesh  # noqa: F401
        import numpy  # noqa: F401
    except ImportError as _e:
        from ._compat import import_problem

        _problem = import_problem(_e)
    else:
        _problem = None
    if _problem is not None:
        raise ImportError(_problem)
    from ._api import program, replay, run, sim, sweep
    from ._errors import ScenarioError, ScenarioIssue
    from ._result import Result, load
    from ._scenario import Scenario, shipped_scenarios
    from ._simulation import Simulation

    __all__ = ["Scenario", "ScenarioError", "ScenarioIssue", "Result", "Simulation", "sim", "sweep", "run", "replay",
               "load", "program", "shipped_scenarios", "EMBEDDED"]

    # The Python-policy API (docs/python.md, "Python policies"), as the
    # extension binds it (pheromesh::pypolicy::bind_policy_types): the same
    # names a pheromesh process offers from _pheromesh_embedded above, so a
    # policy module imports and runs unchanged in a notebook's sim() and in
    # the UAV and place-agent processes.
    from ._pheromesh import (Actions, Broadcast, Deposit, Field, Layer, PlaceModel, Region, Rng,  # noqa: F401
                             Traits, Uav, UavPolicy, UavState, View, rotate, step_of)

    __all__ += ["UavPolicy", "PlaceModel", "Layer", "Traits", "View", "Actions", "Uav", "Rng", "UavState",
                "Broadcast", "Deposit", "Region", "Field", "step_of", "rotate"]
