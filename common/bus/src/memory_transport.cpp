// The in-memory transport (memory.hpp): the domain is a list of writers and
// readers under one mutex; a write copies the core message once and hands
// the copy to every matching reader's queue.
#include "pheromesh/bus/memory.hpp"

#include <fnmatch.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <list>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "pheromesh/bus/topic.hpp"

namespace pheromesh::bus {
namespace {

// What the domain does with a message type: copy it, name its instance.
struct TypeOps {
  std::shared_ptr<const void> (*copy)(const void* message) = nullptr;
  uint64_t (*key)(const void* message) = nullptr;
};

template <typename M>
std::shared_ptr<const void> copy_as(const void* message) {
  return std::make_shared<const M>(*static_cast<const M*>(message));
}
template <typename M>
uint64_t key_as(const void* message) {
  return Topic<M>::key(*static_cast<const M*>(message));
}
template <typename... M>
std::array<TypeOps, kTopicKindCount> type_ops(MessageList<M...> /*types*/) {
  std::array<TypeOps, kTopicKindCount> table{};
  ((table[index_of(Topic<M>::kind)] = TypeOps{&copy_as<M>, &key_as<M>}), ...);
  return table;
}
const TypeOps& ops(TopicKind k) {
  static const std::array<TypeOps, kTopicKindCount> table = type_ops(Messages{});
  return table[index_of(message_kind(k))];
}

bool partitions_match(const std::string& a, const std::string& b) {
  return a == b || fnmatch(a.c_str(), b.c_str(), 0) == 0 || fnmatch(b.c_str(), a.c_str(), 0) == 0;
}

}  // namespace

class MemoryDomain {
 public:
  struct Item {
    std::shared_ptr<const void> message;
    uint64_t writer = 0;
    uint64_t key = 0;
    bool gone = false;  // every writer of the instance is gone
    uint64_t participant = 0;
  };
  struct WriterRec {
    const void* owner;
    TopicKind kind;
    std::string partition;
    QosSpec qos;
    uint64_t id;
    std::map<uint64_t, std::deque<std::shared_ptr<const void>>> history;  // per instance
    uint64_t participant = 0;  // its transport's (SampleInfo::participant)
  };
  // A transport's on_data callback. Called in the writer's thread, after
  // the domain's mutex is released; `mutex` keeps a call and its removal
  // apart (Transport::on_data returns once no call is under way).
  struct Listener {
    std::mutex mutex;
    std::function<void()> callback;
    // A sample came while another thread (or this one, further up) called
    // the callback: the caller calls it once more when it is done.
    std::atomic<bool> again{false};
  };
  struct ReaderRec {
    const void* owner;
    TopicKind kind;
    std::vector<std::string> partitions;
    QosSpec qos;
    Watch watch;
    std::deque<Item> queue;
    std::shared_ptr<Listener> listener{};  // on_data's, if it names this reader
  };

  static bool matches(const WriterRec& w, const ReaderRec& r) {
    return topic_of(w.kind) == topic_of(r.kind) &&
           std::any_of(r.partitions.begin(), r.partitions.end(),
                       [&](const std::string& p) { return partitions_match(p, w.partition); });
  }

  // Keep-last `depth` per instance, in the queue's order.
  static void deliver(ReaderRec& r, Item item) {
    const uint64_t key = item.key;
    const bool gone = item.gone;
    r.queue.push_back(std::move(item));
    if (gone || r.qos.history != QosSpec::History::KeepLast) return;
    auto held = static_cast<int32_t>(
        std::count_if(r.queue.begin(), r.queue.end(), [&](const Item& i) { return !i.gone && i.key == key; }));
    for (auto it = r.queue.begin(); held > r.qos.depth && it != r.queue.end();) {
      if (!it->gone && it->key == key) {
        it = r.queue.erase(it);
        --held;
      } else {
        ++it;
      }
    }
  }

  std::mutex mutex;
  std::condition_variable changed;
  uint64_t next_writer = 1;
  uint64_t next_participant = 1;
  std::list<WriterRec> writers;  // stable addresses
  std::list<ReaderRec> readers;
};

namespace {

class MemoryTransport final : public Transport {
 public:
  MemoryTransport(std::shared_ptr<MemoryDomain> domain, const BusOptions& o) : domain_(std::move(domain)), opt_(o) {
    std::lock_guard<std::mutex> lock(domain_->mutex);
    participant_ = domain_->next_participant++;
  }

