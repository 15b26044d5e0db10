#pragma once
// Opening LCM and running its dispatch loop. One thread per lcm::LCM calls
// handle (LCM allows no other way); handlers only decode, validate and post
// work to the components' inboxes.

#include <atomic>
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <thread>

#include "dynapath/result.h"

namespace dynapath::protocol {

// The URL to use: `url` if not empty, else $LCM_DEFAULT_URL, else LCM's
// default udpm group with ttl=0 (nothing leaves the host).
std::string ResolveLcmUrl(const std::string& url);
// Opens LCM; one clear error when the provider cannot start. A udpm URL
// without recv_buf_size gets WithReceiveBuffer's (net.core.rmem_max read
// here): a receiver kept off the cores, the recorder of `run --log` among
// them, finds more still queued on its socket (on loopback each datagram
// takes some 7 KB of the kernel's 208 KiB default).
Result<std::unique_ptr<lcm::LCM>> OpenLcm(const std::string& url);
// The socket receive buffer a udpm URL asks for when it names none: 2 MiB,
// about 30 ms of a 10,000-message/s exchange with the group's echoes
// (every member receives its own datagrams too) when a process stalls;
// the kernel's default (208 KiB on Debian) holds about 3 ms of it.
inline constexpr int64_t kDefaultReceiveBuffer = int64_t{2} << 20;
// `url` with recv_buf_size=min(kDefaultReceiveBuffer, kernel_max) added
// when it is a udpm URL without one (kernel_max: net.core.rmem_max, above
// which LCM warns; 0: unknown, `url` unchanged). Other URLs unchanged.
std::string WithReceiveBuffer(const std::string& url, int64_t kernel_max);
// True for memq:// (one process, nothing to fragment).
bool IsMemq(const std::string& url);
// Payload bytes of a Bus fragment that fits one Ethernet frame (1500-byte
// MTU: 1472 bytes of UDP payload, less LCM's header with the channel name,
// fragment_t's fields with a run id of at most 64 characters and the
// authentication trailer), so one lost frame costs one small piece.
inline constexpr int kFrameFragmentSize = 1200;
// The fragment size for `url` (resolved): one Ethernet frame for udpm URLs
// whose ttl lets datagrams leave the host, else one 60 KB datagram (the
// loopback's MTU is 64 KB: nothing to gain from small pieces there).
int DefaultFragmentSize(const std::string& url);

class Dispatcher {
 public:
  explicit Dispatcher(lcm::LCM& lcm);
  ~Dispatcher();  // stops and joins
  Dispatcher(const Dispatcher&) = delete;
  Dispatcher& operator=(const Dispatcher&) = delete;

 private:
  lcm::LCM& lcm_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// The process's one SIGINT/SIGTERM handler (installed once): every signal
// sets the returned flag, which the components poll.
const std::atomic<bool>& StopOnSignals();
// The same, and: the first signal writes `first_notice` to stderr (nullptr:
// nothing); when `second_exit_notice` is not nullptr, a second signal writes
// it and ends the process at once (_exit 130). Both strings must live for
// the rest of the process (string literals).
const std::atomic<bool>& StopOnSignals(const char* first_notice, const char* second_exit_notice);

}  // namespace dynapath::protocol
