#pragma once
// A component's mailbox. LCM handlers run on the dispatch thread and must
// stay quick, so they decode, validate and Post the work here; the
// component's own thread runs it. One thread runs tasks, any may post.

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>

namespace dynapath::protocol {

class Inbox {
 public:
  using Clock = std::chrono::steady_clock;

  void Post(std::function<void()> task) {
    {
      std::lock_guard lock(mutex_);
      tasks_.push_back(std::move(task));
    }
    ready_.notify_one();
  }

  // Runs posted tasks until the queue is empty and `deadline` has passed, or
  // until Wake(). Returns the number of tasks run.
  int RunUntil(Clock::time_point deadline) {
    int ran = 0;
    std::unique_lock lock(mutex_);
    while (true) {
      if (!tasks_.empty()) {
        std::function<void()> task = std::move(tasks_.front());
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
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::function<void()>> tasks_;
  bool woken_ = false;
};

}  // namespace dynapath::protocol
