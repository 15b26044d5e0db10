#pragma once
// A component's mailbox. LCM handlers run on the dispatch thread and must
// stay quick, so they decode, validate and Post the work here; the
// component's own thread runs it. One thread runs tasks, any may post.
//
// Bounded: the messages waiting hold at most `max_bytes` (their encoded
// sizes, given to Post). A message that would take them past it is dropped
// and counted, unless nothing waits (any one message the run can send is
// taken). Senders repeat what is not answered, so a drop costs time, not
// results; without the bound a component that falls behind its peers'
// traffic grows without limit (agents re-sending to each other on a busy
// machine grew past 1 GB each before the re-sends were gated).

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>

namespace dynapath::protocol {

class Inbox {
 public:
  using Clock = std::chrono::steady_clock;
  // The bound of every component's mailbox: 256 MiB of waiting messages.
  static constexpr int64_t kDefaultMaxBytes = int64_t{256} << 20;

  explicit Inbox(int64_t max_bytes = kDefaultMaxBytes) : max_bytes_(max_bytes) {}

  // Posts the work of a message of `bytes` encoded bytes (0: not a message,
  // always taken). False when it was dropped (the bound, above).
  bool Post(std::function<void()> task, int64_t bytes = 0) {
    {
      std::lock_guard lock(mutex_);
      if (bytes > 0 && !tasks_.empty() && waiting_bytes_ + bytes > max_bytes_) {
        ++dropped_;
        return false;
      }
      waiting_bytes_ += bytes;
      tasks_.push_back({std::move(task), bytes});
    }
    ready_.notify_one();
    return true;
  }
  // Messages dropped at the bound so far (any thread).
  int64_t dropped() const { return dropped_; }

  // Runs posted tasks until the queue is empty and `deadline` has passed, or
  // until Wake(). Returns the number of tasks run.
  int RunUntil(Clock::time_point deadline) {
    int ran = 0;
    std::unique_lock lock(mutex_);
    while (true) {
      if (!tasks_.empty()) {
        std::function<void()> task = std::move(tasks_.front().run);
        waiting_bytes_ -= tasks_.front().bytes;
        tasks_.pop_front();
        lock.unlock();
        task();
        ++ran;
        lock.lock();
        continue;
      }
      if (woken_ || ran > 0) break;  // return to the caller after a batch of work
      if (ready_.wait_until(lock, deadline) == std::cv_status::timeout && tasks_.empty()) break;
    }
    woken_ = false;
    return ran;
  }

  int RunFor(std::chrono::milliseconds timeout) { return RunUntil(Clock::now() + timeout); }

  // Makes the current or next RunUntil return.
  void Wake() {
    {
      std::lock_guard lock(mutex_);
      woken_ = true;
    }
    ready_.notify_one();
  }

 private:
  struct Task {
    std::function<void()> run;
    int64_t bytes;
  };
  const int64_t max_bytes_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<Task> tasks_;
  int64_t waiting_bytes_ = 0;  // guarded by mutex_
  std::atomic<int64_t> dropped_{0};
  bool woken_ = false;
};

}  // namespace dynapath::protocol
