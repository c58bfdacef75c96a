// Python policies (core/python_policy.hpp, pypolicy/pypolicy.hpp): a
// scenario's `policy { python { module class config } }` imports the module
// beside the scenario (or on $PHEROMESH_PYTHONPATH), reads the class's
// parameters with errors at their lines, and the simulator steps the class;
// every refusal says what and where; a program without the hook refuses the
// block; an exception in a step carries Python's traceback.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>

#include "pheromesh/core/policy_table.hpp"
#include "pheromesh/core/python_policy.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/pypolicy/enable.hpp"

using namespace pheromesh::core;
namespace fs = std::filesystem;

namespace {

// A small policy: each UAV marks its cell and steps to a random free
// neighbour drawn from its own stream (uav.rng).
constexpr const char* kWalk = R"PY(
import pheromesh

class Walk(pheromesh.UavPolicy):
    name = "py_" + __name__  # one module per test: one policy name each
    parameters = {"mark": 1.0, "steps": 1, "label": "walk", "loud": False, "fail_at": 0}

    @classmethod
    def traits(cls, config):
        if config["mark"] > 100:
            raise ValueError("mark must be at most 100")
        return pheromesh.Traits([pheromesh.Layer("trail", evaporation=0.05, diffusion=0.1, max=100)],
                                sensor_radius=1.5, view_radius=2.0, max_step=1.5, reads_neighbours=False)

    def __init__(self, config, uav):
        super().__init__(config, uav)
        self.x, self.y = uav.start

    def step(self, view, actions):
        if view.tick == self.config["fail_at"] and self.config["fail_at"] > 0:
            self.explode(view.tick)
        if view.tick > 0:
            for _ in range(8):
                dx, dy = pheromesh.step_of(self.uav.rng.uniform_below(8))
                nx, ny = self.x + dx, self.y + dy
                if self.uav.in_map(nx, ny) and not self.uav.is_obstacle(nx, ny):
                    self.x, self.y = nx, ny
                    break
        actions.deposit(0, self.x, self.y, self.config["mark"])
        for t in self.uav.sense(self.x, self.y, 1.5):
            actions.detect(t)
        actions.set_state(self.x, self.y)

    def explode(self, tick):
        raise KeyError(f"walk exploded at tick {tick}")

    @classmethod
    def field_summary(cls, config, field):
        if config["label"] == "bad-summary":
            raise ValueError("no summary today")
        return {"cells": field.width * field.height, "corner": field.value(0, field.width - 1, field.height - 1)}

class NotAPolicy:
    pass

class Count(pheromesh.PlaceModel):
    """Counts the deposits on each cell."""
    def __init__(self, config, region):
        super().__init__(config, region)
        self.cells = {}
    def apply(self, deposit, tick):
        assert self.region.x <= deposit.x < self.region.x + self.region.w, "a deposit of another region"
        key = (deposit.layer, deposit.x, deposit.y)
        self.cells[key] = self.cells.get(key, 0.0) + 1.0
        return None
    def value(self, layer, x, y):
        return self.cells.get((layer, x, y), 0.0)

class Counted(Walk):
    name = "counted_" + __name__
    place_model = Count

class BadPlace(Walk):
    name = "badplace_" + __name__
    place_model = int

class Forgetful(Walk):
    name = "forgetful_" + __name__
    def step(self, view, actions):
        pass
)PY";

class PythonScenario : public ::testing::Test {
 protected:
  void SetUp() override {
    pheromesh::pypolicy::enable_python_policies();
    dir_ = fs::temp_directory_path() / ("phm-pypolicy-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    // A module name per test: Python caches a module once imported.
    module_ = std::string("walk_") + ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::ofstream(dir_ / (module_ + ".py")) << kWalk;
  }
  void TearDown() override { fs::remove_all(dir_); }
  // A scenario whose policy block is `python { block }`.
  std::string write(const std::string& block, uint32_t ticks = 30) {
    const std::string path = (dir_ / "s.textproto").string();
    std::ofstream(path) << "map { width: 20 height: 16 tile_size: 5 regions_x: 2 regions_y: 2\n"
                        << "  targets { x: 15 y: 12 } obstacles { x: 8 y: 6 w: 3 h: 2 } }\n"
                        << "swarm { uavs: 4 start_area { x: 0 y: 0 w: 3 h: 3 } }\nrun { ticks: " << ticks << " }\n"
                        << "policy {\n  python {\n" << block << "\n  }\n}\n";
    return path;
  }
  std::string walk(const std::string& cls = "Walk") const {
    return "    module: \"" + module_ + "\"\n    class: \"" + cls + "\"\n";
  }
  fs::path dir_;
  std::string module_;
};

std::string error_of(const Result<ScenarioConfig>& r) { return r.ok() ? std::string("(loaded)") : r.error().message; }

}  // namespace

