#include "protocol/bus.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <lcm/lcm-cpp.hpp>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "dynapath/fragment_nack_t.hpp"
#include "dynapath/heartbeat_t.hpp"
#include "dynapath/step_report_t.hpp"
#include "protocol/auth.h"
#include "protocol/channels.h"
#include "protocol/dispatcher.h"
#include "protocol/fragments.h"
#include "protocol/liveness.h"

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

// Raw bytes sealed under the run's key (here the default, insecure one), as
// a process of the run with a bug would send them: they pass authentication
// and must be caught by decoding and validation.
void PublishSealed(lcm::LCM& lcm, Sealer& sealer, const std::string& channel,
                   const std::vector<uint8_t>& bytes) {
  std::vector<uint8_t> sealed;
  sealer.Seal(channel, bytes.data(), bytes.size(), sealed);
  lcm.publish(channel, sealed.data(), static_cast<unsigned>(sealed.size()));
}

TEST(BusTest, DropsAndCountsForeignAndInvalidMessages) {
  lcm::LCM lcm("memq://");
  Bus other_run(lcm, "run2");
  Bus receiver(lcm, "run1");
  Sealer sealer(InsecureKey());
  const std::string channel = ChannelName("run1", channel::kPolicy);
  int got = 0;
  receiver.Subscribe<policy_t>(channel::kPolicy, [&](policy_t&) { ++got; });
  // Another run's message on our channel name.
  policy_t foreign = Policy("run2", 5);
  std::vector<uint8_t> bytes(static_cast<size_t>(foreign.getEncodedSize()));
  foreign.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  PublishSealed(lcm, sealer, channel, bytes);
  // A message of our run that fails validation (a bad cell code).
  policy_t invalid = Policy("run1", 5);
  invalid.cells[3] = 9;
  bytes.resize(static_cast<size_t>(invalid.getEncodedSize()));
  invalid.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  PublishSealed(lcm, sealer, channel, bytes);
  // Garbage bytes, authenticated.
  PublishSealed(lcm, sealer, channel, {1, 2, 3, 4, 5});
  // A good one last.
  other_run.Publish(channel::kPolicy, Policy("run2", 5));  // goes to run2's channel: unseen
  Bus sender(lcm, "run1");
  sender.Publish(channel::kPolicy, Policy("run1", 5));
  Pump(lcm, [&] { return got > 0 && receiver.counters().dropped >= 3; });
  EXPECT_EQ(got, 1);
  EXPECT_EQ(receiver.counters().dropped, 3);
  EXPECT_EQ(receiver.counters().unauthenticated, 0);
}

