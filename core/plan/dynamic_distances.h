#pragma once
#ifndef DYNAPATH_CORE_PRIVATE  // defined for dynapath_core and the tests of its insides
#error "private to dynapath_core: include its face, dynapath/bfs_oracle.h"
#endif
// Nearest-source distances over a directed graph, kept exact under local
// changes by repairing only what the changes affect (a dynamic multi-source
// breadth-first search in the style of Ramalingam-Reps / LPA*, for unit
// edges). Used by the Incremental Oracle (the grid's 8-connected moves) and
// by the incremental policy evaluation (the top-2 policy graph).
//
// The value of a node is 0 for a source, "none" for a blocked node, and
// otherwise 1 + the smallest value among its successors; values >= `limit`
// count as none (SPEC section 4's depth bound; the oracle has no bound).
//
// A repair takes the nodes whose own definition changed (source or blocked
// status, successor set). Phase 1 withdraws, in increasing order of old
// value, every value that lost all its supports (a successor one lower);
// phase 2 recomputes the withdrawn and changed nodes and relaxes outwards
// Dijkstra-style. The work is proportional to the nodes whose value changes
// and their neighbourhoods, times a heap logarithm.
//
// `Graph` provides:
//   int size() const;
//   bool IsBlocked(int v) const;  bool IsSource(int v) const;
//   template <class F> void ForEachSuccessor(int v, F f) const;
//   template <class F> void ForEachPredecessor(int u, F f) const;
// Predecessors of u are exactly the nodes that have u as a successor.

#include <algorithm>
#include <cstdint>
#include <functional>
#include <queue>
#include <utility>
#include <vector>

namespace dynapath {

class DynamicDistances {
 public:
  static constexpr int32_t kNone = -1;

  // One node whose value changed in the last Build or Repair.
  struct ValueChange {
    int node;
    int32_t old_value;
  };

  const std::vector<int32_t>& values() const { return value_; }
  int32_t value(int node) const { return value_[node]; }

  // Full multi-source breadth-first search from the sources, over
  // predecessors. `limit` <= 0 means no bound.
  template <class Graph>
  void Build(const Graph& graph, int32_t limit) {
    limit_ = limit;
    const int n = graph.size();
    value_.assign(static_cast<size_t>(n), kNone);
    stamp_.assign(static_cast<size_t>(n), 0u);
    epoch_ = 0;
    changes_.clear();
    std::vector<int32_t> queue;
    queue.reserve(static_cast<size_t>(n));
    for (int v = 0; v < n; ++v) {
      if (graph.IsSource(v) && !graph.IsBlocked(v)) {
        value_[v] = 0;
        queue.push_back(v);
      }
    }
    for (size_t head = 0; head < queue.size(); ++head) {
      const int u = queue[head];
      const int32_t next = value_[u] + 1;
      if (!Within(next)) continue;
      graph.ForEachPredecessor(u, [&](int v) {
        if (value_[v] != kNone || graph.IsBlocked(v) || graph.IsSource(v)) return;
        value_[v] = next;
        queue.push_back(v);
      });
    }
  }

  // Restores exact values after the definitions of `changed` nodes changed
  // (duplicates allowed). The values that changed are listed in changes().
  template <class Graph>
  void Repair(const Graph& graph, const std::vector<int>& changed) {
    changes_.clear();
    if (++epoch_ == 0) {  // wrapped: forget every old stamp
      std::fill(stamp_.begin(), stamp_.end(), 0u);
      epoch_ = 1;
    }
    // Phase 1: withdraw unsupported values, lowest old value first, so a
    // node's supports one level down are final when it is checked.
    for (int v : changed) {
      if (value_[v] != kNone) heap_.push({value_[v], v});
    }
    while (!heap_.empty()) {
      // Not a structured binding: clang 14 (the fuzz build) cannot capture
      // one in the lambda below.
      const int level = heap_.top().first;
      const int v = heap_.top().second;
      heap_.pop();
      if (value_[v] != level || Supported(graph, v, level)) continue;
      Set(v, kNone);
      withdrawn_.push_back(v);
      graph.ForEachPredecessor(v, [&](int p) {
        if (value_[p] == level + 1) heap_.push({level + 1, p});
      });
    }
    // Phase 2: best value of every withdrawn or changed node from its
    // successors, then relax outwards in increasing order of value.
    auto seed = [&](int v) {
      if (graph.IsBlocked(v)) {
        if (value_[v] != kNone) Set(v, kNone);  // unreachable: withdrawn in phase 1
        return;
      }
      int32_t best = value_[v];
      if (graph.IsSource(v)) {
        best = 0;
      } else {
        graph.ForEachSuccessor(v, [&](int w) {
          const int32_t via = value_[w] == kNone ? kNone : value_[w] + 1;
          if (via != kNone && Within(via) && (best == kNone || via < best)) best = via;
        });
      }
      if (best != kNone && best != value_[v]) Set(v, best);
      if (best != kNone) heap_.push({best, v});
    };
    for (int v : withdrawn_) seed(v);
    for (int v : changed) seed(v);
    withdrawn_.clear();
    while (!heap_.empty()) {
      const auto [level, u] = heap_.top();
      heap_.pop();
      if (value_[u] != level) continue;
      const int32_t next = level + 1;
      if (!Within(next)) continue;
      graph.ForEachPredecessor(u, [&](int p) {
        if (graph.IsBlocked(p) || graph.IsSource(p)) return;
        if (value_[p] != kNone && value_[p] <= next) return;
        Set(p, next);
        heap_.push({next, p});
      });
    }
  }

  // Nodes whose value changed in the last Repair, each once, with its value
  // before the repair (a node may end with its old value again).
  const std::vector<ValueChange>& changes() const { return changes_; }

 private:
  using Entry = std::pair<int32_t, int>;  // (value, node), smallest first

  bool Within(int32_t value) const { return limit_ <= 0 || value < limit_; }

  // True when `v` may keep value `level`: a source (its value can only go
  // down, phase 2 lowers it), or a successor one lower still holds.
  template <class Graph>
  bool Supported(const Graph& graph, int v, int32_t level) const {
    if (graph.IsBlocked(v)) return false;
    if (graph.IsSource(v)) return true;
    bool supported = false;
    graph.ForEachSuccessor(v, [&](int w) {
      if (value_[w] != kNone && value_[w] == level - 1) supported = true;
    });
    return supported;
  }

  void Set(int v, int32_t value) {
    if (stamp_[v] != epoch_) {
      stamp_[v] = epoch_;
      changes_.push_back({v, value_[v]});
    }
    value_[v] = value;
  }

  int32_t limit_ = 0;
  std::vector<int32_t> value_;
  std::vector<ValueChange> changes_;
  std::vector<uint32_t> stamp_;  // == epoch_: already in changes_
  uint32_t epoch_ = 0;
  std::vector<int> withdrawn_;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap_;
};

}  // namespace dynapath
