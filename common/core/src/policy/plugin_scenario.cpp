// scenario.policy.plugin (scenario.proto, PolicyPlugin): the library found,
// pinned and loaded (plugin_loader.hpp), then the plugin reads its own
// `config` parameters through PluginConfig, whose errors name the file, the
// line and the parameter like every other error of the scenario.
//
// Why `config` is a list of typed key/value parameters rather than a string
// of text the plugin parses, a google.protobuf.Struct or an Any: each
// parameter is a message of the scenario, so the scenario's parser records
// its line and column and an error points at it; protobuf checks the syntax
// and the kind (a number is a number) before the plugin sees it; the plugin
// needs no parser and no schema of its own. A Struct gives the same positions
// behind three levels of nesting per value (`fields { key: "a" value {
// number_value: 1 } }`); an Any needs the plugin's message types in the
// descriptor pool before the file is parsed, that is before the library is
// loaded; a string would need a parser in every plugin and positions mapped
// back through the string's escapes.
#include <algorithm>
#include <cstdlib>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/plugin_loader.hpp"
#include "pheromesh/core/python_policy.hpp"
#include "pheromesh/core/sha256.hpp"
#include "scenario/scenario_internal.hpp"

namespace pheromesh::core::scenario_detail {
namespace {

const char* kind_name(pb::PluginParameter::ValueCase k) {
  switch (k) {
    case pb::PluginParameter::kNumber:
      return "a number";
    case pb::PluginParameter::kText:
      return "a text";
    case pb::PluginParameter::kFlag:
      return "a flag";
    case pb::PluginParameter::VALUE_NOT_SET:
      break;
  }
  return "no value";
}

// PluginConfig over the scenario's `config` entries (of a `plugin` block or
// of a `python` one: both are repeated PluginParameter, field `config`).
template <class Block>
class ScenarioPluginConfig final : public PluginConfig {
 public:
  ScenarioPluginConfig(const Block& msg, const Node& n, Validator& v) : msg_(msg), n_(n), v_(v) {
    read_.assign(static_cast<std::size_t>(msg.config_size()), false);
  }

  std::optional<double> number(std::string_view key) override {
    const int i = take(key, pb::PluginParameter::kNumber, "number");
    if (i < 0) return std::nullopt;
    return msg_.config(i).number();
  }
  std::optional<std::string> text(std::string_view key) override {
    const int i = take(key, pb::PluginParameter::kText, "text");
    if (i < 0) return std::nullopt;
    return msg_.config(i).text();
  }
  std::optional<bool> flag(std::string_view key) override {
    const int i = take(key, pb::PluginParameter::kFlag, "flag");
    if (i < 0) return std::nullopt;
    return msg_.config(i).flag();
  }
  void fail(std::string_view key, std::string_view what) override {
    const int i = find(key);
    const std::string text = "(key \"" + std::string(key) + "\"): " + std::string(what);
    if (i >= 0) {
      v_.fail(n_, "config", text, i);
    } else {
      v_.fail(n_, "config " + text);
    }
  }

  // Every parameter the plugin never asked for.
  void fail_unread(std::string_view policy) {
    std::string asked;
    for (const auto& k : asked_) asked += (asked.empty() ? "" : ", ") + k;
    for (int i = 0; i < msg_.config_size(); ++i) {
      if (read_[static_cast<std::size_t>(i)] || !msg_.config(i).has_key()) continue;
      v_.fail(n_, "config",
              "key \"" + msg_.config(i).key() + "\" is not a parameter of the policy " + std::string(policy) +
                  (asked.empty() ? std::string(" (it reads none)") : " (it reads: " + asked + ")"),
              i);
    }
  }

 private:
  [[nodiscard]] int find(std::string_view key) const {
    for (int i = 0; i < msg_.config_size(); ++i) {
      if (msg_.config(i).key() == key) return i;
    }
    return -1;
  }
  int take(std::string_view key, pb::PluginParameter::ValueCase want, const char* field) {
    if (std::find(asked_.begin(), asked_.end(), key) == asked_.end()) asked_.emplace_back(key);
    const int i = find(key);
    if (i < 0) return -1;
    read_[static_cast<std::size_t>(i)] = true;
    const auto have = msg_.config(i).value_case();
    if (have != want) {
      v_.fail(n_, "config",
              "(key \"" + std::string(key) + "\"): is " + kind_name(have) + "; the plugin reads " +
                  kind_name(want) + " (" + field + ": ...)",
              i);
      return -1;
    }
    return i;
  }

