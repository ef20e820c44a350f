// The cost of signed messages (docs/lcm.md §15): signing one message as a publisher does, and
// verifying it as each receiver does, for the sizes the bus carries (a receipt, a command or a
// state, a prediction, a model snapshot). Target: ≤ 2 µs per message of the lockstep loop.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "bus/bus_node.hpp"
#include "bus/message_signer.hpp"

namespace {

using odonata::bus::MessageSigner;

odonata::bus::BusKey Key() {
  odonata::bus::BusKey k;
  for (std::size_t i = 0; i < k.bytes.size(); ++i) k.bytes[i] = static_cast<unsigned char>(i);
  return k;
}

void BM_Sign(benchmark::State& state) {
  MessageSigner signer(Key(), 1);
  const std::vector<uint8_t> payload(static_cast<std::size_t>(state.range(0)), 0x5a);
  std::vector<uint8_t> bytes;
  int64_t now = odonata::bus::NowUtime();
  for (auto _ : state) {
    bytes = payload;
    signer.Sign("DIMAV_STATE", &bytes, ++now);
    benchmark::DoNotOptimize(bytes.data());
  }
  state.SetBytesProcessed(state.iterations() * state.range(0));
}

void BM_Verify(benchmark::State& state) {
  MessageSigner signer(Key(), 1), receiver(Key(), 2);
  const std::vector<uint8_t> payload(static_cast<std::size_t>(state.range(0)), 0x5a);
  // Messages signed beforehand, each verified once (a second time would be a replay).
  constexpr std::size_t kBatch = 4096;
  std::vector<std::vector<uint8_t>> batch(kBatch, payload);
  int64_t now = odonata::bus::NowUtime();
  std::size_t i = kBatch;
  for (auto _ : state) {
    if (i == kBatch) {
      state.PauseTiming();
      for (auto& b : batch) {
        b = payload;
        signer.Sign("DIMAV_STATE", &b, ++now);
      }
      i = 0;
      state.ResumeTiming();
    }
    std::size_t n = 0;
    const auto v = receiver.Verify("DIMAV_STATE", batch[i].data(), batch[i].size(), now, &n);
    if (v != MessageSigner::Verdict::kAuthentic) state.SkipWithError("not authentic");
    ++i;
  }
  state.SetBytesProcessed(state.iterations() * state.range(0));
}

// 80 B: a receipt; 300 B: a command or a state; 1 kB: a prediction; 64 kB: a model snapshot.
BENCHMARK(BM_Sign)->Arg(80)->Arg(300)->Arg(1024)->Arg(65536);
BENCHMARK(BM_Verify)->Arg(80)->Arg(300)->Arg(1024)->Arg(65536);

}  // namespace

BENCHMARK_MAIN();
