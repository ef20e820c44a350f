// pipeline_recorder URL FILE: records every channel into an LCM event log (as lcm-logger does)
// until SIGINT or SIGTERM. It exists because lcm-logger 1.3.1 keeps LCM's default subscription
// queue of 30 messages: on a loaded machine a lockstep burst overflows it and single messages go
// missing from the log, while this recorder's queue is unbounded.
#include <csignal>
#include <cstdio>
#include <string>

#include <lcm/lcm-cpp.hpp>

namespace {

volatile std::sig_atomic_t g_stop = 0;

void OnSignal(int) { g_stop = 1; }

struct Recorder {
  lcm::LogFile* log;
  int64_t count = 0;

  // Through subscribeFunction, as the services do: LCM 1.3.1's member-function subscription
  // trips UBSan's vptr check in the sanitizer build.
  static void Handle(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Recorder* self) {
    self->Write(rbuf, channel);
  }

  void Write(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    lcm::LogEvent e;
    e.eventnum = count++;
    e.timestamp = rbuf->recv_utime;
    e.channel = channel;
    e.datalen = static_cast<int32_t>(rbuf->data_size);
    e.data = rbuf->data;
    log->writeEvent(&e);
  }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: pipeline_recorder LCM_URL FILE\n");
    return 2;
  }
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  lcm::LCM lcm(argv[1]);
  lcm::LogFile log(argv[2], "w");
  if (!lcm.good() || !log.good()) {
    std::fprintf(stderr, "pipeline_recorder: cannot open LCM or %s\n", argv[2]);
    return 1;
  }
  Recorder recorder{&log};
  lcm::Subscription* sub = lcm.subscribeFunction(".*", &Recorder::Handle, &recorder);
  sub->setQueueCapacity(0);  // unbounded: never drop a message because we were descheduled
  std::FILE* ready = std::fopen((std::string(argv[2]) + ".ready").c_str(), "w");
  if (ready) std::fclose(ready);
  while (!g_stop) lcm.handleTimeout(50);
  while (lcm.handleTimeout(0) > 0) {
  }
  return 0;
}
