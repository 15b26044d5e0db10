#pragma once
// A fixed set of persistent worker threads for data-parallel loops. Threads
// are created once (never per round or per job).

#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace dynapath {

class ThreadPool {
 public:
  // `threads` >= 1 counts the calling thread, which also works in
  // ParallelFor: ThreadPool(1) runs everything in the caller.
  explicit ThreadPool(int threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }

  // Calls body(i) for every i in [0, count), spread over the threads, and
  // returns when all calls have returned. Items are handed out in increasing
  // order; the body must not depend on which thread runs it and must not
  // throw. Not re-entrant: call from one thread at a time, never from inside
  // a body.
  void ParallelFor(int count, const std::function<void(int)>& body);

 private:
  void WorkerLoop();
  // Runs items until none is left; `lock` holds mutex_ on entry and exit.
  void RunItems(std::unique_lock<std::mutex>& lock);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable work_ready_;
  std::condition_variable work_done_;
  const std::function<void(int)>* body_ = nullptr;
  int count_ = 0;
  int next_ = 0;
  int active_ = 0;           // workers inside the current loop
  unsigned generation_ = 0;  // bumped per ParallelFor call
  bool stopping_ = false;
};

}  // namespace dynapath
