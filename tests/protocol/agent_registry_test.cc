// The coordinator's agent registry is keyed by the sender id of heartbeats,
// which anyone on the run's network can make up: it is capped.

#include "coordinator/agent_registry.h"

#include <gtest/gtest.h>

namespace dynapath::coordinator {
namespace {

heartbeat_t Beat(int sender) {
  heartbeat_t beat{};
  beat.role = heartbeat_t::ROLE_AGENT;
  beat.sender = sender;
  return beat;
}

TEST(AgentRegistryTest, MadeUpSenderIdsCannotGrowItWithoutEnd) {
  AgentRegistry registry(60.0);
  for (int id = 0; id < 3 * static_cast<int>(AgentRegistry::kMaxAgents); ++id) {
    registry.OnHeartbeat(Beat(id));
  }
  EXPECT_EQ(registry.Live().size(), AgentRegistry::kMaxAgents);
  EXPECT_EQ(registry.ignored(), 2 * static_cast<int64_t>(AgentRegistry::kMaxAgents));
  // Known agents still update.
  EXPECT_FALSE(registry.OnHeartbeat(Beat(5)));
  EXPECT_TRUE(registry.IsLive(5));
}

TEST(AgentRegistryTest, DeadAgentsMakeRoom) {
  AgentRegistry registry(0.0);  // every agent is dead once a millisecond passes
  for (int id = 0; id < static_cast<int>(AgentRegistry::kMaxAgents); ++id) {
    registry.OnHeartbeat(Beat(id));
  }
  const int64_t start = AgentRegistry::NowMs();
  while (AgentRegistry::NowMs() - start < 2) {
  }
  EXPECT_TRUE(registry.OnHeartbeat(Beat(100000)));
  EXPECT_EQ(registry.ignored(), 0);
}

TEST(AgentRegistryTest, AnAgentMarkedGoneIsNotLiveAndItsLateHeartbeatsAreIgnored) {
  AgentRegistry registry(60.0);
  registry.OnHeartbeat(Beat(1));
  registry.OnHeartbeat(Beat(2));
  registry.MarkGone(2);
  EXPECT_FALSE(registry.IsLive(2));
  EXPECT_FALSE(registry.OnHeartbeat(Beat(2)));  // one still in flight
  EXPECT_FALSE(registry.IsLive(2));
  ASSERT_EQ(registry.Live().size(), 1u);
  EXPECT_EQ(registry.Live()[0].id, 1);
}

}  // namespace
}  // namespace dynapath::coordinator
