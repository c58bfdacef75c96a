"""The Python API (docs/python.md): scenarios, their errors, sim == `pheromesh sim`,
sweeps, recordings and loading outputs. Fast: no DDS, no processes but the CLI."""

import csv
import filecmp
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import pheromesh
from conftest import BUILD, SOURCE, pheromesh_cli

# Metrics that measure this host's speed, not the swarm (frontdoor::is_timing_metric).
TIMING = {"wall_seconds", "uav_steps_per_second"}


def without_timing(metrics: dict) -> dict:
    return {k: v for k, v in metrics.items() if k not in TIMING}


# --- scenarios ------------------------------------------------------------------

def test_a_shipped_scenario_loads_by_name_as_the_cli_takes_it(small_test):
    s = pheromesh.Scenario.load("small-test")
    assert os.path.samefile(s.path, small_test)
    assert (s.name, s.uavs, s.shape, s.ticks) == ("small-test", 4, (30, 30), 300)
    assert s.layers[:3] == ["target", "obstacle", "path"]
    assert "small-test" in pheromesh.shipped_scenarios()
    assert "shao2020-50x50" in pheromesh.shipped_scenarios()


def test_a_scenario_loads_by_path(small_test):
    assert pheromesh.Scenario.load(small_test).name == "small-test"
    assert pheromesh.Scenario.load(str(small_test)).uavs == 4


def test_an_unknown_name_raises_a_scenario_error_listing_the_shipped_ones():
    with pytest.raises(pheromesh.ScenarioError) as e:
        pheromesh.Scenario.load("small-tset")
    assert "small-test" in str(e.value) and "shipped" in str(e.value)
    assert e.value.file == "small-tset"


def test_set_changes_a_field_and_validate_accepts_it():
    s = pheromesh.Scenario.load("small-test").set("swarm.uavs", 6).set("shao.aco.alpha", 2.5)
    assert s.validate() is s
    assert s.uavs == 6
    assert s.overrides == [("swarm.uavs", "6"), ("shao.aco.alpha", "2.5")]
    assert "alpha: 2.5" in s.text


def test_a_set_the_core_refuses_raises_naming_the_field_and_the_set():
    s = pheromesh.Scenario.load("small-test").set("map.tile_size", 3)
    with pytest.raises(pheromesh.ScenarioError) as e:
        s.validate()
    err = e.value
    assert err.field == "map.tile_size"
    assert err.line is None  # it came from the set, not from a line of the file
    assert err.file.endswith("small-test.textproto")
    assert ".set('map.tile_size', 3)" in str(err)
    assert "between 4 and 32" in err.issues[0].text


def test_a_set_of_a_field_that_does_not_exist_raises_naming_it():
    with pytest.raises(pheromesh.ScenarioError) as e:
        pheromesh.Scenario.load("small-test").set("shao.aco.alhpa", 2).validate()
    assert e.value.field == "shao.aco.alhpa"
    assert "alhpa" in str(e.value)


def test_a_bad_file_raises_with_its_file_line_and_field(tmp_path, small_test):
    text = small_test.read_text().replace("tile_size: 6", "tile_size: 40")
    bad = tmp_path / "bad.textproto"
    bad.write_text(text)
    line = next(i for i, l in enumerate(text.splitlines(), 1) if "tile_size: 40" in l)
    with pytest.raises(pheromesh.ScenarioError) as e:
        pheromesh.Scenario.load(bad)
    assert (e.value.file, e.value.line, e.value.field) == (str(bad), line, "map.tile_size")
    assert e.value.column is not None


def test_an_unknown_field_in_a_file_raises_with_its_line(tmp_path, small_test):
    text = small_test.read_text().replace("  uavs: 4\n", "  uavs: 4\n  wings: 2\n")
    bad = tmp_path / "unknown.textproto"
    bad.write_text(text)
    with pytest.raises(pheromesh.ScenarioError) as e:
        pheromesh.Scenario.load(bad)
    assert e.value.line == text.splitlines().index("  wings: 2") + 1
    assert e.value.field == "wings"


