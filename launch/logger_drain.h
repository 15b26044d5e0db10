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

#include <atomic>
#include <chrono>
#include <optional>
#include <string>
#include <thread>

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

// Waits until lcm-logger (process `pid`) has subscribed: LCM opens its
// receiving socket, bound to the URL's port, when the first subscription is
// made, so until then the run's first messages would not be recorded.
// False when `cap` passed first or the process is gone.
bool WaitForLoggerToSubscribe(pid_t pid, int port, std::chrono::milliseconds cap);

// Waits until `pid`'s sockets hold nothing and `file` has kept its size for
// `quiet`, or until `cap` has passed. Returns false on the cap.
bool WaitForLoggerToDrain(pid_t pid, const std::string& file, std::chrono::milliseconds quiet,
                          std::chrono::milliseconds cap);

// lcm-logger's own output ("Opening log file ...", "Logger exiting" on its
// stdout and stderr), which would otherwise land on the user's terminal
// among the run's log lines: the logger writes into a pipe, read here on a
// thread. Its chatter is logged at debug level; any other line (a failure
// to open the file, say) as a warning naming lcm-logger.
class LoggerOutput {
 public:
  LoggerOutput();  // no pipe (write_fd() -1) when it cannot make one
  ~LoggerOutput();
  LoggerOutput(const LoggerOutput&) = delete;
  LoggerOutput& operator=(const LoggerOutput&) = delete;

  // The descriptor the logger's stdout and stderr go to (close-on-exec).
  int write_fd() const { return write_fd_; }
  // After the logger was started: closes this process's write end, so the
  // reader sees the end of the output once the logger exits.
  void Started();

 private:
  void Read();

  int read_fd_ = -1, write_fd_ = -1;
  std::atomic<bool> stop_{false};
  std::thread reader_;
};

// How a line of lcm-logger's output is logged: false for its chatter
// (debug), true for anything else (a warning).
bool IsLoggerComplaint(const std::string& line);

}  // namespace dynapath::launch
