// Output files that are either whole or absent: written under a temporary
// name in the same directory, flushed to the disk (fsync), then renamed over
// the final name, which rename(2) does in one step. A process killed at any
// moment (SIGKILL, OOM, power loss after the fsync) leaves the previous file or
// none, never a truncated one; at worst a stray temporary file
// (".NAME.tmp-PID") stays next to it.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

#include "pheromesh/core/result.hpp"

namespace pheromesh::core {

// The temporary name used for `path`: ".NAME.tmp-PID" in the same directory
// (same file system, so the rename is atomic; hidden, so globs of the output
// directory skip it).
std::string atomic_temp_path(const std::string& path);

// An output file being written. Nothing appears under `path` until commit();
// the destructor of an uncommitted file removes the temporary file.
class AtomicFile {
 public:
  // Creates the temporary file (and the parent directory if missing).
  static Result<AtomicFile> create(const std::string& path);
  AtomicFile(AtomicFile&& other) noexcept;
  AtomicFile& operator=(AtomicFile&& other) noexcept;
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  // Appends bytes; false after any I/O error (which commit() reports).
  bool write(std::string_view bytes);
  // Hands the data written so far to the OS (not to the disk), so that a
  // reader of the temporary file sees it; false on an I/O error.
  bool flush();
  // The stdio stream, for writers that print with fprintf.
  [[nodiscard]] std::FILE* stream() const { return file_; }
  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] const std::string& temp_path() const { return temp_; }

  // fflush + fsync + close + rename onto path() + fsync of the directory.
  // Returns the bytes in the file, or an error naming the file and the cause
  // (the temporary file is removed then).
  Result<std::size_t> commit();

 private:
  AtomicFile(std::string path, std::string temp, std::FILE* file) : path_(std::move(path)), temp_(std::move(temp)), file_(file) {}
  void discard();
  std::string path_;
  std::string temp_;
  std::FILE* file_ = nullptr;
  int error_ = 0;  // first errno seen by write()/flush()
};

// Writes a whole file atomically: create, write, commit.
Result<std::size_t> write_file_atomically(const std::string& path, std::string_view content);

}  // namespace pheromesh::core
