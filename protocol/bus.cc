#include "protocol/bus.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cstring>
#include <thread>

#include "dynapath/fragment_t.hpp"
#include "protocol/channels.h"
#include "protocol/limits.h"
#include "protocol/liveness.h"

namespace dynapath::protocol {
namespace {

// Fragments are paced per this many bytes sent (see fragment_pause_us).
constexpr size_t kPaceBytes = 60000;
// How often the repair thread looks for partial messages to NACK.
constexpr auto kRepairTick = std::chrono::milliseconds(5);

}  // namespace

Bus::Bus(lcm::LCM& lcm, std::string run_id, BusOptions options)
    : lcm_(lcm),
      run_id_(std::move(run_id)),
      options_(options),
      fragments_(BusFragmentLimits(options.max_grid_cells)),
      sent_(options.sent_store_bytes, 256, 30000),
      // Message ids: distinct per process and bus, so a receiver never mixes
      // the fragments of two senders.
      next_message_id_(static_cast<int64_t>(
          (static_cast<uint64_t>(getpid()) << 40) ^
          (static_cast<uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count()) &
           0xffffffffffULL) ^
          (reinterpret_cast<uintptr_t>(this) & 0xfffff0))),
      fault_rng_(options.fault_seed),
      sealer_(options.key),
      verifier_(options.key) {
  if (options_.fragment_above > 0 && options_.repair) {
    AddRoute(Channel(channel::kFragmentNack), static_cast<int64_t>(fragment_nack_t::getHash()),
             [this](const uint8_t* data, int size, const std::string& where) {
               fragment_nack_t nack;
               if (!DecodeExactly(data, size, nack))
                 return Drop(where, "undecodable fragment_nack_t");
               if (nack.run_id != run_id_) return Drop(where, "message of another run");
               if (Status valid = Validate(nack); !valid) {
                 return Drop(where, "fragment_nack_t: " + valid.error().message);
               }
               OnNack(nack);
             });
    repair_thread_ = std::thread([this] { RepairLoop(); });
  }
}

Bus::~Bus() {
  if (repair_thread_.joinable()) {
    {
      std::lock_guard lock(repair_wait_mutex_);
      repair_stop_ = true;
    }
    repair_wake_.notify_all();
    repair_thread_.join();
  }
  if (counters_dropped_ > 0) {
    const BusCounters c = counters();
    spdlog::warn(
        "bus: {} messages dropped ({} unauthenticated, {} replayed, {} undecodable, invalid, "
        "foreign or over a cap), {} taken",
        c.dropped, c.unauthenticated, c.replayed, c.dropped - c.unauthenticated - c.replayed,
        c.received);
  }
  for (lcm::Subscription* subscription : subscriptions_) lcm_.unsubscribe(subscription);
}

std::string Bus::Channel(std::string_view name) const { return ChannelName(run_id_, name); }

double Bus::RepairRoundTripMs() const {
  std::lock_guard lock(const_cast<std::mutex&>(fragments_mutex_));
  return repair_rtt_measured_ ? repair_rtt_ms_ : -1.0;
}

BusCounters Bus::counters() const {
  BusCounters c;
  c.published = counters_published_.load();
  c.received = counters_received_.load();
  c.dropped = counters_dropped_.load();
  c.fragments_received = counters_fragments_.load();
  c.injected_drops = counters_injected_drops_.load();
  c.injected_duplicates = counters_injected_duplicates_.load();
  c.unauthenticated = counters_unauthenticated_.load();
  c.replayed = counters_replayed_.load();
  c.fragments_sent = counters_fragments_sent_.load();
  c.ids_reused = counters_ids_reused_.load();
  c.nacks_sent = counters_nacks_sent_.load();
  c.nacks_received = counters_nacks_received_.load();
  c.pieces_repaired = counters_pieces_repaired_.load();
  c.parity_sent = counters_parity_sent_.load();
  {
    std::lock_guard lock(const_cast<std::mutex&>(fragments_mutex_));
    c.partials_evicted = fragments_.evicted() + fragments_.expired();
    c.pieces_rebuilt = fragments_.rebuilt();
    if (repair_rtt_measured_) c.repair_round_trip_ms = static_cast<int64_t>(repair_rtt_ms_);
  }
  return c;
}

