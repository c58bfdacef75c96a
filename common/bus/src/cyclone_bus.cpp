// Cyclone DDS (C API) transport of the pheromesh bus (transport.hpp). With
// cyclone_samples.hpp, the only code that includes Cyclone headers.
#include "cyclone_bus.hpp"

#include <dds/dds.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cyclone_samples.hpp"
#include "dds_profiles.hpp"
#include "pheromesh/bus/qos.hpp"
#include "pheromesh/bus/security.hpp"
#include "pheromesh/bus/topic.hpp"
#include "pheromesh/bus/transport.hpp"
#include "vendor_pace.hpp"

namespace pheromesh::bus {
namespace {

// The one place where Cyclone return codes become errors (DdsError): it
// records the call, the file and the line.
dds_entity_t checked(dds_entity_t rc, const char* what, const char* file, int line) {
  if (rc < 0) {
    throw DdsError(std::string(what) + " failed: " + dds_strretcode(rc) + " (" + file + ":" + std::to_string(line) +
                   ")");
  }
  return rc;
}
#define PHM_DDS(call) checked((call), #call, __FILE__, __LINE__)

struct QosDeleter {
  void operator()(dds_qos_t* q) const { dds_delete_qos(q); }
};
using QosPtr = std::unique_ptr<dds_qos_t, QosDeleter>;

// The Cyclone adapter of the neutral QoS description (qos.hpp).
QosPtr to_cyclone(const QosSpec& spec) {
  QosPtr q(dds_create_qos());
  dds_qset_reliability(
      q.get(),
      spec.reliability == QosSpec::Reliability::Reliable ? DDS_RELIABILITY_RELIABLE : DDS_RELIABILITY_BEST_EFFORT,
      DDS_MSECS(spec.max_blocking.count()));
  dds_qset_liveliness(
      q.get(),
      spec.liveliness == QosSpec::Liveliness::ManualByTopic ? DDS_LIVELINESS_MANUAL_BY_TOPIC : DDS_LIVELINESS_AUTOMATIC,
      spec.liveliness_lease == QosSpec::kInfiniteLease ? DDS_INFINITY : DDS_MSECS(spec.liveliness_lease.count()));
  dds_qset_durability(q.get(), spec.durability == QosSpec::Durability::TransientLocal ? DDS_DURABILITY_TRANSIENT_LOCAL
                                                                                      : DDS_DURABILITY_VOLATILE);
  if (spec.history == QosSpec::History::KeepAll) {
    dds_qset_history(q.get(), DDS_HISTORY_KEEP_ALL, 0);
  } else {
    dds_qset_history(q.get(), DDS_HISTORY_KEEP_LAST, spec.depth);
  }
  if (spec.ownership == QosSpec::Ownership::Exclusive) {
    dds_qset_ownership(q.get(), DDS_OWNERSHIP_EXCLUSIVE);
    dds_qset_ownership_strength(q.get(), spec.ownership_strength);
  }
  return q;
}

class CycloneTransport;

// What the transport does with one message type M: its Cyclone topic
// descriptor, and writing and taking through cyclone::Convert<M>.
struct Codec {
  const dds_topic_descriptor_t* descriptor = nullptr;
  bool (*write)(CycloneTransport& t, dds_entity_t writer, const void* message) = nullptr;
  void (*take)(CycloneTransport& t, dds_entity_t reader, Watch watch, TakeSink& sink) = nullptr;
};

class CycloneTransport final : public Transport {
 public:
  explicit CycloneTransport(const BusOptions& o) : opt_(o), pace_(o.liveliness_lease) { create_participant(); }

  ~CycloneTransport() override {
    // Deleting a reader waits for a call of its listener under way too.
    dds_delete(participant_);
    if (domain_ > 0) dds_delete(domain_);
  }

  [[nodiscard]] std::string vendor() const override { return "cyclone"; }

  EndpointId open_writer(TopicKind kind, const std::string& partition) override {
    Entry e{kind, Endpoint::Writer, 0, 0, Watch::Samples, {partition}};
    create(e);
    return add(e);
  }

  EndpointId open_reader(TopicKind kind, const std::vector<std::string>& partitions, Watch watch) override {
    Entry e{kind, Endpoint::Reader, 0, 0, watch, partitions};
    create(e);
    return add(e);
  }

