#pragma once
#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/qos.hpp"
#include "pheromesh/bus/transport.hpp"

namespace pheromesh::bus {
core::Result<std::unique_ptr<Transport>> make_fastdds_transport(const BusOptions& options);
// The QoS a Fast DDS endpoint of `kind` gets, read back from the vendor's QoS
// object (tests compare it with topic_qos()).
QosSpec fastdds_effective_qos(TopicKind kind, Endpoint endpoint, std::chrono::milliseconds lease,
                              const Replication& replication = {}, Pacing pacing = Pacing::Lockstep);
}  // namespace pheromesh::bus