TEST_F(PythonScenario, AScenarioImportsTheClassBesideItAndTheTableFindsItsEntry) {
  auto s = load_scenario(write(walk() + "    config { key: \"mark\" number: 3 }"));
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->policy, "py_" + module_);
  ASSERT_TRUE(s->python.has_value());
  EXPECT_EQ(s->python->module, module_);
  EXPECT_EQ(s->python->class_name, "Walk");
  EXPECT_EQ(fs::path(s->python->file), dir_ / (module_ + ".py"));
  ASSERT_NE(find_policy("py_" + module_), nullptr);
  const PolicyTraits t = policy_traits(s.value());
  EXPECT_EQ(t.layers, std::vector<std::string>{"trail"});
  ASSERT_EQ(t.layer_ranges.size(), 1U);
  EXPECT_EQ(t.layer_ranges[0].hi, 100.0F);
  EXPECT_EQ(t.view_radius, 2.0);
  EXPECT_EQ(t.sensor_radius, 1.5);
  EXPECT_FALSE(t.reads_neighbours) << "Traits(..., reads_neighbours=False)";
}

TEST_F(PythonScenario, TheSimulatorStepsTheClassAndASeedGivesTheSameRun) {
  const std::string path = write(walk() + "    config { key: \"mark\" number: 3 }", 40);
  auto s = load_scenario(path);
  ASSERT_TRUE(s.ok()) << s.error().message;
  Simulator a(s.value());
  a.run();
  Simulator b(load_scenario(path).value());
  b.run();
  bool moved = false;
  for (uint32_t u = 0; u < 4; ++u) {
    EXPECT_EQ(a.uav(u).cell(), b.uav(u).cell()) << "uav " << u;
    moved = moved || a.uav(u).cell() != start_cell(s.value(), u);
  }
  EXPECT_TRUE(moved);
  // Another seed: other random numbers, so (almost surely) another walk.
  auto other = load_scenario(path, ScenarioOverrides{{"run.seed", "2", "--seed"}});
  ASSERT_TRUE(other.ok()) << other.error().message;
  Simulator c(other.value());
  c.run();
  bool differs = false;
  for (uint32_t u = 0; u < 4; ++u) differs = differs || c.uav(u).cell() != a.uav(u).cell();
  EXPECT_TRUE(differs);
}

TEST_F(PythonScenario, AnExceptionInAStepCarriesPythonsTraceback) {
  auto s = load_scenario(write(walk() + "    config { key: \"fail_at\" number: 5 }"));
  ASSERT_TRUE(s.ok()) << s.error().message;
  Simulator sim(s.value());
  try {
    sim.run();
    FAIL() << "the run did not stop";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("python policy " + module_ + ".Walk: uav 0 tick 5: step raised:"), std::string::npos) << what;
    EXPECT_NE(what.find("Traceback (most recent call last):"), std::string::npos) << what;
    EXPECT_NE(what.find("in explode"), std::string::npos) << what;
    EXPECT_NE(what.find("KeyError: 'walk exploded at tick 5'"), std::string::npos) << what;
  }
}

TEST_F(PythonScenario, TheClassJudgesTheFinalField) {
  auto s = load_scenario(write(walk()));
  ASSERT_TRUE(s.ok()) << s.error().message;
  const FieldLookup lookup = [](int layer, Cell c) { return static_cast<float>(layer * 1000 + c.x * 100 + c.y); };
  const std::map<std::string, double> m = field_summary(s.value(), lookup);
  EXPECT_EQ(m, (std::map<std::string, double>{{"cells", 320.0}, {"corner", 1915.0}}));
  auto bad = load_scenario(write(walk() + "    config { key: \"label\" text: \"bad-summary\" }"));
  ASSERT_TRUE(bad.ok()) << bad.error().message;
  try {
    field_summary(bad.value(), lookup);
    FAIL() << "field_summary did not throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("field_summary raised:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("ValueError: no summary today"), std::string::npos) << e.what();
  }
}