  bool reach_reserve() override {
    if (!opt_.cell || opt_.cell->reserve.empty()) return false;
    if (domain_ <= 0) {
      // Another bus of this process configured the domain (tests): its
      // peers cannot change under that bus.
      spdlog::default_logger()->warn("cannot name the cell's reserve peers: domain {} is shared in this process",
                                     opt_.domain);
      return false;
    }
    auto& cell = *opt_.cell;
    cell.peers.insert(cell.peers.end(), cell.reserve.begin(), cell.reserve.end());
    cell.reserve.clear();
    // The participant takes its wait sets, topics and endpoints with it; the
    // domain its configuration (Cyclone's peers are the domain's).
    dds_delete(participant_);
    dds_delete(domain_);
    waitsets_.clear();
    topics_.clear();
    participants_.clear();
    create_participant();
    for (Entry& e : entries_) create(e);
    listen();
    return true;
  }

  bool write(EndpointId writer, const void* message) override {
    const Entry& e = entry(writer);
    const bool written = codec(e.kind).write(*this, e.entity, message);
    if (written) pace_.wrote(static_cast<std::size_t>(writer));  // a refused sample asserts nothing
    return written;
  }

  void take(EndpointId reader, TakeSink& sink) override {
    const Entry& e = entry(reader);
    codec(e.kind).take(*this, e.entity, e.watch, sink);
  }

  // Manual-by-topic writers (qos.cpp) that wrote nothing lately are asserted
  // while the process keeps taking from its bus, at most ten times per lease
  // (vendor_pace.hpp).
  void keep_alive() override {
    pace_.round(std::chrono::steady_clock::now(), manual_writers_,
                [&](std::size_t i) { dds_assert_liveliness(entries_[i].entity); });
  }

  bool wait(std::span<const EndpointId> readers, std::chrono::steady_clock::time_point deadline) override {
    const auto left = std::chrono::duration_cast<std::chrono::nanoseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    // One wait set per set of readers, holding their read conditions.
    std::vector<EndpointId> key(readers.begin(), readers.end());
    std::sort(key.begin(), key.end());
    auto it = waitsets_.find(key);
    if (it == waitsets_.end()) {
      const dds_entity_t ws = PHM_DDS(dds_create_waitset(participant_));
      for (const EndpointId id : key) {
        const dds_entity_t cond = entry(id).condition;
        PHM_DDS(dds_waitset_attach(ws, cond, cond));
      }
      it = waitsets_.emplace(std::move(key), ws).first;
    }
    return dds_waitset_wait(it->second, nullptr, 0, left.count()) > 0;
  }

  bool on_data(std::span<const EndpointId> readers, std::function<void()> callback) override {
    // dds_set_listener returns once no call of the reader's listener is
    // under way: after this loop the old callback runs no more.
    for (const EndpointId id : listened_) PHM_DDS(dds_set_listener(entry(id).entity, nullptr));
    listened_.clear();
    on_data_ = std::move(callback);
    if (!on_data_) return true;
    listened_.assign(readers.begin(), readers.end());
    listen();
    return true;
  }

  bool flush(std::span<const EndpointId> writers, std::chrono::milliseconds timeout) override {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    bool all = true;
    for (const EndpointId id : writers) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (dds_wait_for_acks(entry(id).entity, DDS_MSECS(std::max<int64_t>(0, left.count()))) != DDS_RETCODE_OK)
        all = false;
    }
    return all;
  }

  [[nodiscard]] uint32_t matched(EndpointId writer) override {
    dds_publication_matched_status_t st{};
    if (dds_get_publication_matched_status(entry(writer).entity, &st) != DDS_RETCODE_OK) return 0;
    return st.current_count;
  }

  [[nodiscard]] BusStats stats() const override { return stats_; }

  // For the codecs: a write (a failure counted and logged), a dropped sample.
  bool write_sample(dds_entity_t writer, const void* sample) {
    const dds_return_t rc = dds_write(writer, sample);
    if (rc != DDS_RETCODE_OK) {
      ++stats_.writes_failed;
      spdlog::default_logger()->warn("dds_write failed: {}", dds_strretcode(rc));
      return false;
    }
    return true;
  }
  void dropped() { ++stats_.samples_dropped; }

