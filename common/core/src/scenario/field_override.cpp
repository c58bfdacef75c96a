#include "scenario/field_override.hpp"

#include <google/protobuf/descriptor.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

namespace pheromesh::core::field_override {

namespace {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

// One component of a path: a field name and, for a repeated field, an index.
struct Step {
  std::string name;
  std::optional<int> index;
};

bool name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; }

Result<std::vector<Step>> split_path(std::string_view path) {
  const auto bad = [&](const std::string& why) {
    return Error{"'" + std::string(path) + "' is not a field path (" + why +
                 "; a path is field names joined by '.', e.g. swarm.uavs or map.targets[2].x)"};
  };
  if (path.empty()) return bad("it is empty");
  std::vector<Step> steps;
  std::size_t i = 0;
  while (true) {
    Step s;
    while (i < path.size() && name_char(path[i])) s.name += path[i++];
    if (s.name.empty())
      return bad(i < path.size() ? "'" + std::string(1, path[i]) + "' where a field name belongs"
                                 : "a field name is missing at its end");
    if (i < path.size() && path[i] == '[') {
      const std::size_t close = path.find(']', i);
      if (close == std::string_view::npos) return bad("a '[' without its ']'");
      const std::string_view digits = path.substr(i + 1, close - i - 1);
      int index = 0;
      const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
      if (digits.empty() || ec != std::errc() || end != digits.data() + digits.size() || index < 0) {
        return bad("'[" + std::string(digits) + "]' is not an index (0, 1, 2, ...)");
      }
      s.index = index;
      i = close + 1;
    }
    steps.push_back(std::move(s));
    if (i == path.size()) break;
    if (path[i] != '.') return bad("'" + std::string(1, path[i]) + "' after '" + steps.back().name + "'");
    ++i;
  }
  return steps;
}

std::string field_names(const Descriptor* d) {
  std::string s;
  for (int i = 0; i < d->field_count(); ++i) s += (i == 0 ? "" : ", ") + d->field(i)->name();
  return s;
}

// "swarm (Swarm)" or the root's name.
std::string describe(const std::string& at, const Descriptor* d, std::string_view root_name) {
  return at.empty() ? std::string(root_name) : at + " (" + d->name() + ")";
}

// What a field holds, for messages: "int32", "a repeated double", "enum Kind".
std::string type_of(const FieldDescriptor* fd) {
  if (fd->cpp_type() == FieldDescriptor::CPPTYPE_ENUM) return "enum " + fd->enum_type()->name();
  if (fd->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) return "message " + fd->message_type()->name();
  return fd->type_name();
}

template <class T>
std::optional<T> parse_integer(std::string_view v) {
  if (!v.empty() && v.front() == '+') v.remove_prefix(1);
  T out{};
  const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
  if (v.empty() || ec != std::errc() || end != v.data() + v.size()) return std::nullopt;
  return out;
}

std::optional<double> parse_real(std::string_view v) {
  if (!v.empty() && v.front() == '+') v.remove_prefix(1);
  double out = 0;
  const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
  if (v.empty() || ec != std::errc() || end != v.data() + v.size()) return std::nullopt;
  return out;
}

std::optional<bool> parse_bool(std::string_view v) {
  for (const char* t : {"true", "True", "t", "1"}) {
    if (v == t) return true;
  }
  for (const char* f : {"false", "False", "f", "0"}) {
    if (v == f) return false;
  }
  return std::nullopt;
}

// Sets scalar `fd` of `m` (entry `index` if repeated); an error names `path`.
std::optional<std::string> set_scalar(Message& m, const FieldDescriptor* fd, std::optional<int> index,
                                      std::string_view value, const std::string& path) {
  const Reflection* r = m.GetReflection();
  const std::string quoted = "'" + std::string(value) + "'";
  const std::string what = " (" + path + " is " + (fd->is_repeated() ? "a repeated " : "") + type_of(fd) + ")";
  const auto not_a = [&](const std::string& kind) { return quoted + " is not " + kind + what; };
  const auto out_of_range = [&] { return quoted + " is out of range" + what; };
  switch (fd->cpp_type()) {
    case FieldDescriptor::CPPTYPE_INT32:
    case FieldDescriptor::CPPTYPE_INT64: {
      const auto v = parse_integer<int64_t>(value);
      if (!v) return not_a(parse_integer<uint64_t>(value) ? "in range" : "an integer");
      if (fd->cpp_type() == FieldDescriptor::CPPTYPE_INT32) {
        if (*v < std::numeric_limits<int32_t>::min() || *v > std::numeric_limits<int32_t>::max()) return out_of_range();
        const auto v32 = static_cast<int32_t>(*v);
        index ? r->SetRepeatedInt32(&m, fd, *index, v32) : r->SetInt32(&m, fd, v32);
      } else {
        index ? r->SetRepeatedInt64(&m, fd, *index, *v) : r->SetInt64(&m, fd, *v);
      }
      return std::nullopt;
    }
    case FieldDescriptor::CPPTYPE_UINT32:
    case FieldDescriptor::CPPTYPE_UINT64: {
      const auto v = parse_integer<uint64_t>(value);
      if (!v) return not_a(parse_integer<int64_t>(value) ? "a non-negative integer" : "an integer");
      if (fd->cpp_type() == FieldDescriptor::CPPTYPE_UINT32) {
        if (*v > std::numeric_limits<uint32_t>::max()) return out_of_range();
        const auto v32 = static_cast<uint32_t>(*v);
        index ? r->SetRepeatedUInt32(&m, fd, *index, v32) : r->SetUInt32(&m, fd, v32);
      } else {
        index ? r->SetRepeatedUInt64(&m, fd, *index, *v) : r->SetUInt64(&m, fd, *v);
      }
      return std::nullopt;
    }
    case FieldDescriptor::CPPTYPE_DOUBLE:
    case FieldDescriptor::CPPTYPE_FLOAT: {
      const auto v = parse_real(value);
      if (!v) return not_a("a number");
      if (fd->cpp_type() == FieldDescriptor::CPPTYPE_FLOAT) {
        if (std::isfinite(*v) && std::fabs(*v) > std::numeric_limits<float>::max()) return out_of_range();
        const auto f = static_cast<float>(*v);
        index ? r->SetRepeatedFloat(&m, fd, *index, f) : r->SetFloat(&m, fd, f);
      } else {
        index ? r->SetRepeatedDouble(&m, fd, *index, *v) : r->SetDouble(&m, fd, *v);
      }
      return std::nullopt;
    }
    case FieldDescriptor::CPPTYPE_BOOL: {
      const auto v = parse_bool(value);
      if (!v) return not_a("true or false");
      index ? r->SetRepeatedBool(&m, fd, *index, *v) : r->SetBool(&m, fd, *v);
      return std::nullopt;
    }
    case FieldDescriptor::CPPTYPE_ENUM: {
      const auto* e = fd->enum_type();
      const auto* ev = e->FindValueByName(std::string(value));
      if (ev == nullptr) {
        if (const auto n = parse_integer<int32_t>(value)) ev = e->FindValueByNumber(*n);
      }
      if (ev == nullptr) {
        std::string names;
        for (int i = 0; i < e->value_count(); ++i) names += (i == 0 ? "" : ", ") + e->value(i)->name();
        return quoted + " is not a value of enum " + e->name() + what + "; its values: " + names;
      }
      index ? r->SetRepeatedEnum(&m, fd, *index, ev) : r->SetEnum(&m, fd, ev);
      return std::nullopt;
    }
    case FieldDescriptor::CPPTYPE_STRING: {
      std::string v(value);
      if (v.size() >= 2 && v.front() == '"' && v.back() == '"') v = v.substr(1, v.size() - 2);
      index ? r->SetRepeatedString(&m, fd, *index, std::move(v)) : r->SetString(&m, fd, std::move(v));
      return std::nullopt;
    }
    case FieldDescriptor::CPPTYPE_MESSAGE:
      break;
  }
  return path + " holds a message, not a value";
}

// A list of keyed parameters, `repeated PluginParameter config` (a plugin's
// or a Python policy's): entries of a message type with a string `key` and a
// oneof `value`. Such an entry is addressed by its key (`param.NAME`), never
// by its position, which names another parameter once the lines are reordered.
bool keyed_parameters(const FieldDescriptor* fd) {
  if (fd == nullptr || !fd->is_repeated() || fd->cpp_type() != FieldDescriptor::CPPTYPE_MESSAGE) return false;
  const Descriptor* e = fd->message_type();
  const FieldDescriptor* key = e->FindFieldByName("key");
  return key != nullptr && key->cpp_type() == FieldDescriptor::CPPTYPE_STRING && !key->is_repeated() &&
         e->FindOneofByName("value") != nullptr;
}

// The member of the `value` oneof a new parameter gets from its text: flag
// for true / false, number for what reads as one, else text.
const FieldDescriptor* member_for(const Descriptor* entry, std::string_view value) {
  const auto* oneof = entry->FindOneofByName("value");
  const auto of_type = [&](FieldDescriptor::CppType t) -> const FieldDescriptor* {
    for (int i = 0; i < oneof->field_count(); ++i) {
      if (oneof->field(i)->cpp_type() == t) return oneof->field(i);
    }
    return nullptr;
  };
  const FieldDescriptor* chosen = nullptr;
  if (value == "true" || value == "false") chosen = of_type(FieldDescriptor::CPPTYPE_BOOL);
  if (chosen == nullptr && parse_real(value)) chosen = of_type(FieldDescriptor::CPPTYPE_DOUBLE);
  if (chosen == nullptr) chosen = of_type(FieldDescriptor::CPPTYPE_STRING);
  return chosen != nullptr ? chosen : oneof->field(0);
}

// Sets the parameter `key` of the list `config` of `m` (its entry's value, of
// the kind the entry has; a new entry when the list has no such key).
// `at` is the path of `m`. Returns the entry's field path.
Result<std::string> set_parameter(Message& m, const FieldDescriptor* config, const std::string& key,
                                  std::string_view value, const std::string& at) {
  const Reflection* r = m.GetReflection();
  const Descriptor* entry_type = config->message_type();
  const FieldDescriptor* key_fd = entry_type->FindFieldByName("key");
  const auto* oneof = entry_type->FindOneofByName("value");
  const int size = r->FieldSize(m, config);
  int index = -1;
  for (int j = 0; j < size && index < 0; ++j) {
    const Message& e = r->GetRepeatedMessage(m, config, j);
    if (e.GetReflection()->GetString(e, key_fd) == key) index = j;
  }
  Message* e = nullptr;
  if (index < 0) {
    e = r->AddMessage(&m, config);
    e->GetReflection()->SetString(e, key_fd, key);
    index = size;
  } else {
    e = r->MutableRepeatedMessage(&m, config, index);
  }
  const FieldDescriptor* member = e->GetReflection()->GetOneofFieldDescriptor(*e, oneof);
  if (member == nullptr) member = member_for(entry_type, value);
  const std::string path = at + "." + config->name() + "[" + std::to_string(index) + "]." + member->name();
  if (auto err = set_scalar(*e, member, std::nullopt, value, path)) {
    return Error{at + ".param." + key + ": " + *err};
  }
  return path;
}

}  // namespace

