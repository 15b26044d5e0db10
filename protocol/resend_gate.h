#pragma once
// When to answer another process's request for a round's shards again
// (shards_t.needs_round: "I still lack round r; re-send yours").
//
// Every request is answered by a multicast re-send, so one answer serves
// every process that lacks the round, and answering the same round again
// within one repair interval only adds load. Without this gate, a process
// that fell behind on a loaded machine worked through a backlog of requests
// that had long been answered, each re-send reached the others as a fresh
// request, and three agents on 30x30 sent a thousand 13 KB messages a
// second to each other for minutes while their inboxes grew past 1 GB.
// With it, what a process sends in answer is at most one message per round
// per interval, however many requests arrive.

#include <algorithm>
#include <cstdint>
#include <map>

namespace dynapath::protocol {

// How long to wait before repeating a request, or for a re-send to answer
// later requests, from the measured round trip (ms; negative: none yet):
// two round trips and 5 ms, from 5 ms to `cap_ms`; 20 ms until one is
// measured.
inline int64_t RepeatIntervalMs(double round_trip_ms, int64_t cap_ms) {
  if (round_trip_ms < 0) return 20;
  return std::clamp<int64_t>(static_cast<int64_t>(2 * round_trip_ms + 5), 5, cap_ms);
}

class ResendGate {
 public:
  // True when round `round` may be re-sent at `now_ms` (and records it);
  // false when it was re-sent less than `interval_ms` ago. Rounds below
  // `oldest_kept` are forgotten (their shards are no longer kept).
  bool Allow(int64_t round, int64_t oldest_kept, int64_t now_ms, int64_t interval_ms) {
    sent_ms_.erase(sent_ms_.begin(), sent_ms_.lower_bound(oldest_kept));
    auto [at, inserted] = sent_ms_.try_emplace(round, now_ms);
    if (inserted) return true;
    if (now_ms - at->second < interval_ms) return false;
    at->second = now_ms;
    return true;
  }
  // A new batch or epoch: nothing was re-sent of it yet.
  void Reset() { sent_ms_.clear(); }

 private:
  std::map<int64_t, int64_t> sent_ms_;  // round -> when it was last re-sent
};

}  // namespace dynapath::protocol