  // The participant of the remote writer `publication` that `reader`
  // matched (SampleInfo::participant), looked up in the built-in
  // publication data once per writer; 0 if Cyclone no longer knows it.
  uint64_t participant_of(dds_entity_t reader, dds_instance_handle_t publication) {
    if (publication == 0) return 0;
    if (auto it = participants_.find(publication); it != participants_.end()) return it->second;
    dds_builtintopic_endpoint_t* ep = dds_get_matched_publication_data(reader, publication);
    if (ep == nullptr) return 0;
    const uint64_t p = participant_id(ep->participant_key.v);
    dds_builtintopic_free_endpoint(ep);
    participants_.emplace(publication, p);
    return p;
  }

 private:
  struct Entry {
    TopicKind kind;
    Endpoint endpoint;
    dds_entity_t entity;
    dds_entity_t condition;  // readers only
    Watch watch;
    std::vector<std::string> partitions;  // a writer's one, a reader's patterns
  };

  void create_participant() {
    const std::string config = opt_.cell ? cyclone_cell_config(*opt_.cell, opt_.swarm_processes)
                                         : cyclone_config(opt_.profile, opt_.peers, opt_.swarm_processes);
    if (!config.empty()) {
      // Returns an error if the domain already exists in this process; that is
      // fine for a second bus in the same process (tests).
      const dds_entity_t d = dds_create_domain(opt_.domain, config.c_str());
      if (d < 0 && d != DDS_RETCODE_PRECONDITION_NOT_MET) PHM_DDS(d);
      domain_ = d > 0 ? d : 0;
    }
    QosPtr pq(dds_create_qos());
    if (!opt_.secure_dir.empty()) set_security(pq.get(), opt_);
    participant_ = PHM_DDS(dds_create_participant(opt_.domain, pq.get(), nullptr));
  }

  // The endpoint `e` describes, made in the current participant.
  void create(Entry& e) {
    std::vector<const char*> names;
    names.reserve(e.partitions.size());
    for (const auto& p : e.partitions) names.push_back(p.c_str());
    QosPtr pq(dds_create_qos());
    dds_qset_partition(pq.get(), static_cast<uint32_t>(names.size()), names.data());
    if (e.endpoint == Endpoint::Writer) {
      const dds_entity_t publisher = PHM_DDS(dds_create_publisher(participant_, pq.get(), nullptr));
      QosPtr wq =
          to_cyclone(endpoint_qos(e.kind, Endpoint::Writer, opt_.liveliness_lease, opt_.replication, opt_.pacing));
      e.entity = PHM_DDS(dds_create_writer(publisher, topic(e.kind), wq.get(), nullptr));
      return;
    }
    const dds_entity_t subscriber = PHM_DDS(dds_create_subscriber(participant_, pq.get(), nullptr));
    QosPtr rq = to_cyclone(reader_qos_for(
        endpoint_qos(e.kind, Endpoint::Reader, opt_.liveliness_lease, opt_.replication, opt_.pacing), e.watch));
    e.entity = PHM_DDS(dds_create_reader(subscriber, topic(e.kind), rq.get(), nullptr));
    // A read condition on its unread samples (including the no-writers
    // notifications of departures) wakes wait().
    e.condition = PHM_DDS(dds_create_readcondition(e.entity, DDS_NOT_READ_SAMPLE_STATE));
  }

  // The data-available listener of the readers on_data names: Cyclone calls
  // it in the thread that stored the sample (its receive thread, or the
  // delivery queue's).
  void listen() {
    if (!on_data_ || listened_.empty()) return;
    const std::unique_ptr<dds_listener_t, decltype(&dds_delete_listener)> l(dds_create_listener(this),
                                                                            &dds_delete_listener);
    dds_lset_data_available(
        l.get(), [](dds_entity_t /*reader*/, void* self) { static_cast<CycloneTransport*>(self)->on_data_(); });
    for (const EndpointId id : listened_) PHM_DDS(dds_set_listener(entry(id).entity, l.get()));
  }

  EndpointId add(const Entry& e) {
    entries_.push_back(e);
    if (e.endpoint == Endpoint::Writer && manual_liveliness(e.kind)) manual_writers_.push_back(entries_.size() - 1);
    return static_cast<EndpointId>(entries_.size() - 1);
  }
  [[nodiscard]] const Entry& entry(EndpointId id) const { return entries_.at(static_cast<std::size_t>(id)); }