namespace {

// A parameter line (`config { key: ... }`) named by its position: refused.
// The entry's key, if there is one, says the name.
Error keyed_by_position(const Message& msg, const FieldDescriptor* fd, const Step& step, std::string_view path,
                        const std::string& at, const std::string& here) {
  const Message* m = &msg;
  const Reflection* r = msg.GetReflection();
  std::string key;
  if (step.index && *step.index < r->FieldSize(*m, fd)) {
    const Message& e = r->GetRepeatedMessage(*m, fd, *step.index);
    key = e.GetReflection()->GetString(e, e.GetDescriptor()->FindFieldByName("key"));
  }
  const std::string by_name = (at.empty() ? std::string() : at + ".") + "param." + (key.empty() ? "NAME" : key);
  return Error{
      "'" + std::string(path) + "': a parameter is set by its key, " + by_name + "=VALUE" +
      (key.empty() ? std::string() : " (" + here + "[" + std::to_string(*step.index) + "] is \"" + key + "\")") +
      "; by its position it would set another parameter once the " + step.name + " lines are reordered"};
}

// A repeated field needs the index of an existing entry, any other field none.
std::optional<Error> index_error(const Message& msg, const FieldDescriptor* fd, const Step& step,
                                 const std::string& here, const std::string& example_tail) {
  const Message* m = &msg;
  const Reflection* r = msg.GetReflection();
  if (fd->is_repeated()) {
    const int size = r->FieldSize(*m, fd);
    if (!step.index) {
      return Error{here + " is a repeated field (" + std::to_string(size) +
                   " entries): name one entry by its index, e.g. " + here + "[0]" + example_tail +
                   "; an override changes an entry, it does not add or remove one"};
    }
    if (*step.index >= size) {
      return Error{here + "[" + std::to_string(*step.index) + "]: no such entry, " + here + " has " +
                   std::to_string(size) + (size == 1 ? " entry" : " entries") +
                   (size > 0 ? " (0.." + std::to_string(size - 1) + ")" : "") +
                   "; an override changes an entry, it does not add one"};
    }
  } else if (step.index) {
    return Error{here + " is not a repeated field: leave out [" + std::to_string(*step.index) + "]"};
  }
  return std::nullopt;
}

// Another member of the field's oneof is set: an override does not switch it.
std::optional<Error> oneof_error(const Message& msg, const FieldDescriptor* fd, const Step& step, const std::string& at,
                                 const std::string& canonical) {
  const Message* m = &msg;
  const Reflection* r = msg.GetReflection();
  if (const auto* oneof = fd->real_containing_oneof()) {
    const FieldDescriptor* chosen = r->GetOneofFieldDescriptor(*m, oneof);
    if (chosen != nullptr && chosen != fd) {
      const std::string prefix = at.empty() ? "" : at + ".";
      return Error{canonical + ": " + prefix + step.name + " and " + prefix + chosen->name() +
                   " are members of the oneof " + prefix + oneof->name() + ", and " + prefix + chosen->name() +
                   " is set; an override does not switch a oneof to another member (change it in the file)"};
    }
  }
  return std::nullopt;
}

}  // namespace