def test_set_refuses_a_value_of_no_scenario_type():
    with pytest.raises(TypeError):
        pheromesh.Scenario.load("small-test").set("swarm.uavs", [1, 2])


# --- sim ------------------------------------------------------------------------

def test_sim_equals_pheromesh_sim_file_for_file(tmp_path):
    cli_out, py_out = tmp_path / "cli", tmp_path / "py"
    pheromesh_cli("sim", "small-test", "--seed", "3", "--ticks", "80", "--set", "shao.aco.alpha=2", "--tracks",
                  "--quiet", "--out", str(cli_out))
    s = pheromesh.Scenario.load("small-test").set("shao.aco.alpha", 2)
    r = pheromesh.sim(s, seed=3, ticks=80, tracks=True, out=py_out)
    # The files sim(out=) writes are the CLI's, byte for byte.
    for f in ("series.csv", "final_field.csv", "final_field.txt", "tracks.csv"):
        assert filecmp.cmp(cli_out / f, py_out / f, shallow=False), f
    # And the Result in memory holds the same numbers as the CLI's files.
    cli = pheromesh.load(cli_out)
    assert without_timing(r.metrics) == without_timing(cli.metrics)
    assert r.series.keys() == cli.series.keys()
    for k in r.series:
        np.testing.assert_array_equal(r.series[k], cli.series[k], err_msg=k)
        assert r.series[k].dtype == cli.series[k].dtype, k
    assert list(r.fields) == list(cli.fields) == s.layers
    for layer, a in r.fields.items():
        assert a.tobytes() == cli.fields[layer].tobytes(), layer
    for k in r.tracks:
        assert list(r.tracks[k]) == list(cli.tracks[k]), k
    assert r.metrics["ticks"] == 80 and r.series["tick"][-1] == 80


def test_sim_results_are_numpy_arrays_shaped_rows_by_cols_over_the_buffer_they_own(tmp_path):
    r = pheromesh.sim("small-test", ticks=30, out=tmp_path)
    path = r.fields["path"]
    assert path.shape == (30, 30) and path.dtype == np.float32
    assert not path.flags.owndata and path.base is not None  # the simulator's buffer, not a copy
    assert path.max() > 0
    # Indexed [y, x]: every row of final_field.csv (layer, x, y, value) is at a[y, x].
    with open(tmp_path / "final_field.csv", newline="") as f:
        rows = [row for row in csv.DictReader(f) if row["layer"] == "path"]
    assert len(rows) == 30 * 30
    assert sum(float(row["value"]) > 0 for row in rows) > 0
    for row in rows:
        assert path[int(row["y"]), int(row["x"])] == np.float32(row["value"]), row
    assert len(r.series["tick"]) == 31 and r.series["coverage"].dtype == np.float64
    assert r.tracks is None
    assert r.metrics["coverage"] == r.series["coverage"][-1]


def test_the_seed_and_a_set_change_the_run_and_the_same_seed_repeats_it():
    a = pheromesh.sim("small-test", seed=1, ticks=60)
    b = pheromesh.sim("small-test", seed=1, ticks=60)
    c = pheromesh.sim("small-test", seed=2, ticks=60)
    d = pheromesh.sim(pheromesh.Scenario.load("small-test").set("shao.aco.beta", 4), seed=1, ticks=60)
    assert a.fields["path"].tobytes() == b.fields["path"].tobytes()
    assert a.fields["path"].tobytes() != c.fields["path"].tobytes()
    assert a.fields["path"].tobytes() != d.fields["path"].tobytes()


def test_sim_with_faults_kills_as_the_cli_does(tmp_path):
    r = pheromesh.sim("small-test", ticks=40, faults="kill uav:1 @10t", out=tmp_path / "py")
    assert r.metrics["processes_killed"] == 1
    assert r.series["uavs_reporting"][5] == 4 and r.series["uavs_reporting"][20] == 3
    pheromesh_cli("sim", "small-test", "--ticks", "40", "--faults", "kill uav:1 @10t", "--quiet", "--out",
                  str(tmp_path / "cli"))
    assert filecmp.cmp(tmp_path / "cli" / "final_field.csv", tmp_path / "py" / "final_field.csv", shallow=False)


