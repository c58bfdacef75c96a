// Fuzz harness: a console recording file (docs/recording.md) through
// read_recording, then what `pheromesh replay` does with an accepted one:
// the ReplayIndex (every frame applied with the live console's apply()),
// states at a few times and their /api/frame JSON. Input: the file's bytes.
//
// read_recording takes a path (it reads a file that may still be growing),
// so each input is written to one scratch file of this process first.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "pheromesh/console/recording.hpp"
#include "pheromesh/console/view.hpp"

using namespace pheromesh;

namespace {

const std::string& scratch_path() {
  static const std::string path = [] {
    const char* dir = std::getenv("TMPDIR");
    std::string p = std::string(dir != nullptr && *dir != '\0' ? dir : "/tmp") + "/pheromesh-fuzz-recording-" +
                    std::to_string(::getpid()) + ".phmrec";
    std::atexit([] { std::remove(scratch_path().c_str()); });
    return p;
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string& path = scratch_path();
  {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);
  }
  auto rec = console::read_recording(path);
  if (!rec) {
    if (rec.error().message.empty()) __builtin_trap();  // a refusal must say why
    return 0;
  }
  const console::ConsoleInfo info = rec->info;
  const console::ReplayIndex index(std::move(rec.value()));
  const double t0 = index.t0(), t1 = index.t1();
  for (const double t : {t0 - 1.0, t0, (t0 + t1) / 2.0, t1, t1 + 1.0}) {
    const console::ConsoleState s = index.at(t);
    const uint16_t layers = static_cast<uint16_t>(s.layers.size() < 4 ? s.layers.size() + 1 : 4);
    for (uint16_t layer = 0; layer < layers; ++layer) {
      // The server dumps with error_handler_t::replace; strings in a
      // recording need not be UTF-8.
      (void)console::frame_json(s, info, layer, 0).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    }
  }
  (void)console::info_json(info).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return 0;
}
