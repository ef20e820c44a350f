// Publishes malformed traffic on the project's channels, for the bad-input integration test:
// wrong fingerprints, truncated and random bytes, NaN/Inf fields, out-of-range commands,
// stale (duplicate / out-of-order), negative and far-future sequence numbers, and absurd array
// counts.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "odonata/beat_state_t.hpp"
#include "odonata/control_t.hpp"
#include "odonata/heartbeat_t.hpp"
#include "odonata/plant_state_t.hpp"
#include "odonata/prediction_t.hpp"
#include "odonata/wing_command_t.hpp"

namespace {

template <class Msg>
std::vector<uint8_t> Encode(const Msg& m) {
  std::vector<uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  return buf;
}

odonata::wing_command_t Command(int64_t seq) {
  odonata::wing_command_t c{};
  c.seq = seq;
  for (int w = 0; w < 4; ++w) {
    c.freq_hz[w] = 5.4;
    c.amp_rad[w] = 1.0;
    c.pitch_mean_rad[w] = 1.57;
    c.pitch_amp_rad[w] = 0.78;
  }
  c.num_excitations = 1;
  c.excitation_names = {"u_roll_rad"};
  c.excitations = {0.0};
  c.source = "bad-input-test";
  return c;
}

odonata::plant_state_t State(int64_t seq) {
  odonata::plant_state_t s{};
  s.seq = seq;
  s.command_seq = seq - 1;
  return s;
}

odonata::beat_state_t Beat(int64_t seq) {
  odonata::beat_state_t b{};
  b.seq = seq;
  b.command_seq = seq - 1;
  return b;
}

// A short LC02 datagram whose channel name has no terminating NUL: LCM 1.3.1 hands it to
// subscribers with data_size -1. Sent with a plain UDP socket, as lcm_publish cannot make one.
void SendUnterminatedChannel(const std::string& url) {
  const auto at = url.find("://"), colon = url.rfind(':'), query = url.find('?');
  if (at == std::string::npos || colon == std::string::npos || colon < at + 3) return;
  const std::string group = url.substr(at + 3, colon - at - 3);
  const int port = std::atoi(
      url.substr(colon + 1, query == std::string::npos ? std::string::npos : query - colon - 1)
          .c_str());
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) return;
  unsigned char ttl = 0;
  setsockopt(fd, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<uint16_t>(port));
  inet_pton(AF_INET, group.c_str(), &to.sin_addr);
  const char packet[] = {'L', 'C', '0', '2', 0,   0,   0,   1,   'D', 'I',
                         'M', 'A', 'V', '_', 'S', 'T', 'A', 'T', 'E'};
  sendto(fd, packet, sizeof packet, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
  close(fd);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: bad_input_publisher LCM_URL ROUNDS [PERIOD_MS]\n");
    return 2;
  }
  lcm::LCM lcm(argv[1]);
  if (!lcm.good()) return 1;
  const int rounds = std::atoi(argv[2]);
  const int period_ms = argc > 3 ? std::atoi(argv[3]) : 5;
  std::mt19937_64 rng(99);
  const std::vector<std::string> channels = {
      "DIMAV_COMMAND",   "DIMAV_STATE",   "DIMAV_BEAT_STATE", "ODONATA_PREDICTION",
      "ODONATA_CONTROL", "ODONATA_MODEL", "ODONATA_HEARTBEAT"};
  for (int r = 0; r < rounds; ++r) {
    for (const auto& ch : channels) {
      // A valid message of another type: wrong fingerprint for this channel.
      odonata::heartbeat_t hb{};
      hb.service = "bad";
      auto wrong = Encode(hb);
      if (ch != "ODONATA_HEARTBEAT")
        lcm.publish(ch, wrong.data(), static_cast<unsigned>(wrong.size()));
      // Random bytes.
      std::vector<uint8_t> noise(1 + rng() % 200);
      for (auto& b : noise) b = static_cast<uint8_t>(rng());
      lcm.publish(ch, noise.data(), static_cast<unsigned>(noise.size()));
    }
    // Truncated messages of the right type.
    auto cmd = Encode(Command(1));
    lcm.publish("DIMAV_COMMAND", cmd.data(), static_cast<unsigned>(cmd.size() / 2));
    auto st = Encode(State(1));
    lcm.publish("DIMAV_STATE", st.data(), static_cast<unsigned>(st.size() - 3));
    auto bt = Encode(Beat(1));
    lcm.publish("DIMAV_BEAT_STATE", bt.data(), static_cast<unsigned>(bt.size() - 5));
    // A correct fingerprint with an absurd array count.
    auto big = Encode(Command(2));
    const std::size_t count_at = 8 + 8 + 8 + 8 + 6 * 4 * 8;  // fingerprint, utime, seq, t_s, arrays
    big[count_at] = 0x7f;
    lcm.publish("DIMAV_COMMAND", big.data(), static_cast<unsigned>(big.size()));
    // NaN and Inf fields; stale sequence numbers (already used: must not rewrite history).
    odonata::plant_state_t nan_state = State(2);
    nan_state.attitude_rad[0] = NAN;
    lcm.publish("DIMAV_STATE", &nan_state);
    odonata::wing_command_t inf_cmd = Command(3);
    inf_cmd.freq_hz[0] = INFINITY;
    lcm.publish("DIMAV_COMMAND", &inf_cmd);
    // Well-formed but stale (a seq the run never reaches again) and far outside the limits.
    odonata::wing_command_t wild = Command(-7);
    wild.freq_hz[1] = 1e6;  // far outside the actuator limits
    wild.amp_rad[2] = -50;
    lcm.publish("DIMAV_COMMAND", &wild);
    lcm.publish("DIMAV_STATE", &nan_state);
    odonata::plant_state_t stale = State(-100);
    lcm.publish("DIMAV_STATE", &stale);
    // Well-formed, within limits, but with a seq far in the future or negative: if accepted, either
    // would make every genuine message after it look stale and stall the run.
    odonata::wing_command_t leap = Command(int64_t{1} << 40);
    lcm.publish("DIMAV_COMMAND", &leap);
    odonata::wing_command_t negative = Command(-3);
    lcm.publish("DIMAV_COMMAND", &negative);
    odonata::plant_state_t future = State(int64_t{1} << 40);
    lcm.publish("DIMAV_STATE", &future);
    // The same for the beat states: NaN, stale, negative and far-future seqs.
    odonata::beat_state_t nan_beat = Beat(2);
    nan_beat.u_roll_applied_rad = NAN;
    lcm.publish("DIMAV_BEAT_STATE", &nan_beat);
    odonata::beat_state_t stale_beat = Beat(-100);
    lcm.publish("DIMAV_BEAT_STATE", &stale_beat);
    odonata::beat_state_t future_beat = Beat(int64_t{1} << 40);
    lcm.publish("DIMAV_BEAT_STATE", &future_beat);
    // A prediction whose count claims more outputs than the arrays hold. encode() trusts the
    // count, so build a consistent one and then overwrite the count in the bytes.
    odonata::prediction_t p{};
    p.num_outputs = 1;
    p.names = {"roll_rad"};
    p.measured = p.predicted = p.free_run = p.next = p.max_entropy = p.arx_predicted =
        p.arx_free_run = {0.0};
    p.linear_share = {0.0};
    p.rules = {1};
    auto pb = Encode(p);
    pb[8 + 8 + 8 + 8 + 3] = 5;  // fingerprint, utime, seq, sample; then int32 num_outputs
    lcm.publish("ODONATA_PREDICTION", pb.data(), static_cast<unsigned>(pb.size()));
    // A well-formed prediction for a sample far ahead: if scored, the monitor would take the
    // genuine ones after it for a new run and throw the run's accuracy away.
    p.sample = int64_t{1} << 40;
    lcm.publish("ODONATA_PREDICTION", &p);
    odonata::control_t bad_control{};
    bad_control.command = 99;
    bad_control.target = "nobody-in-particular";
    lcm.publish("ODONATA_CONTROL", &bad_control);
    SendUnterminatedChannel(argv[1]);
    usleep(static_cast<useconds_t>(period_ms * 1000));
  }
  return 0;
}
