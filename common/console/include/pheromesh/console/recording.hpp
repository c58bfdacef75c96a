// Recording of a console session: the ConsoleInfo, then every Frame, in a
// protobuf file that carries its own schema (docs/recording.md).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/console/state.hpp"
#include "pheromesh/core/atomic_file.hpp"
#include "pheromesh/core/result.hpp"

namespace pheromesh::console {

struct Recording {
  ConsoleInfo info;
  std::string created_utc;     // ISO 8601
  std::string writer;          // e.g. "pheromesh 0.1.0"
  std::vector<Frame> frames;
  bool truncated = false;      // the file ended inside a frame (e.g. the writer was killed)
  std::string warning;         // what was wrong with the end of the file, if truncated
};

class RecordingWriter {
 public:
  // Starts the recording `path` and writes the header. The frames go to a
  // temporary file next to it (temp_path(), core/atomic_file.hpp) that
  // becomes `path` when the writer is closed, so `path` is never a cut file;
  // a ground station killed mid-run leaves its frames in the temporary file,
  // which `pheromesh replay` reads like any recording cut short.
  static core::Result<std::unique_ptr<RecordingWriter>> open(const std::string& path, const ConsoleInfo& info);
  // close(), errors ignored.
  ~RecordingWriter();
  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;

  // Appends one frame and flushes it to the OS, so a killed ground station
  // leaves every frame written before it died. False on an I/O error.
  bool write(const Frame& f);
  [[nodiscard]] uint64_t bytes_written() const { return bytes_; }
  [[nodiscard]] const std::string& path() const { return path_; }
  // Where the frames are until close(); "" once closed.
  [[nodiscard]] const std::string& temp_path() const;
  // Syncs the file to the disk and renames it to path(); the bytes written,
  // or why it failed. Further writes return false.
  core::Result<uint64_t> close();

 private:
  RecordingWriter() = default;
  std::string path_;
  std::optional<core::AtomicFile> file_;
  uint64_t bytes_ = 0;
  uint64_t last_version_ = 0;
};

// Reads a whole recording. Errors name the file, the byte offset and what is
// wrong; a file cut inside its last frame reads as the frames before it,
// with `truncated` set.
core::Result<Recording> read_recording(const std::string& path);

// Random access by time over a recording's frames: the state after the last
// frame with t_s <= t (the first frame's state for earlier t).
class ReplayIndex {
 public:
  explicit ReplayIndex(Recording rec);
  [[nodiscard]] const Recording& recording() const { return rec_; }
  [[nodiscard]] double t0() const;
  [[nodiscard]] double t1() const;
  // Rebuilds from the nearest checkpoint at or before t.
  [[nodiscard]] ConsoleState at(double t_s) const;

 private:
  Recording rec_;
  std::vector<std::pair<std::size_t, ConsoleState>> checkpoints_;  // (frames applied, state)
};

}  // namespace pheromesh::console
