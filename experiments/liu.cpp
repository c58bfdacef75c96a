// Liu 2022 (ESUSTPM) Liu 2022 Sec. 5: Liu 2022 Table 2 (five search methods, with and
// without targets) and Liu 2022 Sec. 5.3 (prior information, Liu 2022 Fig. 24, Liu 2022 Fig. 25, Liu 2022 Fig. 26, Liu 2022 Fig. 27), run with the
// core's liu_swarm simulation.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "experiment.hpp"
#include "flight.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/liu/swarm.hpp"
#include "pheromesh/liu/tpm.hpp"
#include "pheromesh/cliutil/scenario_paths.hpp"

namespace pheromesh::cli::experiments {

namespace {

using core::LiuPolicy;
using core::LiuPrior;
using core::LiuSensor;
using core::LiuStartVelocity;
using core::LiuSwarmConfig;
using core::LiuSwarmResult;
using core::Vec2;

// Liu 2022 Sec. 5.4: "five simulations ... are executed 10 times" (the statistics of
// Liu 2022 Fig. 28, Liu 2022 Fig. 29, Liu 2022 Fig. 30). Liu 2022 Table 2 and Liu 2022 Fig. 24, Liu 2022 Fig. 25, Liu 2022 Fig. 26, Liu 2022 Fig. 27 do not say how many runs they show.
constexpr uint32_t kPaperRuns = 10;

std::string fmt(double v, int prec = 2) {
  if (!std::isfinite(v)) return "–";
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", prec, v);
  return b;
}

LiuSwarmResult simulate(const LiuSwarmConfig& c, uint64_t seed) {
  auto r = core::run_liu_swarm(c, seed);
  if (!r) throw std::runtime_error(r.error().message);
  return std::move(r).value();
}

struct SensorSpec {
  LiuSensor sensor;
  std::string tag;   // appended to row names
  std::string file;  // plot file suffix
};

const std::vector<SensorSpec>& sensors() {
  static const std::vector<SensorSpec> s{{LiuSensor::kNoisy, "", "noisy"},
                                         {LiuSensor::kAlgorithm1, " [Alg. 1 sensor]", "alg1"}};
  return s;
}

std::string confirmation_list(const LiuSwarmResult& r) {
  std::string s;
  for (const auto& c : r.confirmation_cycle) s += (s.empty() ? "" : " ") + (c ? std::to_string(*c) : std::string("-"));
  return s;
}

// Mean of per-run series, cycle by cycle.
template <typename T>
Series mean_series(const std::string& name, const std::vector<std::vector<T>>& runs) {
  Series s{name, {}};
  if (runs.empty()) return s;
  for (std::size_t k = 0; k < runs.front().size(); ++k) {
    double sum = 0.0;
    for (const auto& r : runs) sum += static_cast<double>(r[k]);
    s.points.emplace_back(static_cast<double>(k), sum / static_cast<double>(runs.size()));
  }
  return s;
}

std::string common_setup(uint32_t runs) {
  return "10x10 grid of 100 m cells, 10 UAVs from §5's start positions (mowers from their lanes), 200 cycles of 1 s "
         "flown in Δt = 10 ms steps, Pd = 0.3, Pf = 0.1, printed eq. (5), θ = 0.95; " +
         std::to_string(runs) + " runs with seeds 1.." + std::to_string(runs) +
         ", the same seeds for every configuration. Two sensor readings: noisy (detections drawn with Pd / Pf) and "
         "Algorithm 1's (eq. 4 exactly when the cell holds a target)";
}

// ---------------------------------------------------------------------------
// Liu 2022 Table 2
// ---------------------------------------------------------------------------

struct MethodSpec {
  LiuPolicy policy;
  std::string name;
  bool paper_method;             // false: our variant, no paper figure
  double visited, eu, found;     // Liu 2022 Table 2, "grid with target"
  double visited_nt, eu_nt;      // Liu 2022 Table 2, "grid without target"
};

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

// The paper's five (the first five, Liu 2022 Table 2's order) and our variant.
const std::vector<MethodSpec>& methods() {
  static const std::vector<MethodSpec> m{
      {LiuPolicy::kEsustpm, "ESUSTPM", true, 89, 40.23, 3, 95, 40.24},
      {LiuPolicy::kLawnmower, "mower", true, 100, 52.34, 0, 100, 52.34},
      {LiuPolicy::kRandom, "random", true, 26, 43.92, 0, 29, 42.76},
      {LiuPolicy::kBoids, "Boids", true, 53, 42.86, 1, 40, 43.93},
      {LiuPolicy::kGuidedBoids, "guided Boids", true, 75, 42.11, 2, 82, 43.53},
      {LiuPolicy::kEsustpmDisperse, "ESUSTPM-disperse (ours)", false, kNone, kNone, kNone, kNone, kNone},
  };
  return m;
}
constexpr std::size_t kPaperMethods = 5;
constexpr std::size_t kDisperse = 5;

struct MethodSamples {  // one (sensor, method, variant)
  std::vector<double> visited, eu, eu_binary, found, false_conf, observations, all_found_cycle;
  std::vector<std::vector<double>> eu_series;
  std::vector<std::vector<int64_t>> visited_series;
  std::vector<std::vector<uint32_t>> found_series;
  void add(const LiuSwarmResult& r) {
    visited.push_back(static_cast<double>(r.visited_cells));
    eu.push_back(r.final_eu);
    eu_binary.push_back(core::binary_entropy_bits(r.final_tpm));
    found.push_back(r.targets_found);
    false_conf.push_back(r.false_confirmations);
    observations.push_back(static_cast<double>(r.observations));
    // A run that never confirmed every target counts as the full run length:
    // "time to find all targets" is then censored at 200 cycles.
    all_found_cycle.push_back(r.all_found_cycle ? *r.all_found_cycle : static_cast<double>(r.eu_per_cycle.size() - 1));
    eu_series.push_back(r.eu_per_cycle);
    visited_series.push_back(r.visited_per_cycle);
    found_series.push_back(r.found_per_cycle);
  }
};

// Per run, the rank of method 0 (ESUSTPM) among the paper's five on one
// metric: 1 = best; ties share the mean of their ranks.
std::vector<double> esustpm_rank(const std::vector<const std::vector<double>*>& per_method, bool lower_is_better) {
  std::vector<double> out;
  if (per_method.empty()) return out;
  for (std::size_t run = 0; run < per_method[0]->size(); ++run) {
    const double mine = (*per_method[0])[run];
    double better = 0, ties = 0;
    for (std::size_t m = 1; m < per_method.size(); ++m) {
      const double v = (*per_method[m])[run];
      if (std::fabs(v - mine) < 1e-9) {
        ++ties;
      } else if (lower_is_better ? v < mine : v > mine) {
        ++better;
      }
    }
    out.push_back(1.0 + better + 0.5 * ties);
  }
  return out;
}

// Verdict of a Liu 2022 Table 2 row. visited / found: auto_verdict's test with the
// cause when it differs. EU: the metric only spans ~40–53 bit over every
// search (50 = the untouched map), so auto_verdict's 15 % band would call
// almost anything reproduced; reproduced here means within 1 bit (2 % of 50)
// or the paper's figure inside our 95 % CI (5 runs or more).
enum class Metric : uint8_t { kVisited, kEu, kFound };
std::string table2_verdict(const Row& r, Metric metric, LiuPolicy policy, LiuSensor sensor) {
  if (metric == Metric::kEu) {
    const double m = mean(r.ours), p = *r.paper;
    const Interval ci = ci95(r.ours);
    const bool in_ci = r.ours.size() >= 5 && p >= ci.lo && p <= ci.hi;
    if (in_ci || std::fabs(m - p) <= 1.0) return "reproduced";
    const std::string by = fmt(std::fabs(m - p), 1) + " bit " + (m > p ? "higher" : "lower");
    if (policy == LiuPolicy::kEsustpm) {
      return "differs: " + by + "; no search with ESUSTPM's look budget can reach it (investigation)";
    }
    if (policy == LiuPolicy::kLawnmower) {
      return "differs: " + by +
             (sensor == LiuSensor::kNoisy ? "; false alarms (P = 0.75) lower it"
                                          : "; its 3 target cells are detected twice (P = 0.9)");
    }
    return "differs: " + by + "; this EU rewards re-entering few cells (investigation)";
  }
  // auto_verdict's test, but with fewer than 5 runs (a --distributed check)
  // the t interval is too wide to mean anything: the 15 % band alone.
  std::string a = auto_verdict(r);
  if (r.ours.size() < 5 && a == "reproduced" && *r.paper != 0.0 && std::fabs(mean(r.ours) / *r.paper - 1) > 0.15) {
    Row no_ci = r;
    no_ci.ours.assign(1, mean(r.ours));
    a = auto_verdict(no_ci);
  }
  if (a == "reproduced") return a;
  if (metric == Metric::kFound) {
    if (sensor == LiuSensor::kNoisy)
      return a + ": printed eq. (5) holds a target cell's P near 0.4, θ is rarely passed";
    return a + ": with a noiseless sensor three entries confirm a target cell";
  }
  switch (policy) {
    case LiuPolicy::kEsustpm:
      return a + ": Table 1's neighbour rules hold a rigid lattice that drifts as one body";
    case LiuPolicy::kBoids:
      return a + ": Boids rule weights not given (ours equal)";
    case LiuPolicy::kGuidedBoids:
      return a + ": Boids rule weights not given (ours equal)";
    case LiuPolicy::kRandom:
      return a + ": cause not found (random collision avoidance not specified)";
    default:
      return a;
  }
}

// --- sensitivity study over the quantities the paper leaves unstated --------

struct Setting {
  std::string name;
  std::function<void(LiuSwarmConfig&)> apply;
};

const std::vector<Setting>& settings() {
  static const std::vector<Setting> s{
      {"ours (cycle 1 s, printed eq. 5, θ 0.95, random start heading, unlimited range)", [](LiuSwarmConfig&) {}},
      {"cycle 0.5 s", [](LiuSwarmConfig& c) { c.params.cycle_s = 0.5; }},
      {"cycle 2 s", [](LiuSwarmConfig& c) { c.params.cycle_s = 2.0; }},
      {"cycle 4 s", [](LiuSwarmConfig& c) { c.params.cycle_s = 4.0; }},
      {"Bayesian miss update", [](LiuSwarmConfig& c) { c.params.miss_update = core::MissUpdate::kBayes; }},
      {"θ = 0.9", [](LiuSwarmConfig& c) { c.params.confirm_threshold = 0.9; }},
      {"θ = 0.99", [](LiuSwarmConfig& c) { c.params.confirm_threshold = 0.99; }},
      {"start at rest", [](LiuSwarmConfig& c) { c.start_velocity = LiuStartVelocity::kRest; }},
      {"communication range 250 m", [](LiuSwarmConfig& c) { c.params.comm_range_m = 250.0; }},
      {"communication range 150 m", [](LiuSwarmConfig& c) { c.params.comm_range_m = 150.0; }},
      {"confirmed cells keep guiding", [](LiuSwarmConfig& c) { c.release_confirmed_cells = false; }},
      {"Boids separation weight 2", [](LiuSwarmConfig& c) { c.params.boids_separation_weight = 2.0; }},
      {"Boids guidance weight 2", [](LiuSwarmConfig& c) { c.params.boids_guidance_weight = 2.0; }},
      {"cycle 2 s + Bayesian miss",
       [](LiuSwarmConfig& c) {
         c.params.cycle_s = 2.0;
         c.params.miss_update = core::MissUpdate::kBayes;
       }},
  };
  return s;
}

std::string pm(const std::vector<double>& v, int prec = 1) { return fmt(mean(v), prec) + " ± " + fmt(stddev(v), prec); }

struct StudyCell {  // one (setting, sensor)
  std::string setting, sensor;
  double rank_visited, rank_eu, rank_eu_binary, rank_found, esustpm_visited, esustpm_eu, mower_eu, disperse_visited;
};
struct Study {
  std::string md;
  std::vector<StudyCell> cells;
};

// One table per sensor: every setting, with targets, `runs` runs each.
Study sensitivity_study(uint32_t runs, const Progress& progress, uint32_t& done, uint32_t total) {
  Study out;
  std::string& md = out.md;
  const auto& ms = methods();
  for (const SensorSpec& sp : sensors()) {
    md += "\n**" + std::string(sp.sensor == LiuSensor::kNoisy ? "Noisy sensor" : "Algorithm 1 sensor") +
          "**, three targets, " + std::to_string(runs) + " runs per cell (seeds 1.." + std::to_string(runs) +
          "), mean ± sd; ranks are ESUSTPM's among the paper's five per run (1 = best), mean. Table 2's ranks: "
          "visited 2 (after the mower), EU 1, found 1.\n\n"
          "| setting | ESUSTPM visited | ESUSTPM EU [bit] | ESUSTPM found | rank visited | rank EU | rank EU as Σ H(P) "
          "| rank found | lowest EU (method) | mower EU (Table 2: 52.34) | ESUSTPM looks | disperse visited | disperse "
          "EU "
          "| disperse found |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Setting& st : settings()) {
      std::vector<MethodSamples> s(ms.size());
      for (uint32_t run = 0; run < runs; ++run) {
        for (std::size_t mi = 0; mi < ms.size(); ++mi) {
          LiuSwarmConfig c;
          c.policy = ms[mi].policy;
          c.sensor = sp.sensor;
          st.apply(c);
          s[mi].add(simulate(c, run + 1));
          progress(++done, total);
        }
      }
      std::vector<const std::vector<double>*> vis, eu, eub, found;
      for (std::size_t mi = 0; mi < kPaperMethods; ++mi) {
        vis.push_back(&s[mi].visited);
        eu.push_back(&s[mi].eu);
        eub.push_back(&s[mi].eu_binary);
        found.push_back(&s[mi].found);
      }
      std::size_t lowest = 0;
      for (std::size_t mi = 1; mi < kPaperMethods; ++mi) {
        if (mean(s[mi].eu) < mean(s[lowest].eu)) lowest = mi;
      }
      md += "| " + st.name + " | " + pm(s[0].visited) + " | " + pm(s[0].eu, 2) + " | " + pm(s[0].found) + " | " +
            fmt(mean(esustpm_rank(vis, false)), 1) + " | " + fmt(mean(esustpm_rank(eu, true)), 1) + " | " +
            fmt(mean(esustpm_rank(eub, true)), 1) + " | " + fmt(mean(esustpm_rank(found, false)), 1) + " | " +
            fmt(mean(s[lowest].eu), 2) + " (" + ms[lowest].name + ") | " + pm(s[1].eu, 2) + " | " +
            fmt(mean(s[0].observations), 0) + " | " + pm(s[kDisperse].visited) + " | " + pm(s[kDisperse].eu, 2) +
            " | " + pm(s[kDisperse].found) + " |\n";
      out.cells.push_back({st.name, sp.file, mean(esustpm_rank(vis, false)), mean(esustpm_rank(eu, true)),
                           mean(esustpm_rank(eub, true)), mean(esustpm_rank(found, false)), mean(s[0].visited),
                           mean(s[0].eu), mean(s[1].eu), mean(s[kDisperse].visited)});
    }
  }
  return out;
}

using Samples = std::vector<std::vector<std::array<MethodSamples, 2>>>;

std::vector<std::string> table2_notes(const Samples& samples) {
  const auto& ms = methods();
  const auto found_of = [&](std::size_t si) {
    std::string s;
    for (std::size_t mi = 0; mi < ms.size(); ++mi) {
      s += (mi ? ", " : "") + ms[mi].name + " " + fmt(mean(samples[si][mi][0].found));
    }
    return s;
  };
  return {
      "Runs: Table 2 reads like single runs and does not give a count; §5.4 runs each method 10 times for its "
      "statistics, so 10 is the default. We report mean ± sd; the paper's value is one draw of its distribution.",
      "Sensor. The brief's sensor draws each look: a detection with Pd = 0.3 on a target cell, a false alarm with "
      "Pf = 0.1 elsewhere. Algorithm 1 instead branches on the truth (eq. 4 if the cell holds a target, eq. 5 if "
      "not) and §5 says \"When the UAV and the target are in the same cell ... the target is considered to be "
      "detected\", so the paper's sensor looks noiseless, Pd and Pf entering only the equations. Both are reported; "
      "rows marked [Alg. 1 sensor] use the paper's reading. Mean targets found, noisy: " +
          found_of(0) + "; Alg. 1: " + found_of(1) + " (paper 3, 0, 0, 1, 2).",
      "Why the noisy sensor finds almost nothing: with the printed eq. (5) a miss multiplies P by 7/9 wherever P "
      "is, so on a target cell (30 % detections, odds x3) P does not rise towards 1 but hovers around 0.4 (long-run "
      "mean 0.37); passing θ = 0.95 needs about three detections in a row. A target cell observed 20 times is "
      "confirmed with probability 0.19, 50 times 0.37 (Monte Carlo of the update alone). The Bayesian miss "
      "(MissUpdate::kBayes) would not cap P like this; we keep the printed equation.",
      "Mower with targets, Algorithm 1 sensor: 51.19, not 52.34 — its three target cells are entered twice, both "
      "times detected (P = 0.9, below θ), which lowers the EU by 1.15 bit. Table 2 prints 52.34 for both variants.",
      "EU is -Σ P log2 P over the 100 cells (pheromesh/liu/tpm.hpp: the paper names the metric but never defines it; "
      "this "
      "sum fits Table 2's range, 50 for an even map). Under it the EU rises after one or two misses per cell "
      "(0.53 and 0.52 bit vs 0.50) and falls only after three, so a method's EU depends on how often it re-enters "
      "cells, not only on coverage. With Algorithm 1's sensor the no-target mower gives 52.34 exactly, Table 2's "
      "value: it supports this EU, one TPM update per cell entry (not per Δt or per cycle: either would drive P "
      "to ~0 in 200 cycles), a 1 s cycle and a start cell that is not observed.",
      "Cycle length: not given. Ours 1 s = 100 intervals of 10 ms (LiuParams::cycle_s), so a UAV flies 2 km in "
      "200 cycles. UAVs decide once per cycle (§5.1.2 \"the step size is constant in each cycle\") and fly that "
      "velocity for the cycle; the TPM is updated whenever a UAV enters a cell.",
      "ESUSTPM covers fewer cells than the paper (89/95). With Table 1's constants the neighbour terms of eqs. "
      "(7)-(9) reach |β| ≈ 6000 within 20 m of c = 120 m, as strong as rule 4's pull, so the ten UAVs hold a "
      "rigid lattice and the swarm drifts as one body across the map instead of spreading. Possible causes on "
      "the paper's side we cannot check: its neighbour choice \"by the distance and TPM\", a limited "
      "communication range (value not given), a longer cycle. We do not tune these to hit the number.",
      "θ (confirmation threshold) is not given; ours 0.95 (three detections from 0.5). A confirmed cell is kept "
      "as found (latched) and no longer attracts rule 4 / guided Boids (§4: \"After the targets are found, the "
      "agents will continue to execute the coverage of the remaining area\").",
      "Start velocity: not given. UAVs start at max speed in a random direction (eq. 12; §2.2 \"mass points with "
      "the maximum velocity\"); at rest, unguided Boids on §5's 100 m start lattice are in equilibrium and never "
      "move. This is the only randomness of ESUSTPM and Boids besides the sensor.",
      "Mower: each UAV sweeps its own row (eq. 14, b reversed at the border), starting at the row's west cell: §5's "
      "start positions cover only rows 1-5. Random search: eq. (12)-(13) with a new direction every cycle; the "
      "paper's collision avoidance of random searchers is not specified and not modelled. Boids weights are equal "
      "(not given), safe distance 120 m.",
  };
}

struct LookBudget {
  int looks_mean, looks_max;  // ESUSTPM's looks per run, no targets, Liu 2022 Algorithm 1 sensor
  double bound_mean, bound_max;
  int needed;
  double mower_looks, mower_eu;
};

// "The claim" of the investigation: Liu 2022 Table 2's ranking against our means.
std::string table2_claim(const Samples& samples) {
  const auto m = [&](std::size_t si, std::size_t mi, const std::vector<double> MethodSamples::*f) {
    return fmt(mean(samples[si][mi][0].*f), 2);
  };
  return "### The claim\n\n"
         "Table 2 (and Figs. 11–12, 20–22, 28–30) ranks ESUSTPM first: the lowest EU (40.23 bit with targets, 40.24 "
         "without), the most targets found (3, the only method to find all), and second only to the mower on visited "
         "cells (89 / 95). Ours, 10x10, ten UAVs, 200 cycles, the same sensor and TPM for every method: ESUSTPM's EU "
         "is " +
         m(0, 0, &MethodSamples::eu) + " bit (noisy sensor) and " + m(1, 0, &MethodSamples::eu) +
         " (Algorithm 1's), against random search's " + m(0, 2, &MethodSamples::eu) + " / " +
         m(1, 2, &MethodSamples::eu) + "; it visits " + m(0, 0, &MethodSamples::visited) + " / " +
         m(1, 0, &MethodSamples::visited) + " cells against unguided Boids' " + m(0, 3, &MethodSamples::visited) +
         " / " + m(1, 3, &MethodSamples::visited) + " and guided Boids' " + m(0, 4, &MethodSamples::visited) + " / " +
         m(1, 4, &MethodSamples::visited) + "; with Algorithm 1's sensor it confirms " +
         m(1, 0, &MethodSamples::found) + " targets against guided Boids' " + m(1, 4, &MethodSamples::found) +
         ", with the noisy sensor nobody confirms more than a fraction of one. The rank rows above give the "
         "verdicts.\n\n";
}

std::string table2_second_reading(const LookBudget& b) {
  return "### Second, independent reading of eqs. (1)–(14) against the code\n\n"
         "| paper | what it says | code | agrees? |\n|---|---|---|---|\n"
         "| eq. (1) | bivariate Gaussian density of a target, σ1, σ2, ρ | `gaussian_mixture_prior` (liu/src/tpm.cpp) | "
         "yes; σ0 and ρ unstated (ours σ0 = 1 cell, ρ = 0); not used by Table 2 (uniform prior) |\n"
         "| eq. (2) | P_mn = Σ α_i ∬_cell f_i | `gaussian_mixture_prior` | yes; α_i unstated (1), clipped to [0, 1] |\n"
         "| eq. (3) | an unsearched cell keeps P | only entered cells are updated (`run_liu_swarm`, `LiuPlace::apply`) "
         "| "
         "yes |\n"
         "| eq. (4) | detection: P' = Pd P / ((Pd − Pf) P + Pf) | `tpm_after_detection` | yes (hand-worked tests "
         "in test_liu_tpm.cpp) |\n"
         "| eq. (5) | miss: P' = (1 − Pd) P / (1 − Pf) as printed | `tpm_after_miss`, `MissUpdate::kAsPrinted` | yes; "
         "the print is not the Bayesian posterior (that is `kBayes`, in the study) |\n"
         "| Alg. 1 | update branches on whether the cell holds a target | `LiuSensor::kAlgorithm1` | yes; the "
         "`noisy` reading draws detections with Pd / Pf instead (both reported) |\n"
         "| §2.4 | the sensor reads P of its cell and the 8 around; senses a target only in its own cell | one "
         "update per cell *entered*; the 8 neighbours only guide rule 4 | yes; \"when the UAV arrives\" read as "
         "entering a cell (the start cell is visited, not observed) |\n"
         "| eq. (6) | mvel = ¼ Σ β_i F_i/‖F_i‖ over 3 nearest neighbours and the best nearby cell | "
         "`esustpm_objective_velocity` | yes; F_i points from the neighbour to the UAV, so β > 0 (d < c) repels "
         "(§5 \"repel each other when the distance ... is less than the safe distance\"); rule 4 uses |β_4| towards "
         "the cell (literally β_4 < 0 at 141 m would push the UAV *away* from a diagonal best cell) |\n"
         "| eqs. (7)–(9) | g = t(1 − e^{−(d−c)²/δ'²}), a = k(d−c)e^{−(d−c)²/δ²}, β = a g | `liu_gain` | yes "
         "(hand-worked in test_liu_tpm.cpp) |\n"
         "| eqs. (10)–(11) | P += mvel Δt | `advance_uav`, clipped to 10 m/s, reflected at the border (§2.2) | yes |\n"
         "| eqs. (12)–(13) | random direction rnd(2,1)/‖·‖, step S = 10 | `random_direction`, "
         "`random_search_step` | yes; a new direction each cycle; the collision avoidance §5.1.2 mentions is not "
         "specified and not modelled |\n"
         "| eq. (14) | mower P += b l Δt, b reversed at the border, l = 10 | `mower_advance` | yes; one row per "
         "UAV (10 rows, 10 UAVs), each from its row's west end |\n"
         "| §5.1.4–5.1.5 | Boids with / without guidance, safe distance 120 m | `boids_step`, "
         "`boids_guided_step` | the rule weights are not given (ours equal; weights 2 in the study) |\n"
         "| Table 2 \"environmental uncertainty\" | not defined | `environmental_uncertainty` = −Σ P log2 P | "
         "unstated; fits: our no-target mower with Algorithm 1's sensor gives exactly " +
         fmt(b.mower_eu, 2) +
         " (Table 2: 52.34). Σ H(P) (binary entropy) cannot fit: an untouched 10x10 map alone is 100 bit |\n"
         "| Table 2 \"visited grid number\" | not defined | `VisitedCells`: cells any UAV has been over, start "
         "cells included | unstated |\n"
         "| the baselines' sensing | not said | every method runs the same loop: same sensor draw per cell "
         "entered, same eqs. (4)–(5), same θ, same visited and EU bookkeeping (`run_liu_swarm`; "
         "`LiuUavPolicy::observe` on the real swarm); only the velocity decision differs | fair baselines by "
         "construction |\n\n"
         "No bug was found on this second reading: the code computes what the equations say, and every departure "
         "is a choice where the paper is silent, each in the list below and in the study.\n\n";
}

std::string table2_unstated() {
  return "### Quantities the paper leaves unstated\n\n"
         "Map 10x10 (stated), cell size 100 m (inferred from §5's coordinates), 10 UAVs (stated), speed 10 m/s "
         "(stated), Δt = 10 ms (stated), 200 cycles (stated), Pd = 0.3 / Pf = 0.1 (stated), targets and start "
         "positions (stated), Table 1's rule constants (stated). **Unstated:** the length of a time cycle (ours 1 s: "
         "how many Δt a cycle holds), whether the sensor is noisy or Algorithm 1's truth branch, whether eq. (5) is "
         "meant as printed or as the Bayesian posterior, θ (ours 0.95), the start velocity (ours max speed, random "
         "heading), the communication range (ours unlimited), how \"the three closest neighbours chosen by the "
         "distance and TPM\" weighs the TPM (ours: distance only), whether a confirmed cell keeps attracting rule 4 "
         "(ours: no, §4), the Boids rule weights (ours equal), the EU formula, what counts as visited, and how many "
         "runs Table 2 shows (ours 10, as §5.4).\n\n";
}

std::string table2_look_budget(const LookBudget& b) {
  return "### The look budget: Table 2's ESUSTPM row is out of reach\n\n"
         "Under −Σ P log2 P with printed eq. (5), a cell's EU *rises* after one or two misses (0.50 → 0.53 → 0.52 "
         "bit) and falls only after three or more: the EU of a search is set by how many looks it makes and how "
         "it spreads them. Without targets and with Algorithm 1's sensor every look is a miss, so the lowest EU "
         "any search can leave with 95 visited cells (85 of them looked at: the 10 start cells are visited without "
         "a look) is an exact minimum over allocations of the looks (`liu_lowest_eu`, dynamic programming). "
         "ESUSTPM made " +
         std::to_string(b.looks_mean) + " looks per run on average (most " + std::to_string(b.looks_max) +
         "; its zig-zag enters more cells per metre than the mower's " + fmt(b.mower_looks, 0) +
         "): the lowest reachable EU is " + fmt(b.bound_mean, 2) + " bit with " + std::to_string(b.looks_mean) +
         " looks and " + fmt(b.bound_max, 2) + " with " + std::to_string(b.looks_max) +
         ", above Table 2's 40.24, which needs at least " + std::to_string(b.needed) +
         " looks perfectly spread. A longer cycle gives more looks, but the same cycle gives the mower more looks "
         "too, and Table 2's mower EU of 52.34 — which our 1 s cycle reproduces exactly — fixes the mower at about "
         "two looks per cell. So the two rows of Table 2 cannot both hold under one cycle length with this EU.\n\n";
}

std::string table2_sensitivity(const Study& study, uint32_t study_runs) {
  return "### Sensitivity study\n\n"
         "Each unstated quantity varied alone from our reading (and one pair), " +
         std::to_string(study_runs) +
         " runs per setting, every method with the same seeds; the \"rank EU as Σ H(P)\" column ranks by the "
         "binary-entropy EU of the same final maps.\n" +
         study.md + "\n";
}

std::string table2_conclusion(const Study& study) {
  // Conclusion, from the study's numbers.
  double min_rank_eu = 1e9, min_rank_eu_b = 1e9;
  std::string at_eu, at_eu_b;
  std::vector<std::string> vis_ok;
  for (const StudyCell& c : study.cells) {
    if (c.rank_eu < min_rank_eu) {
      min_rank_eu = c.rank_eu;
      at_eu = c.setting + " (" + c.sensor + ")";
    }
    if (c.rank_eu_binary < min_rank_eu_b) {
      min_rank_eu_b = c.rank_eu_binary;
      at_eu_b = c.setting + " (" + c.sensor + ")";
    }
    if (c.rank_visited <= 2.5) {
      vis_ok.push_back(c.setting + " (" + c.sensor + ": visited " + fmt(c.esustpm_visited, 1) + ", mower EU " +
                       fmt(c.mower_eu, 2) + ")");
    }
  }
  std::string vis_list;
  for (const auto& v : vis_ok) vis_list += (vis_list.empty() ? "" : "; ") + v;
  return "### Conclusion\n\n"
         "**Not reproducible under any fair reading.** In none of the " +
         std::to_string(study.cells.size()) + " settings × sensors is ESUSTPM first on EU: its best mean rank is " +
         fmt(min_rank_eu, 1) + " (" + at_eu + "), and " + fmt(min_rank_eu_b, 1) + " (" + at_eu_b +
         ") if EU is read as the binary entropy. It reaches Table 2's visited-cell rank (2, after the mower) only "
         "in: " +
         (vis_list.empty() ? std::string("no setting") : vis_list) +
         " — settings whose mower EU is far from Table 2's 52.34, which our reading reproduces. The look budget "
         "above shows why no reading of the cycle can give both. The ranking the paper reports is not a matter of "
         "our reading or a bug of ours: with its own equations, Table 1's constants and the same sensor for "
         "every method, ESUSTPM's swarm holds a lattice (|β| ≈ 6000 m/s within 20 m of c = 120 m, as strong as "
         "rule 4) and drifts as one body, and the EU metric that fits the mower rewards re-entering few cells, "
         "which random search and Boids do more. The parts that are reproduced: the mower (100 cells; 52.34 bit "
         "exactly with Algorithm 1's sensor), random search's EU, guided Boids' visited cells, and, with "
         "Algorithm 1's sensor, ESUSTPM confirming nearly all three targets (row above).\n\n"
         "**A variant that does what the paper wanted.** ESUSTPM-disperse (`search: \"esustpm_disperse\"`, "
         "docs/policies/liu.md) keeps eqs. (6)–(9) and rule 4 but drops the attracting half of the neighbour rules "
         "(β_i < 0, i ≤ 3). Same sensor, TPM, speed and seeds: see the variants table (visited cells at cycle 200, "
         "and the distributed policy). It pays for it in this EU (it spreads its looks even more), the price of "
         "the metric's reward for re-entry.\n";
}

// The investigation of Liu 2022 Table 2 (docs/policies/liu.md holds the same text).
// Every number in it is computed from this report's runs.
std::string table2_investigation(const Samples& samples, const LookBudget& b, const Study& study, uint32_t study_runs) {
  std::string md = "## Investigation: Table 2's ranking, examined (issue 17)\n\n";
  md += table2_claim(samples);
  md += table2_second_reading(b);
  md += table2_unstated();
  md += table2_look_budget(b);
  md += table2_sensitivity(study, study_runs);
  md += table2_conclusion(study);
  return md;
}

void describe_table2(Report& rep, uint32_t runs) {
  rep.title = "Liu 2022 Table 2 — five search methods, with and without targets, and ESUSTPM-disperse (ours)";
  rep.source = "Liu et al. 2022, §5.1–5.2, Table 2, Figs. 11–12 and 20–22";
  rep.setup = common_setup(runs) +
              ". Targets (400, 500), (400, 700), (700, 500), or none; uniform prior 0.5. Every method — the paper's "
              "five and our variant — flies the same loop with the same sensor, the same TPM and the same "
              "bookkeeping (run_liu_swarm): only the velocity decision differs";
  rep.csv_header = {"run", "seed", "sensor", "method", "targets", "visited", "final_eu", "found",
                    "confirmation_cycles", "false_confirmations", "observations"};
}

// Flies every (run, sensor, method, with/without targets) in the simulator;
// samples[sensor][method][variant], variant 0 = with targets, 1 = without.
Samples fly_table2(Report& rep, uint32_t runs, const Progress& progress, uint32_t& done, uint32_t total) {
  const auto& ms = methods();
  const auto& ss = sensors();
  std::vector<std::vector<std::array<MethodSamples, 2>>> samples(ss.size(),
                                                                 std::vector<std::array<MethodSamples, 2>>(ms.size()));
  for (uint32_t run = 0; run < runs; ++run) {
    const uint64_t seed = run + 1;
    for (std::size_t si = 0; si < ss.size(); ++si) {
      for (std::size_t mi = 0; mi < ms.size(); ++mi) {
        for (int variant = 0; variant < 2; ++variant) {
          LiuSwarmConfig c;
          c.policy = ms[mi].policy;
          c.sensor = ss[si].sensor;
          if (variant == 1) c.targets.clear();
          const LiuSwarmResult r = simulate(c, seed);
          samples[si][mi][static_cast<std::size_t>(variant)].add(r);
          rep.csv_rows.push_back({std::to_string(run), std::to_string(seed), ss[si].file, ms[mi].name,
                                  variant == 0 ? "3" : "0", std::to_string(r.visited_cells), fmt(r.final_eu, 4),
                                  std::to_string(r.targets_found), confirmation_list(r),
                                  std::to_string(r.false_confirmations), std::to_string(r.observations)});
          progress(++done, total);
        }
      }
    }
  }
  return samples;
}

std::optional<double> paper_value(const MethodSpec& m, double v) {
  if (!m.paper_method) return std::nullopt;
  return v;
}

// The five Liu 2022 Table 2 rows of each method under sensor si.
void add_method_rows(Report& rep, const Samples& samples, std::size_t si) {
  const auto& ms = methods();
  const std::string& tag = sensors()[si].tag;
  const LiuSensor sensor = sensors()[si].sensor;
  for (std::size_t mi = 0; mi < ms.size(); ++mi) {
    const MethodSpec& m = ms[mi];
    const MethodSamples& w = samples[si][mi][0];
    const MethodSamples& wo = samples[si][mi][1];
    const std::string fc = "false confirmations per run: " + fmt(mean(w.false_conf)) + " (with targets), " +
                           fmt(mean(wo.false_conf)) + " (without)";
    const auto add = [&](const std::string& metric, double paper, const std::vector<double>& ours,
                         const std::string& unit, const std::string& note, Metric kind) {
      Row r{m.name + " " + metric + tag, paper_value(m, paper), ours, unit, note, ""};
      if (m.paper_method) r.verdict = table2_verdict(r, kind, m.policy, sensor);
      rep.rows.push_back(std::move(r));
    };
    add("visited", m.visited, w.visited, "cell", "", Metric::kVisited);
    add("EU", m.eu, w.eu, "bit", "", Metric::kEu);
    add("found", m.found, w.found, "target", fc, Metric::kFound);
    add("visited, no targets", m.visited_nt, wo.visited, "cell", "", Metric::kVisited);
    add("EU, no targets", m.eu_nt, wo.eu, "bit", "", Metric::kEu);
  }
}

// Verdict on "ESUSTPM ranks `paper`": reproduced when its mean rank is
// within half a rank of the paper's; reversed when a baseline the paper
// ranks below it beats it with disjoint 95 % CIs; otherwise differs.
void add_rank_row(Report& rep, const std::string& what, double paper,
                  const std::vector<const std::vector<double>*>& per_method, bool lower_is_better,
                  const std::string& why, const std::string& suffix) {
  const auto& ms = methods();
  std::vector<double> ranks = esustpm_rank(per_method, lower_is_better);
  const Interval mine = ci95(*per_method[0]);
  std::string beaten_by;
  for (std::size_t mi = 1; mi < per_method.size(); ++mi) {
    const bool paper_ranks_it_below = what != "visited cells" || ms[mi].policy != LiuPolicy::kLawnmower;
    const Interval other = ci95(*per_method[mi]);
    const bool beats = lower_is_better ? other.hi < mine.lo : other.lo > mine.hi;
    if (paper_ranks_it_below && beats) beaten_by += (beaten_by.empty() ? "" : ", ") + ms[mi].name;
  }
  const double mr = mean(ranks);
  std::string verdict;
  if (mr <= paper + 0.5) {
    verdict = "reproduced";
  } else if (!beaten_by.empty()) {
    verdict = "reversed: " + beaten_by + " beat" + (beaten_by.find(',') == std::string::npos ? "s" : "") +
              " it (disjoint 95 % CIs); " + why;
  } else {
    verdict = "differs: mean rank " + fmt(mr, 1) + ", no baseline significantly better; " + why;
  }
  rep.rows.push_back({"ESUSTPM's rank on " + what + suffix + " (1 = best of the five)", paper, std::move(ranks), "rank",
                      "per run, ties share their mean rank", verdict});
}

// Liu 2022 Table 2's claim is a ranking: ESUSTPM's rank among the five, per run.
void add_rank_rows(Report& rep, const Samples& samples, std::size_t si) {
  const std::string& tag = sensors()[si].tag;
  const LiuSensor sensor = sensors()[si].sensor;
  for (int variant = 0; variant < 2; ++variant) {
    const auto v = static_cast<std::size_t>(variant);
    std::vector<const std::vector<double>*> vis, eu, found;
    for (std::size_t mi = 0; mi < kPaperMethods; ++mi) {
      vis.push_back(&samples[si][mi][v].visited);
      eu.push_back(&samples[si][mi][v].eu);
      found.push_back(&samples[si][mi][v].found);
    }
    const std::string nt = variant == 0 ? "" : ", no targets";
    add_rank_row(rep, "EU", 1, eu, true, "this EU falls only where a cell is looked at ≥ 3 times", nt + tag);
    add_rank_row(rep, "visited cells", 2, vis, false, "Table 1's rules hold a lattice that drifts as one body",
                 nt + tag);
    if (variant == 0) {
      add_rank_row(rep, "targets found", 1, found, false,
                   sensor == LiuSensor::kNoisy ? "under the printed eq. (5) almost nobody confirms a target"
                                               : "guided Boids re-enter target cells as often",
                   nt + tag);
    }
  }
}

// Plots: Liu 2022 Fig. 21 (EU, targets), Liu 2022 Fig. 12 (EU, no targets), Liu 2022 Fig. 20 (visited), Liu 2022 Fig.
// 22 (found).
void add_table2_plots(Report& rep, const Samples& samples, std::size_t si) {
  const auto& ms = methods();
  const auto& ss = sensors();
  const LiuSensor sensor = ss[si].sensor;
  const std::string sensor_name = sensor == LiuSensor::kNoisy ? "noisy sensor" : "Algorithm 1 sensor";
  Plot eu_t{"fig21-eu-" + ss[si].file + ".svg",
            "EU vs cycle, 3 targets (Fig. 21), " + sensor_name,
            "cycle",
            "environmental uncertainty [bit]",
            {}};
  Plot eu_nt{"fig12-eu-" + ss[si].file + ".svg",
             "EU vs cycle, no targets (Fig. 12), " + sensor_name,
             "cycle",
             "environmental uncertainty [bit]",
             {}};
  Plot vis{"fig20-visited-" + ss[si].file + ".svg",
           "Visited cells vs cycle, 3 targets (Fig. 20), " + sensor_name,
           "cycle",
           "visited cells",
           {}};
  Plot found{"fig22-found-" + ss[si].file + ".svg",
             "Targets found vs cycle (Fig. 22), " + sensor_name,
             "cycle",
             "targets confirmed (mean)",
             {}};
  for (std::size_t mi = 0; mi < ms.size(); ++mi) {
    eu_t.series.push_back(mean_series(ms[mi].name, samples[si][mi][0].eu_series));
    eu_nt.series.push_back(mean_series(ms[mi].name, samples[si][mi][1].eu_series));
    vis.series.push_back(mean_series(ms[mi].name, samples[si][mi][0].visited_series));
    found.series.push_back(mean_series(ms[mi].name, samples[si][mi][0].found_series));
  }
  rep.plots.push_back(std::move(eu_t));
  rep.plots.push_back(std::move(eu_nt));
  rep.plots.push_back(std::move(vis));
  rep.plots.push_back(std::move(found));
}

// Our variant against the paper's policy, same sensor, same seeds.
void add_disperse_comparisons(Report& rep, const Samples& samples, std::size_t si) {
  const std::string& tag = sensors()[si].tag;
  const MethodSamples& e = samples[si][0][0];
  const MethodSamples& d = samples[si][kDisperse][0];
  const std::string base = "ESUSTPM (Liu 2022, search \"esustpm\")";
  const std::string var = "ESUSTPM-disperse (ours, search \"esustpm_disperse\", docs/policies/liu.md)";
  rep.comparisons.push_back({"visited cells at cycle 200, 3 targets" + tag, "cell", base, var, false, e.visited,
                             d.visited, "Table 2's first column"});
  rep.comparisons.push_back({"EU at cycle 200, 3 targets" + tag, "bit", base, var, true, e.eu, d.eu,
                             "Table 2's second column (lower is better)"});
  rep.comparisons.push_back(
      {"targets found by cycle 200" + tag, "target", base, var, false, e.found, d.found, "Table 2's third column"});
  rep.comparisons.push_back({"cycles to confirm all three targets" + tag, "cycle", base, var, true, e.all_found_cycle,
                             d.all_found_cycle, "a run that never confirms all three counts as 200 (censored)"});
}

// One search flown as the distributed `liu` policy.
struct DistributedSearch {
  std::string name, patch, via;
  bool paper;
};

// The same searches as the distributed `liu` policy: the TPM in the place
// agents, one sensor stream per UAV, neighbours from the UAV's view.
const std::vector<DistributedSearch>& distributed_searches() {
  static const std::vector<DistributedSearch> flown{
      {"ESUSTPM", "", "policy `liu`, scenarios/liu2022-table2.textproto (noisy sensor)", true},
      {"ESUSTPM-disperse (ours)", "name: \"liu2022-table2-disperse\" policy { liu { search: \"esustpm_disperse\" } }",
       "policy `liu`, scenarios/liu2022-table2-disperse.textproto (noisy sensor)", false},
      {"ESUSTPM [Alg. 1 sensor]", "name: \"liu2022-table2-alg1\" policy { liu { sensor: \"algorithm1\" } }",
       "policy `liu`, liu2022-table2 with sensor \"algorithm1\"", true},
      {"ESUSTPM-disperse (ours) [Alg. 1 sensor]",
       "name: \"liu2022-table2-disperse-alg1\" policy { liu { search: \"esustpm_disperse\" sensor: \"algorithm1\" } }",
       "policy `liu`, liu2022-table2 with search \"esustpm_disperse\", sensor \"algorithm1\"", false},
  };
  return flown;
}

// The rows of one distributed search (its samples in r).
void add_distributed_rows(Report& rep, const DistributedSearch& f,
                          const std::vector<std::map<std::string, double>>& r) {
  const auto paper = [&](double v) -> std::optional<double> {
    if (!f.paper) return std::nullopt;
    return v;
  };
  const std::string via = f.via + ", in-process simulator = lockstep run of the processes";
  for (auto [key, label, pv, unit] : std::vector<std::tuple<std::string, std::string, double, std::string>>{
           {"visited_cells", "visited cells", 89, "cell"},
           {"environmental_uncertainty", "EU", 40.23, "bit"},
           {"real_targets_confirmed", "targets found", 3, "target"}}) {
    Row row{f.name + " " + label + ", distributed policy", paper(pv), field_samples(r, key), unit, via, ""};
    if (f.paper) {
      const Metric kind = key == "visited_cells"            ? Metric::kVisited
                          : key == "real_targets_confirmed" ? Metric::kFound
                                                            : Metric::kEu;
      row.verdict =
          table2_verdict(row, kind, LiuPolicy::kEsustpm, f.patch.empty() ? LiuSensor::kNoisy : LiuSensor::kAlgorithm1);
    }
    rep.rows.push_back(std::move(row));
  }
}

void add_distributed_table2(Report& rep, uint32_t runs) {
  const std::string file = "liu2022-table2.textproto";
  std::vector<std::vector<std::map<std::string, double>>> dist;
  for (const DistributedSearch& f : distributed_searches()) {
    dist.push_back(simulate_scenario(file, runs, f.patch));  // the text goes to the processes with --distributed
    add_distributed_rows(rep, f, dist.back());
  }
  rep.comparisons.push_back(
      {"visited cells at tick 200, distributed policy (noisy sensor)", "cell", "ESUSTPM (policy liu, search esustpm)",
       "ESUSTPM-disperse (policy liu, search esustpm_disperse)", false, field_samples(dist[0], "visited_cells"),
       field_samples(dist[1], "visited_cells"), "the real-swarm policy: place agents hold the TPM"});
  rep.comparisons.push_back(
      {"visited cells at tick 200, distributed policy [Alg. 1 sensor]", "cell", "ESUSTPM (policy liu, search esustpm)",
       "ESUSTPM-disperse (policy liu, search esustpm_disperse)", false, field_samples(dist[2], "visited_cells"),
       field_samples(dist[3], "visited_cells"), "the real-swarm policy: place agents hold the TPM"});
}

// The look budget: how low can EU go at all, having visited Liu 2022 Table 2's cells?
LookBudget look_budget(const Samples& samples) {
  const core::LiuParams lp;
  const MethodSamples& e_nt = samples[1][0][1];  // ESUSTPM, Liu 2022 Algorithm 1 sensor, no targets
  const MethodSamples& m_nt = samples[1][1][1];  // mower, the same
  const auto looks_max = static_cast<int>(*std::max_element(e_nt.observations.begin(), e_nt.observations.end()));
  const int looks_mean = static_cast<int>(std::lround(mean(e_nt.observations)));
  // Start cells are visited without a look (a UAV "arrives" only in cells it
  // enters); Liu 2022 Table 2's 95 no-target cells then need >= 85 looked-at cells.
  const double bound_mean = core::liu_lowest_eu(85, 100, looks_mean, lp);
  const double bound_max = core::liu_lowest_eu(85, 100, looks_max, lp);
  int needed = looks_max;
  while (needed < 2000 && core::liu_lowest_eu(85, 100, needed, lp) > 40.24) needed += 10;
  return LookBudget{looks_mean, looks_max, bound_mean, bound_max, needed, mean(m_nt.observations), mean(m_nt.eu)};
}

void add_look_budget_row(Report& rep, const LookBudget& b) {
  rep.rows.push_back(
      {"lowest EU any search can reach with 95 cells visited and ESUSTPM's look budget, no targets "
       "[Alg. 1 sensor]",
       40.24,
       {b.bound_max},
       "bit",
       "exact minimum over every allocation of the " + std::to_string(b.looks_max) +
           " looks (the most ESUSTPM made in a run; mean " + std::to_string(b.looks_mean) + " → " +
           fmt(b.bound_mean, 2) + " bit); Table 2's 40.24 needs ≥ " + std::to_string(b.needed) +
           " looks. Mower looks per run: " + fmt(b.mower_looks, 0),
       b.bound_max > 40.24 ? "differs: Table 2's pair (95 cells, 40.24 bit) is out of reach of any search "
                             "with these looks"
                           : "reproduced: the pair is within reach of these looks"});
}

Report run_table2(uint32_t runs, const Progress& progress) {
  Report rep;
  describe_table2(rep, runs);
  const auto& ms = methods();
  const auto& ss = sensors();
  const uint32_t study_runs = runs;
  const uint32_t total = runs * static_cast<uint32_t>(ss.size() * ms.size() * 2) +
                         study_runs * static_cast<uint32_t>(ss.size() * settings().size() * ms.size());
  uint32_t done = 0;
  const Samples samples = fly_table2(rep, runs, progress, done, total);
  for (std::size_t si = 0; si < ss.size(); ++si) {
    add_method_rows(rep, samples, si);
    add_rank_rows(rep, samples, si);
    add_table2_plots(rep, samples, si);
    add_disperse_comparisons(rep, samples, si);
  }
  add_distributed_table2(rep, runs);
  const LookBudget budget = look_budget(samples);
  add_look_budget_row(rep, budget);

  // The sensitivity study.
  const Study study = sensitivity_study(study_runs, progress, done, total);
  rep.investigation = table2_investigation(samples, budget, study, study_runs);
  rep.notes = table2_notes(samples);
  rep.notes.push_back("The sensitivity study's runs are summarised in the investigation's tables, not in results.csv.");
  return rep;
}

// ---------------------------------------------------------------------------
// Prior information, Liu 2022 Sec. 5.3
// ---------------------------------------------------------------------------

struct PriorScenario {
  std::string name;
  LiuPrior prior;
  std::vector<Vec2> targets;
};

const std::vector<PriorScenario>& prior_scenarios() {
  static const std::vector<PriorScenario> s{
      {"uniform 0.5", LiuPrior::kUniform, {core::kLiuTargets.begin(), core::kLiuTargets.end()}},
      {"accurate prior", LiuPrior::kAccurate, {core::kLiuTargets.begin(), core::kLiuTargets.end()}},
      {"wrong prior (Fig. 27a)", LiuPrior::kWrong, {core::kLiuTargets[0], core::kLiuTargets[1]}},
      {"wrong prior (Fig. 27b)", LiuPrior::kWrong, {core::kLiuUnexpectedTarget}},
  };
  return s;
}

std::size_t map_index(Vec2 v) {
  const core::Cell c = core::cell_of(v, core::LiuParams{});
  return static_cast<std::size_t>(c.y) * 10U + static_cast<std::size_t>(c.x);
}

struct PriorSamples {
  std::vector<double> all_found;  // 1 / 0 per run
  std::vector<double> all_found_cycle;  // runs that confirmed every target
  std::vector<double> found, final_eu, eu_drop, false_conf;
  std::vector<double> p_absent, p_unexpected;  // final P at (700, 500), (300, 200)
  std::vector<std::vector<double>> eu_series;
  std::vector<std::vector<uint32_t>> found_series;
  double prior_eu = 0.0, prior_absent = 0.0, prior_unexpected = 0.0;
};

using PriorSampleTable = std::vector<std::vector<PriorSamples>>;  // [sensor][scenario]

void describe_priors(Report& rep, uint32_t runs) {
  rep.title = "Liu 2022 §5.3 — ESUSTPM with accurate, wrong and no prior information (Figs. 24–27)";
  rep.source = "Liu et al. 2022, §5.3, Figs. 23–27";
  rep.setup = common_setup(runs) +
              ". ESUSTPM only. Priors: eq. (2) mixture with one component per expected target at the centre of its "
              "cell, σ0 = 1 cell, α_i = 1, ρ = 0 (the paper gives none of these). Scenarios: uniform 0.5 with the "
              "three targets (Fig. 25 'without prior'); prior at the three targets (Figs. 24–26); prior at the three, "
              "target at (700, 500) absent (Fig. 27a); prior at the three, the only target at (300, 200) (Fig. 27b)";
  rep.csv_header = {"run", "seed", "sensor", "scenario", "found", "all_found_cycle", "confirmation_cycles",
                    "final_eu", "false_confirmations", "p_700_500", "p_300_200"};
}

// Flies scenario k under sensor si once and adds it to s and the CSV.
void fly_prior_run(Report& rep, std::size_t si, std::size_t k, uint32_t run, PriorSamples& s) {
  const auto& sc = prior_scenarios();
  const auto& ss = sensors();
  const std::size_t absent = map_index(core::kLiuAbsentPriorTarget);
  const std::size_t unexpected = map_index(core::kLiuUnexpectedTarget);
  const uint64_t seed = run + 1;
  LiuSwarmConfig c;
  c.policy = LiuPolicy::kEsustpm;
  c.sensor = ss[si].sensor;
  c.prior = sc[k].prior;
  c.targets = sc[k].targets;
  const LiuSwarmResult r = simulate(c, seed);
  const std::vector<double> prior = core::liu_prior_map(c);
  s.prior_eu = r.eu_per_cycle.front();
  s.prior_absent = prior[absent];
  s.prior_unexpected = prior[unexpected];
  s.all_found.push_back(r.all_found_cycle ? 1.0 : 0.0);
  if (r.all_found_cycle) s.all_found_cycle.push_back(*r.all_found_cycle);
  s.found.push_back(r.targets_found);
  s.final_eu.push_back(r.final_eu);
  s.eu_drop.push_back(r.eu_per_cycle.front() - r.final_eu);
  s.false_conf.push_back(r.false_confirmations);
  s.p_absent.push_back(r.final_tpm[absent]);
  s.p_unexpected.push_back(r.final_tpm[unexpected]);
  s.eu_series.push_back(r.eu_per_cycle);
  s.found_series.push_back(r.found_per_cycle);
  rep.csv_rows.push_back({std::to_string(run), std::to_string(seed), ss[si].file, sc[k].name,
                          std::to_string(r.targets_found), r.all_found_cycle ? std::to_string(*r.all_found_cycle) : "",
                          confirmation_list(r), fmt(r.final_eu, 4), std::to_string(r.false_confirmations),
                          fmt(r.final_tpm[absent], 4), fmt(r.final_tpm[unexpected], 4)});
}

// The rows of every scenario under sensor si.
void add_prior_rows(Report& rep, const PriorSampleTable& samples, std::size_t si, uint32_t runs) {
  const auto& sc = prior_scenarios();
  const std::string& tag = sensors()[si].tag;
  for (std::size_t k = 0; k < sc.size(); ++k) {
    const PriorSamples& s = samples[si][k];
    const std::string n = sc[k].name + ": ";
    const std::size_t targets = sc[k].targets.size();
    rep.rows.push_back({n + "all " + std::to_string(targets) + " target(s) confirmed" + tag, std::nullopt, s.all_found,
                        "share of runs", "", ""});
    rep.rows.push_back({n + "cycles to confirm all targets" + tag, std::nullopt, s.all_found_cycle, "cycle",
                        std::to_string(s.all_found_cycle.size()) + " of " + std::to_string(runs) +
                            " runs confirmed all; the others are left out",
                        ""});
    rep.rows.push_back({n + "targets found" + tag, std::nullopt, s.found, "target",
                        "false confirmations per run: " + fmt(mean(s.false_conf)), ""});
    rep.rows.push_back({n + "final EU" + tag, std::nullopt, s.final_eu, "bit", "prior EU " + fmt(s.prior_eu), ""});
    rep.rows.push_back({n + "EU drop from the prior" + tag, std::nullopt, s.eu_drop, "bit", "", ""});
    if (sc[k].prior == LiuPrior::kWrong && targets == 2) {
      rep.rows.push_back({n + "final P at (700, 500), no target" + tag, std::nullopt, s.p_absent, "",
                          "prior " + fmt(s.prior_absent, 3) + "; the paper: the cell \"becomes white\"", ""});
    }
    if (sc[k].prior == LiuPrior::kWrong && targets == 1) {
      rep.rows.push_back({n + "final P at (300, 200), the target" + tag, std::nullopt, s.p_unexpected, "",
                          "prior " + fmt(s.prior_unexpected, 4) + "; the paper: the cell \"becomes red\"", ""});
    }
  }
}

void add_prior_plots(Report& rep, const PriorSampleTable& samples, std::size_t si) {
  const auto& sc = prior_scenarios();
  const auto& ss = sensors();
  const std::string sensor_name = ss[si].sensor == LiuSensor::kNoisy ? "noisy sensor" : "Algorithm 1 sensor";
  Plot found{"fig25-found-" + ss[si].file + ".svg",
             "Targets found vs cycle (Fig. 25), " + sensor_name,
             "cycle",
             "targets confirmed (mean)",
             {}};
  Plot eu{"priors-eu-" + ss[si].file + ".svg",
          "EU vs cycle by prior, " + sensor_name,
          "cycle",
          "environmental uncertainty [bit]",
          {}};
  for (std::size_t k = 0; k < sc.size(); ++k) {
    found.series.push_back(mean_series(sc[k].name, samples[si][k].found_series));
    eu.series.push_back(mean_series(sc[k].name, samples[si][k].eu_series));
  }
  rep.plots.push_back(std::move(found));
  rep.plots.push_back(std::move(eu));
}

// The paper's qualitative claims against ours under sensor si.
std::string prior_claims_note(const PriorSampleTable& samples, std::size_t si) {
  const auto& ss = sensors();
  const PriorSamples& uni = samples[si][0];
  const PriorSamples& acc = samples[si][1];
  const PriorSamples& a27 = samples[si][2];
  const PriorSamples& b27 = samples[si][3];
  const std::string sensor_name = ss[si].sensor == LiuSensor::kNoisy ? "Noisy sensor" : "Algorithm 1 sensor";
  const double su = mean(uni.all_found), sa = mean(acc.all_found);
  const double cu = mean(uni.all_found_cycle), ca = mean(acc.all_found_cycle);
  const bool faster = sa > su || (sa == su && sa > 0 && ca < cu);
  return (sensor_name +
          ", Figs. 25–26 (\"accurate prior information can improve the searching efficiency\"): all "
          "three targets confirmed in " +
          fmt(100 * sa, 0) + " % of runs with the accurate prior (mean cycle " + fmt(ca, 1) + ") vs " +
          fmt(100 * su, 0) + " % with the uniform 0.5 (mean cycle " + fmt(cu, 1) + "). " +
          (faster ? "Ours shows the claim." : "Ours does not show the claim.") +
          " Fig. 27a (absent target \"becomes white\"): P at (700, 500) went from " + fmt(a27.prior_absent, 3) +
          " to " + fmt(mean(a27.p_absent), 3) + " on average; both real targets confirmed in " +
          fmt(100 * mean(a27.all_found), 0) +
          " % of runs. Fig. 27b (unexpected target \"becomes red\"): (300, 200) "
          "confirmed in " +
          fmt(100 * mean(b27.all_found), 0) + " % of runs (prior there " + fmt(b27.prior_unexpected, 4) +
          ", final mean " + fmt(mean(b27.p_unexpected), 3) + "). " +
          (mean(b27.all_found) >= 0.5 && mean(a27.p_absent) < a27.prior_absent
               ? "The wrong priors are overcome."
               : "The wrong priors are not overcome in most runs."));
}

void add_prior_notes(Report& rep, const PriorSampleTable& samples) {
  rep.notes.insert(
      rep.notes.end(),
      {"Runs: the paper does not say how many runs Fig. 26's boxplots hold; 10 as in §5.4.",
       "sd = 0 under Algorithm 1's sensor with a mixture prior is not a bug: ESUSTPM has no randomness of its own, "
       "the sensor is then noiseless, and the random start heading only breaks ties on a flat map, which a mixture "
       "prior never has. Every run is the same run.",
       "The paper gives no numbers for §5.3 (boxplots and maps only), so no row has a paper value.",
       "Prior: the paper gives neither σ0 nor α_i (nor Fig. 23's values). Ours: σ0 = 1 cell and α_i = 1, so a "
       "cell's P is the chance the expected target lies in it: 0.147 on the target's cell, up to 0.19 between the "
       "two close targets, about 0 far away. So the accurate prior starts its targets *below* the uniform 0.5 — "
       "it helps by pulling the swarm to the right cells, but a target cell must then climb further to pass θ. "
       "A larger α (peaks near 1) would favour the accurate prior more; we do not tune it.",
       "Final EU is not comparable across priors: a mixture prior starts at " + fmt(samples[0][1].prior_eu) +
           " bit (most cells ≈ 0) against 50 for the uniform map. The \"EU drop\" rows give the change.",
       "Same simulation and choices as liu-table2 (cycle of 1 s, one TPM update per cell entry, θ = 0.95, "
       "printed eq. 5, random start headings, confirmed cells released from guidance); see its notes."});
}

Report run_priors(uint32_t runs, const Progress& progress) {
  Report rep;
  describe_priors(rep, runs);
  const auto& sc = prior_scenarios();
  const auto& ss = sensors();
  std::vector<std::vector<PriorSamples>> samples(ss.size(), std::vector<PriorSamples>(sc.size()));
  const uint32_t total = runs * static_cast<uint32_t>(ss.size() * sc.size());
  uint32_t done = 0;
  for (uint32_t run = 0; run < runs; ++run) {
    for (std::size_t si = 0; si < ss.size(); ++si) {
      for (std::size_t k = 0; k < sc.size(); ++k) {
        fly_prior_run(rep, si, k, run, samples[si][k]);
        progress(++done, total);
      }
    }
  }
  for (std::size_t si = 0; si < ss.size(); ++si) {
    add_prior_rows(rep, samples, si, runs);
    add_prior_plots(rep, samples, si);
  }
  for (std::size_t si = 0; si < ss.size(); ++si) rep.notes.push_back(prior_claims_note(samples, si));
  add_prior_notes(rep, samples);
  return rep;
}

}  // namespace