def test_a_bad_fault_schedule_raises():
    with pytest.raises(ValueError, match="faults"):
        pheromesh.sim("small-test", ticks=10, faults="kill uav:1 @soon")
    with pytest.raises(ValueError):
        pheromesh.sim("small-test", ticks=10, faults="kill uav:99 @2t")  # no such UAV


def test_sim_with_a_bad_seed_override_raises_naming_the_argument():
    with pytest.raises(pheromesh.ScenarioError) as e:
        pheromesh.sim("small-test", ticks=0)
    assert e.value.field == "run.ticks"
    assert "sim(ticks=0)" in str(e.value)


# --- record, replay, load ------------------------------------------------------

def test_sim_records_the_console_and_replay_reads_it(tmp_path):
    rec = tmp_path / "rec" / "sim.phrec"
    pheromesh.sim("small-test", ticks=20, record=rec)
    assert rec.stat().st_size > 0
    said = pheromesh.replay.check(rec)
    assert "small-test" in said and "frames" in said


def test_load_reads_an_outputs_folder_back_into_the_same_result(tmp_path):
    r = pheromesh.sim("small-test", ticks=25, tracks=True, out=tmp_path)
    back = pheromesh.load(tmp_path)
    assert back.metrics == r.metrics
    for layer in r.fields:
        np.testing.assert_array_equal(back.fields[layer], r.fields[layer])
    for k in r.series:
        np.testing.assert_array_equal(back.series[k], r.series[k])
    assert back.source == str(tmp_path)
    with pytest.raises(FileNotFoundError):
        pheromesh.load(tmp_path / "nothing")


# --- sweep ----------------------------------------------------------------------

def test_sweep_runs_every_combination_and_seed_and_each_row_is_that_sim():
    table = pheromesh.sweep("small-test", {"shao.aco.alpha": [1, 3]}, seeds=[1, 2], jobs=2, ticks=30,
                            metrics=["coverage", "targets_found", "deposits_sent"])
    assert list(table.columns) == ["shao.aco.alpha", "seed", "coverage", "targets_found", "deposits_sent"]
    assert len(table) == 4
    assert list(zip(table["shao.aco.alpha"], table["seed"])) == [(1, 1), (1, 2), (3, 1), (3, 2)]
    one = pheromesh.sim(pheromesh.Scenario.load("small-test").set("shao.aco.alpha", 3), seed=2, ticks=30)
    row = table[(table["shao.aco.alpha"] == 3) & (table["seed"] == 2)].iloc[0]
    assert row["coverage"] == one.metrics["coverage"]
    assert row["deposits_sent"] == one.metrics["deposits_sent"]


