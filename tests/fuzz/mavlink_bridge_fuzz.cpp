// Fuzz harness: odonata-mavlink's core (mavlink/bridge_core.hpp) fed what a hostile link could
// send: the input is a run of datagrams, each a length byte then that many bytes, arriving 5 ms
// apart (a length byte of 0 holds the clock back, as a burst does). Whatever arrives, the core
// must count what it drops, never throw, and make grid samples in order of k whose values are
// finite but where the sample is a gap; with a link key, nothing unsigned gets through.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "mavlink/bridge_core.hpp"
#include "mavlink/link_signature.hpp"

namespace {

namespace mav = odonata::mavlink;

void Check(bool ok) {
  if (!ok) __builtin_trap();
}

void Run(std::string_view bytes, mav::BridgeOptions options) {
  mav::BridgeCore core(std::move(options));
  double t = 0.0;
  std::int64_t last_k = -1;
  std::size_t at = 0;
  while (at < bytes.size()) {
    const std::size_t n = static_cast<std::uint8_t>(bytes[at++]);
    if (n > 0) t += 0.005;
    const std::string_view datagram = bytes.substr(at, n);
    at += datagram.size();
    core.Feed(datagram, t);
    core.EndOfDatagram(t);
    for (const mav::GridSample& s : core.TakeSamples()) {
      Check(s.k > last_k);
      last_k = s.k;
      Check(s.values.size() == core.field_names().size());
      if (!s.gap())
        for (const double v : s.values) Check(std::isfinite(v));
    }
    (void)core.Silent(t);
  }
  Check(core.gap_samples() <= core.grid_samples());
  (void)core.Summary().dump();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  mav::BridgeOptions chosen;
  chosen.fields = {"ATTITUDE.pitch", "SERVO_OUTPUT_RAW.servo3_raw", "HEARTBEAT.base_mode"};
  Run(bytes, chosen);
  mav::BridgeOptions given;
  given.fields = {"ATTITUDE@1:1.pitchspeed", "ACTUATOR_OUTPUT_STATUS.actuator[1]"};
  given.rate_hz = 50.0;
  given.max_gap = 0;
  Run(bytes, given);
  mav::BridgeOptions keyed = given;
  keyed.signature_check = mav::SignatureCheckFor(mav::LinkKey{});
  keyed.unsigned_frames = mav::UnsignedFrames::kRefuse;
  bool unsigned_through = false;
  keyed.on_frame = [&unsigned_through](const mav::Frame& f) {
    if (!f.is_signed()) unsigned_through = true;
  };
  Run(bytes, keyed);
  Check(!unsigned_through);
  return 0;
}
