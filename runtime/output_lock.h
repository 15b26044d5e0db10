#pragma once
// One writer per output directory. A run's --out and a study's directory are
// locked for as long as their writer runs: an advisory flock(2) on
// DIR/.dynapath.lock, which holds the holder's pid and command line. A
// second writer is refused at once, naming the holder. The kernel drops the
// lock with the last descriptor of its holder, so a killed holder (even by
// SIGKILL) never blocks the next run; the file itself is removed by a holder
// that ends normally.
//
// A launcher that starts the process writing the files (the coordinator of
// `dynapath run --agents N`) hands it the locked descriptor; the child
// adopts it (OutputLock::Adopt), so the lock covers the files until the
// writer is gone, whoever of the two ends first.

#include <string>

#include "dynapath/result.h"

namespace dynapath::runtime {

inline constexpr const char* kLockFileName = ".dynapath.lock";

class OutputLock {
 public:
  // Creates `dir` (and its parents) if needed and locks it. `option` names
  // the option for errors ("out"). Fails (kUnavailable) when another process
  // holds the lock: "option --out: DIR is in use by pid P (COMMAND): ...",
  // and with the system's reason when DIR cannot be created or is not a
  // writable directory.
  static Result<OutputLock> Acquire(const std::string& dir, const std::string& option);
  // Takes over descriptor `fd`, inherited from the process that locked `dir`:
  // it must be that lock file, open and locked by us (flock on a shared open
  // file description succeeds). Adopted locks are not removed on release.
  static Result<OutputLock> Adopt(const std::string& dir, int fd);

  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&& other) noexcept;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  ~OutputLock();

  // The locked descriptor (close-on-exec), to hand to a child.
  int fd() const { return fd_; }
  const std::string& path() const { return path_; }

 private:
  OutputLock(int fd, std::string path, bool owner)
      : fd_(fd), path_(std::move(path)), owner_(owner) {}
  void Release();

  int fd_ = -1;
  std::string path_;
  bool owner_ = false;
};

// A run's --out: locked, and DIR/results.csv and DIR/results_detailed.csv
// not directories.
Result<OutputLock> LockResultDirectory(const std::string& dir);

// This process's command line, as the lock file records it ("dynapath run
// --local --out x"), at most 1000 characters.
std::string OwnCommandLine();

}  // namespace dynapath::runtime
