#include "attach_command.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <vector>

#include "launcher.hpp"

namespace pheromesh::cli {

int run_attach(AttachOptions o) {
  if (o.dds == "mixed") {
    // $PHEROMESH_DDS=mixed describes a swarm of both vendors; one process
    // takes one, and either reaches every process of such a swarm.
    o.dds = "fastdds";
    spdlog::info("the monitor is one process: it runs on Fast DDS (either vendor reaches a mixed swarm)");
  }
  const std::string exe = executable_dir() + "/pheromesh-ground";
  // clang-format off: flag, value
  std::vector<std::string> args{exe,
                                "--attach",
                                "--domain",
                                std::to_string(o.domain),
                                "--dds",
                                o.dds,
                                "--dds-profile",
                                o.dds_profile,
                                "--out",
                                o.out_dir,
                                "--attach-timeout",
                                std::to_string(o.timeout_s),
                                "--progress",
                                std::to_string(o.progress_s),
                                "--log-level",
                                o.log_level};
  // clang-format on
  if (!o.dds_peers.empty()) args.insert(args.end(), {"--dds-peers", o.dds_peers});
  if (o.http_port) args.insert(args.end(), {"--http", std::to_string(*o.http_port), "--http-bind", o.http_bind});
  if (!o.record.empty()) args.insert(args.end(), {"--record", o.record});
  if (!o.secure.empty()) args.insert(args.end(), {"--secure", o.secure});
  std::error_code ec;
  std::filesystem::create_directories(o.out_dir, ec);
  if (ec) {
    spdlog::error("cannot make {}: {}", o.out_dir, ec.message());
    return 2;
  }
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  execv(exe.c_str(), argv.data());
  spdlog::error("cannot execute {}: {}", exe, std::strerror(errno));
  return 3;
}

}  // namespace pheromesh::cli
