#include "security_command.hpp"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <vector>

#include "pheromesh/auth/pki.hpp"
#include "pheromesh/bus/security.hpp"
#include "pheromesh/core/scenario.hpp"

namespace pheromesh::cli {
namespace {

namespace fs = std::filesystem;

// Writes `text` to `path` with `mode` (created with it, so a key is never
// readable by others, not even for a moment); an error message or nullopt.
std::optional<std::string> write_file(const fs::path& path, const std::string& text, mode_t mode) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, mode);
  if (fd < 0) return "cannot write " + path.string() + ": " + std::strerror(errno);
  // An existing file keeps its old mode under O_CREAT: set it.
  bool ok = ::fchmod(fd, mode) == 0;
  std::size_t done = 0;
  while (ok && done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    ok = n > 0;
    if (ok) done += static_cast<std::size_t>(n);
  }
  const std::string err = ok ? std::string() : std::strerror(errno);
  ::close(fd);
  if (!ok) return "cannot write " + path.string() + ": " + err;
  return std::nullopt;
}

// The files of an earlier `security init` in `dir` (what --force replaces).
std::vector<fs::path> earlier_files(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const char* f : {"ca.pem", "ca.key", "governance.xml", "governance.p7s", "identities.txt"}) {
    if (fs::exists(dir / f)) out.push_back(dir / f);
  }
  std::ifstream list(dir / "identities.txt");
  for (std::string name; std::getline(list, name);) {
    if (!name.empty() && name.find('/') == std::string::npos && name != "." && name != ".." && fs::is_directory(dir / name)) {
      out.push_back(dir / name);
    }
  }
  return out;
}

// The swarm's size from the options, else from the scenario; 0, or 2 with
// the error logged.
int swarm_shape_of(const SecurityInitOptions& o, bus::SwarmShape& shape) {
  shape.uavs = o.uavs;
  shape.regions = o.regions;
  shape.standby = o.standby ? 1 : 0;
  shape.probes = o.probes;
  if (!o.scenario.empty()) {
    auto s = core::load_scenario(o.scenario);
    if (!s) {
      spdlog::error("invalid scenario:\n{}", s.error().message);
      return 2;
    }
    if (shape.uavs == 0) shape.uavs = s->uavs;
    if (shape.regions == 0) shape.regions = s->geometry().region_count();
    if (s->standby) shape.standby = 1;
  }
  if (shape.uavs == 0 || shape.regions == 0) {
    spdlog::error("the swarm's size is unknown: give --scenario (and --uavs if the run overrides it), or --uavs and "
                  "--regions");
    return 2;
  }
  if (o.days == 0) {
    spdlog::error("--days must be at least 1");
    return 2;
  }
  return 0;
}

// DIR made (the owner's only) and empty of an earlier init's files (--force);
// 0, or 2 with the error logged.
int prepare_security_dir(const fs::path& dir, bool force) {
  std::error_code ec;
  const std::vector<fs::path> earlier = earlier_files(dir);
  if (!earlier.empty() && !force) {
    spdlog::error("{} already holds a swarm's security files ({} and {} more); pass --force to replace them all "
                  "(every process of the swarm then needs the new ones)",
                  dir.string(), earlier.front().string(), earlier.size() - 1);
    return 2;
  }
  for (const auto& p : earlier) fs::remove_all(p, ec);
  fs::create_directories(dir, ec);
  if (ec) {
    spdlog::error("cannot make {}: {}", dir.string(), ec.message());
    return 2;
  }
  // Private keys live here: the directory is the owner's only.
  fs::permissions(dir, fs::perms::owner_all, ec);
  return 0;
}

// One process's folder: its key and certificate, signed by the CA, and its
// signed permissions; an error message if a step fails.
std::optional<std::string> write_identity(const fs::path& dir, const bus::Grant& g, const auth::KeyPair& ca,
                                          const auth::Validity& v, const std::string& from, const std::string& to) {
  std::error_code ec;
  const fs::path d = dir / g.name;
  fs::create_directories(d, ec);
  if (ec) return "cannot make " + d.string() + ": " + ec.message();
  auto id = auth::make_identity(ca, g.name, v);
  if (!id) return id.error().message;
  const std::string perms = bus::permissions_xml(g, from, to);
  auto perms_signed = auth::smime_sign(ca, perms);
  if (!perms_signed) return perms_signed.error().message;
  if (auto e = write_file(d / "key.pem", id->key, 0600)) return e;
  if (auto e = write_file(d / "cert.pem", id->cert, 0644)) return e;
  if (auto e = write_file(d / "permissions.xml", perms, 0644)) return e;
  if (auto e = write_file(d / "permissions.p7s", perms_signed.value(), 0644)) return e;
  return std::nullopt;
}

}  // namespace

int run_security_init(const SecurityInitOptions& o) {
  auto protection = bus::parse_protection(o.protection);
  if (!protection) {
    spdlog::error("{}", protection.error().message);
    return 2;
  }
  bus::SwarmShape shape;
  if (const int rc = swarm_shape_of(o, shape); rc != 0) return rc;

  const fs::path dir(o.dir);
  if (const int rc = prepare_security_dir(dir, o.force); rc != 0) return rc;

  const auth::Validity v = auth::validity_from_now(o.days);
  const std::string from = auth::permissions_date(v.not_before), to = auth::permissions_date(v.not_after);
  auto ca = auth::make_ca("pheromesh swarm CA", v);
  if (!ca) {
    spdlog::error("{}", ca.error().message);
    return 3;
  }
  auto fail = [](const std::string& msg) {
    spdlog::error("{}", msg);
    return 3;
  };
  if (auto e = write_file(dir / "ca.key", ca->key, 0600)) return fail(*e);
  if (auto e = write_file(dir / "ca.pem", ca->cert, 0644)) return fail(*e);
  const std::string governance = bus::governance_xml(protection.value());
  auto gov_signed = auth::smime_sign(ca.value(), governance);
  if (!gov_signed) return fail(gov_signed.error().message);
  if (auto e = write_file(dir / "governance.xml", governance, 0644)) return fail(*e);
  if (auto e = write_file(dir / "governance.p7s", gov_signed.value(), 0644)) return fail(*e);

  std::string names;
  const std::vector<bus::Grant> grants = bus::swarm_grants(shape);
  for (const auto& g : grants) {
    if (auto e = write_identity(dir, g, ca.value(), v, from, to)) return fail(*e);
    names += g.name + "\n";
  }
  if (auto e = write_file(dir / "identities.txt", names, 0644)) return fail(*e);
  std::printf("%s: CA, governance (protection %s) and %zu identities (%u place agents%s, %u UAVs, ground, monitor%s), "
              "valid until %s UTC\n",
              dir.string().c_str(), bus::to_string(protection.value()), grants.size(), shape.regions,
              shape.standby > 0 ? " with standbys" : "", shape.uavs,
              shape.probes > 0 ? (", " + std::to_string(shape.probes) + " probes").c_str() : "", to.c_str());
  std::printf("run the swarm with: pheromesh run SCENARIO --secure %s\n", dir.string().c_str());
  return 0;
}

}  // namespace pheromesh::cli
