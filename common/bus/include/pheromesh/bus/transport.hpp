// The vendor seam of the bus: what a DDS vendor (or the in-memory bus) must
// provide, type-erased. Endpoints are opened per TopicKind (its QoS, from
// the table in qos.cpp) and partitions; samples cross as the core message of
// the endpoint's topic (topic.hpp), which each transport converts with its
// Convert<M> into its own generated type. Everything typed, every bound
// check before writing and every role's wiring lives above this seam, once
// for all transports (typed.hpp, bus.hpp).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "pheromesh/bus/qos.hpp"

namespace pheromesh::bus {

// A vendor call failed (entity creation, a refused permission, a bad
// profile). Each vendor turns its return codes into this in exactly one
// place, which names the call, the file and the line.
class DdsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The bus was used out of order (e.g. a UAV state published before
// join_uav): the same error on every transport, thrown above the seam.
class BusMisuse : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

// Samples dropped by the bus itself (structurally malformed: sequence bounds,
// unknown enum values) and writes it refused or that failed.
struct BusStats {
  uint64_t samples_dropped = 0;
  uint64_t writes_refused = 0;
  uint64_t writes_failed = 0;
  // Samples taken through the typed readers and their payload bytes
  // (core::payload_bytes: the same measure on every transport).
  uint64_t samples_taken = 0;
  uint64_t bytes_taken = 0;
};

// An endpoint a transport opened (index into its own table).
enum class EndpointId : uint32_t {};

// Whether a reader reports the departure of its writers (their liveliness
// lost, their process ended) besides their samples; the New... ones take
// none of the writers' history (a volatile reader: a place agent started
// again takes no deposits its dead life already counted).
enum class Watch : uint8_t { Samples, SamplesAndDepartures, NewSamplesOnly, NewSamplesAndDepartures };

inline bool watches_departures(Watch w) {
  return w == Watch::SamplesAndDepartures || w == Watch::NewSamplesAndDepartures;
}

// The reader QoS of `kind` as `watch` asks for it.
inline QosSpec reader_qos_for(QosSpec q, Watch watch) {
  if (watch == Watch::NewSamplesOnly || watch == Watch::NewSamplesAndDepartures) {
    q.durability = QosSpec::Durability::Volatile;
  }
  return q;
}

// Who a taken sample came from, as this participant identifies them.
struct SampleInfo {
  uint64_t writer = 0;    // the DDS writer (Cyclone: publication handle; Fast DDS: GUID folded to 64 bits)
  uint64_t instance = 0;  // the instance (its key), 0 if unknown
  // The writer's participant: its GUID prefix folded to 64 bits
  // (participant_id), the same on every vendor, so a Cyclone and a Fast DDS
  // reader name one remote process alike; 0 if unknown. Every writer of one
  // process shares it: a receiver can tell that a UAV's detections come
  // from the process that writes its states, or a field chunk from the
  // place agent whose health it heard.
  uint64_t participant = 0;
};

// An RTPS GUID prefix (its first 12 bytes: host, process, participant)
// folded to 64 bits, FNV-1a. Never 0 for a real prefix.
inline uint64_t participant_id(const uint8_t* guid_prefix12) {
  uint64_t x = 14695981039346656037ULL;
  for (int i = 0; i < 12; ++i) {
    x ^= guid_prefix12[i];
    x *= 1099511628211ULL;
  }
  return x == 0 ? 1 : x;
}

// What take() hands over; `message` points to the core message of the
// reader's topic, valid during the call only.
class TakeSink {
 public:
  virtual ~TakeSink() = default;
  // A message the transport shares (the in-memory transport's, one for every
  // reader): the sink copies what it keeps.
  virtual void sample(const void* message, const SampleInfo& info) = 0;
  // A message the transport converted for this take and drops after the
  // call (a DDS sample's): the sink may move from it - a view's tiles and
  // neighbours are not copied again.
  virtual void sample_owned(void* message, const SampleInfo& info) { sample(message, info); }
  // Every writer of an instance, or one writer, is gone (Watch::
  // SamplesAndDepartures readers only). `key_message` holds the instance's
  // key fields when the vendor delivers them, else nullptr: then `info`
  // names the instance or the writer.
  virtual void gone(const void* key_message, const SampleInfo& info) = 0;
};

class Transport {
 public:
  virtual ~Transport() = default;
  Transport() = default;
  Transport(const Transport&) = delete;
  Transport& operator=(const Transport&) = delete;

  [[nodiscard]] virtual std::string vendor() const = 0;

  // A writer of `kind`'s topic and QoS into one partition, and a reader of
  // it from several (DDS fnmatch patterns). Throw DdsError if the vendor
  // refuses (e.g. DDS Security permissions).
  virtual EndpointId open_writer(TopicKind kind, const std::string& partition) = 0;
  virtual EndpointId open_reader(TopicKind kind, const std::vector<std::string>& partitions, Watch watch) = 0;

  // `message`: the core message of the writer's topic, within the IDL bounds
  // (checked above the seam). False if the vendor's write failed (counted).
  virtual bool write(EndpointId writer, const void* message) = 0;
  // Everything the reader holds; a sample over a bound is dropped and counted.
  virtual void take(EndpointId reader, TakeSink& sink) = 0;
  // Asserts the manual-by-topic writers (qos.hpp), at most ten times per
  // liveliness lease: called by every take of the bus, so that a hung
  // process loses its liveliness too.
  virtual void keep_alive() = 0;

  // Block until one of `readers` holds a sample not yet taken (or a
  // departure notice) or `deadline` passes; true if one does.
  virtual bool wait(std::span<const EndpointId> readers, std::chrono::steady_clock::time_point deadline) = 0;
  // From now on call `callback` in the thread that delivers a sample (or a
  // departure notice) to one of `readers`, once it is stored, instead of
  // only waking wait(); an empty callback (or other readers) replaces the
  // registration. Replacing or removing it returns only once no call of the
  // old one is under way, so the caller may then destroy what it uses. The
  // callback must not block: the thread that runs it delivers the samples.
  // False, with nothing registered, where the transport has no such thread.
  virtual bool on_data(std::span<const EndpointId> /*readers*/, std::function<void()> /*callback*/) { return false; }
  // Block until the matched readers acknowledged every sample `writers` wrote,
  // or `timeout` passes; true if all were.
  virtual bool flush(std::span<const EndpointId> writers, std::chrono::milliseconds timeout) = 0;
  // Readers matched by `writer` now.
  [[nodiscard]] virtual uint32_t matched(EndpointId writer) = 0;

  // Samples dropped and writes failed (writes_refused is counted above).
  [[nodiscard]] virtual BusStats stats() const = 0;

  // Cell discovery (CellDiscovery::reserve): name the cell's reserve peers
  // as well from now on, so that this process discovers them (a realtime
  // UAV's backup gateway, once its home is gone). The vendors fix a
  // participant's peers when they create it, so the participant is made
  // again with the wider list and every endpoint opened again in it under
  // its EndpointId; samples its readers held and had not taken are dropped,
  // and the writers' histories start empty. False, with nothing changed, if
  // there is no reserve to reach (not a cell member, or reached already).
  virtual bool reach_reserve() { return false; }
};

}  // namespace pheromesh::bus
