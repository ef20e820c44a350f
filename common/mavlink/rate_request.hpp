#pragma once
// What odonata-mavlink sends to a vehicle, and only when asked (--request-rate ATTITUDE=100): the
// standard MAV_CMD_SET_MESSAGE_INTERVAL in a COMMAND_LONG per message, as a ground station sends
// it. Knows no sockets: the service feeds it the frames it hears and sends the frames Due gives.
//
// Protocol (MAVLink's Command Protocol): a command is sent once the target (sysid:compid) has
// been heard — over UDP its address is only known then —, and again every kResendS seconds until
// a COMMAND_ACK for command 511 from the target answers it, at most kMaxAttempts times. An ack
// does not say which message it is for; acks answer requests in the order they were sent, so each
// is taken as the answer to the oldest request awaiting one. The rates asked for are the
// vehicle's to grant: the grid's rate is still chosen from what arrives.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mavlink/frame_decoder.hpp"

namespace odonata::mavlink {

inline constexpr double kResendS = 1.5;
inline constexpr int kMaxAttempts = 3;

/// One request, parsed from "MESSAGE=HZ".
struct RateRequest {
  std::string message;  ///< "ATTITUDE"
  std::uint32_t message_id = 0;
  double rate_hz = 0.0;  ///< > 0
};

/// Parses "ATTITUDE=100".
/// @throws std::invalid_argument: no '=', a message the table does not know, a rate that is not a
///   number in (0, 10000] Hz.
RateRequest ParseRateRequest(const std::string& text);

class RateRequester {
 public:
  RateRequester(std::vector<RateRequest> requests, std::uint8_t target_system,
                std::uint8_t target_component);

  /// A frame heard: from the target, it may be the first (commands become due) or an answer.
  void Observe(const Frame& frame);
  /// The frames to send now (each a whole MAVLink 2 frame), and when they were sent.
  std::vector<std::string> Due(double now_s);

  bool target_heard() const { return target_heard_; }
  /// One line per request: "ATTITUDE at 100 Hz: accepted" / "…: refused (MAV_RESULT 3)" / "…:
  /// no answer after 3 tries" / "…: waiting for 1:1 to be heard".
  std::vector<std::string> Status() const;
  nlohmann::json Summary() const;

 private:
  struct Pending {
    RateRequest request;
    int attempts = 0;
    double last_sent_s = 0.0;
    int result = -1;  ///< MAV_RESULT once answered
  };
  std::vector<Pending> pending_;
  std::uint8_t target_system_, target_component_;
  bool target_heard_ = false;
  std::uint8_t seq_ = 0;
};

}  // namespace odonata::mavlink