  ~MemoryTransport() override {
    if (listener_) {
      std::lock_guard<std::mutex> lock(listener_->mutex);  // no call under way, and none after
      listener_->callback = nullptr;
    }
    auto& d = *domain_;
    {
      std::lock_guard<std::mutex> lock(d.mutex);
      // This participant's writers leave: readers that watch departures hear
      // of every instance they wrote.
      for (auto& w : d.writers) {
        if (w.owner != this) continue;
        for (auto& r : d.readers) {
          if (r.owner == this || !watches_departures(r.watch) || !MemoryDomain::matches(w, r)) continue;
          for (const auto& [key, samples] : w.history) {
            if (!samples.empty()) MemoryDomain::deliver(r, {samples.back(), w.id, key, true, w.participant});
          }
        }
      }
      d.writers.remove_if([&](const auto& w) { return w.owner == this; });
      d.readers.remove_if([&](const auto& r) { return r.owner == this; });
    }
    d.changed.notify_all();
  }

  [[nodiscard]] std::string vendor() const override { return "memory"; }

  EndpointId open_writer(TopicKind kind, const std::string& partition) override {
    std::lock_guard<std::mutex> lock(domain_->mutex);
    const QosSpec q = endpoint_qos(kind, Endpoint::Writer, opt_.liveliness_lease, opt_.replication, opt_.pacing);
    domain_->writers.push_back({this, kind, partition, q, domain_->next_writer++, {}, participant_});
    return add({&domain_->writers.back(), nullptr});
  }

  EndpointId open_reader(TopicKind kind, const std::vector<std::string>& partitions, Watch watch) override {
    {
      std::lock_guard<std::mutex> lock(domain_->mutex);
      const QosSpec q = reader_qos_for(
          endpoint_qos(kind, Endpoint::Reader, opt_.liveliness_lease, opt_.replication, opt_.pacing), watch);
      domain_->readers.push_back({this, kind, partitions, q, watch, {}});
      auto& r = domain_->readers.back();
      // Transient-local: the history of the writers it matches.
      if (q.durability == QosSpec::Durability::TransientLocal) {
        for (const auto& w : domain_->writers) {
          if (w.qos.durability != QosSpec::Durability::TransientLocal || !MemoryDomain::matches(w, r)) continue;
          for (const auto& [key, samples] : w.history) {
            for (const auto& s : samples) MemoryDomain::deliver(r, {s, w.id, key, false, w.participant});
          }
        }
      }
      endpoints_.push_back({nullptr, &r});
    }
    domain_->changed.notify_all();
    return static_cast<EndpointId>(endpoints_.size() - 1);
  }

  bool write(EndpointId writer, const void* message) override {
    std::vector<std::shared_ptr<MemoryDomain::Listener>> to_call;
    {
      std::lock_guard<std::mutex> lock(domain_->mutex);
      auto& w = *endpoint(writer).writer;
      const TypeOps& t = ops(w.kind);
      std::shared_ptr<const void> copy = t.copy(message);
      const uint64_t key = t.key(message);
      auto& kept = w.history[key];
      kept.push_back(copy);
      while (w.qos.history == QosSpec::History::KeepLast && std::ssize(kept) > w.qos.depth) kept.pop_front();
      for (auto& r : domain_->readers) {
        if (!MemoryDomain::matches(w, r)) continue;
        MemoryDomain::deliver(r, {copy, w.id, key, false, w.participant});
        if (r.listener && std::find(to_call.begin(), to_call.end(), r.listener) == to_call.end()) {
          to_call.push_back(r.listener);
        }
      }
    }
    domain_->changed.notify_all();
    // One call of a listener at a time, as a vendor's receive thread makes
    // them, and no writer waits for another thread's call: two processes'
    // callbacks that write to each other would otherwise wait for each
    // other. A sample that comes while a call is under way (in another
    // thread, or in this one further up: a callback that writes to a reader
    // of its own transport) is left to that call's thread, which calls once
    // more when it is done.
    thread_local std::vector<const MemoryDomain::Listener*> calling;
    for (const auto& l : to_call) {
      l->again = true;
      if (std::find(calling.begin(), calling.end(), l.get()) != calling.end()) continue;
      while (l->again.load()) {
        std::unique_lock<std::mutex> lock(l->mutex, std::try_to_lock);
        if (!lock) break;  // its caller sees `again` once it is done
        l->again = false;
        if (!l->callback) break;
        calling.push_back(l.get());
        l->callback();
        calling.pop_back();
      }
    }
    return true;
  }

