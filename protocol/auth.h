#pragma once
// Message authentication of a run (docs/RELIABILITY.md, "Threat model and
// authentication").
//
// Every message the Bus publishes carries a trailer after its LCM encoding:
//
//   sender (8) | counter (8) | tag (32) | magic "DPA1" (4)
//
// `tag` is keyed BLAKE2b-256 (libsodium crypto_generichash) under the run's
// key, over the channel name, the encoded bytes, sender and counter. The
// trailer comes after the struct so that lcm-spy and lcm-logger, which know
// nothing of it, still decode and record every message (LCM's decoders read
// the struct and ignore what follows).
//
// Receivers check the tag before anything else reads the bytes, then the
// replay window: `sender` is random per Bus, `counter` counts that Bus's
// messages from 1, and a receiver accepts each (sender, counter) once and
// only within the last kReplayWindow counters of that sender.
//
// No confidentiality: anyone on the network reads every message.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "dynapath/result.h"

namespace dynapath::protocol {

constexpr size_t kAuthKeyBytes = 32;
constexpr size_t kAuthTagBytes = 32;
constexpr size_t kAuthTrailerBytes = 8 + 8 + kAuthTagBytes + 4;
// A secret file holds at least this many characters (32 hex digits: 128 bits).
constexpr size_t kMinSecretChars = 32;
constexpr size_t kMaxSecretFileBytes = 4096;

// The key of a run. `insecure`: the all-zero key everyone knows (--insecure):
// messages are still checked for corruption and replays, but anyone can
// forge them.
struct RunKey {
  std::array<uint8_t, kAuthKeyBytes> bytes{};
  bool insecure = true;
};

RunKey InsecureKey();
// The key of a secret's text (a secret file's contents): BLAKE2b-256 of the
// text without surrounding whitespace. Error when shorter than
// kMinSecretChars.
Result<RunKey> KeyFromSecretText(std::string_view text);
// A new secret: 32 random bytes as 64 hex digits.
std::string NewSecretText();
// Reads the secret file at `path` (a regular file or /dev/fd/N of a pipe).
// Errors: unreadable, longer than kMaxSecretFileBytes, or a regular file
// that other users may read or write (chmod 600 it).
Result<std::string> ReadSecretText(const std::string& path);
// ReadSecretText, then KeyFromSecretText.
Result<RunKey> ReadSecretFile(const std::string& path);
// Writes a new secret to `path`, created with mode 0600; fails when the
// file exists.
Status WriteNewSecretFile(const std::string& path);

// The LCM-encoded bytes of a message that may carry a trailer: `size`
// without the trailer when the bytes end in one (unverified: for log readers
// and passive listeners), else `size`.
int PayloadSize(const uint8_t* data, int size);

// Appends trailers. Thread-safe.
class Sealer {
 public:
  explicit Sealer(const RunKey& key);
  // `out` = data followed by its trailer.
  void Seal(std::string_view channel, const uint8_t* data, size_t size, std::vector<uint8_t>& out);
  uint64_t sender() const { return sender_; }

 private:
  RunKey key_;
  uint64_t sender_;
  std::atomic<uint64_t> counter_{0};
};

// Checks trailers. One thread (the dispatch thread).
class Verifier {
 public:
  // Counters a sender may lag behind its newest accepted message.
  static constexpr uint64_t kReplayWindow = 4096;
  // Senders whose windows are kept (the oldest is forgotten beyond).
  static constexpr size_t kMaxSenders = 4096;

  explicit Verifier(const RunKey& key);

  enum class Verdict { kOk, kUnauthenticated, kReplayed };
  // kOk: `*payload_size` is the size of the LCM-encoded message.
  Verdict Check(std::string_view channel, const uint8_t* data, int size, int* payload_size);

 private:
  struct Window {
    uint64_t highest = 0;
    std::vector<uint64_t> seen;  // bit c % kReplayWindow: counter c seen
    uint64_t last_use = 0;
  };
  bool Accept(uint64_t sender, uint64_t counter);

  RunKey key_;
  std::unordered_map<uint64_t, Window> windows_;
  uint64_t uses_ = 0;
};

}  // namespace dynapath::protocol
