#include "lcmtypes/protocol/bus.h"

#include <gtest/gtest.h>

#include <chrono>
#include <lcm/lcm-cpp.hpp>
#include <optional>
#include <vector>

#include "lcmtypes/protocol/channels.h"

namespace dynapath::protocol {
namespace {

policy_t Policy(const std::string& run, int side) {
  policy_t m{};
  m.run_id = run;
  m.approach = "fedAsynQ_EqAvg";
  m.time_step = 7;
  m.rows = side;
  m.cols = side;
  m.num_cells = side * side;
  for (int i = 0; i < m.num_cells; ++i) {
    m.cells.push_back(static_cast<int8_t>(i % 7 == 0 ? 0 : (i % 11 == 0 ? 2 : 1)));
    m.actions.push_back(static_cast<int8_t>(m.cells.back() == 1 ? i % 8 : -1));
    m.reaches.push_back(static_cast<int8_t>(m.cells.back() == 1 ? i % 2 : -1));
  }
  return m;
}

// Dispatches memq:// until `done` or `limit` passes.
template <class Done>
void Pump(lcm::LCM& lcm, Done done,
          std::chrono::milliseconds limit = std::chrono::milliseconds(1000)) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (!done() && std::chrono::steady_clock::now() < end) lcm.handleTimeout(10);
}

TEST(BusTest, LargeMessagesTravelInFragmentsAndArriveWhole) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  BusOptions options;
  options.fragment_above = 2000;
  options.fragment_size = 1024;  // the smallest piece the Bus makes
  Bus sender(lcm, "run1", options);
  Bus receiver(lcm, "run1", options);
  std::vector<policy_t> got;
  receiver.Subscribe<policy_t>(channel::kPolicy, [&](policy_t& m) { got.push_back(m); });
  const policy_t sent = Policy("run1", 40);  // 4800 bytes of arrays: 5 fragments
  sender.Publish(channel::kPolicy, sent);
  Pump(lcm, [&] { return !got.empty(); });
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].cells, sent.cells);
  EXPECT_EQ(got[0].actions, sent.actions);
  EXPECT_EQ(got[0].reaches, sent.reaches);
  EXPECT_GE(receiver.counters().fragments_received, 4);
  EXPECT_EQ(receiver.counters().dropped, 0);
}

TEST(BusTest, DuplicatedFragmentsDeliverOnce) {
  lcm::LCM lcm("memq://");
  BusOptions options;
  options.fragment_above = 2000;
  options.fragment_size = 1024;         // the smallest piece the Bus makes
  options.duplicate_probability = 1.0;  // every fragment sent twice
  Bus sender(lcm, "run1", options);
  Bus receiver(lcm, "run1");
  int got = 0;
  receiver.Subscribe<policy_t>(channel::kPolicy, [&](policy_t&) { ++got; });
  sender.Publish(channel::kPolicy, Policy("run1", 40));
  Pump(
      lcm, [&] { return false; }, std::chrono::milliseconds(200));
  EXPECT_EQ(got, 1);
}

TEST(BusTest, DropsAndCountsForeignAndInvalidMessages) {
  lcm::LCM lcm("memq://");
  Bus other_run(lcm, "run2");
  Bus receiver(lcm, "run1");
  int got = 0;
  receiver.Subscribe<policy_t>(channel::kPolicy, [&](policy_t&) { ++got; });
  // Another run's message on our channel name.
  policy_t foreign = Policy("run2", 5);
  std::vector<uint8_t> bytes(static_cast<size_t>(foreign.getEncodedSize()));
  foreign.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  lcm.publish(ChannelName("run1", channel::kPolicy), bytes.data(),
              static_cast<unsigned>(bytes.size()));
  // A message of our run that fails validation (a bad cell code).
  policy_t invalid = Policy("run1", 5);
  invalid.cells[3] = 9;
  bytes.resize(static_cast<size_t>(invalid.getEncodedSize()));
  invalid.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  lcm.publish(ChannelName("run1", channel::kPolicy), bytes.data(),
              static_cast<unsigned>(bytes.size()));
  // Garbage bytes.
  const uint8_t garbage[5] = {1, 2, 3, 4, 5};
  lcm.publish(ChannelName("run1", channel::kPolicy), garbage, sizeof garbage);
  // A good one last.
  other_run.Publish(channel::kPolicy, Policy("run2", 5));  // goes to run2's channel: unseen
  Bus sender(lcm, "run1");
  sender.Publish(channel::kPolicy, Policy("run1", 5));
  Pump(lcm, [&] { return got > 0 && receiver.counters().dropped >= 3; });
  EXPECT_EQ(got, 1);
  EXPECT_EQ(receiver.counters().dropped, 3);
}

TEST(BusTest, InjectedDropsLoseMessages) {
  lcm::LCM lcm("memq://");
  BusOptions options;
  options.drop_probability = 1.0;
  Bus sender(lcm, "run1", options);
  Bus receiver(lcm, "run1");
  int got = 0;
  receiver.Subscribe<policy_t>(channel::kPolicy, [&](policy_t&) { ++got; });
  sender.Publish(channel::kPolicy, Policy("run1", 5));
  Pump(
      lcm, [&] { return false; }, std::chrono::milliseconds(200));
  EXPECT_EQ(got, 0);
  EXPECT_EQ(sender.counters().injected_drops, 1);
}

}  // namespace
}  // namespace dynapath::protocol