std::string Bus::TrafficSummary() const {
  const BusCounters c = counters();
  return "published " + std::to_string(c.published) + ", received " + std::to_string(c.received) +
         ", dropped " + std::to_string(c.dropped) + " (" + std::to_string(c.unauthenticated) +
         " unauthenticated, " + std::to_string(c.replayed) + " replayed, " +
         std::to_string(c.dropped - c.unauthenticated - c.replayed) + " invalid)" +
         (c.fragments_sent + c.fragments_received + c.nacks_sent > 0
              ? "; fragments " + std::to_string(c.fragments_sent) + " sent, " +
                    std::to_string(c.fragments_received) + " received, " +
                    std::to_string(c.ids_reused) + " resends reusing their id, " +
                    std::to_string(c.nacks_sent) + " NACKs sent, " +
                    std::to_string(c.nacks_received) + " answered with " +
                    std::to_string(c.pieces_repaired) + " pieces, " +
                    (c.parity_sent + c.pieces_rebuilt > 0
                         ? std::to_string(c.parity_sent) + " parity pieces sent, " +
                               std::to_string(c.pieces_rebuilt) + " pieces rebuilt from parity, "
                         : std::string()) +
                    std::to_string(c.partials_evicted) + " partial messages dropped" +
                    (c.repair_round_trip_ms >= 0
                         ? ", repair round trip " + std::to_string(c.repair_round_trip_ms) + " ms"
                         : std::string())
              : std::string());
}

void Bus::PublishRaw(const std::string& channel, const void* data, size_t size) {
  int copies = 1;
  if (options_.drop_probability > 0.0 || options_.duplicate_probability > 0.0) {
    std::lock_guard lock(fault_mutex_);
    if (fault_rng_.Uniform() < options_.drop_probability) {
      copies = 0;
      ++counters_injected_drops_;
    } else if (fault_rng_.Uniform() < options_.duplicate_probability) {
      copies = 2;
      ++counters_injected_duplicates_;
    }
  }
  std::vector<uint8_t> sealed;
  for (int i = 0; i < copies; ++i) {
    // Each copy gets its own counter: an injected duplicate stands for a
    // sender's resend (which handlers must tolerate), not for a replay.
    sealer_.Seal(channel, static_cast<const uint8_t*>(data), size, sealed);
    lcm_.publish(channel, sealed.data(), static_cast<unsigned>(sealed.size()));
    ++counters_published_;
  }
}

void Bus::PublishBytes(const std::string& channel, const std::vector<uint8_t>& bytes,
                       int64_t fingerprint) {
  if (options_.fragment_above <= 0 || static_cast<int>(bytes.size()) <= options_.fragment_above) {
    PublishRaw(channel, bytes.data(), bytes.size());
    return;
  }
  const int piece = std::max(1024, options_.fragment_size);
  const uint64_t hash = SentStore::Hash(bytes);
  const int64_t now = SteadyMs();
  std::shared_ptr<const SentMessage> message;
  {
    std::lock_guard lock(sent_mutex_);
    message = sent_.Find(channel, bytes, hash, piece, now);
    if (message) {
      // A resend: same id and pieces, so receivers combine it with what
      // they hold of the earlier attempts.
      ++counters_ids_reused_;
    } else {
      auto fresh = std::make_shared<SentMessage>();
      fresh->channel = channel;
      fresh->id = next_message_id_.fetch_add(1);
      fresh->fingerprint = fingerprint;
      fresh->hash = hash;
      fresh->piece = piece;
      fresh->bytes = bytes;
      fresh->sent_ms = now;
      message = fresh;
      sent_.Add(message, now);
    }
  }
  SendPieces(*message, nullptr, false);
}