std::vector<Experiment> liu_experiments() {
  return {
      {"liu-table2",
       "Liu 2022 Table 2: visited cells, EU and targets found for ESUSTPM, mower, random, Boids, guided Boids; "
       "sensitivity study; ESUSTPM-disperse (ours)",
       kPaperRuns, [](uint32_t runs, const Progress& p) { return run_table2(runs, p); },
       "Table 2's ranking not reproducible under any fair reading: ESUSTPM is first on EU in none of 28 "
       "settings (random beats it) and visits fewer cells than Boids (its lattice drifts as one body); the mower "
       "(52.34 bit exactly, Alg. 1 sensor) and random search's EU reproduced; ESUSTPM-disperse (ours) visits "
       "+124 % cells [89, 168]"},
      {"liu-priors", "Liu 2022 §5.3 / Figs. 25–27: ESUSTPM with accurate, wrong and uniform priors", kPaperRuns,
       [](uint32_t runs, const Progress& p) { return run_priors(runs, p); },
       "Figs. 25-27 reproduced with Algorithm 1's sensor (accurate prior: all 3 targets in 10/10 runs vs 6/10 "
       "uniform; both wrong priors overcome); not shown with the noisy sensor (printed eq. 5: no target confirmed)"},
  };
}

}  // namespace pheromesh::cli::experiments