TEST(BusTest, DropsUnauthenticatedAndReplayedMessagesBeforeDecoding) {
  lcm::LCM lcm("memq://");
  BusOptions keyed;
  keyed.key = *KeyFromSecretText("0123456789abcdef0123456789abcdef-run-a");
  BusOptions other_key;
  other_key.key = *KeyFromSecretText("0123456789abcdef0123456789abcdef-run-b");
  Bus receiver(lcm, "run1", keyed);
  int got = 0;
  receiver.Subscribe<policy_t>(channel::kPolicy, [&](policy_t&) { ++got; });
  const std::string channel = ChannelName("run1", channel::kPolicy);
  // A valid message without a tag, and one with another run's key (or
  // --insecure): both unauthenticated.
  const policy_t policy = Policy("run1", 5);
  std::vector<uint8_t> bytes(static_cast<size_t>(policy.getEncodedSize()));
  policy.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  lcm.publish(channel, bytes.data(), static_cast<unsigned>(bytes.size()));
  Bus stranger(lcm, "run1", other_key);
  stranger.Publish(channel::kPolicy, policy);
  Bus insecure(lcm, "run1");
  insecure.Publish(channel::kPolicy, policy);
  // A well-tagged message, then the same bytes again (a replay).
  Sealer sealer(keyed.key);
  std::vector<uint8_t> sealed;
  sealer.Seal(channel, bytes.data(), bytes.size(), sealed);
  lcm.publish(channel, sealed.data(), static_cast<unsigned>(sealed.size()));
  lcm.publish(channel, sealed.data(), static_cast<unsigned>(sealed.size()));
  // The same tagged message moved to another channel of the run.
  const std::string report = ChannelName("run1", channel::kReport);
  receiver.Subscribe<step_report_t>(channel::kReport, [&](step_report_t&) { ++got; });
  lcm.publish(report, sealed.data(), static_cast<unsigned>(sealed.size()));
  Pump(lcm, [&] { return receiver.counters().dropped >= 5; });
  EXPECT_EQ(got, 1);
  const BusCounters c = receiver.counters();
  EXPECT_EQ(c.unauthenticated, 4);
  EXPECT_EQ(c.replayed, 1);
  EXPECT_EQ(c.dropped, 5);
  EXPECT_EQ(receiver.TrafficSummary(),
            "published 0, received 1, dropped 5 (4 unauthenticated, 1 replayed, 0 invalid)");
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

// The NACKs of a run as a passive listener sees them: each one's missing
// pieces.
class NackListener {
 public:
  void Handle(const lcm::ReceiveBuffer* buffer, const std::string& /*channel*/) {
    const auto* data = static_cast<const uint8_t*>(buffer->data);
    const int size = PayloadSize(data, static_cast<int>(buffer->data_size));
    fragment_nack_t nack;
    if (nack.decode(data, 0, size) != size) {
      ++undecoded;
      return;
    }
    std::vector<int32_t> missing;
    for (int32_t i = 0; i < nack.count; ++i) {
      if (NackBit(nack.missing, i)) missing.push_back(i);
    }
    nacked.push_back(std::move(missing));
  }
  std::vector<std::vector<int32_t>> nacked;
  int undecoded = 0;
};

// Selective repair through a transport that loses chosen pieces: the
// receiver NACKs the pieces it lacks, the sender re-sends exactly the
// pieces NACKed (again when a repair is lost too) and the message completes
// once. How many NACKs that takes depends on timing: a receiver that hears
// nothing within the retry interval (20 ms here) asks again, and on a
// loaded machine the dispatch thread can be away that long. So the test
// checks the pieces re-sent against the NACKs it sees, not a count; the
// intervals themselves are FragmentAssembler's, checked in fragments_test.
TEST(BusTest, NackedPiecesAndOnlyThoseAreResent) {
  lcm::LCM lcm("memq://");
  BusOptions options;
  options.fragment_above = 2000;
  options.fragment_size = 1024;
  std::mutex mutex;
  std::vector<int32_t> repaired;
  int repairs_of_3 = 0;
  BusOptions lossy = options;
  lossy.drop_fragment = [&](const fragment_t& f, bool repair) {
    std::lock_guard lock(mutex);
    if (repair) {
      repaired.push_back(f.index);
      return f.index == 3 && repairs_of_3++ == 0;  // the first repair of 3 is lost too
    }
    return f.index == 1 || f.index == 3;
  };
  Bus sender(lcm, "run1", lossy);
  Bus receiver(lcm, "run1", options);
  NackListener listener;
  lcm.subscribe(ChannelName("run1", channel::kFragmentNack), &NackListener::Handle, &listener);
  std::vector<policy_t> got;
  receiver.Subscribe<policy_t>(channel::kPolicy, [&](policy_t& m) { got.push_back(m); });
  const policy_t sent = Policy("run1", 40);  // 5 pieces
  sender.Publish(channel::kPolicy, sent);
  Pump(
      lcm, [&] { return !got.empty(); }, std::chrono::milliseconds(3000));
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].cells, sent.cells);
  // A NACK sent just before the last repair completed the message reaches
  // the listener and the sender in one dispatch.
  Pump(lcm, [&] {
    return receiver.counters().nacks_sent == static_cast<int64_t>(listener.nacked.size());
  });
  EXPECT_EQ(listener.undecoded, 0);
  ASSERT_GE(listener.nacked.size(), 2u);
  // The first NACK asks for the two lost pieces (and for pieces after the
  // first still under way, if the dispatch thread was away longer than the
  // quiet period between them); piece 0, which made the message known, never.
  const std::vector<int32_t>& first = listener.nacked.front();
  const std::vector<int32_t> lost = {1, 3};
  EXPECT_TRUE(std::includes(first.begin(), first.end(), lost.begin(), lost.end()))
      << ::testing::PrintToString(first);
  for (const std::vector<int32_t>& nack : listener.nacked) {
    EXPECT_TRUE(std::find(nack.begin(), nack.end(), 0) == nack.end());
  }
  // Exactly the pieces NACKed are re-sent, NACK by NACK; 3 at least twice,
  // as its first repair was lost.
  std::vector<int32_t> asked;
  for (const std::vector<int32_t>& nack : listener.nacked) {
    asked.insert(asked.end(), nack.begin(), nack.end());
  }
  {
    std::lock_guard lock(mutex);
    EXPECT_EQ(repaired, asked);
    EXPECT_GE(std::count(repaired.begin(), repaired.end(), 3), 2);
  }
  const auto nacks = static_cast<int64_t>(listener.nacked.size());
  EXPECT_EQ(receiver.counters().nacks_sent, nacks);
  EXPECT_EQ(sender.counters().nacks_received, nacks);
  EXPECT_EQ(sender.counters().pieces_repaired, static_cast<int64_t>(asked.size()));
  EXPECT_GE(receiver.counters().repair_round_trip_ms, 0);
  // Nothing more is asked for once complete.
  Pump(
      lcm, [&] { return false; }, std::chrono::milliseconds(200));
  EXPECT_EQ(receiver.counters().nacks_sent, nacks);
  EXPECT_EQ(got.size(), 1u);
}

