// forger URL SECONDS KEY_FILE: what an attacker on the bus of a signed system can send without
// the key, for SECONDS (signed_bus_test.sh): every kind of well-formed forged message the probe
// of issue 24 used (a lone state 0, far, negative and duplicate seqs, receipts far ahead in the
// consumers' names, control commands and replies, a snapshot, a heartbeat of a consumer that does
// not exist), each sent unsigned and signed with a wrong key; the key file's own key stamped a
// minute ago (a log replayed later); and every genuine signed message it overhears, sent again
// at once (capture and replay). Prints how many it sent of each.
#include <poll.h>
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bus/bus_node.hpp"
#include "bus/message_signer.hpp"
#include "odonata/ack_t.hpp"
#include "odonata/control_reply_t.hpp"
#include "odonata/control_t.hpp"
#include "odonata/heartbeat_t.hpp"
#include "odonata/model_snapshot_t.hpp"
#include "odonata/plant_state_t.hpp"
#include "odonata/wing_command_t.hpp"

namespace {

using odonata::bus::MessageSigner;

volatile std::sig_atomic_t g_stop = 0;

template <class Msg>
std::vector<uint8_t> Encode(const Msg& m) {
  std::vector<uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

struct Forged {
  std::string channel;
  std::vector<uint8_t> bytes;
};

std::vector<Forged> ForgedKinds(int64_t now) {
  std::vector<Forged> out;
  for (int64_t seq : {int64_t{0}, int64_t{1} << 40, int64_t{-5}, int64_t{5}}) {
    odonata::plant_state_t s{};
    s.utime = now;
    s.seq = seq;
    s.command_seq = seq == 0 ? -1 : seq;
    out.push_back({"DIMAV_STATE", Encode(s)});
    odonata::wing_command_t c{};
    c.utime = now;
    c.seq = seq;
    c.source = "forger";
    out.push_back({"DIMAV_COMMAND", Encode(c)});
  }
  for (const char* consumer : {"identifier", "logger"}) {
    odonata::ack_t a{};
    a.utime = now;
    a.service = std::string("odonata-") + consumer;
    a.instance = consumer;
    a.state_seq = 1'000'000;
    out.push_back({"ODONATA_ACK", Encode(a)});
  }
  int8_t commands[] = {odonata::control_t::FREEZE, odonata::control_t::SHUTDOWN,
                       odonata::control_t::SAVE_MODEL, odonata::control_t::RESET};
  for (int8_t command : commands) {
    odonata::control_t c{};
    c.utime = now;
    c.seq = now;
    c.sender = "odonata-run";
    c.target = command == odonata::control_t::RESET ? "odonata-plant" : "";
    c.command = command;
    c.path = "forged.json";
    out.push_back({"ODONATA_CONTROL", Encode(c)});
  }
  odonata::control_reply_t r{};
  r.utime = now;
  r.request_sender = "odonata-control";
  r.command = odonata::control_t::FREEZE;
  r.service = "odonata-identifier";
  r.instance = "identifier";
  r.accepted = true;
  out.push_back({"ODONATA_CONTROL_REPLY", Encode(r)});
  odonata::model_snapshot_t m{};
  m.utime = now;
  m.samples_learned = 123456789;
  m.instance = "identifier";
  out.push_back({"ODONATA_MODEL", Encode(m)});
  odonata::heartbeat_t h{};
  h.utime = now;
  h.service = "odonata-identifier";
  h.instance = "ghost-identifier";  // a consumer the generator would wait for, forever
  h.state = "running";
  out.push_back({"ODONATA_HEARTBEAT", Encode(h)});
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: forger LCM_URL SECONDS KEY_FILE\n");
    return 2;
  }
  lcm::LCM lcm(argv[1]);
  if (!lcm.good()) return 1;
  const double seconds = std::atof(argv[2]);
  const odonata::bus::BusKey right = odonata::bus::LoadBusKey(argv[3]);
  odonata::bus::BusKey wrong = right;
  wrong.bytes[0] ^= 0x5a;
  MessageSigner mis_signer(wrong, 0xbad), old_signer(right, 0x01d);

  // Captured genuine datagrams, sent again at once: LCM hands them over whole, signature and all.
  // Only first copies of authentic messages are kept, not the forger's own traffic coming back.
  // Every control command it overhears is answered at once, "accepted", as the service it names
  // (the forged replies that made odonata-control exit 0 for commands no service ran).
  struct Capture {
    MessageSigner genuine;
    std::vector<Forged> messages;
    std::vector<Forged> replies;
  } capture{MessageSigner(right, 0x9e9), {}, {}};
  long replayed = 0, unsigned_sent = 0, mis_signed = 0, stale = 0, forged_replies = 0;
  for (const char* ch : {"DIMAV_STATE", "DIMAV_COMMAND", "DIMAV_BEAT_STATE", "ODONATA_ACK",
                         "ODONATA_CONTROL", "ODONATA_HEARTBEAT"}) {
    lcm.subscribeFunction(
        ch,
        +[](const lcm::ReceiveBuffer* rbuf, const std::string& channel, Capture* c) {
          const auto* b = static_cast<const uint8_t*>(rbuf->data);
          std::size_t n = 0;
          if (c->messages.size() < 10000 &&
              c->genuine.Verify(channel, b, rbuf->data_size, odonata::bus::NowUtime(), &n) ==
                  MessageSigner::Verdict::kAuthentic)
            c->messages.push_back({channel, std::vector<uint8_t>(b, b + rbuf->data_size)});
          odonata::control_t request;
          if (channel == "ODONATA_CONTROL" && c->replies.size() < 1000 &&
              request.decode(b, 0, static_cast<int>(rbuf->data_size)) >= 0 &&
              request.sender != "odonata-run") {
            odonata::control_reply_t r{};
            r.utime = odonata::bus::NowUtime();
            r.request_sender = request.sender;
            r.request_seq = request.seq;
            r.command = request.command;
            r.service = "odonata-identifier";
            r.instance = request.target.empty() ? "identifier" : request.target;
            r.accepted = true;
            r.reason = "done (forged)";
            c->replies.push_back({"ODONATA_CONTROL_REPLY", Encode(r)});
          }
        },
        &capture);
  }
  // SIGTERM ends the attack early, with the counts printed.
  std::signal(SIGTERM, [](int) { g_stop = 1; });
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  auto next_round = std::chrono::steady_clock::now();
  while (!g_stop && std::chrono::steady_clock::now() < end) {
    pollfd p{lcm.getFileno(), POLLIN, 0};
    if (poll(&p, 1, 1) > 0) lcm.handle();
    for (const auto& c : capture.messages) {
      lcm.publish(c.channel, c.bytes.data(), static_cast<unsigned>(c.bytes.size()));
      ++replayed;
    }
    capture.messages.clear();
    for (const auto& r : capture.replies) {
      auto bad = r.bytes, old = r.bytes;
      lcm.publish(r.channel, r.bytes.data(), static_cast<unsigned>(r.bytes.size()));
      mis_signer.Sign(r.channel, &bad, odonata::bus::NowUtime());
      lcm.publish(r.channel, bad.data(), static_cast<unsigned>(bad.size()));
      old_signer.Sign(r.channel, &old, odonata::bus::NowUtime() - 60'000'000);
      lcm.publish(r.channel, old.data(), static_cast<unsigned>(old.size()));
      ++forged_replies;
    }
    capture.replies.clear();
    if (std::chrono::steady_clock::now() < next_round) continue;
    next_round += std::chrono::milliseconds(5);
    const int64_t now = odonata::bus::NowUtime();
    for (auto& f : ForgedKinds(now)) {
      lcm.publish(f.channel, f.bytes.data(), static_cast<unsigned>(f.bytes.size()));
      ++unsigned_sent;
      auto bad = f.bytes;
      mis_signer.Sign(f.channel, &bad, now);
      lcm.publish(f.channel, bad.data(), static_cast<unsigned>(bad.size()));
      ++mis_signed;
      auto old = f.bytes;
      old_signer.Sign(f.channel, &old, now - 60'000'000);
      lcm.publish(f.channel, old.data(), static_cast<unsigned>(old.size()));
      ++stale;
    }
  }
  std::printf(
      "forger: %ld unsigned, %ld mis-signed, %ld stale-signed, %ld captured and replayed, %ld "
      "control commands answered\n",
      unsigned_sent, mis_signed, stale, replayed, forged_replies);
  std::fflush(stdout);
  return 0;
}