TEST_F(PythonScenario, APlaceModelInPythonKeepsTheLayers) {
  auto s = load_scenario(write(walk("Counted"), 30));
  ASSERT_TRUE(s.ok()) << s.error().message;
  Simulator sim(s.value());
  sim.run();
  // Every step deposits once; Count counts them where they fell.
  double total = 0.0;
  for (int32_t y = 0; y < s->height; ++y) {
    for (int32_t x = 0; x < s->width; ++x) total += sim.field_value(0, {x, y});
  }
  EXPECT_EQ(total, static_cast<double>(sim.uav_steps()));
  EXPECT_GT(total, 100.0);
  const std::string e = error_of(load_scenario(write(walk("BadPlace"))));
  EXPECT_NE(e.find("field 'policy.python.class': " + module_ +
                   ".BadPlace.place_model must be a subclass of pheromesh.PlaceModel (or None)"),
            std::string::npos)
      << e;
}

TEST_F(PythonScenario, AStepThatSaysNothingOfWhereTheUavIsIsAnError) {
  auto s = load_scenario(write(walk("Forgetful")));
  ASSERT_TRUE(s.ok()) << s.error().message;
  Simulator sim(s.value());
  EXPECT_THROW(
      {
        try {
          sim.run();
        } catch (const std::runtime_error& e) {
          EXPECT_NE(std::string(e.what()).find("step did not call actions.set_state"), std::string::npos) << e.what();
          throw;
        }
      },
      std::runtime_error);
}

TEST_F(PythonScenario, ModuleAndClassAreRequired) {
  const std::string path = write("    config { key: \"mark\" number: 3 }");
  const std::string e = error_of(load_scenario(path));
  EXPECT_NE(e.find(path + ":6:3: field 'policy.python.module': required field is missing"), std::string::npos) << e;
  EXPECT_NE(e.find("field 'policy.python.class': required field is missing"), std::string::npos) << e;
}

TEST_F(PythonScenario, AModuleNotFoundNamesTheFoldersSearched) {
  setenv("PHEROMESH_PYTHONPATH", "/nonexistent/a:/nonexistent/b", 1);
  const std::string path = write("    module: \"no_such_policy_module\"\n    class: \"X\"");
  auto r = load_scenario(path);
  unsetenv("PHEROMESH_PYTHONPATH");
  const std::string e = error_of(r);
  EXPECT_NE(e.find(path + ":7:5: field 'policy.python.module': no Python module \"no_such_policy_module\" in " +
                   dir_.string()),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("/nonexistent/a, /nonexistent/b"), std::string::npos) << e;
}

TEST_F(PythonScenario, AModuleOnPheromeshPythonpathIsFound) {
  const fs::path elsewhere = dir_ / "lib";
  fs::create_directories(elsewhere);
  std::ofstream(elsewhere / ("far_" + module_ + ".py")) << kWalk;
  setenv("PHEROMESH_PYTHONPATH", ("/nonexistent:" + elsewhere.string()).c_str(), 1);
  auto s = load_scenario(write("    module: \"far_" + module_ + "\"\n    class: \"Walk\""));
  unsetenv("PHEROMESH_PYTHONPATH");
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(fs::path(s->python->file), elsewhere / ("far_" + module_ + ".py"));
}

TEST_F(PythonScenario, AModuleThatFailsToImportShowsItsTraceback) {
  std::ofstream(dir_ / "broken_policy.py") << "import pheromesh\n\nx = 1 +\n";
  const std::string path = write("    module: \"broken_policy\"\n    class: \"X\"");
  const std::string e = error_of(load_scenario(path));
  EXPECT_NE(e.find("field 'policy.python.module': importing \"broken_policy\" raised:"), std::string::npos) << e;
  EXPECT_NE(e.find("SyntaxError"), std::string::npos) << e;
  EXPECT_NE(e.find("broken_policy.py\", line 3"), std::string::npos) << e;
}

