// odonata-mavlink's latency: from a MAVLink datagram leaving a vehicle to the signals_t sample it
// completes arriving on the bus. Sends ATTITUDE frames at --rate-hz over UDP to a running bridge
// (started with the same --rate, one field of ATTITUDE) and times each VEHICLE_SIGNALS message
// from the latest datagram sent before it: a grid sample is complete once a later frame arrives,
// and the bridge publishes it on that datagram. The figure includes the bus's own hop (one LCM
// publish and receive), so it bounds what the bridge adds from above; the bare hop is measured
// too (an LCM loopback of the same size) so the two can be told apart. Run it with
// bench/mavlink/run_mavlink_bench.sh, which starts the bridge in a private network namespace.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <lcm/lcm-cpp.hpp>

#include "mavlink/frame_encoder.hpp"
#include "mavlink/mavlink_messages.hpp"
#include "odonata/signals_t.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double Us(Clock::duration d) { return std::chrono::duration<double, std::micro>(d).count(); }

struct Percentiles {
  double p50 = 0, p99 = 0, max = 0;
  std::size_t n = 0;
};

Percentiles Summarise(std::vector<double> v) {
  if (v.empty()) return {};
  std::sort(v.begin(), v.end());
  auto at = [&v](double q) { return v[static_cast<std::size_t>(q * (v.size() - 1))]; };
  return {at(0.5), at(0.99), v.back(), v.size()};
}

struct Sink {
  std::mutex mutex;
  std::vector<Clock::time_point> sent;  // datagram send times, in order
  std::vector<double> latency_us;
  long received = 0;
  void On(const lcm::ReceiveBuffer*, const std::string&, const odonata::signals_t*) {
    const Clock::time_point now = Clock::now();
    std::lock_guard<std::mutex> lock(mutex);
    ++received;
    // The latest datagram sent before this message: the one that completed its sample.
    const auto it = std::upper_bound(sent.begin(), sent.end(), now);
    if (it != sent.begin()) latency_us.push_back(Us(now - *(it - 1)));
  }
};

struct Echo {
  Clock::time_point sent;
  std::vector<double> latency_us;
  void On(const lcm::ReceiveBuffer*, const std::string&) {
    latency_us.push_back(Us(Clock::now() - sent));
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::string lcm_url = "udpm://239.255.76.67:7667?ttl=0", target = "127.0.0.1";
  unsigned port = 14550;
  double rate_hz = 100.0, seconds = 10.0;
  CLI::App app{"Times odonata-mavlink from datagram to published sample (see the file's header)."};
  app.add_option("--lcm-url", lcm_url)->capture_default_str();
  app.add_option("--udp-port", port, "the bridge's port")->capture_default_str();
  app.add_option("--rate-hz", rate_hz, "ATTITUDE frames per second")->capture_default_str();
  app.add_option("--seconds", seconds)->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  lcm::LCM lcm(lcm_url);
  if (!lcm.good()) return std::fprintf(stderr, "cannot open %s\n", lcm_url.c_str()), 1;
  Sink sink;
  lcm.subscribe("VEHICLE_SIGNALS", &Sink::On, &sink);
  Echo echo;
  lcm.subscribe("BENCH_MAVLINK_PING", &Echo::On, &echo);
  std::atomic<bool> done{false};
  std::thread receiver([&] {
    while (!done) lcm.handleTimeout(50);
  });

  boost::asio::io_context io;
  boost::asio::ip::udp::socket socket(io, boost::asio::ip::udp::v4());
  const boost::asio::ip::udp::endpoint to(boost::asio::ip::make_address(target),
                                          static_cast<unsigned short>(port));
  const odonata::mavlink::MessageDef& attitude = *odonata::mavlink::FindByName("ATTITUDE");
  const auto period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / rate_hz));
  const auto frames = static_cast<long>(seconds * rate_hz);
  Clock::time_point next = Clock::now();
  for (long i = 0; i < frames; ++i) {
    std::this_thread::sleep_until(next);
    next += period;
    odonata::mavlink::PayloadBuilder p(attitude);
    p.Set("time_boot_ms", static_cast<double>(10 * i)).Set("pitchspeed", std::sin(0.05 * i));
    const std::string frame =
        odonata::mavlink::EncodeFrameV2(attitude, p.bytes(), static_cast<std::uint8_t>(i), 1, 1);
    {
      std::lock_guard<std::mutex> lock(sink.mutex);
      sink.sent.push_back(Clock::now());
    }
    socket.send_to(boost::asio::buffer(frame), to);
    // The bare hop, every tenth frame: an LCM message of a signals_t's size out and back in.
    if (i % 10 == 5) {
      std::vector<std::uint8_t> ping(96, 0);
      echo.sent = Clock::now();
      lcm.publish("BENCH_MAVLINK_PING", ping.data(), static_cast<unsigned>(ping.size()));
    }
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  done = true;
  receiver.join();
  const Percentiles bridge = Summarise(sink.latency_us);
  const Percentiles hop = Summarise(echo.latency_us);
  std::printf("frames sent %ld, samples received %ld\n", frames, sink.received);
  std::printf("datagram -> signals_t received: p50 %.0f us, p99 %.0f us, max %.0f us (%zu)\n",
              bridge.p50, bridge.p99, bridge.max, bridge.n);
  std::printf("bare LCM hop (publish -> receive): p50 %.0f us, p99 %.0f us (%zu)\n", hop.p50,
              hop.p99, hop.n);
  std::printf("bridge's own share (p50 difference): %.0f us\n", bridge.p50 - hop.p50);
  return 0;
}