  [[nodiscard]] bool manual_liveliness(TopicKind k) const {
    return endpoint_qos(k, Endpoint::Writer, opt_.liveliness_lease, opt_.replication, opt_.pacing).liveliness ==
           QosSpec::Liveliness::ManualByTopic;
  }

  static const Codec& codec(TopicKind k);

  // Topics are created when a process first writes or reads one: under DDS
  // Security a participant may create only the topics its permissions name
  // (Cyclone's check_create_topic), and a UAV's name few of them.
  dds_entity_t topic(TopicKind k) {
    const TopicKind t = topic_of(k);
    if (auto it = topics_.find(t); it != topics_.end()) return it->second;
    const dds_entity_t e =
        PHM_DDS(dds_create_topic(participant_, codec(t).descriptor, topic_name(t), nullptr, nullptr));
    topics_.emplace(t, e);
    return e;
  }

  // DDS Security through the participant's properties (Cyclone's builtin
  // plugins, found by library name; docs/security.md).
  static void set_security(dds_qos_t* q, const BusOptions& o) {
    auto f = find_security_files(o.secure_dir, o.identity.empty() ? o.process_name : o.identity);
    if (!f) throw DdsError(f.error().message);
    const auto file = [](const std::string& path) { return "file:" + std::filesystem::absolute(path).string(); };
    dds_qset_prop(q, "dds.sec.auth.library.path", "dds_security_auth");
    dds_qset_prop(q, "dds.sec.auth.library.init", "init_authentication");
    dds_qset_prop(q, "dds.sec.auth.library.finalize", "finalize_authentication");
    dds_qset_prop(q, "dds.sec.crypto.library.path", "dds_security_crypto");
    dds_qset_prop(q, "dds.sec.crypto.library.init", "init_crypto");
    dds_qset_prop(q, "dds.sec.crypto.library.finalize", "finalize_crypto");
    dds_qset_prop(q, "dds.sec.access.library.path", "dds_security_ac");
    dds_qset_prop(q, "dds.sec.access.library.init", "init_access_control");
    dds_qset_prop(q, "dds.sec.access.library.finalize", "finalize_access_control");
    dds_qset_prop(q, "dds.sec.auth.identity_ca", file(f->ca).c_str());
    dds_qset_prop(q, "dds.sec.auth.identity_certificate", file(f->cert).c_str());
    dds_qset_prop(q, "dds.sec.auth.private_key", file(f->key).c_str());
    dds_qset_prop(q, "dds.sec.access.permissions_ca", file(f->ca).c_str());
    dds_qset_prop(q, "dds.sec.access.governance", file(f->governance).c_str());
    dds_qset_prop(q, "dds.sec.access.permissions", file(f->permissions).c_str());
  }

