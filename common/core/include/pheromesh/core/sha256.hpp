// SHA-256 (FIPS 180-4) through OpenSSL's libcrypto, for pinning the exact
// build of a policy plugin (policy_plugin.hpp).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "pheromesh/core/result.hpp"

namespace pheromesh::core {

// The digest as 64 lowercase hex digits.
std::string sha256_hex(std::span<const uint8_t> data);
std::string sha256_hex(std::string_view data);
// Of a file's bytes; an error names the file and why it cannot be read.
Result<std::string> sha256_file_hex(const std::string& path);
// Whether `s` is 64 hex digits (either case).
bool is_sha256_hex(std::string_view s);

}  // namespace pheromesh::core