def test_sweep_without_pandas_returns_columns(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas raises ImportError
    table = pheromesh.sweep("small-test", {"swarm.uavs": [2]}, seeds=range(1, 3), jobs=1, ticks=10)
    assert isinstance(table, dict)
    assert table["seed"] == [1, 2] and table["swarm.uavs"] == [2, 2]
    assert len(table["coverage"]) == 2


def test_sweep_refuses_a_bad_value_before_running_anything():
    with pytest.raises(pheromesh.ScenarioError) as e:
        pheromesh.sweep("small-test", {"map.tile_size": [6, 2]}, seeds=[1], ticks=10)
    assert e.value.field == "map.tile_size"
    with pytest.raises(TypeError):
        pheromesh.sweep("small-test", {"shao.aco.alpha": 2}, seeds=[1])
    with pytest.raises(KeyError):
        pheromesh.sweep("small-test", {"shao.aco.alpha": [1]}, seeds=[1], ticks=5, metrics=["no_such_metric"])


# --- the package ----------------------------------------------------------------

def test_help_documents_the_api():
    for f in (pheromesh.sim, pheromesh.sweep, pheromesh.run, pheromesh.Scenario.load, pheromesh.Scenario.set,
              pheromesh.load, pheromesh.Result, pheromesh.ScenarioError):
        assert f.__doc__ and len(f.__doc__) > 60, f
    assert "seed" in pheromesh.sim.__doc__ and "faults" in pheromesh.sim.__doc__
    assert pheromesh.sim.__annotations__["return"] in ("Result", pheromesh.Result)


def test_inside_a_pheromesh_process_the_package_does_not_load_the_extension():
    # A pheromesh process that embeds Python registers _pheromesh_embedded;
    # importing the package there must not load a second copy of the core.
    code = (
        "import sys, types\n"
        "m = types.ModuleType('_pheromesh_embedded')\n"
        "class UavPolicy: pass\n"
        "m.UavPolicy = UavPolicy\n"
        "sys.modules['_pheromesh_embedded'] = m\n"
        "import pheromesh\n"
        "assert pheromesh.EMBEDDED\n"
        "assert pheromesh.UavPolicy is UavPolicy\n"
        "assert 'pheromesh._pheromesh' not in sys.modules, 'the extension was loaded'\n"
        "assert not hasattr(pheromesh, 'sim')\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 0, done.stderr
    # And outside one it does.
    done = subprocess.run([sys.executable, "-c", "import sys, pheromesh; assert not pheromesh.EMBEDDED; "
                           "assert 'pheromesh._pheromesh' in sys.modules"], capture_output=True, text=True,
                          timeout=60, check=False)
    assert done.returncode == 0, done.stderr


def test_a_policy_parameter_is_set_by_its_key_and_its_position_is_refused_naming_the_key():
    example = SOURCE / "examples" / "python" / "repulsive-coverage-python.textproto"
    s = pheromesh.Scenario.load(example)
    marked = s.copy().set("policy.python.param.evaporation", 0.2)
    a = pheromesh.sim(s, ticks=40)
    b = pheromesh.sim(marked, ticks=40)
    assert a.fields["repulsion"].tobytes() != b.fields["repulsion"].tobytes()
    assert "number: 0.2" in marked.text
    with pytest.raises(pheromesh.ScenarioError, match=r"policy\.python\.param\.evaporation=VALUE"):
        s.copy().set("policy.python.config[1].number", 0.2).validate()


def test_sweep_has_nan_for_a_time_a_run_did_not_reach_and_a_number_where_it_did():
    t = pheromesh.sweep("small-test", {"shao.aco.alpha": [1]}, seeds=range(1, 9), jobs=2, ticks=70,
                        metrics=["targets_found", "ticks_to_all_targets"])
    reached = t["targets_found"] == len(pheromesh.Scenario.load("small-test").targets)
    assert reached.any() and not reached.all()  # the horizon cuts some runs short, so both cases occur
    assert t.loc[~reached, "ticks_to_all_targets"].isna().all()
    assert (t.loc[reached, "ticks_to_all_targets"] <= 70).all()
    with pytest.raises(KeyError, match="no metric 'coverag'"):
        pheromesh.sweep("small-test", {"shao.aco.alpha": [1]}, seeds=[1], ticks=5, metrics=["coverag"])


def test_run_domain_auto_claims_a_domain_no_other_claim_of_this_host_holds():
    from pheromesh._api import AUTO_DOMAINS, _claimed_domain

    with _claimed_domain() as a:
        with _claimed_domain() as b:
            assert a != b and a in AUTO_DOMAINS and b in AUTO_DOMAINS
            # Another process sees both held too.
            code = ("import pheromesh._api as api\n"
                    "with api._claimed_domain() as c: print(c)\n")
            done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60,
                                  check=False)
            assert done.returncode == 0, done.stderr
            assert int(done.stdout) not in (a, b)
    with _claimed_domain() as again:
        assert again <= a  # released at the end of the block: the first free one is taken again
    with pytest.raises(ValueError, match="domain"):
        pheromesh.run("small-test", domain="anywhere")
    with pytest.raises(ValueError, match="twice"):
        pheromesh.run("small-test", domain=5, args=["--domain", "6"])
