// main() for the fuzz harnesses when libFuzzer is not linked in (GCC builds, and CI's short
// runs): feeds every file of the given corpus directories, then a fixed number of mutations of
// them (bit flips, byte sets, insertions, deletions, truncations, splices) from a seeded
// generator, so a run is repeatable. A crash, a sanitizer report or an uncaught exception fails
// the run; the input that did it stays in ./.fuzz-current-<harness> (written before each run).
//
// Usage: HARNESS [--runs N] [--seed S] [--max-len BYTES] CORPUS_DIR_OR_FILE...
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

using Bytes = std::vector<uint8_t>;

Bytes ReadFile(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), {});
}

Bytes Mutate(const std::vector<Bytes>& corpus, std::mt19937_64& rng, std::size_t max_len) {
  Bytes b = corpus.empty() ? Bytes{} : corpus[rng() % corpus.size()];
  const int edits = 1 + static_cast<int>(rng() % 8);
  for (int e = 0; e < edits; ++e) {
    const std::size_t n = b.size();
    switch (rng() % 7) {
      case 0:  // flip a bit
        if (n) b[rng() % n] ^= static_cast<uint8_t>(1u << (rng() % 8));
        break;
      case 1: {  // set a byte to an interesting value
        static const uint8_t values[] = {0,   1,   0x7f, 0x80, 0xff, '0', '9', ',', '\n',
                                         '"', '-', '.',  'e',  '[',  ']', '{', '}', ':'};
        if (n) b[rng() % n] = values[rng() % sizeof values];
        break;
      }
      case 2:  // insert random bytes
        b.insert(b.begin() + static_cast<long>(n ? rng() % (n + 1) : 0),
                 static_cast<std::size_t>(1 + rng() % 8), static_cast<uint8_t>(rng()));
        break;
      case 3:  // delete a range
        if (n) {
          const std::size_t at = rng() % n, len = 1 + rng() % std::min<std::size_t>(n - at, 16);
          b.erase(b.begin() + static_cast<long>(at), b.begin() + static_cast<long>(at + len));
        }
        break;
      case 4:  // truncate
        if (n) b.resize(rng() % n);
        break;
      case 5: {  // splice with another entry
        if (corpus.empty()) break;
        const Bytes& o = corpus[rng() % corpus.size()];
        if (o.empty()) break;
        const std::size_t from = rng() % o.size(), len = 1 + rng() % (o.size() - from);
        b.insert(b.begin() + static_cast<long>(n ? rng() % (n + 1) : 0),
                 o.begin() + static_cast<long>(from), o.begin() + static_cast<long>(from + len));
        break;
      }
      case 6: {  // overwrite 4 bytes with a big-endian extreme integer (counts, lengths)
        static const uint32_t values[] = {0, 1, 0x7fffffffu, 0x80000000u, 0xffffffffu, 1u << 30};
        if (n >= 4) {
          const std::size_t at = rng() % (n - 3);
          const uint32_t v = values[rng() % (sizeof values / sizeof values[0])];
          for (int k = 0; k < 4; ++k)
            b[at + static_cast<std::size_t>(k)] = static_cast<uint8_t>(v >> (24 - 8 * k));
        }
        break;
      }
    }
  }
  if (b.size() > max_len) b.resize(max_len);
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  long runs = 10000;
  uint64_t seed = 1;
  std::size_t max_len = 1 << 16;
  std::vector<Bytes> corpus;
  const std::string name = std::filesystem::path(argv[0]).filename().string();
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc) {
      runs = std::atol(argv[++i]);
    } else if (a == "--seed" && i + 1 < argc) {
      seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (a == "--max-len" && i + 1 < argc) {
      max_len = static_cast<std::size_t>(std::atol(argv[++i]));
    } else if (std::filesystem::is_directory(a)) {
      for (const auto& e : std::filesystem::directory_iterator(a))
        if (e.is_regular_file()) corpus.push_back(ReadFile(e.path()));
    } else if (std::filesystem::is_regular_file(a)) {
      corpus.push_back(ReadFile(a));
    } else {
      std::fprintf(stderr, "%s: no such corpus '%s'\n", name.c_str(), a.c_str());
      return 2;
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  long executions = 0;
  const auto run_one = [&](const Bytes& b) {
    // Saved before the run: a sanitizer abort leaves no chance afterwards.
    std::ofstream(".fuzz-current-" + name, std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    LLVMFuzzerTestOneInput(b.data(), b.size());
    ++executions;
  };
  for (const Bytes& b : corpus) run_one(b);
  std::mt19937_64 rng(seed);
  for (long r = 0; r < runs; ++r) run_one(Mutate(corpus, rng, max_len));
  std::filesystem::remove(".fuzz-current-" + name);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "%s: %ld executions (%zu corpus entries, %ld mutations, seed %llu) in %.1f s, no crash\n",
      name.c_str(), executions, corpus.size(), runs, static_cast<unsigned long long>(seed), s);
  return 0;
}
