#pragma once
// Starting and stopping the run's recorder (dynapath-recorder, for --log)
// without losing the run's first or last messages.
//
// Its first messages go out as soon as the run starts, so the recorder must
// have subscribed before. At the end, by the time the launcher stops it
// every other process has exited, so everything they sent is already queued
// for it: waiting until its sockets are empty and its file has stopped
// growing, then asking it to stop (it writes what LCM still holds for it),
// loses nothing. Without that wait a loaded machine lost the last steps of
// the last approach (seen as a render with 1 frame of 6).

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>

namespace dynapath::launch {

// Bytes queued on the UDP sockets of process `pid` (its /proc/PID/fd sockets
// looked up in /proc/PID/net/udp and udp6); nullopt when /proc cannot say.
std::optional<long long> QueuedUdpBytes(pid_t pid);

// The port of an LCM "udpm://ADDRESS[:PORT][?OPTIONS]" URL (LCM's 7667
// when none is given); nullopt for another provider or a bad port.
std::optional<int> UdpmPort(const std::string& url);

// Whether process `pid` holds a UDP socket bound to `port`, other than one
// it inherited from this process; nullopt when /proc cannot say (the
// process gone).
std::optional<bool> HasUdpSocketOnPort(pid_t pid, int port);

// Waits until the recorder (process `pid`) has subscribed: LCM opens its
// receiving socket, bound to the URL's port, when the first subscription is
// made, so until then the run's first messages would not be recorded.
// False when `cap` passed first or the process is gone.
bool WaitForLoggerToSubscribe(pid_t pid, int port, std::chrono::milliseconds cap);

// Waits until `pid`'s sockets hold nothing and `file` has kept its size for
// `quiet`, or until `cap` has passed. Returns false on the cap.
bool WaitForLoggerToDrain(pid_t pid, const std::string& file, std::chrono::milliseconds quiet,
                          std::chrono::milliseconds cap);

}  // namespace dynapath::launch
