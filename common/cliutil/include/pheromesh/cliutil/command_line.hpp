// What every pheromesh program does with its command line before its own
// work: --version, `help [SUBCOMMAND]`, an unknown subcommand or flag answered
// with the nearest known name ("did you mean --ticks?"), and the one syntax
// of a duration flag (a number with an optional unit, plain = seconds).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pheromesh/core/result.hpp"

namespace CLI {
class App;
class Validator;
}  // namespace CLI

namespace pheromesh::cli {

// "pheromesh-uav 0.1.0": the line --version prints.
std::string version_line(const std::string& program);

// The Levenshtein distance (insertions, deletions, substitutions) of a and b.
std::size_t edit_distance(std::string_view a, std::string_view b);

// The known name nearest to `typed`, if it is near enough to be a typo:
// at most a third of the typed length away (at least 1, at most 3), or one
// of them a prefix of the other. Ties go to the first in `known`.
std::optional<std::string> did_you_mean(std::string_view typed, const std::vector<std::string>& known);

// A duration flag's value in seconds: a number >= 0 with an optional unit,
// ms, s, m (or min) or h; a plain number is seconds ("20", "90s", "10m",
// "1h", "2500ms", "1.5h"). The error names `flag` and says what it takes.
core::Result<double> parse_duration_s(std::string_view text, std::string_view flag);

// The CLI11 check of a duration flag (parse_duration_s); with `to_seconds`
// the value becomes the number of seconds ("10m" -> "600") for an option
// bound to a number.
CLI::Validator duration_validator(bool to_seconds);

// Adds --version to `app` (the parse below answers it).
void add_version_flag(CLI::App& app);

// Parses argv into `app` as CLI11 would, and answers what the program does
// not run for: --version and --help (exit 0), `help [SUBCOMMAND ...]` for an
// app with subcommands (exit 0), an unknown subcommand or flag (a message
// with the nearest known name, exit 2), any other CLI11 error (its message
// and exit code). nullopt: parsed, run the program.
std::optional<int> parse_command_line(CLI::App& app, int argc, const char* const* argv);

}  // namespace pheromesh::cli
