// The web console of a real ground station under a flood of refused
// requests (docs/console.md, "Limits"): every one is counted, at most five
// in ten seconds reach the log and the recording, and the rest are
// summarised once. Domain 85, console port 18660. Backend-free: runs once.
#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers
using nlohmann::json;

TEST(ConsoleLimits, AFloodOfCommandsWithoutTheTokenIsCountedInFullButLoggedAndRecordedAtMostFiveTimesWithASummary) {
  const std::string out = out_dir("console-refusals");
  const std::string url = "http://127.0.0.1:18660";
  // 500 ticks at 25 Hz: 20 s, so that the 10 s window of the refusals ends
  // while the ground station still runs.
  Background b = start_run("small-test.textproto", out, 85, "--uavs 2 --ticks 500 --rate 25 --http 18660");
  bool up = false;
  for (int i = 0; i < 150 && !up; ++i) {
    up = run("curl -sf " + url + "/api/info").exit_code == 0;
    if (!up) std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  ASSERT_TRUE(up) << slurp(b.out_path);
  const Output flood =
      run("for i in $(seq 30); do curl -s -o /dev/null -w '%{http_code} ' -X POST "
          "-H 'Content-Type: application/json' -d '{\"kind\":\"pause\"}' " +
          url + "/api/command; done");
  std::string all401;
  for (int i = 0; i < 30; ++i) all401 += "401 ";
  EXPECT_EQ(flood.text, all401);
  bool counted = false;
  std::string metrics;
  for (int i = 0; i < 50 && !counted; ++i) {  // /metrics is rebuilt with each frame (5 a second)
    metrics = run("curl -s " + url + "/metrics").text;
    counted = metrics.find("pheromesh_console_http_refused_total{reason=\"unauthorised\"} 30\n") != std::string::npos;
    if (!counted) std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  EXPECT_TRUE(counted) << metrics;
  EXPECT_NE(metrics.find("pheromesh_console_commands_total{result=\"refused\"} 30\n"), std::string::npos) << metrics;
  ASSERT_EQ(wait_exit(b.pid, std::chrono::seconds(120)), 0) << slurp(b.out_path);

  const std::string log = slurp(b.out_path);  // the ground station logs through the launcher
  std::size_t lines = 0;
  for (auto p = log.find("console request from"); p != std::string::npos; p = log.find("console request from", p + 1))
    ++lines;
  EXPECT_EQ(lines, 5U) << log;
  EXPECT_NE(log.find("console: suppressed 25 refused requests"), std::string::npos) << log;

  // The final state is built from the same frames as the recording.
  std::ifstream in(out + "/console_final.json");
  json final;
  ASSERT_TRUE(in >> final) << "no console_final.json";
  int logged = 0, summaries = 0;
  for (const auto& c : final["commands"]) {
    if (c["ok"].get<bool>()) continue;
    const std::string what = c["what"];
    if (what == "suppressed 25 refused requests") {
      ++summaries;
    } else {
      EXPECT_EQ(what, "POST /api/command (Content-Length 16)") << c.dump();
      ++logged;
    }
  }
  EXPECT_EQ(logged, 5) << final["commands"].dump();
  EXPECT_EQ(summaries, 1) << final["commands"].dump();
}
