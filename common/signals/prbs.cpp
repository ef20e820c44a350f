#include "signals/prbs.hpp"

#include <random>
#include <stdexcept>

namespace odonata::signals {
namespace {
// Feedback taps (bit masks, bit 0 = stage 1) of maximal-length LFSRs, orders 3..31 (Xilinx
// XAPP052).
std::uint32_t TapsFor(int order) {
  static const int kTaps[32][4] = {{0},
                                   {0},
                                   {0},
                                   {3, 2},
                                   {4, 3},
                                   {5, 3},
                                   {6, 5},
                                   {7, 6},
                                   {8, 6, 5, 4},
                                   {9, 5},
                                   {10, 7},
                                   {11, 9},
                                   {12, 6, 4, 1},
                                   {13, 4, 3, 1},
                                   {14, 5, 3, 1},
                                   {15, 14},
                                   {16, 15, 13, 4},
                                   {17, 14},
                                   {18, 11},
                                   {19, 6, 2, 1},
                                   {20, 17},
                                   {21, 19},
                                   {22, 21},
                                   {23, 18},
                                   {24, 23, 22, 17},
                                   {25, 22},
                                   {26, 6, 2, 1},
                                   {27, 5, 2, 1},
                                   {28, 25},
                                   {29, 27},
                                   {30, 6, 4, 1},
                                   {31, 28}};
  std::uint32_t mask = 0;
  for (const int t : kTaps[order]) {
    if (t > 0) mask |= std::uint32_t{1} << (t - 1);
  }
  return mask;
}
}  // namespace

Prbs::Prbs(int order, int samples_per_bit, double amplitude, std::uint64_t seed)
    : order_(order), samples_per_bit_(samples_per_bit), amplitude_(amplitude) {
  if (order < 3 || order > 31 || samples_per_bit < 1) {
    throw std::invalid_argument("Prbs: need 3 <= order <= 31 and samples_per_bit >= 1");
  }
  taps_ = TapsFor(order);
  std::mt19937_64 rng(seed);
  const std::uint32_t mask = static_cast<std::uint32_t>(period_bits());
  do {
    register_ = static_cast<std::uint32_t>(rng()) & mask;
  } while (register_ == 0);
}

std::vector<double> Prbs::Generate(std::size_t count) {
  std::vector<double> out(count);
  for (std::size_t i = 0; i < count; ++i) {
    if (sample_in_bit_ == 0) {
      // Galois form: shift right, and toggle the tap bits when a 1 falls out.
      const std::uint32_t out_bit = register_ & 1u;
      current_ = out_bit ? amplitude_ : -amplitude_;
      register_ >>= 1;
      if (out_bit) register_ ^= taps_;
    }
    out[i] = current_;
    sample_in_bit_ = (sample_in_bit_ + 1) % samples_per_bit_;
  }
  return out;
}

}  // namespace odonata::signals
