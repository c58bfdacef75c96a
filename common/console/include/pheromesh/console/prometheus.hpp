// Prometheus text exposition format, version 0.0.4: families with HELP and
// TYPE, samples with escaped label values.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace pheromesh::console {

class Exposition {
 public:
  using Labels = std::vector<std::pair<std::string, std::string>>;
  // Starts a family; its samples follow. `type`: counter | gauge | untyped.
  void family(const std::string& name, const std::string& type, const std::string& help);
  // A sample of the current family (name may carry a suffix such as _total).
  void sample(const std::string& name, const Labels& labels, double value);
  void sample(const std::string& name, double value) { sample(name, {}, value); }
  [[nodiscard]] const std::string& text() const { return out_; }

  static std::string escape_label(const std::string& v);
  static std::string escape_help(const std::string& v);
  static std::string format_value(double v);

 private:
  std::string out_;
};

inline constexpr const char* kExpositionContentType = "text/plain; version=0.0.4; charset=utf-8";

}  // namespace pheromesh::console
