// A checker for the part of JSON Schema (2020-12) that
// docs/schema/metrics.schema.json uses: type (one or a list), properties,
// required, additionalProperties (true, false or a schema), items, enum,
// minimum, $ref to "#/$defs/NAME", and the annotations title, description,
// $schema, $id. Any other keyword is an error of the schema itself, so the
// schema cannot use a rule this checker would silently skip. nlohmann-json has
// no validator; this is small enough to read in one go.
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

namespace pheromesh::test {

class SchemaSubset {
 public:
  explicit SchemaSubset(nlohmann::json schema) : root_(std::move(schema)) {}

  // Every violation of `doc`, each as "PATH: what" (PATH a JSON pointer);
  // empty if `doc` conforms.
  [[nodiscard]] std::vector<std::string> check(const nlohmann::json& doc) const {
    std::vector<std::string> errors;
    check(root_, doc, "", errors);
    return errors;
  }

 private:
  nlohmann::json root_;

  static bool has_type(const nlohmann::json& v, const std::string& t) {
    if (t == "object") return v.is_object();
    if (t == "array") return v.is_array();
    if (t == "string") return v.is_string();
    if (t == "boolean") return v.is_boolean();
    if (t == "null") return v.is_null();
    if (t == "integer") return v.is_number_integer() || (v.is_number_float() && std::floor(v.get<double>()) == v.get<double>());
    if (t == "number") return v.is_number();
    return false;
  }

  void check(const nlohmann::json& schema, const nlohmann::json& v, const std::string& path,
             std::vector<std::string>& errors) const {
    static const std::set<std::string> kKnown = {"type",  "properties", "required", "additionalProperties",
                                                 "items", "enum",       "minimum",  "$ref",
                                                 "title", "description", "$schema", "$id", "$defs"};
    const std::string at = path.empty() ? "/" : path;
    for (const auto& [key, value] : schema.items()) {
      if (!kKnown.contains(key)) errors.push_back(at + ": the schema uses '" + key + "', which this checker does not know");
    }
    if (schema.contains("$ref")) {
      const std::string ref = schema["$ref"].get<std::string>();
      const std::string prefix = "#/$defs/";
      if (ref.rfind(prefix, 0) != 0 || !root_["$defs"].contains(ref.substr(prefix.size()))) {
        errors.push_back(at + ": unresolved $ref " + ref);
        return;
      }
      check(root_["$defs"][ref.substr(prefix.size())], v, path, errors);
      return;
    }
    if (schema.contains("type")) {
      std::vector<std::string> types;
      if (schema["type"].is_string()) {
        types.push_back(schema["type"].get<std::string>());
      } else {
        types = schema["type"].get<std::vector<std::string>>();
      }
      bool any = false;
      for (const auto& t : types) any = any || has_type(v, t);
      if (!any) {
        errors.push_back(at + ": " + v.dump() + " is not of type " + schema["type"].dump());
        return;
      }
    }
    if (schema.contains("enum")) {
      bool in = false;
      for (const auto& e : schema["enum"]) in = in || e == v;
      if (!in) errors.push_back(at + ": " + v.dump() + " is not one of " + schema["enum"].dump());
    }
    if (schema.contains("minimum") && v.is_number() && v.get<double>() < schema["minimum"].get<double>()) {
      errors.push_back(at + ": " + v.dump() + " is below the minimum " + schema["minimum"].dump());
    }
    if (v.is_object()) {
      for (const auto& r : schema.value("required", nlohmann::json::array())) {
        if (!v.contains(r.get<std::string>())) errors.push_back(at + ": the required key '" + r.get<std::string>() + "' is missing");
      }
      const nlohmann::json props = schema.value("properties", nlohmann::json::object());
      for (const auto& [key, value] : v.items()) {
        const std::string p = path + "/" + key;
        if (props.contains(key)) {
          check(props[key], value, p, errors);
        } else if (schema.contains("additionalProperties")) {
          const auto& extra = schema["additionalProperties"];
          if (extra.is_boolean()) {
            if (!extra.get<bool>()) errors.push_back(p + ": a key the schema does not document");
          } else {
            check(extra, value, p, errors);
          }
        }
      }
    }
    if (v.is_array() && schema.contains("items")) {
      for (std::size_t i = 0; i < v.size(); ++i) check(schema["items"], v[i], path + "/" + std::to_string(i), errors);
    }
  }
};

}  // namespace pheromesh::test
