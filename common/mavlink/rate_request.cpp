#include "mavlink/rate_request.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "mavlink/frame_encoder.hpp"
#include "mavlink/mavlink_messages.hpp"

namespace odonata::mavlink {
namespace {

constexpr double kMaxRequestHz = 10000.0;
constexpr int kMavResultAccepted = 0;

}  // namespace

RateRequest ParseRateRequest(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos)
    throw std::invalid_argument("--request-rate takes MESSAGE=HZ (e.g. ATTITUDE=100), not '" +
                                text + "'");
  RateRequest r;
  r.message = text.substr(0, eq);
  const MessageDef* m = FindByName(r.message);
  if (m == nullptr)
    throw std::invalid_argument("--request-rate: no message '" + r.message +
                                "' in odonata's MAVLink table (odonata-log topics lists them)");
  r.message_id = m->id;
  const std::string hz = text.substr(eq + 1);
  std::size_t used = 0;
  try {
    r.rate_hz = std::stod(hz, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != hz.size() || hz.empty() || !(r.rate_hz > 0.0) || r.rate_hz > kMaxRequestHz)
    throw std::invalid_argument("--request-rate " + r.message +
                                ": the rate must be a number of Hz in (0, 10000], not '" + hz +
                                "'");
  return r;
}

RateRequester::RateRequester(std::vector<RateRequest> requests, std::uint8_t target_system,
                             std::uint8_t target_component)
    : target_system_(target_system), target_component_(target_component) {
  for (RateRequest& r : requests) pending_.push_back(Pending{std::move(r)});
}

void RateRequester::Observe(const Frame& frame) {
  if (frame.sysid != target_system_ || frame.compid != target_component_) return;
  target_heard_ = true;
  if (frame.message == nullptr || frame.message->name != "COMMAND_ACK") return;
  const MessageDef& ack = *frame.message;
  if (Field(frame, *FindField(ack, "command")) != kCmdSetMessageInterval) return;
  for (Pending& p : pending_) {
    if (p.attempts > 0 && p.result < 0) {
      p.result = static_cast<int>(Field(frame, *FindField(ack, "result")));
      return;
    }
  }
}

std::vector<std::string> RateRequester::Due(double now_s) {
  std::vector<std::string> frames;
  if (!target_heard_) return frames;
  const MessageDef& command = *FindByName("COMMAND_LONG");
  for (Pending& p : pending_) {
    if (p.result >= 0 || p.attempts >= kMaxAttempts) continue;
    if (p.attempts > 0 && now_s - p.last_sent_s < kResendS) continue;
    ++p.attempts;
    p.last_sent_s = now_s;
    frames.push_back(
        EncodeFrameV2(command,
                      SetMessageIntervalPayload(target_system_, target_component_,
                                                p.request.message_id, 1e6 / p.request.rate_hz),
                      seq_++));
  }
  return frames;
}

std::vector<std::string> RateRequester::Status() const {
  std::vector<std::string> lines;
  for (const Pending& p : pending_) {
    char hz[32];
    std::snprintf(hz, sizeof hz, "%g", p.request.rate_hz);
    std::string line = p.request.message + " at " + hz + " Hz: ";
    if (p.result == kMavResultAccepted)
      line += "accepted";
    else if (p.result > 0)
      line += "refused (MAV_RESULT " + std::to_string(p.result) + ")";
    else if (p.attempts >= kMaxAttempts)
      line += "no answer after " + std::to_string(p.attempts) + " tries";
    else if (!target_heard_)
      line += "waiting for " + std::to_string(target_system_) + ":" +
              std::to_string(target_component_) + " to be heard";
    else
      line += "sent " + std::to_string(p.attempts) + " time(s), awaiting the answer";
    lines.push_back(std::move(line));
  }
  return lines;
}

nlohmann::json RateRequester::Summary() const {
  nlohmann::json j = nlohmann::json::array();
  for (const Pending& p : pending_)
    j.push_back({{"message", p.request.message},
                 {"rate_hz", p.request.rate_hz},
                 {"attempts", p.attempts},
                 {"result", p.result < 0 ? nlohmann::json() : nlohmann::json(p.result)}});
  return j;
}

}  // namespace odonata::mavlink