  BusOptions opt_;
  KeepAlivePace pace_;
  std::vector<std::size_t> manual_writers_;  // indices into entries_
  BusStats stats_;
  dds_entity_t domain_ = 0;
  dds_entity_t participant_ = 0;
  std::map<TopicKind, dds_entity_t> topics_;
  std::vector<Entry> entries_;
  std::map<std::vector<EndpointId>, dds_entity_t> waitsets_;  // readers -> their wait set
  std::function<void()> on_data_;                             // on_data's callback
  std::vector<EndpointId> listened_;                          // the readers it listens to
  // Remote writers' participants by publication handle (participant_of):
  // one entry per writer matched in the process's life.
  std::unordered_map<dds_instance_handle_t, uint64_t> participants_;
};

// Takes everything available from `reader` with loaned buffers.
template <typename M>
void take_as(CycloneTransport& t, dds_entity_t reader, Watch watch, TakeSink& sink) {
  using Sample = typename cyclone::Convert<M>::Sample;
  constexpr int kBatch = 64;
  void* buf[kBatch];
  dds_sample_info_t info[kBatch];
  for (;;) {
    buf[0] = nullptr;
    const dds_return_t n = dds_take(reader, buf, info, kBatch, kBatch);
    if (n <= 0) return;
    for (int i = 0; i < n; ++i) {
      const auto& s = *static_cast<const Sample*>(buf[i]);
      SampleInfo who{info[i].publication_handle, info[i].instance_handle};
      if (info[i].valid_data) {
        who.participant = t.participant_of(reader, info[i].publication_handle);
        if (auto m = cyclone::Convert<M>::in(s)) {
          sink.sample_owned(&*m, who);
        } else {
          t.dropped();
        }
      } else if (watches_departures(watch) && info[i].instance_state != DDS_ALIVE_INSTANCE_STATE) {
        // No data, the key fields only: every writer of the instance is gone.
        const auto key = cyclone::Convert<M>::in(s);
        sink.gone(key ? &*key : nullptr, who);
      }
    }
    dds_return_loan(reader, buf, n);
    if (n < kBatch) return;
  }
}

template <typename M>
bool write_as(CycloneTransport& t, dds_entity_t writer, const void* message) {
  return cyclone::Convert<M>::out(*static_cast<const M*>(message),
                                  [&](const auto* sample) { return t.write_sample(writer, sample); });
}

template <typename... M>
std::array<Codec, kTopicKindCount> codecs(MessageList<M...> /*types*/) {
  std::array<Codec, kTopicKindCount> table{};
  ((table[index_of(Topic<M>::kind)] = Codec{cyclone::Convert<M>::descriptor(), &write_as<M>, &take_as<M>}), ...);
  return table;
}

const Codec& CycloneTransport::codec(TopicKind k) {
  static const std::array<Codec, kTopicKindCount> table = codecs(Messages{});
  return table[index_of(message_kind(k))];
}

}  // namespace

QosSpec cyclone_effective_qos(TopicKind kind, Endpoint endpoint, std::chrono::milliseconds lease,
                              const Replication& replication, Pacing pacing) {
  const QosPtr q = to_cyclone(endpoint_qos(kind, endpoint, lease, replication, pacing));
  QosSpec s;
  dds_reliability_kind_t rel{};
  dds_duration_t blocking = 0;
  dds_qget_reliability(q.get(), &rel, &blocking);
  s.reliability = rel == DDS_RELIABILITY_RELIABLE ? QosSpec::Reliability::Reliable : QosSpec::Reliability::BestEffort;
  s.max_blocking = std::chrono::milliseconds(blocking / DDS_NSECS_IN_MSEC);
  dds_durability_kind_t dur{};
  dds_qget_durability(q.get(), &dur);
  s.durability =
      dur == DDS_DURABILITY_TRANSIENT_LOCAL ? QosSpec::Durability::TransientLocal : QosSpec::Durability::Volatile;
  dds_history_kind_t hist{};
  int32_t depth = 0;
  dds_qget_history(q.get(), &hist, &depth);
  s.history = hist == DDS_HISTORY_KEEP_ALL ? QosSpec::History::KeepAll : QosSpec::History::KeepLast;
  s.depth = hist == DDS_HISTORY_KEEP_ALL ? 0 : depth;
  dds_liveliness_kind_t live{};
  dds_duration_t lease_ns = 0;
  dds_qget_liveliness(q.get(), &live, &lease_ns);
  s.liveliness_lease =
      lease_ns == DDS_INFINITY ? QosSpec::kInfiniteLease : std::chrono::milliseconds(lease_ns / DDS_NSECS_IN_MSEC);
  s.liveliness =
      live == DDS_LIVELINESS_MANUAL_BY_TOPIC ? QosSpec::Liveliness::ManualByTopic : QosSpec::Liveliness::Automatic;
  dds_ownership_kind_t own = DDS_OWNERSHIP_SHARED;
  if (dds_qget_ownership(q.get(), &own) && own == DDS_OWNERSHIP_EXCLUSIVE) {
    s.ownership = QosSpec::Ownership::Exclusive;
    int32_t strength = 0;
    if (endpoint == Endpoint::Writer && dds_qget_ownership_strength(q.get(), &strength))
      s.ownership_strength = strength;
  }
  return s;
}

core::Result<std::unique_ptr<Transport>> make_cyclone_transport(const BusOptions& options) {
  try {
    return std::unique_ptr<Transport>(std::make_unique<CycloneTransport>(options));
  } catch (const std::exception& e) {
    return core::Error{std::string("cyclone: ") + e.what()};
  }
}

}  // namespace pheromesh::bus