TEST_F(PythonScenario, AClassThatIsMissingOrNotAPolicyIsRefusedAtItsLine) {
  const std::string path = write(walk("Nope"));
  const std::string e = error_of(load_scenario(path));
  EXPECT_NE(e.find(path + ":8:5: field 'policy.python.class': the module \"" + module_ + "\" ("), std::string::npos)
      << e;
  EXPECT_NE(e.find(") has no class \"Nope\""), std::string::npos) << e;
  const std::string e2 = error_of(load_scenario(write(walk("NotAPolicy"))));
  EXPECT_NE(e2.find("field 'policy.python.class': \"" + module_ + ".NotAPolicy\" is not a subclass of "
                    "pheromesh.UavPolicy"),
            std::string::npos)
      << e2;
}

TEST_F(PythonScenario, ParametersAreCheckedAtTheirLines) {
  const std::string path = write(walk() +
                                 "    config { key: \"mark\" text: \"a lot\" }\n"
                                 "    config { key: \"steps\" number: 1.5 }\n"
                                 "    config { key: \"colour\" text: \"red\" }\n"
                                 "    config { key: \"loud\" flag: true }");
  const std::string e = error_of(load_scenario(path));
  EXPECT_NE(e.find(path + ":9:5: field 'policy.python.config[0]': (key \"mark\"): is a text; the plugin reads a number"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find(path + ":10:5: field 'policy.python.config[1]': (key \"steps\"): must be a whole number"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find(path + ":11:5: field 'policy.python.config[2]': key \"colour\" is not a parameter of the policy "
                          "py_" + module_ + " (it reads: mark, steps, label, loud, fail_at)"),
            std::string::npos)
      << e;
  EXPECT_EQ(e.find("config[3]"), std::string::npos) << e;  // loud: a flag, as the default
}

TEST_F(PythonScenario, APolicyNameIsOneClassAndNotABuiltInPolicys) {
  ASSERT_TRUE(load_scenario(write(walk())).ok());
  // The same class again (a second scenario, a sweep): the same entry.
  ASSERT_TRUE(load_scenario(write(walk())).ok());
  // Another module whose class says the same name.
  std::ofstream(dir_ / "same_name.py") << "import pheromesh\nclass Walk(pheromesh.UavPolicy):\n    name = \"py_" +
                                              module_ + "\"\n";
  const std::string path = write("    module: \"same_name\"\n    class: \"Walk\"");
  const std::string e = error_of(load_scenario(path));
  EXPECT_NE(e.find(path + ":8:5: field 'policy.python.class': the policy name \"py_" + module_ +
                   "\" of same_name.Walk is taken by another Python class this program loaded"),
            std::string::npos)
      << e;
  std::ofstream(dir_ / "liu_again.py") << "import pheromesh\nclass Liu(pheromesh.UavPolicy):\n    name = \"liu\"\n";
  const std::string e2 = error_of(load_scenario(write("    module: \"liu_again\"\n    class: \"Liu\"")));
  EXPECT_NE(e2.find("the policy name \"liu\" of liu_again.Liu is a built-in policy's or a plugin's"), std::string::npos)
      << e2;
}

TEST_F(PythonScenario, AnErrorOfTheTraitsIsReportedAtTheClass) {
  const std::string path = write(walk() + "    config { key: \"mark\" number: 500 }");
  const std::string e = error_of(load_scenario(path));
  EXPECT_NE(e.find(path + ":8:5: field 'policy.python.class': " + module_ + ".Walk.traits(config) raised:"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("ValueError: mark must be at most 100"), std::string::npos) << e;
}

TEST_F(PythonScenario, AProgramWithoutPythonSupportRefusesTheBlock) {
  const PythonPolicyHook* hook = python_policy_hook();
  set_python_policy_hook(nullptr);
  const std::string path = write(walk());
  const std::string e = error_of(load_scenario(path));
  set_python_policy_hook(hook);
  EXPECT_NE(e.find(path + ":6:3: field 'policy.python': this program was built without Python support"),
            std::string::npos)
      << e;
}

TEST_F(PythonScenario, TextWithoutAFileLooksOnlyOnThePath) {
  // parse_scenario: no folder of its own; the module is not on the path.
  const std::string e = error_of(parse_scenario(
      "map { width: 20 height: 16 } swarm { uavs: 2 start_area { x: 0 y: 0 w: 3 h: 3 } }\n"
      "policy { python { module: \"" + module_ + "\" class: \"Walk\" } }",
      "text"));
  EXPECT_NE(e.find("no Python module \"" + module_ + "\""), std::string::npos) << e;
}
