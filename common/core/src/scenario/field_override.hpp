// One scalar field of any protobuf message, set from text by its field path:
// what `--set PATH=VALUE` does to a scenario (scenario.hpp, ScenarioOverride).
// Generic on purpose (protobuf reflection), so that every scalar and enum
// field of every message works, a new scenario field included, without a
// table to keep in step with scenario.proto.
#pragma once

#include <google/protobuf/message.h>

#include <string>
#include <string_view>

#include "pheromesh/core/result.hpp"

namespace pheromesh::core::field_override {

// Sets the field at `path` of `msg` to `value`, parsed for the field's type.
//   path   textproto field names joined by '.', an entry of a repeated field
//          by its index: "swarm.uavs", "policy.liu.p_detection",
//          "map.targets[2].x", "fault[0]". Every message on the way is
//          created if absent; an entry of a repeated field must exist (no
//          entry is added); a member of a oneof is refused while the message
//          sets another member of that oneof.
//   value  integers in decimal, reals as C++ reads them (1e-3, inf, nan:
//          validation refuses what it refuses in a file), bools true/false
//          (also 1/0, t/f, True/False as in text format), an enum by name or
//          number, a string as given (one pair of surrounding double quotes
//          is removed).
// A list of keyed parameters (`repeated PluginParameter config` of a plugin
// or Python policy) is reached by key, not by position:
//   "policy.plugin.param.speed" sets the value of the entry with key "speed"
//   (of the kind it has: number, text or flag); with no such entry, one is
//   added, a number for a value that reads as one, a flag for true / false,
//   else a text (the policy then checks it as a line of the file).
//   "policy.plugin.config[1].number" is refused, naming the key of entry 1:
//   reordering the lines would silently make it another parameter.
// Returns the field's path as scenario validation names it (equal to `path`
// for a well-formed one), or why not; an unknown field name lists the valid
// names at that level. `root_name` names `msg` in messages ("the scenario").
Result<std::string> set_field(google::protobuf::Message& msg, std::string_view path, std::string_view value,
                              std::string_view root_name);

}  // namespace pheromesh::core::field_override
