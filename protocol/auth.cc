#include "protocol/auth.h"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace dynapath::protocol {
namespace {

constexpr uint8_t kMagic[4] = {'D', 'P', 'A', '1'};

void InitSodium() {
  // Idempotent and thread-safe; fails only when the kernel gives no
  // randomness (no getrandom, no /dev/urandom): not an input or a run-time
  // condition a caller could handle, and libsodium's own randombytes aborts
  // in that case too. Say why before doing the same.
  if (sodium_init() < 0) {
    std::fputs("dynapath: libsodium cannot initialise (no source of randomness)\n", stderr);
    std::abort();
  }
}

void PutU64(uint8_t* out, uint64_t value) {
  for (int i = 0; i < 8; ++i) out[i] = static_cast<uint8_t>(value >> (8 * i));
}

uint64_t GetU64(const uint8_t* in) {
  uint64_t value = 0;
  for (int i = 0; i < 8; ++i) value |= static_cast<uint64_t>(in[i]) << (8 * i);
  return value;
}

// The tag of a message: over the channel (length first, so that channel and
// payload cannot trade bytes), the payload and the trailer's sender and
// counter (`ids`, 16 bytes).
void ComputeTag(const RunKey& key, std::string_view channel, const uint8_t* data, size_t size,
                const uint8_t* ids, uint8_t* tag) {
  crypto_generichash_state state;
  crypto_generichash_init(&state, key.bytes.data(), key.bytes.size(), kAuthTagBytes);
  uint8_t length[8];
  PutU64(length, channel.size());
  crypto_generichash_update(&state, length, sizeof length);
  crypto_generichash_update(&state, reinterpret_cast<const uint8_t*>(channel.data()),
                            channel.size());
  crypto_generichash_update(&state, data, size);
  crypto_generichash_update(&state, ids, 16);
  crypto_generichash_final(&state, tag, kAuthTagBytes);
}

std::string_view Trim(std::string_view text) {
  const char* blanks = " \t\r\n";
  const size_t begin = text.find_first_not_of(blanks);
  if (begin == std::string_view::npos) return {};
  const size_t end = text.find_last_not_of(blanks);
  return text.substr(begin, end - begin + 1);
}

}  // namespace

RunKey InsecureKey() { return RunKey{}; }

Result<RunKey> KeyFromSecretText(std::string_view text) {
  InitSodium();
  const std::string_view secret = Trim(text);
  if (secret.size() < kMinSecretChars) {
    return Error::Corrupt("the secret is too short: " + std::to_string(secret.size()) +
                          " characters, at least " + std::to_string(kMinSecretChars) +
                          " needed (make one with `dynapath secret FILE`)");
  }
  RunKey key;
  key.insecure = false;
  crypto_generichash(key.bytes.data(), key.bytes.size(),
                     reinterpret_cast<const uint8_t*>(secret.data()), secret.size(), nullptr, 0);
  return key;
}

std::string NewSecretText() {
  InitSodium();
  uint8_t random[32];
  randombytes_buf(random, sizeof random);
  char hex[2 * sizeof random + 1];
  sodium_bin2hex(hex, sizeof hex, random, sizeof random);
  sodium_memzero(random, sizeof random);
  return std::string(hex);
}

Result<std::string> ReadSecretText(const std::string& path) {
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int error = errno;
    return Error::File(error, "cannot open secret file " + path + ": " + std::strerror(error));
  }
  struct stat info {};
  if (fstat(fd, &info) != 0) {
    close(fd);
    return Error::Io("cannot stat secret file " + path + ": " + std::strerror(errno));
  }
  if (S_ISREG(info.st_mode) && (info.st_mode & (S_IRWXG | S_IRWXO)) != 0) {
    close(fd);
    return Error{"secret file " + path + " may be read or written by other users (mode " +
                 std::to_string((info.st_mode >> 6) & 7) + std::to_string((info.st_mode >> 3) & 7) +
                 std::to_string(info.st_mode & 7) + "): chmod 600 it"};
  }
  std::string text;
  char buffer[512];
  while (true) {
    const ssize_t got = read(fd, buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      close(fd);
      return Error::Io("cannot read secret file " + path + ": " + std::strerror(errno));
    }
    if (got == 0) break;
    text.append(buffer, static_cast<size_t>(got));
    if (text.size() > kMaxSecretFileBytes) {
      close(fd);
      return Error::Corrupt("secret file " + path + " is larger than " +
                            std::to_string(kMaxSecretFileBytes) + " bytes: not a secret file?");
    }
  }
  close(fd);
  sodium_memzero(buffer, sizeof buffer);
  return text;
}

