#pragma once
// MAVLink 2 message signing, checked on what a link delivers (the MAVLink "Message Signing"
// specification): a signed frame ends in 13 bytes — link id, a 48-bit timestamp (10 µs units
// since 2015-01-01) and the first 6 bytes of SHA-256(secret key ‖ the frame from its start byte
// to the timestamp's end). The key is the link's 32-byte secret; ground stations that take a
// passphrase (MAVProxy, QGroundControl) use SHA-256 of the passphrase as the key.
//
// Only the signature is checked here; a replayed frame's timestamp is not (odonata listens and
// never acts on what it hears, so a replayed sample is noise, not a command).

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "mavlink/frame_decoder.hpp"

namespace odonata::mavlink {

using LinkKey = std::array<std::uint8_t, 32>;

/// The key in `path`: 64 hex digits (whitespace ignored), e.g. `printf %s PASSPHRASE | sha256sum`.
/// @throws std::runtime_error naming the file and what is wrong (unreadable, not 64 hex digits).
LinkKey ReadLinkKey(const std::string& path);

/// The 6 signature bytes of a frame whose bytes up to the signature's own 6 are `signed_part`
/// (start byte to the end of the timestamp) under `key`.
std::array<std::uint8_t, 6> LinkSignature(const LinkKey& key, std::string_view signed_part);

/// The decoder's check of a signed frame under `key` (FrameDecoder::SignatureCheck).
FrameDecoder::SignatureCheck SignatureCheckFor(const LinkKey& key);

/// 10 µs units since 2015-01-01 00:00 UTC: a signature's timestamp, from the system clock.
std::uint64_t SigningTimestampNow();

/// `frame`, an unsigned MAVLink 2 frame of a message the table knows, signed under `key`: the
/// incompat flag set, the checksum made again over it, then link id, the 48-bit timestamp and the
/// signature. A vehicle that enforces signing takes only such frames; each timestamp must be
/// newer than the link's last (the caller keeps them increasing).
/// @throws std::invalid_argument for a frame that is no whole unsigned MAVLink 2 frame of a
///   known message.
std::string SignFrameV2(std::string_view frame, const LinkKey& key, std::uint8_t link_id,
                        std::uint64_t timestamp_10us);

}  // namespace odonata::mavlink
