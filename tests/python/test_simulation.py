"""pheromesh.Simulation (docs/python.md, "Simulation"): a run a tick at a time
equals `pheromesh sim`, with and without faults injected between ticks; what
it shows between ticks; collectors; sim(fields_every=k). No DDS."""

import filecmp

import numpy as np
import pandas as pd
import pytest

import pheromesh
from conftest import pheromesh_cli

# What `pheromesh sim --out` writes that does not depend on this host's speed.
SAME_FILES = ("series.csv", "final_field.csv", "final_field.txt")
TIMING = {"wall_seconds", "uav_steps_per_second"}


def same_files(a, b, files=SAME_FILES):
    return all(filecmp.cmp(a / f, b / f, shallow=False) for f in files)


def field_bytes(fields):
    return {layer: a.tobytes() for layer, a in fields.items()}


# --- stepping == pheromesh sim --------------------------------------------------

def test_stepping_100_ticks_gives_the_files_and_field_of_pheromesh_sim_ticks_100(tmp_path):
    pheromesh_cli("sim", "small-test", "--seed", "3", "--ticks", "100", "--quiet", "--out", str(tmp_path / "cli"))
    sim = pheromesh.Simulation("small-test", seed=3, ticks=100)
    assert sim.tick == 0 and not sim.done
    for _ in range(99):
        sim.step()
    before_last = field_bytes(sim.fields)
    sim.step()
    assert sim.tick == 100 and sim.done
    r = sim.result(out=tmp_path / "py")
    assert same_files(tmp_path / "cli", tmp_path / "py")
    cli = pheromesh.load(tmp_path / "cli")
    assert field_bytes(r.fields) == field_bytes(cli.fields) == field_bytes(sim.fields)
    assert {k: v for k, v in r.metrics.items() if k not in TIMING} == \
        {k: v for k, v in cli.metrics.items() if k not in TIMING}
    # The guard: the field of tick 99 is not the final one, so the comparison can fail.
    assert before_last != field_bytes(cli.fields)


def test_step_n_and_run_until_are_single_steps_in_bulk():
    one = pheromesh.Simulation("small-test", seed=5, ticks=60)
    while not one.done:
        one.step()
    bulk = pheromesh.Simulation("small-test", seed=5, ticks=60).step(17).run(until=40).run()
    assert field_bytes(one.result().fields) == field_bytes(bulk.result().fields)
    assert bulk.tick == 60


def test_a_kill_at_tick_40_from_python_equals_faults_kill_uav_1_at_40t(tmp_path):
    pheromesh_cli("sim", "small-test", "--ticks", "100", "--faults", "kill uav:1 @40t", "--quiet", "--out",
                  str(tmp_path / "cli"))
    sim = pheromesh.Simulation("small-test", ticks=100)
    sim.run(until=39)
    assert sim.uavs["alive"].tolist() == [True, True, True, True]
    assert sim.kill("uav:1") == []
    assert sim.uavs["alive"].tolist() == [True, False, True, True]
    sim.run()
    r = sim.result(out=tmp_path / "py")
    assert same_files(tmp_path / "cli", tmp_path / "py")
    assert r.metrics["processes_killed"] == 1
    assert r.series["uavs_reporting"][39] == 4 and r.series["uavs_reporting"][40] == 3
    # The guard: without the kill the run is another one.
    unharmed = pheromesh.sim("small-test", ticks=100)
    assert field_bytes(unharmed.fields) != field_bytes(r.fields)


def test_a_stop_and_a_place_kill_between_ticks_equal_the_same_schedule_given_to_sim():
    given = pheromesh.sim("small-test", ticks=80, seed=2,
                          faults="kill uav:3 @5t; stop place:1 @20t for 2s; kill place:2 @30t")
    sim = pheromesh.Simulation("small-test", ticks=80, seed=2, faults="kill uav:3 @5t")
    sim.run(until=19)
    notes = sim.stop("place:1", seconds=2)
    assert len(notes) == 1 and "does not change simulated numbers" in notes[0]
    sim.kill("place:2", at=30)  # scheduled ahead
    r = sim.run().result()
    assert field_bytes(r.fields) == field_bytes(given.fields)
    for k in r.series:
        np.testing.assert_array_equal(r.series[k], given.series[k], err_msg=k)
    assert r.metrics["deposits_lost"] == given.metrics["deposits_lost"] > 0
    assert r.notes == given.notes


def test_what_cannot_be_done_between_ticks_is_refused_naming_the_problem():
    sim = pheromesh.Simulation("small-test", ticks=30)
    sim.run(until=10)
    with pytest.raises(ValueError, match=r"uav-99 does not exist \(this swarm has 4 UAVs: uav:0-3\)"):
        sim.kill("uav:99")
    with pytest.raises(ValueError, match="place-9 does not exist"):
        sim.kill("place:9")
    with pytest.raises(ValueError, match=r"tick 5 has already run \(the next tick is 11\)"):
        sim.kill("uav:0", at=5)
    with pytest.raises(ValueError, match="cannot restart"):
        sim.fault("restart uav:1 @12t for 1s")
    with pytest.raises(ValueError, match="names only"):
        sim.kill("uav:1 @12t")
    with pytest.raises(ValueError, match="seconds"):
        sim.stop("place:1", seconds=0)
    assert sim.uavs["alive"].all()  # nothing refused took effect
    sim.kill("uav:2")
    sim.step()
    with pytest.raises(ValueError, match=r"uav:2 is already dead \(killed at tick 11\)"):
        sim.kill("uav:2")
    with pytest.raises(ValueError, match=r"only 19 tick\(s\) left"):
        sim.step(20)
    with pytest.raises(ValueError, match="run it to the end first|run\\(\\) it to the end first"):
        sim.result()
    with pytest.raises(ValueError, match="until"):
        sim.run(until=3)
    sim.run()
    with pytest.raises(ValueError, match="0 tick"):
        sim.step()
    with pytest.raises(ValueError, match="the run has ended"):
        sim.fault("kill uav:0 @31t")