Result<RunKey> ReadSecretFile(const std::string& path) {
  Result<std::string> text = ReadSecretText(path);
  if (!text) return text.error();
  Result<RunKey> key = KeyFromSecretText(*text);
  sodium_memzero(text->data(), text->size());
  if (!key) return key.error().Prefixed("secret file " + path + ": ");
  return key;
}

Status WriteNewSecretFile(const std::string& path) {
  const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) return Error::Io("cannot create " + path + ": " + std::strerror(errno));
  const std::string text = NewSecretText() + "\n";
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t wrote = write(fd, text.data() + done, text.size() - done);
    if (wrote < 0 && errno == EINTR) continue;
    if (wrote < 0) {
      const std::string why = std::strerror(errno);
      close(fd);
      unlink(path.c_str());
      return Error::Io("cannot write " + path + ": " + why);
    }
    done += static_cast<size_t>(wrote);
  }
  if (close(fd) != 0) return Error::Io("cannot write " + path + ": " + std::strerror(errno));
  return Ok{};
}

int PayloadSize(const uint8_t* data, int size) {
  if (data == nullptr || size < static_cast<int>(kAuthTrailerBytes)) return size;
  if (std::memcmp(data + size - 4, kMagic, 4) != 0) return size;
  return size - static_cast<int>(kAuthTrailerBytes);
}

Sealer::Sealer(const RunKey& key) : key_(key) {
  InitSodium();
  randombytes_buf(&sender_, sizeof sender_);
}

void Sealer::Seal(std::string_view channel, const uint8_t* data, size_t size,
                  std::vector<uint8_t>& out) {
  out.resize(size + kAuthTrailerBytes);
  if (size > 0) std::memcpy(out.data(), data, size);
  uint8_t* trailer = out.data() + size;
  PutU64(trailer, sender_);
  PutU64(trailer + 8, counter_.fetch_add(1, std::memory_order_relaxed) + 1);
  ComputeTag(key_, channel, data, size, trailer, trailer + 16);
  std::memcpy(trailer + 16 + kAuthTagBytes, kMagic, 4);
}

Verifier::Verifier(const RunKey& key) : key_(key) { InitSodium(); }

Verifier::Verdict Verifier::Check(std::string_view channel, const uint8_t* data, int size,
                                  int* payload_size) {
  const int payload = PayloadSize(data, size);
  if (payload == size) return Verdict::kUnauthenticated;  // no trailer
  const uint8_t* trailer = data + payload;
  uint8_t tag[kAuthTagBytes];
  ComputeTag(key_, channel, data, static_cast<size_t>(payload), trailer, tag);
  if (sodium_memcmp(tag, trailer + 16, kAuthTagBytes) != 0) return Verdict::kUnauthenticated;
  if (!Accept(GetU64(trailer), GetU64(trailer + 8))) return Verdict::kReplayed;
  *payload_size = payload;
  return Verdict::kOk;
}

bool Verifier::Accept(uint64_t sender, uint64_t counter) {
  if (counter == 0) return false;  // senders count from 1
  auto it = windows_.find(sender);
  if (it == windows_.end()) {
    if (windows_.size() >= kMaxSenders) {
      // Forget the sender heard from least recently (processes that left).
      auto oldest = windows_.begin();
      for (auto w = windows_.begin(); w != windows_.end(); ++w) {
        if (w->second.last_use < oldest->second.last_use) oldest = w;
      }
      windows_.erase(oldest);
    }
    it = windows_.emplace(sender, Window{}).first;
    it->second.seen.assign(kReplayWindow / 64, 0);
  }
  Window& window = it->second;
  window.last_use = ++uses_;
  auto bit = [&](uint64_t c) -> std::pair<uint64_t&, uint64_t> {
    const uint64_t slot = c % kReplayWindow;
    return {window.seen[slot / 64], uint64_t{1} << (slot % 64)};
  };
  if (counter > window.highest) {
    // Slide: counters between the old and the new highest are unseen.
    if (counter - window.highest >= kReplayWindow) {
      std::fill(window.seen.begin(), window.seen.end(), 0);
    } else {
      for (uint64_t c = window.highest + 1; c < counter; ++c) {
        auto [word, mask] = bit(c);
        word &= ~mask;
      }
    }
    window.highest = counter;
    auto [word, mask] = bit(counter);
    word |= mask;
    return true;
  }
  if (window.highest - counter >= kReplayWindow) return false;  // too old to tell
  auto [word, mask] = bit(counter);
  if ((word & mask) != 0) return false;
  word |= mask;
  return true;
}

}  // namespace dynapath::protocol
