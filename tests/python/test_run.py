"""pheromesh.run flies real processes (the launcher, `pheromesh run`) and returns
the same Result as pheromesh.sim: a small scenario in lockstep over Cyclone DDS
equals the simulator, field byte for byte. A few seconds; DDS on loopback, on
its own domain (PHEROMESH_TEST_DOMAIN)."""

import os

import numpy as np

import pheromesh

DOMAIN = os.environ.get("PHEROMESH_TEST_DOMAIN", "121")


def test_a_lockstep_run_of_real_processes_equals_the_simulator(tmp_path):
    s = pheromesh.Scenario.load("small-test").set("shao.aco.alpha", 2)
    ran = pheromesh.run(s, seed=5, ticks=40, clock="lockstep", dds="cyclone", tracks=True, out=tmp_path / "run",
                        args=["--domain", DOMAIN], timeout=240)
    sim = pheromesh.sim(s, seed=5, ticks=40, tracks=True)
    assert ran.source == str(tmp_path / "run")
    assert ran.metrics["runner"] != sim.metrics["runner"]  # really the processes
    assert ran.metrics["dds"] and "dds" not in sim.metrics
    for key in ("policy", "ticks", "uavs", "coverage", "covered_cells", "targets_found", "acquisition_ticks",
                "revisit_response_ticks", "deposits_sent", "deposits_applied", "deposits_rejected", "field"):
        assert ran.metrics.get(key) == sim.metrics.get(key), key
    assert ran.fields.keys() == sim.fields.keys()
    for layer in sim.fields:
        assert ran.fields[layer].tobytes() == sim.fields[layer].tobytes(), layer
    for k in sim.series:
        np.testing.assert_array_equal(ran.series[k], sim.series[k], err_msg=k)
    for k in sim.tracks:
        assert list(ran.tracks[k]) == list(sim.tracks[k]), k