  const Block& msg_;
  const Node& n_;
  Validator& v_;
  std::vector<bool> read_;
  std::vector<std::string> asked_;
};

// Keys present, unique, and each with a value; false when not.
template <class Block>
bool check_parameters(const Block& msg, const Node& n, Validator& v) {
  bool ok = true;
  for (int i = 0; i < msg.config_size(); ++i) {
    const pb::PluginParameter& p = msg.config(i);
    const Node pn = n.child("config", i);
    if (!p.has_key() || p.key().empty()) {
      v.required(pn, "key");
      ok = false;
      continue;
    }
    if (p.value_case() == pb::PluginParameter::VALUE_NOT_SET) {
      v.fail(n, "config", "(key \"" + p.key() + "\"): has no value; give number:, text: or flag:", i);
      ok = false;
    }
    for (int j = 0; j < i; ++j) {
      if (msg.config(j).key() == p.key()) {
        v.fail(n, "config", "(key \"" + p.key() + "\"): same key as config[" + std::to_string(j) + "]", i);
        ok = false;
        break;
      }
    }
  }
  return ok;
}

// The pins the library must match: the scenario's, then the environment's.
std::optional<std::vector<PluginPin>> pins_of(const pb::PolicyPlugin& msg, const Node& n, Validator& v) {
  std::vector<PluginPin> pins;
  bool ok = true;
  if (msg.has_sha256()) {
    if (is_sha256_hex(msg.sha256())) {
      pins.push_back({msg.sha256(), "the scenario"});
    } else {
      v.fail(n, "sha256", "must be 64 hex digits (the library's SHA-256, as `pheromesh validate` prints it)");
      ok = false;
    }
  }
  if (const char* env = std::getenv(kPluginPinEnv); env != nullptr && *env != '\0') {
    if (is_sha256_hex(env)) {
      pins.push_back({env, std::string("$") + kPluginPinEnv});
    } else {
      v.fail(n, "library", std::string("$") + kPluginPinEnv + " must be 64 hex digits (got \"" + env + "\")");
      ok = false;
    }
  }
  if (!ok) return std::nullopt;
  return pins;
}

}  // namespace

void build_plugin_policy(const pb::PolicyPlugin& msg, const Node& n, Validator& v, ScenarioConfig& cfg,
                         const PluginSite* site) {
  if (site == nullptr) {
    v.fail(n, "a policy plugin is loaded from a scenario file only, not from text received or built in memory (a "
              "monitor attaching to such a run needs --scenario FILE)");
    return;
  }
  bool ok = true;
  if (!msg.has_library() || msg.library().empty()) {
    v.required(n, "library");
    ok = false;
  }
  if (!msg.has_name() || msg.name().empty()) {
    v.required(n, "name");
    ok = false;
  }
  const auto pins = pins_of(msg, n, v);
  ok = check_parameters(msg, n, v) && pins.has_value() && ok;
  if (!ok) return;

  auto path = resolve_plugin_library(msg.library(), site->scenario_dir);
  if (!path) {
    v.fail(n, "library", path.error().message);
    return;
  }
  auto loaded = load_policy_plugin(path.value(), msg.name(), pins.value());
  if (!loaded) {
    // The scenario's pin refused: said at its line; anything else at the library's.
    const bool scenario_pin = loaded.error().message.find("but the scenario pins") != std::string::npos;
    v.fail(n, scenario_pin ? "sha256" : "library", loaded.error().message);
    return;
  }
  const LoadedPlugin& l = *loaded.value();
  cfg.policy = std::string(l.plugin->name);
  cfg.plugin = ScenarioConfig::PluginSource{l.library, l.sha256, pins->empty() ? std::string() : pins->front().by};

  ScenarioPluginConfig<pb::PolicyPlugin> config(msg, n, v);
  try {
    l.plugin->parse(config, cfg);
  } catch (const std::exception& e) {
    v.fail(n, "library", "the plugin's parser threw: " + std::string(e.what()));
    return;
  }
  config.fail_unread(l.plugin->name);
  if (cfg.policy_config != nullptr && cfg.policy_config->policy() != l.plugin->name) {
    v.fail(n, "name",
           "the plugin's parser set the config of policy '" + std::string(cfg.policy_config->policy()) +
               "', not of '" + std::string(l.plugin->name) + "'");
    return;
  }
  cfg.policy = std::string(l.plugin->name);
  if (!v.empty()) return;
  // The traits now, so that a plugin whose traits fail is refused by
  // `validate` at its line rather than by every process at start.
  try {
    const PolicyTraits t = l.plugin->traits(cfg);
    if (t.layers.empty()) v.fail(n, "name", "the policy declares no pheromone layer (PolicyTraits::layers)");
    if (!t.layer_ranges.empty() && t.layer_ranges.size() != t.layers.size()) {
      v.fail(n, "name",
             "the policy gives " + std::to_string(t.layer_ranges.size()) + " layer ranges for " +
                 std::to_string(t.layers.size()) + " layers (PolicyTraits::layer_ranges)");
    }
  } catch (const std::exception& e) {
    v.fail(n, "name", "the plugin's traits threw: " + std::string(e.what()));
  }
}

void build_python_policy(const pb::PolicyPython& msg, const Node& n, Validator& v, ScenarioConfig& cfg,
                         const PluginSite* site) {
  bool ok = true;
  if (!msg.has_module() || msg.module().empty()) {
    v.required(n, "module");
    ok = false;
  }
  if (!msg.has_class_() || msg.class_().empty()) {
    v.required(n, "class");
    ok = false;
  }
  ok = check_parameters(msg, n, v) && ok;
  if (!ok) return;
  const PythonPolicyHook* hook = python_policy_hook();
  if (hook == nullptr) {
    v.fail(n, std::string(kNoPythonSupport));
    return;
  }
  PythonPolicyBlock block{msg.module(), msg.class_(), site == nullptr ? std::string() : site->scenario_dir};
  ScenarioPluginConfig<pb::PolicyPython> config(msg, n, v);
  std::vector<PythonPolicyError> errors;
  try {
    errors = hook->build(block, config, cfg);
  } catch (const std::exception& e) {
    errors.push_back({"class", e.what()});
  }
  for (const auto& e : errors) {
    if (e.field.empty()) {
      v.fail(n, e.message);
    } else {
      v.fail(n, e.field.c_str(), e.message);
    }
  }
  if (!errors.empty()) return;
  config.fail_unread(cfg.policy);
}

}  // namespace pheromesh::core::scenario_detail