Result<std::string> set_field(Message& msg, std::string_view path, std::string_view value, std::string_view root_name) {
  auto split = split_path(path);
  if (!split) return split.error();
  const std::vector<Step>& steps = split.value();
  Message* m = &msg;
  std::string at;  // the path walked so far, as validation names it
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const Step& step = steps[i];
    const Descriptor* d = m->GetDescriptor();
    const Reflection* r = m->GetReflection();
    const FieldDescriptor* fd = d->FindFieldByName(step.name);
    if (const FieldDescriptor* config = d->FindFieldByName("config");
        fd == nullptr && step.name == "param" && keyed_parameters(config)) {
      const std::string here = at.empty() ? step.name : at + "." + step.name;
      if (step.index || i + 2 != steps.size() || steps[i + 1].index) {
        return Error{"'" + std::string(path) + "': name one parameter by its key, e.g. " + here +
                     ".speed (the key of a `config { key: \"speed\" ... }` line)"};
      }
      return set_parameter(*m, config, steps[i + 1].name, value, at);
    }
    if (fd == nullptr) {
      return Error{"'" + step.name + "' is not a field of " + describe(at, d, root_name) +
                   "; its fields: " + field_names(d)};
    }
    const std::string here = at.empty() ? step.name : at + "." + step.name;
    const bool message = fd->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE;
    const std::string example_tail =
        message && fd->message_type()->field_count() > 0 ? "." + fd->message_type()->field(0)->name() : "";
    if (fd->is_map()) return Error{here + " is a map field, which --set does not reach"};
    if (keyed_parameters(fd)) return keyed_by_position(*m, fd, step, path, at, here);
    if (auto err = index_error(*m, fd, step, here, example_tail)) return *err;
    const std::string canonical = step.index ? here + "[" + std::to_string(*step.index) + "]" : here;
    if (auto err = oneof_error(*m, fd, step, at, canonical)) return *err;
    const bool last = i + 1 == steps.size();
    if (message) {
      if (last) {
        return Error{canonical + " is a message (" + fd->message_type()->name() +
                     "), not a value: set one of its fields, e.g. " + canonical + example_tail +
                     "; its fields: " + field_names(fd->message_type())};
      }
      m = step.index ? r->MutableRepeatedMessage(m, fd, *step.index) : r->MutableMessage(m, fd);
      at = canonical;
      continue;
    }
    if (!last) {
      return Error{canonical + " is " + type_of(fd) + ", not a message: nothing inside it to set ('" +
                   steps[i + 1].name + "')"};
    }
    if (auto err = set_scalar(*m, fd, step.index, value, canonical)) return Error{*err};
    return canonical;
  }
  return Error{"'" + std::string(path) + "' names no field"};  // unreachable: split_path gives >= 1 step
}

}  // namespace pheromesh::core::field_override