void Bus::SendPieces(const SentMessage& message, const std::vector<uint8_t>* only, bool repair) {
  fragment_t fragment{};
  fragment.run_id = run_id_;
  fragment.message_id = message.id;
  fragment.fingerprint = message.fingerprint;
  fragment.total_size = static_cast<int32_t>(message.bytes.size());
  fragment.count = message.count();
  // Parity pieces go with every whole sending (not with NACK answers) of a
  // message of two pieces or more.
  const bool with_parity = only == nullptr && options_.parity_group >= 2 && fragment.count >= 2 &&
                           (!options_.parity_after_loss ||
                            SteadyMs() - last_loss_ms_.load() < options_.parity_hold_ms);
  fragment.group_size = with_parity ? options_.parity_group : 0;
  const int32_t groups = with_parity ? ParityGroups(fragment.count, fragment.group_size) : 0;
  std::vector<std::vector<uint8_t>> parities(static_cast<size_t>(groups),
                                             std::vector<uint8_t>(message.piece, 0));
  std::vector<uint8_t> encoded;
  size_t paced = 0;
  const auto send = [&] {
    encoded.resize(static_cast<size_t>(fragment.getEncodedSize()));
    fragment.encode(encoded.data(), 0, static_cast<int>(encoded.size()));
    if (paced >= kPaceBytes && options_.fragment_pause_us > 0) {
      std::this_thread::sleep_for(std::chrono::microseconds(options_.fragment_pause_us));
      paced = 0;
    }
    paced += encoded.size();
    ++counters_fragments_sent_;
    if (repair) ++counters_pieces_repaired_;
    if (options_.drop_fragment && options_.drop_fragment(fragment, repair)) {
      ++counters_injected_drops_;
      return;
    }
    PublishRaw(message.channel, encoded.data(), encoded.size());
  };
  for (int32_t i = 0; i < fragment.count; ++i) {
    if (only != nullptr && !NackBit(*only, i)) continue;
    const size_t begin = static_cast<size_t>(i) * static_cast<size_t>(message.piece);
    const size_t end = std::min(message.bytes.size(), begin + static_cast<size_t>(message.piece));
    fragment.index = i;
    fragment.offset = static_cast<int32_t>(begin);
    fragment.size = static_cast<int32_t>(end - begin);
    fragment.data.assign(message.bytes.begin() + static_cast<ptrdiff_t>(begin),
                         message.bytes.begin() + static_cast<ptrdiff_t>(end));
    if (with_parity) {
      std::vector<uint8_t>& parity = parities[static_cast<size_t>(i % groups)];
      for (size_t j = 0; j < fragment.data.size(); ++j) parity[j] ^= fragment.data[j];
    }
    send();
  }
  fragment.parity = true;
  fragment.offset = 0;
  for (int32_t g = 0; g < groups; ++g) {
    fragment.index = g;
    fragment.data = std::move(parities[static_cast<size_t>(g)]);
    fragment.size = static_cast<int32_t>(fragment.data.size());
    ++counters_parity_sent_;
    send();
  }
}

void Bus::OnNack(const fragment_nack_t& nack) {
  std::shared_ptr<const SentMessage> message;
  {
    std::lock_guard lock(sent_mutex_);
    message = sent_.Get(nack.channel, nack.message_id, SteadyMs());
  }
  // Another sender's message (NACKs reach every process), or one too old.
  if (!message) return;
  if (message->count() != nack.count) return Drop(nack.channel, "NACK of another piece count");
  ++counters_nacks_received_;
  last_loss_ms_ = SteadyMs();
  SendPieces(*message, &nack.missing, true);
}

void Bus::RepairLoop() {
  while (true) {
    {
      std::unique_lock lock(repair_wait_mutex_);
      if (repair_wake_.wait_for(lock, kRepairTick, [this] { return repair_stop_.load(); })) return;
    }
    std::vector<Nack> due;
    {
      std::lock_guard lock(fragments_mutex_);
      if (fragments_.pending() == 0) continue;
      // Quiet long enough that reordering is not taken for loss; retry
      // after two round trips of a repair.
      const auto min_quiet = static_cast<double>(options_.nack_quiet_ms);
      const auto min_retry = static_cast<double>(options_.nack_retry_ms);
      const auto quiet = static_cast<int64_t>(
          repair_rtt_measured_
              ? std::clamp(1.5 * repair_rtt_ms_ + 1, min_quiet, std::max(min_quiet, 200.0))
              : std::max(min_quiet, 15.0));
      const auto retry = static_cast<int64_t>(
          std::clamp(2 * repair_rtt_ms_ + 10, min_retry, std::max(min_retry, 1000.0)));
      due = fragments_.DueNacks(SteadyMs(), quiet, retry, options_.max_nacks);
    }
    for (Nack& nack : due) {
      fragment_nack_t message{};
      message.run_id = run_id_;
      message.channel = std::move(nack.channel);
      message.message_id = nack.message_id;
      message.count = nack.count;
      message.bitmap_size = static_cast<int32_t>(nack.missing.size());
      message.missing = std::move(nack.missing);
      ++counters_nacks_sent_;
      last_loss_ms_ = SteadyMs();
      Publish(channel::kFragmentNack, message);
    }
  }
}

