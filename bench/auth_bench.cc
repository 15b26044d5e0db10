// Cost of message authentication (protocol/auth.h): sealing and
// checking one message of a given size, as every Bus does per message.

#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "protocol/auth.h"

namespace {

using dynapath::protocol::KeyFromSecretText;
using dynapath::protocol::Sealer;
using dynapath::protocol::Verifier;

const std::string kChannel = "DYNAPATH/r20261201-000000-1/SHARDS";

void BM_Seal(benchmark::State& state) {
  Sealer sealer(*KeyFromSecretText(std::string(64, 'a')));
  const std::vector<uint8_t> payload(static_cast<size_t>(state.range(0)), 7);
  std::vector<uint8_t> out;
  for (auto _ : state) {
    sealer.Seal(kChannel, payload.data(), payload.size(), out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * state.range(0));
}
BENCHMARK(BM_Seal)->Arg(100)->Arg(2000)->Arg(60000);

// Sealed fresh each time (a new counter), checked once: the receive path.
void BM_SealAndCheck(benchmark::State& state) {
  const auto key = *KeyFromSecretText(std::string(64, 'a'));
  Sealer sealer(key);
  Verifier verifier(key);
  const std::vector<uint8_t> payload(static_cast<size_t>(state.range(0)), 7);
  std::vector<uint8_t> out;
  int size = 0;
  for (auto _ : state) {
    sealer.Seal(kChannel, payload.data(), payload.size(), out);
    if (verifier.Check(kChannel, out.data(), static_cast<int>(out.size()), &size) !=
        Verifier::Verdict::kOk) {
      state.SkipWithError("check failed");
      break;
    }
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * state.range(0));
}
BENCHMARK(BM_SealAndCheck)->Arg(100)->Arg(2000)->Arg(60000);

}  // namespace

BENCHMARK_MAIN();