# --- what a Simulation shows between ticks ---------------------------------------

def test_fields_are_read_only_float32_arrays_rows_by_cols_that_later_ticks_leave_alone():
    sim = pheromesh.Simulation("small-test", ticks=50)
    f0 = sim.fields
    assert list(f0) == pheromesh.Scenario.load("small-test").layers
    path = f0["path"]
    assert path.shape == (30, 30) and path.dtype == np.float32
    assert not path.flags.writeable
    with pytest.raises(ValueError):
        path[0, 0] = 1.0
    assert path.max() > 0  # tick 0 deposited where the UAVs start
    kept = path.copy()
    sim.step(10)
    assert np.array_equal(path, kept)  # the array of tick 0 is its own buffer
    assert not np.array_equal(sim.fields["path"], kept)
    assert sim.fields["path"] is sim.fields["path"]  # gathered once per tick


def test_uavs_targets_metrics_and_series_show_the_run_so_far():
    sim = pheromesh.Simulation("small-test", ticks=300, seed=1)
    u = sim.uavs
    assert set(u) == {"uav", "x", "y", "vx", "vy", "heading", "role", "alive"}
    assert u["uav"].tolist() == [0, 1, 2, 3] and u["x"].dtype == np.float64 and u["alive"].dtype == bool
    assert all(isinstance(r, str) for r in u["role"])
    start = (u["x"].copy(), u["y"].copy())
    sim.step(20)
    assert not (np.array_equal(sim.uavs["x"], start[0]) and np.array_equal(sim.uavs["y"], start[1]))
    never = pheromesh.Simulation("small-test", ticks=10, faults="kill uav:2 @0t").uavs
    assert never["alive"].tolist() == [True, True, False, True]
    assert np.isnan(never["x"][2]) and not np.isnan(never["x"][1])  # it never flew: no position
    early = sim.metrics
    assert early["ticks"] == 20  # the last tick run so far
    assert len(sim.series["tick"]) == 21 and sim.series["tick"][-1] == 20
    assert early["coverage"] == sim.series["coverage"][-1]
    sim.run()
    t = sim.targets
    assert t["target"].tolist() == list(range(len(pheromesh.Scenario.load("small-test").targets)))
    found = sorted(int(k) for k in t["found_tick"] if k >= 0)
    assert found == sim.metrics["acquisition_ticks"]
    assert sim.metrics["covered_cells"] > early["covered_cells"]


# --- collectors and fields over time ------------------------------------------------

def test_collectors_give_one_row_per_tick_beside_the_built_in_measures():
    sim = pheromesh.Simulation("small-test", ticks=40, collect={
        "path_total": lambda s: float(s.fields["path"].sum()),
        "alive": lambda s: int(s.uavs["alive"].sum()),
    })
    sim.run(until=9)
    sim.kill("uav:0")
    sim.run()
    df = sim.frame()
    assert isinstance(df, pd.DataFrame)
    built_in = list(sim.series)
    assert list(df.columns) == built_in + ["path_total", "alive"]
    assert df.shape == (41, len(built_in) + 2)
    assert df["tick"].tolist() == list(range(41))
    assert df["alive"].tolist() == [4] * 10 + [3] * 31  # killed from tick 10: not alive after tick 9
    assert df["path_total"].iloc[-1] == pytest.approx(float(sim.result().fields["path"].sum()))
    assert df["path_total"].nunique() > 1


def test_a_collector_named_as_a_built_in_column_is_refused():
    sim = pheromesh.Simulation("small-test", ticks=5, collect={"coverage": lambda s: 0})
    with pytest.raises(ValueError, match="built-in"):
        sim.frame()
    with pytest.raises(TypeError, match="callable"):
        pheromesh.Simulation("small-test", ticks=5, collect={"x": 3})


def test_sim_fields_every_10_returns_ticks_over_10_frames_of_every_layer():
    r = pheromesh.sim("small-test", ticks=100, seed=4, fields_every=10)
    assert list(r.fields_over_time) == r.layers
    for layer, frames in r.fields_over_time.items():
        assert frames.shape == (10, 30, 30) and frames.dtype == np.float32, layer
        assert frames[-1].tobytes() == r.fields[layer].tobytes(), layer  # tick 100 is the last frame
    assert r.fields_ticks.tolist() == list(range(10, 101, 10))
    # The frame of tick 40 is the field a Simulation shows after tick 40.
    sim = pheromesh.Simulation("small-test", ticks=100, seed=4).run(until=40)
    assert r.fields_over_time["path"][3].tobytes() == sim.fields["path"].tobytes()
    assert r.fields_over_time["path"][2].tobytes() != sim.fields["path"].tobytes()
    # k need not divide the run: 100 // 7 frames, ticks 7..98.
    r7 = pheromesh.sim("small-test", ticks=100, fields_every=7)
    assert r7.fields_over_time["target"].shape == (14, 30, 30)
    assert r7.fields_ticks[-1] == 98
    assert pheromesh.sim("small-test", ticks=10).fields_over_time is None
    with pytest.raises(ValueError, match="fields_every"):
        pheromesh.sim("small-test", ticks=10, fields_every=0)
