#pragma once
// Stopping lcm-logger without losing the run's last messages.
//
// lcm-logger stops on SIGINT at once: datagrams still queued on its socket,
// or read but not yet written (it flushes every 100 ms), are lost. On a
// loaded machine that was the last steps of the last approach (seen as a
// render with 1 frame of 6). By the time the launcher stops it every other
// process has exited, so everything they sent is already queued for the
// logger; waiting until its sockets are empty and its file has stopped
// growing is then enough.

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>

namespace dynapath::launch {

// Bytes queued on the UDP sockets of process `pid` (its /proc/PID/fd sockets
// looked up in /proc/PID/net/udp and udp6); nullopt when /proc cannot say.
std::optional<long long> QueuedUdpBytes(pid_t pid);

// Waits until `pid`'s sockets hold nothing and `file` has kept its size for
// `quiet`, or until `cap` has passed. Returns false on the cap.
bool WaitForLoggerToDrain(pid_t pid, const std::string& file, std::chrono::milliseconds quiet,
                          std::chrono::milliseconds cap);

}  // namespace dynapath::launch
