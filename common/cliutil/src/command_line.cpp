#include "pheromesh/cliutil/command_line.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>


namespace pheromesh::cli {

namespace {

bool starts_with_dash(std::string_view s) { return s.size() > 1 && s.front() == '-'; }

// A negative number is a value, never a flag (e.g. --set run.seed=-1 or a
// bench's range): not worth a "did you mean".
bool is_number(std::string_view s) {
  std::string t(s);
  char* end = nullptr;
  std::strtod(t.c_str(), &end);
  return !t.empty() && end != t.c_str() && *end == '\0';
}

// The subcommands a user may type at `app` (the hidden ones, group "", left
// out of the suggestions but still accepted).
std::vector<CLI::App*> subcommands_of(CLI::App& app) {
  return app.get_subcommands([](CLI::App*) { return true; });
}

std::vector<std::string> visible_subcommand_names(CLI::App& app) {
  std::vector<std::string> names;
  for (CLI::App* s : subcommands_of(app)) {
    if (!s->get_group().empty()) names.push_back(s->get_name());
  }
  return names;
}

CLI::App* find_subcommand(CLI::App& app, const std::string& name) {
  for (CLI::App* s : subcommands_of(app)) {
    if (s->check_name(name)) return s;
  }
  return nullptr;
}

// "pheromesh bench": the command as typed so far.
std::string command_path(const CLI::App& app) {
  const CLI::App* parent = app.get_parent();
  return parent == nullptr ? app.get_name() : command_path(*parent) + " " + app.get_name();
}

std::string root_name(const CLI::App& app) {
  const CLI::App* a = &app;
  while (a->get_parent() != nullptr) a = a->get_parent();
  return a->get_name();
}

std::string unknown_subcommand(CLI::App& at, const std::string& typed) {
  std::string msg = command_path(at) + ": unknown subcommand '" + typed + "'";
  if (auto near = did_you_mean(typed, visible_subcommand_names(at))) msg += " — did you mean '" + *near + "'?";
  std::string list;
  for (const auto& n : visible_subcommand_names(at)) list += (list.empty() ? "" : ", ") + n;
  msg += "\n  subcommands: " + list;
  const std::string tail = command_path(at).substr(root_name(at).size());
  msg += "\n  `" + root_name(at) + " help" + tail + " SUBCOMMAND` explains one";
  return msg;
}

// The flags a user may give to the deepest parsed subcommand of `app` (its own
// and those of the commands above it): "--ticks", "-j".
std::vector<std::string> flag_names(const CLI::App& deepest) {
  std::vector<std::string> names;
  for (const CLI::App* a = &deepest; a != nullptr; a = a->get_parent()) {
    for (const CLI::Option* o : a->get_options()) {
      for (const auto& l : o->get_lnames()) names.push_back("--" + l);
      for (const auto& s : o->get_snames()) names.push_back("-" + s);
    }
  }
  return names;
}

CLI::App* deepest_parsed(CLI::App& app) {
  CLI::App* cur = &app;
  for (;;) {
    const auto parsed = cur->get_subcommands();
    if (parsed.empty()) return cur;
    cur = parsed.back();
  }
}

// Before CLI11 sees the line: `help [SUBCOMMAND ...]` and an unknown
// subcommand, which CLI11 would only answer with "A subcommand is required".
std::optional<int> walk_subcommands(CLI::App& app, int argc, const char* const* argv) {
  CLI::App* cur = &app;
  bool help_asked = false;
  for (int i = 1; i < argc; ++i) {
    const std::string tok = argv[i];
    if (tok == "--") return std::nullopt;
    if (starts_with_dash(tok)) {
      help_asked = help_asked || tok == "-h" || tok == "--help";
      // Skip an option's value ("--log-level debug"), unless given with '='.
      if (tok.find('=') == std::string::npos) {
        const CLI::Option* o = cur->get_option_no_throw(tok);
        if (o != nullptr && o->get_items_expected_max() > 0 && i + 1 < argc) ++i;
      }
      continue;
    }
    if (subcommands_of(*cur).empty()) return std::nullopt;  // the command's own arguments
    if (cur == &app && tok == "help" && find_subcommand(app, "help") == nullptr) {
      CLI::App* shown = &app;
      for (int j = i + 1; j < argc; ++j) {
        const std::string name = argv[j];
        if (starts_with_dash(name)) continue;
        if (subcommands_of(*shown).empty()) break;
        CLI::App* next = find_subcommand(*shown, name);
        if (next == nullptr) {
          std::fprintf(stderr, "%s\n", unknown_subcommand(*shown, name).c_str());
          return 2;
        }
        shown = next;
      }
      // As `pheromesh bench scale --help` prints it: the usage line names the
      // whole command.
      std::cout << (shown == &app ? app.help() : shown->help(command_path(*shown->get_parent())));
      return 0;
    }
    CLI::App* next = find_subcommand(*cur, tok);
    if (next == nullptr) {
      std::fprintf(stderr, "%s\n", unknown_subcommand(*cur, tok).c_str());
      return 2;
    }
    cur = next;
  }
  // No subcommand where one is needed (`pheromesh`, `pheromesh bench`): what
  // there is to run, rather than CLI11's "A subcommand is required".
  if (!help_asked && cur->get_require_subcommand_min() > 0 && !subcommands_of(*cur).empty()) {
    const std::string help = cur == &app ? app.help() : cur->help(command_path(*cur->get_parent()));
    std::string list;
    for (const auto& n : visible_subcommand_names(*cur)) list += (list.empty() ? "" : ", ") + n;
    const std::string tail = command_path(*cur).substr(root_name(*cur).size());
    std::fprintf(stderr, "%s\n%s: which subcommand? one of: %s\n  `%s help%s SUBCOMMAND` explains one\n",
                 help.c_str(), command_path(*cur).c_str(), list.c_str(), root_name(*cur).c_str(), tail.c_str());
    return 2;
  }
  return std::nullopt;
}

// An argument CLI11 did not expect: a flag nobody has gets the nearest
// known flag; anything else CLI11's own message.
int explain_extras(CLI::App& app, const CLI::ExtrasError& e) {
  CLI::App* deepest = deepest_parsed(app);
  const auto known = flag_names(*deepest);
  std::string msg;
  for (const auto& extra : app.remaining(true)) {
    if (!starts_with_dash(extra) || is_number(extra)) continue;
    const std::string name = extra.substr(0, extra.find('='));
    msg += (msg.empty() ? "" : "\n") + command_path(*deepest) + ": unknown flag '" + name + "'";
    if (auto near = did_you_mean(name, known)) msg += " — did you mean " + *near + "?";
  }
  if (msg.empty()) msg = e.what();
  msg += "\n  `" + command_path(*deepest) + " --help` lists its flags";
  std::fprintf(stderr, "%s\n", msg.c_str());
  return 2;
}

}  // namespace

std::string version_line(const std::string& program) { return program + " " + PHEROMESH_VERSION; }

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::optional<std::string> did_you_mean(std::string_view typed, const std::vector<std::string>& known) {
  // Ignore the dashes when measuring: "--tick" is one edit from "--ticks".
  const auto bare = [](std::string_view s) {
    while (!s.empty() && s.front() == '-') s.remove_prefix(1);
    return s;
  };
  const std::string_view t = bare(typed);
  if (t.empty()) return std::nullopt;
  const std::size_t limit = std::clamp<std::size_t>(t.size() / 3, 1, 3);
  std::optional<std::string> best;
  std::size_t best_d = limit + 1;
  for (const auto& k : known) {
    const std::string_view b = bare(k);
    if (b.empty() || k == typed) continue;
    std::size_t d = edit_distance(t, b);
    // A clipped name ("--dur" for "--duration") is as good as a typo.
    if (t.size() >= 3 && (b.starts_with(t) || t.starts_with(b))) d = std::min(d, limit);
    if (d < best_d) {
      best_d = d;
      best = k;
    }
  }
  return best;
}

core::Result<double> parse_duration_s(std::string_view text, std::string_view flag) {
  const auto refuse = [&] {
    return core::Error{std::string(flag) + " " + std::string(text) +
                       ": a duration is a number >= 0 with an optional unit ms, s, m or h, e.g. 20 (seconds), 90s, "
                       "10m, 1h, 2500ms"};
  };
  const std::string t(text);
  if (t.empty()) return refuse();
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (end == t.c_str() || !std::isfinite(v) || v < 0) return refuse();
  const std::string unit(end);
  if (unit.empty() || unit == "s") return v;
  if (unit == "ms") return v / 1000.0;
  if (unit == "m" || unit == "min") return v * 60.0;
  if (unit == "h") return v * 3600.0;
  return refuse();
}

CLI::Validator duration_validator(bool to_seconds) {
  return CLI::Validator(
      [to_seconds](std::string& v) -> std::string {
        auto d = parse_duration_s(v, "");
        if (!d) return d.error().message.substr(1);  // CLI11 names the flag
        if (to_seconds) {
          char buf[32];
          std::snprintf(buf, sizeof buf, "%.17g", d.value());
          v = buf;
        }
        return {};
      },
      "DURATION");
}

void add_version_flag(CLI::App& app) { app.add_flag("--version")->description("Print the version and exit"); }

std::optional<int> parse_command_line(CLI::App& app, int argc, const char* const* argv) {
  if (app.get_option_no_throw("--version") != nullptr) {
    for (int i = 1; i < argc; ++i) {
      if (std::string_view(argv[i]) == "--") break;
      if (std::string_view(argv[i]) == "--version") {
        std::printf("%s\n", version_line(app.get_name()).c_str());
        return 0;
      }
    }
  }
  if (auto rc = walk_subcommands(app, argc, argv)) return rc;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ExtrasError& e) {
    return explain_extras(app, e);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return std::nullopt;
}

}  // namespace pheromesh::cli
