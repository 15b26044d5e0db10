#include "dynapath/thread_pool.h"

namespace dynapath {

ThreadPool::ThreadPool(int threads) {
  for (int i = 1; i < threads; ++i) workers_.emplace_back([this] { WorkerLoop(); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  work_ready_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

void ThreadPool::RunItems(std::unique_lock<std::mutex>& lock) {
  while (next_ < count_) {
    const int item = next_++;
    const std::function<void(int)>& body = *body_;
    lock.unlock();
    body(item);
    lock.lock();
  }
}

void ThreadPool::ParallelFor(int count, const std::function<void(int)>& body) {
  if (count <= 0) return;
  if (workers_.empty() || count == 1) {
    for (int i = 0; i < count; ++i) body(i);
    return;
  }
  std::unique_lock<std::mutex> lock(mutex_);
  body_ = &body;
  count_ = count;
  next_ = 0;
  ++generation_;
  work_ready_.notify_all();
  RunItems(lock);
  work_done_.wait(lock, [this] { return active_ == 0; });
  body_ = nullptr;
  count_ = 0;
}

void ThreadPool::WorkerLoop() {
  unsigned seen = 0;
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    work_ready_.wait(lock, [&] { return stopping_ || (generation_ != seen && next_ < count_); });
    if (stopping_) return;
    seen = generation_;
    ++active_;
    RunItems(lock);
    if (--active_ == 0) work_done_.notify_all();
  }
}

}  // namespace dynapath
