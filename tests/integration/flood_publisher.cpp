// flood_publisher URL SECONDS [snapshots]: the floods of issue 24 point 5, as fast as LCM sends
// them for SECONDS — predictions of 1000 outputs with names never seen before, model snapshots
// of about 14 MB from ever new instances, heartbeats of ever new peers, and random bytes on every
// channel — so run_flood_bench.sh can read what the monitor and the logger hold meanwhile. With
// `snapshots`, only the 14 MB snapshots (issue 51 point 4: what they cost a signed run).
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "odonata/heartbeat_t.hpp"
#include "odonata/model_snapshot_t.hpp"
#include "odonata/prediction_t.hpp"

int main(int argc, char** argv) {
  if (argc != 3 && !(argc == 4 && std::string(argv[3]) == "snapshots")) {
    std::fprintf(stderr, "usage: flood_publisher LCM_URL SECONDS [snapshots]\n");
    return 2;
  }
  const bool only_snapshots = argc == 4;
  lcm::LCM lcm(argv[1]);
  if (!lcm.good()) return 1;
  const auto end =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(std::atof(argv[2]));
  std::mt19937_64 rng(7);
  long predictions = 0, snapshots = 0, heartbeats = 0, garbage = 0;
  for (int64_t k = 0; std::chrono::steady_clock::now() < end; ++k) {
    if (only_snapshots) {
      odonata::model_snapshot_t m{};
      m.seq = k;
      m.instance = "flood-" + std::to_string(k);
      m.num_regressors = 900000;
      m.regressor_mid = m.regressor_half = std::vector<double>(900000, 1.0);
      snapshots += lcm.publish("ODONATA_MODEL", &m) == 0;
      continue;
    }
    odonata::prediction_t p{};
    p.seq = k;
    p.sample = k;
    p.num_outputs = 1000;
    for (int i = 0; i < p.num_outputs; ++i)
      p.names.push_back("out_" + std::to_string(k) + "_" + std::to_string(i));
    p.measured = p.predicted = p.free_run = p.next = p.max_entropy = p.arx_predicted =
        p.arx_free_run = std::vector<double>(1000, 0.5);
    p.linear_share = std::vector<double>(1000, 0.0);
    p.rules = std::vector<int32_t>(1000, 1);
    p.learning = 1;
    predictions += lcm.publish("ODONATA_PREDICTION", &p) == 0;
    if (k % 4 == 0) {
      // A snapshot whose regressor arrays make it about 14 MB.
      odonata::model_snapshot_t m{};
      m.seq = k;
      m.instance = "flood-" + std::to_string(k);
      m.num_regressors = 900000;
      m.regressor_mid = m.regressor_half = std::vector<double>(900000, 1.0);
      snapshots += lcm.publish("ODONATA_MODEL", &m) == 0;
    }
    odonata::heartbeat_t h{};
    h.seq = k;
    h.service = "odonata-identifier";
    h.instance = "peer-" + std::to_string(k);
    h.state = "running";
    heartbeats += lcm.publish("ODONATA_HEARTBEAT", &h) == 0;
    std::vector<uint8_t> noise(1 + rng() % 60000);
    for (auto& b : noise) b = static_cast<uint8_t>(rng());
    for (const std::string& ch : {std::string("DIMAV_STATE"), std::string("ODONATA_PREDICTION"),
                                  "FLOOD_" + std::to_string(k)})  // and a channel never seen
      garbage += lcm.publish(ch, noise.data(), static_cast<unsigned>(noise.size())) == 0;
  }
  std::printf(
      "flood: %ld predictions of 1000 new outputs, %ld snapshots of 14 MB, %ld heartbeats of "
      "new peers, %ld garbage messages\n",
      predictions, snapshots, heartbeats, garbage);
  return 0;
}