// Parity pieces (BusOptions::parity_group): a policy of 5 pieces with groups
// of 2 makes 3 interleaved groups, {0, 3}, {1, 4} and {2}. Losing 0 and 4
// (one per group) costs no NACK: both are rebuilt. Losing 0 and 3 (both of
// one group) is rebuilt as far as it can be and NACKed for the rest. The
// receiver waits a second of quiet before a NACK and before asking again,
// so that NACKs are counted as loss makes them, not as a loaded machine's
// scheduling does.
TEST(BusTest, ParityPiecesRebuildOneLostPiecePerGroup) {
  for (const std::vector<int32_t>& lost :
       {std::vector<int32_t>{0, 4}, std::vector<int32_t>{0, 3}}) {
    lcm::LCM lcm("memq://");
    BusOptions options;
    options.fragment_above = 2000;
    options.fragment_size = 1024;
    options.parity_group = 2;
    options.parity_after_loss = false;  // from the first message
    options.nack_quiet_ms = 1000;
    options.nack_retry_ms = 1000;
    std::mutex mutex;
    int parity_pieces = 0;
    BusOptions lossy = options;
    lossy.drop_fragment = [&](const fragment_t& f, bool repair) {
      std::lock_guard lock(mutex);
      if (f.parity) {
        ++parity_pieces;
        return false;
      }
      return !repair && std::find(lost.begin(), lost.end(), f.index) != lost.end();
    };
    Bus sender(lcm, "run1", lossy);
    Bus receiver(lcm, "run1", options);
    std::vector<policy_t> got;
    receiver.Subscribe<policy_t>(channel::kPolicy, [&](policy_t& m) { got.push_back(m); });
    const policy_t sent = Policy("run1", 40);
    sender.Publish(channel::kPolicy, sent);
    Pump(
        lcm, [&] { return !got.empty(); }, std::chrono::milliseconds(3000));
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0].cells, sent.cells);
    std::lock_guard lock(mutex);
    EXPECT_EQ(parity_pieces, 3);
    EXPECT_EQ(sender.counters().parity_sent, 3);
    if (lost[1] == 4) {
      EXPECT_EQ(receiver.counters().pieces_rebuilt, 2);
      EXPECT_EQ(receiver.counters().nacks_sent, 0);
      EXPECT_EQ(sender.counters().pieces_repaired, 0);
    } else {
      EXPECT_EQ(receiver.counters().nacks_sent, 1);
      // One repair makes the group rebuildable; the NACK asked for both.
      EXPECT_EQ(sender.counters().pieces_repaired, 2);
    }
  }
}

