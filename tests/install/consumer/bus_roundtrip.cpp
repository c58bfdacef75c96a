// With the installed pheromesh::bus: a Fast DDS bus (a UAV) sends one deposit
// to a Cyclone DDS bus (its home place agent) in this process, on loopback;
// both buses are then closed. Fails unless the deposit arrives intact, which
// takes both vendors' libraries and generated types from the install.
//   bus_roundtrip DOMAIN
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "pheromesh/bus/bus.hpp"

using namespace pheromesh;  // NOLINT
using Clock = std::chrono::steady_clock;

namespace {

std::unique_ptr<bus::Bus> open(const std::string& vendor, const std::string& name, uint32_t domain) {
  bus::BusOptions o;
  o.process_name = name;
  o.domain = domain;
  auto b = bus::make_bus(vendor, o);
  if (!b) {
    std::fprintf(stderr, "%s bus: %s\n", vendor.c_str(), b.error().message.c_str());
    return nullptr;
  }
  return std::move(b).value();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: bus_roundtrip DOMAIN\n");
    return 2;
  }
  const auto domain = static_cast<uint32_t>(std::strtoul(argv[1], nullptr, 10));
  std::string vendors;
  for (const auto& v : bus::available_vendors()) vendors += " " + v;
  std::printf("vendors:%s\n", vendors.c_str());

  auto place = open("cyclone", "place-0", domain);
  auto uav = open("fastdds", "uav-0", domain);
  if (!place || !uav) return 1;
  place->subscribe_deposits(0);
  uav->offer_deposits(std::vector<core::RegionId>{0});  // as a place agent forwarding to region 0
  const auto deadline = Clock::now() + std::chrono::seconds(20);
  while (uav->matched_deposit_readers(0) == 0 && Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (uav->matched_deposit_readers(0) == 0) {
    std::fprintf(stderr, "the Fast DDS writer never matched the Cyclone reader\n");
    return 1;
  }
  const core::DepositMsg sent{0, 1, 3, 0, 0, 1, {4, 5}, 0.5F, {}};
  if (!uav->publish_deposit(sent, 0)) {
    std::fprintf(stderr, "publish_deposit failed\n");
    return 1;
  }
  std::vector<core::DepositMsg> got;
  while (got.empty() && place->wait({bus::TopicKind::Deposit}, deadline)) place->take_deposits(got);
  if (got.size() != 1 || got[0].seq != sent.seq || got[0].tick != sent.tick || got[0].cell.x != sent.cell.x ||
      got[0].cell.y != sent.cell.y || got[0].amount != sent.amount) {
    std::fprintf(stderr, "the deposit did not arrive intact (%zu received)\n", got.size());
    return 1;
  }
  std::printf("deposit %s -> %s: seq %u, cell (%d, %d), amount %.2f\n", uav->vendor().c_str(), place->vendor().c_str(),
              got[0].seq, got[0].cell.x, got[0].cell.y, static_cast<double>(got[0].amount));
  uav.reset();  // closes the Fast DDS participant
  place.reset();
  std::printf("buses closed\n");
  return 0;
}