  bool on_data(std::span<const EndpointId> readers, std::function<void()> callback) override {
    // The writers' threads stand in for a vendor's receive thread.
    if (listener_) {
      std::lock_guard<std::mutex> lock(listener_->mutex);  // waits for a call under way
      listener_->callback = nullptr;
    }
    {
      std::lock_guard<std::mutex> lock(domain_->mutex);
      for (const auto& ref : endpoints_) {
        if (ref.reader != nullptr) ref.reader->listener.reset();
      }
      listener_.reset();
      if (callback) {
        listener_ = std::make_shared<MemoryDomain::Listener>();
        listener_->callback = std::move(callback);
        for (const EndpointId id : readers) endpoint(id).reader->listener = listener_;
      }
    }
    return true;
  }

  void take(EndpointId reader, TakeSink& sink) override {
    std::deque<MemoryDomain::Item> items;
    {
      std::lock_guard<std::mutex> lock(domain_->mutex);
      items.swap(endpoint(reader).reader->queue);
    }
    for (const auto& i : items) {
      const SampleInfo info{i.writer, i.key + 1, i.participant};  // instance 0 means unknown
      if (i.gone) {
        sink.gone(i.message.get(), info);
      } else {
        sink.sample(i.message.get(), info);
      }
    }
  }

  void keep_alive() override {}

  bool wait(std::span<const EndpointId> readers, std::chrono::steady_clock::time_point deadline) override {
    std::unique_lock<std::mutex> lock(domain_->mutex);
    return domain_->changed.wait_until(lock, deadline, [&] {
      return std::any_of(readers.begin(), readers.end(),
                         [&](EndpointId id) { return !endpoint(id).reader->queue.empty(); });
    });
  }

  bool flush(std::span<const EndpointId> /*writers*/, std::chrono::milliseconds /*timeout*/) override { return true; }

  [[nodiscard]] uint32_t matched(EndpointId writer) override {
    std::lock_guard<std::mutex> lock(domain_->mutex);
    const auto& w = *endpoint(writer).writer;
    return static_cast<uint32_t>(std::count_if(domain_->readers.begin(), domain_->readers.end(),
                                               [&](const auto& r) { return MemoryDomain::matches(w, r); }));
  }

  [[nodiscard]] BusStats stats() const override { return {}; }

 private:
  struct Ref {
    MemoryDomain::WriterRec* writer;
    MemoryDomain::ReaderRec* reader;
  };
  EndpointId add(Ref r) {
    endpoints_.push_back(r);
    return static_cast<EndpointId>(endpoints_.size() - 1);
  }
  [[nodiscard]] const Ref& endpoint(EndpointId id) const { return endpoints_.at(static_cast<std::size_t>(id)); }

  std::shared_ptr<MemoryDomain> domain_;
  BusOptions opt_;
  uint64_t participant_ = 0;  // this transport's participant id in the domain
  std::vector<Ref> endpoints_;
  std::shared_ptr<MemoryDomain::Listener> listener_;  // on_data's
};

}  // namespace

std::shared_ptr<MemoryDomain> make_memory_domain() { return std::make_shared<MemoryDomain>(); }

std::unique_ptr<Transport> make_memory_transport(std::shared_ptr<MemoryDomain> domain, const BusOptions& options) {
  return std::make_unique<MemoryTransport>(std::move(domain), options);
}

std::unique_ptr<Bus> make_memory_bus(std::shared_ptr<MemoryDomain> domain, const BusOptions& options) {
  return std::make_unique<Bus>(make_memory_transport(std::move(domain), options));
}

}  // namespace pheromesh::bus
