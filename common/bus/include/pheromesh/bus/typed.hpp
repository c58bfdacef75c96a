// Typed endpoints over a Bus's transport: Writer<M> writes core message M
// into one or more partitions (one DDS writer each), Reader<M> takes M from
// the partitions it was opened on. Both follow Topic<M> (topic.hpp): its
// kind (topic, type, QoS), its routing rule and its IDL bounds, checked here
// once for every transport.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/topic.hpp"
#include "pheromesh/bus/transport.hpp"

namespace pheromesh::bus {

template <typename M>
class Writer {
 public:
  // `kind`: the QoS row to use (a kind whose topic is M's).
  explicit Writer(Bus& bus, TopicKind kind = Topic<M>::kind) : bus_(&bus), kind_(kind) {}

  // Opens the DDS writer of `partition` now (before flying: no endpoint is
  // created while a swarm flies, docs/architecture.md "Views").
  EndpointId offer(const std::string& partition) {
    if (auto it = ids_.find(partition); it != ids_.end()) return it->second;
    if (Bus::in_data_callback()) {
      throw BusMisuse("a " + std::string(topic_name(kind_)) + " writer into partition '" + partition +
                      "' would be created in a receive thread's callback (Bus::on_data); offer it before flying");
    }
    const EndpointId id = bus_->transport().open_writer(kind_, partition);
    ids_.emplace(partition, id);
    bus_->opened(kind_, Endpoint::Writer, id);
    return id;
  }

  // Into the partition Topic<M> routes it to.
  bool write(const M& m) requires RoutedByMessage<M> { return write(m, Topic<M>::partition(m)); }
  // Into `partition`; false if refused (over an IDL bound) or failed.
  bool write(const M& m, const std::string& partition) {
    if (const BoundCheck o = Topic<M>::oversize(m)) return bus_->refuse(*o);
    return bus_->transport().write(offer(partition), &m);
  }

  // Readers matched by the writer of `partition` (0 if not offered).
  [[nodiscard]] uint32_t matched(const std::string& partition) const {
    const auto it = ids_.find(partition);
    return it == ids_.end() ? 0 : bus_->transport().matched(it->second);
  }

 private:
  Bus* bus_;
  TopicKind kind_;
  std::map<std::string, EndpointId> ids_;
};

template <typename M>
class Reader {
 public:
  Reader(Bus& bus, const std::vector<std::string>& partitions, TopicKind kind = Topic<M>::kind,
         Watch watch = Watch::Samples)
      : bus_(&bus), id_(bus.transport().open_reader(kind, partitions, watch)), watch_(watch) {
    bus.opened(kind, Endpoint::Reader, id_);
  }

  // Appends what arrived since the last take.
  void take(std::vector<M>& out) {
    std::vector<uint32_t> ignored;
    take(out, ignored);
  }
  // Also appends the Topic<M>::key of every instance whose writers are gone
  // (a reader opened with Watch::SamplesAndDepartures).
  void take(std::vector<M>& out, std::vector<uint32_t>& departed) {
    bus_->transport().keep_alive();
    Sink sink(out, departed, watches_departures(watch_) ? &departures_ : nullptr);
    const std::size_t before = out.size();
    bus_->transport().take(id_, sink);
    std::size_t bytes = 0;
    for (std::size_t i = before; i < out.size(); ++i) bytes += core::payload_bytes(out[i]);
    bus_->taken(out.size() - before, bytes);
  }

  bool wait(std::chrono::steady_clock::time_point deadline) {
    const EndpointId ids[] = {id_};
    return bus_->transport().wait(ids, deadline);
  }

  [[nodiscard]] EndpointId id() const { return id_; }

 private:
  // Which key each writer and instance wrote, so that a departure the vendor
  // names only by writer or instance (Fast DDS) is reported by key too.
  struct Seen {
    std::map<uint64_t, uint32_t> by_writer, by_instance;
  };

  class Sink final : public TakeSink {
   public:
    Sink(std::vector<M>& out, std::vector<uint32_t>& departed, Seen* seen)
        : out_(out), departed_(departed), seen_(seen) {}
    void sample(const void* message, const SampleInfo& info) override {
      keep(M(*static_cast<const M*>(message)), info);
    }
    void sample_owned(void* message, const SampleInfo& info) override {
      keep(std::move(*static_cast<M*>(message)), info);
    }
    void gone(const void* key_message, const SampleInfo& info) override {
      if (seen_ == nullptr) return;
      if (key_message != nullptr) {
        departed_.push_back(static_cast<uint32_t>(Topic<M>::key(*static_cast<const M*>(key_message))));
      } else if (auto i = seen_->by_instance.find(info.instance); info.instance != 0 && i != seen_->by_instance.end()) {
        departed_.push_back(i->second);
      } else if (auto w = seen_->by_writer.find(info.writer); info.writer != 0 && w != seen_->by_writer.end()) {
        departed_.push_back(w->second);
      }
    }

   private:
    void keep(M&& m, const SampleInfo& info) {
      if constexpr (requires(M & x, uint64_t w) { x.writer = w; }) m.writer = info.writer;  // ClockMsg
      if constexpr (requires(M & x, uint64_t p) { x.participant = p; }) m.participant = info.participant;
      if (seen_ != nullptr) {
        const auto key = static_cast<uint32_t>(Topic<M>::key(m));
        seen_->by_writer[info.writer] = key;
        if (info.instance != 0) seen_->by_instance[info.instance] = key;
      }
      out_.push_back(std::move(m));
    }
    std::vector<M>& out_;
    std::vector<uint32_t>& departed_;
    Seen* seen_;  // null: departures not watched
  };

  Bus* bus_;
  EndpointId id_;
  Watch watch_;
  Seen departures_;
};

}  // namespace pheromesh::bus