// By default parity pieces go out while the Bus has seen loss lately: none
// on a clean link, then with every whole sending for parity_hold_ms after
// a NACK. (The receiver waits a second of quiet and asks again only after
// a second, and the hold is long: one NACK, and parity on the third
// message, however the test thread is stalled on a loaded machine.)
TEST(BusTest, ParityPiecesStartOnceLossIsSeen) {
  lcm::LCM lcm("memq://");
  BusOptions options;
  options.fragment_above = 2000;
  options.fragment_size = 1024;
  options.parity_group = 2;
  options.nack_quiet_ms = 1000;
  options.nack_retry_ms = 1000;
  options.parity_hold_ms = 30000;
  int sending = 0;
  BusOptions lossy = options;
  lossy.drop_fragment = [&](const fragment_t& f, bool repair) {
    return sending == 1 && !repair && !f.parity && f.index == 2;  // the second message loses 2
  };
  Bus sender(lcm, "run1", lossy);
  Bus receiver(lcm, "run1", options);
  int got = 0;
  receiver.Subscribe<policy_t>(channel::kPolicy, [&](policy_t&) { ++got; });
  for (sending = 0; sending < 3; ++sending) {
    sender.Publish(channel::kPolicy, Policy("run1", 40 + sending));
    Pump(
        lcm, [&] { return got > sending; }, std::chrono::milliseconds(3000));
    ASSERT_EQ(got, sending + 1);
    // Clean first message: no parity; the second was repaired by a NACK;
    // the third carries parity pieces (3 groups of 5 pieces).
    EXPECT_EQ(sender.counters().parity_sent, sending < 2 ? 0 : 3) << sending;
  }
  EXPECT_EQ(receiver.counters().nacks_sent, 1);
}

// A component's resend of the same bytes reuses the message id: its pieces
// fill the gaps the first attempt left (here without NACKs).
TEST(BusTest, ResendOfTheSameMessageFillsGaps) {
  lcm::LCM lcm("memq://");
  BusOptions options;
  options.fragment_above = 2000;
  options.fragment_size = 1024;
  options.repair = false;
  int attempt = 0;
  BusOptions lossy = options;
  lossy.drop_fragment = [&](const fragment_t& f, bool) {
    return attempt == 0 ? (f.index == 0 || f.index == 2) : (f.index != 0 && f.index != 2);
  };
  Bus sender(lcm, "run1", lossy);
  Bus receiver(lcm, "run1", options);
  int got = 0;
  receiver.Subscribe<policy_t>(channel::kPolicy, [&](policy_t&) { ++got; });
  const policy_t sent = Policy("run1", 40);
  sender.Publish(channel::kPolicy, sent);
  Pump(
      lcm, [&] { return false; }, std::chrono::milliseconds(100));
  EXPECT_EQ(got, 0);
  attempt = 1;  // only the pieces the first attempt lost get through
  sender.Publish(channel::kPolicy, sent);
  Pump(lcm, [&] { return got > 0; });
  EXPECT_EQ(got, 1);
  EXPECT_EQ(sender.counters().ids_reused, 1);
  // Other bytes are another message.
  sender.Publish(channel::kPolicy, Policy("run1", 41));
  EXPECT_EQ(sender.counters().ids_reused, 1);
}

// Pieces of one Ethernet frame only when datagrams leave the host.
TEST(BusTest, FragmentSizeFollowsTheUrlsTtl) {
  EXPECT_EQ(DefaultFragmentSize("udpm://239.255.76.67:7667?ttl=1"), kFrameFragmentSize);
  EXPECT_EQ(DefaultFragmentSize("udpm://239.255.76.67:7667?recv_buf_size=2000000&ttl=3"),
            kFrameFragmentSize);
  EXPECT_EQ(DefaultFragmentSize("udpm://239.255.76.67:7667?ttl=0"), 60000);
  EXPECT_EQ(DefaultFragmentSize("udpm://239.255.76.67:7667"), 60000);
  EXPECT_EQ(DefaultFragmentSize("udpm://239.255.76.67:7667?ttl=x"), 60000);
  EXPECT_EQ(DefaultFragmentSize("memq://"), 60000);
  EXPECT_EQ(DefaultFragmentSize("file:///tmp/log?mode=w&ttl=1"), 60000);
}