void Bus::AddRoute(const std::string& channel, int64_t fingerprint, Deliver deliver) {
  // The dispatch thread reads routes_ without a lock: a route added while it
  // runs can reallocate the list it is walking.
  assert(!dispatching_ && "Bus::Subscribe after dispatching started");
  auto [it, inserted] = routes_.try_emplace(channel);
  it->second.push_back(Route{fingerprint, std::move(deliver)});
  if (inserted) {
    // LCM channel arguments are regexes; run ids and names hold no
    // metacharacters (CheckRunId), so the name matches only itself.
    lcm::Subscription* subscription = lcm_.subscribe(channel, &Bus::OnRaw, this);
    // The default queue of 30 drops bursts (a batch's shards, fragments).
    subscription->setQueueCapacity(100000);
    subscriptions_.push_back(subscription);
  }
}

void Bus::OnRaw(const lcm::ReceiveBuffer* buffer, const std::string& channel) {
  dispatching_.store(true, std::memory_order_relaxed);
  const auto* data = static_cast<const uint8_t*>(buffer->data);
  int size = 0;
  // Before anything reads the bytes: only messages of this run's key, once.
  switch (verifier_.Check(channel, data, static_cast<int>(buffer->data_size), &size)) {
    case Verifier::Verdict::kOk:
      break;
    case Verifier::Verdict::kUnauthenticated:
      ++counters_unauthenticated_;
      return Drop(channel, "no valid authentication tag (forged, corrupt, or another secret)");
    case Verifier::Verdict::kReplayed:
      ++counters_replayed_;
      return Drop(channel, "replayed message");
  }
  if (PeekFingerprint(data, size) == static_cast<int64_t>(fragment_t::getHash())) {
    OnFragment(channel, data, size);
  } else {
    Dispatch(channel, data, size);
  }
}

void Bus::Dispatch(const std::string& channel, const uint8_t* data, int size) {
  auto it = routes_.find(channel);
  if (it == routes_.end()) return;
  const int64_t fingerprint = PeekFingerprint(data, size);
  bool delivered = false;
  for (const Route& route : it->second) {  // every subscriber of this type
    if (route.fingerprint == fingerprint) {
      route.deliver(data, size, channel);
      delivered = true;
    }
  }
  if (!delivered) Drop(channel, "message of an unexpected type");
}

void Bus::OnFragment(const std::string& channel, const uint8_t* data, int size) {
  fragment_t fragment{};
  if (!DecodeExactly(data, size, fragment)) return Drop(channel, "undecodable fragment_t");
  if (fragment.run_id != run_id_) return Drop(channel, "fragment of another run");
  if (Status valid = Validate(fragment); !valid) {
    return Drop(channel, "fragment_t: " + valid.error().message);
  }
  ++counters_fragments_;
  FragmentAssembler::Outcome outcome;
  {
    std::lock_guard lock(fragments_mutex_);
    outcome = fragments_.Add(channel, fragment, SteadyMs());
    if (outcome.repair_round_trip >= 0) {
      const auto sample = static_cast<double>(outcome.repair_round_trip);
      repair_rtt_ms_ = repair_rtt_measured_ ? 0.875 * repair_rtt_ms_ + 0.125 * sample : sample;
      repair_rtt_measured_ = true;
    }
  }
  if (outcome.kind == FragmentAssembler::Outcome::Kind::kDropped) return Drop(channel, outcome.why);
  if (outcome.kind == FragmentAssembler::Outcome::Kind::kComplete) {
    Dispatch(channel, outcome.bytes.data(), static_cast<int>(outcome.bytes.size()));
  }
}

void Bus::Drop(const std::string& channel, const std::string& why) {
  const int64_t dropped = ++counters_dropped_;
  const int64_t now = SteadyMs();
  // At most one warning a second: a flood of garbage must not flood the log.
  if (now - last_warning_ms_ >= 1000) {
    spdlog::warn("dropped a message on {}: {} ({} dropped so far{})", channel, why, dropped,
                 warnings_suppressed_ > 0
                     ? ", " + std::to_string(warnings_suppressed_) + " warnings suppressed"
                     : std::string());
    last_warning_ms_ = now;
    warnings_suppressed_ = 0;
  } else {
    ++warnings_suppressed_;
  }
}

}  // namespace dynapath::protocol
