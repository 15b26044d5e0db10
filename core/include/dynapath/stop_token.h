#pragma once
// A request to stop long work (Ctrl-C): a flag another thread or a signal
// handler sets and never clears. The core knows no signals; the long loops
// (learners' episodes and rounds, the local trainer) check it every few
// iterations and end early. Null: never stopped. Unset, it changes nothing.

#include <atomic>

namespace dynapath {

using StopToken = const std::atomic<bool>*;

inline bool StopRequested(StopToken stop) {
  return stop != nullptr && stop->load(std::memory_order_relaxed);
}

}  // namespace dynapath