// A udpm URL without a receive buffer asks for 2 MiB, or the kernel's
// most when that is less (LCM warns above it); a URL's own is kept.
TEST(BusTest, UdpmUrlsAskForAReceiveBuffer) {
  EXPECT_EQ(WithReceiveBuffer("udpm://239.255.76.67:7667?ttl=0", int64_t{4} << 20),
            "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=2097152");
  EXPECT_EQ(WithReceiveBuffer("udpm://239.255.76.67:7667", 212992),
            "udpm://239.255.76.67:7667?recv_buf_size=212992");
  EXPECT_EQ(WithReceiveBuffer("udpm://239.255.76.67:7667?recv_buf_size=9000&ttl=1", 1 << 30),
            "udpm://239.255.76.67:7667?recv_buf_size=9000&ttl=1");
  EXPECT_EQ(WithReceiveBuffer("udpm://239.255.76.67:7667?ttl=0", 0),
            "udpm://239.255.76.67:7667?ttl=0");
  EXPECT_EQ(WithReceiveBuffer("memq://", 1 << 30), "memq://");
  EXPECT_EQ(WithReceiveBuffer("file:///tmp/log?mode=w", 1 << 30), "file:///tmp/log?mode=w");
}

// Paused is not dead: a process that did not run for longer than half the
// timeout (SIGSTOP, a debugger) counts the coordinator's silence again from
// its wake-up; a coordinator silent while this process runs is still gone
// after the timeout.
TEST(CoordinatorWatchTest, OwnPauseIsNotTheCoordinatorsSilence) {
  lcm::LCM lcm("memq://");
  Bus coordinator(lcm, "run1");
  Bus agent(lcm, "run1");
  CoordinatorWatch watch(agent, nullptr);
  heartbeat_t beat{};
  beat.run_id = "run1";
  beat.role = heartbeat_t::ROLE_COORDINATOR;
  beat.state = heartbeat_t::STATE_RUNNING;
  coordinator.Publish(channel::kHeartbeat, beat);
  Pump(lcm, [&] { return watch.Seen(); });
  ASSERT_TRUE(watch.Seen());
  using Verdict = CoordinatorWatch::Verdict;
  const double timeout = 1.0;
  EXPECT_EQ(watch.Check(10, timeout), Verdict::kRunning);

  // "Paused" for 2.5 s (no check at all): over twice the timeout, yet running.
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  EXPECT_EQ(watch.Check(10, timeout), Verdict::kRunning);

  // Running and checking often while the coordinator stays silent: gone
  // once the timeout has passed since the wake-up.
  Verdict verdict = Verdict::kRunning;
  const auto start = std::chrono::steady_clock::now();
  while (verdict == Verdict::kRunning &&
         std::chrono::steady_clock::now() - start < std::chrono::seconds(5)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    verdict = watch.Check(10, timeout);
  }
  EXPECT_EQ(verdict, Verdict::kGone);
  EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(990));
}

}  // namespace
}  // namespace dynapath::protocol

namespace dynapath::protocol {
namespace {

// Others' silence is counted from the end of the caller's last gap between
// checks longer than the bound (its own pause), from 0 before any.
TEST(ResumeClockTest, CountsFromTheEndOfTheLastLongGap) {
  ResumeClock clock(1000);
  EXPECT_EQ(clock.CountedFrom(5000), 0);
  EXPECT_EQ(clock.CountedFrom(5020), 0);
  EXPECT_EQ(clock.CountedFrom(6020), 0);  // exactly the bound: not a pause
  EXPECT_EQ(clock.CountedFrom(8000), 8000);
  EXPECT_EQ(clock.CountedFrom(8500), 8000);
  EXPECT_EQ(clock.CountedFrom(9600), 9600);
}

}  // namespace
}  // namespace dynapath::protocol
