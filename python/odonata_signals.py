"""Publish odonata's signals_t from Python with the standard library only.

Debian bookworm ships no python3-lcm, so a vehicle written in Python could not talk to odonata.
This module writes what lcm-gen's Python code and LCM's udpm provider would (docs/lcm.md §9,
§14): the signals_t encoding (lcm-gen's fingerprint, big-endian fields, strings with a length
and a NUL) in an LC02 datagram, or in LC03 fragments when the message is larger than one.

    from odonata_signals import SignalsPublisher
    pub = SignalsPublisher()                      # LCM_DEFAULT_URL, else udpm ttl=0
    pub.publish(seq=k, names=["vz_mps", "throttle"], values=[vz, throttle])

Only publishing: odonata's services read signals_t; a vehicle needs to send it. With the
system's shared key (SignalsPublisher(key_path=...), the file the services' --key reads) every
message is signed as odonata's services sign theirs (docs/lcm.md §15), so an identifier with the
key takes it.
"""
import hashlib
import os
import socket
import struct
import time
import urllib.parse

# lcm-gen's hash of signals_t (lcmtypes/odonata_signals_t.lcm), rotated left by one bit as its
# generated code does for a type with no nested types. tests/python checks it against the C++
# header lcm-gen writes from the same file, so a change to the type cannot go unnoticed.
_BASE_HASH = 0xD1C5EFC156B0DAF0
FINGERPRINT = ((_BASE_HASH << 1) & 0xFFFFFFFFFFFFFFFF) | (_BASE_HASH >> 63)

CHANNEL = "VEHICLE_SIGNALS"
DEFAULT_URL = "udpm://239.255.76.67:7667?ttl=0"

# LCM 1.3.1's udpm limits (lcm_udpm.c): a whole message in one LC02 datagram up to this many bytes
# of channel + NUL + payload, else LC03 fragments of at most this much payload each.
_SHORT_MAX = 65499
_FRAGMENT_MAX = 65423
_MAGIC_SHORT = 0x4C433032
_MAGIC_LONG = 0x4C433033


def _string(s):
    b = s.encode("utf-8")
    if b"\0" in b:
        raise ValueError(f"an LCM string cannot hold a NUL: {s!r}")
    return struct.pack(">i", len(b) + 1) + b + b"\0"


def encode_signals(utime, seq, source, names, values):
    """signals_t as lcm-gen encodes it: fingerprint, utime, seq, source, num_signals, names[],
    values[]."""
    names = list(names)
    values = [float(v) for v in values]
    if len(names) != len(values):
        raise ValueError(f"{len(names)} names but {len(values)} values")
    out = [struct.pack(">Qqq", FINGERPRINT, int(utime), int(seq)), _string(source),
           struct.pack(">i", len(names))]
    out += [_string(n) for n in names]
    out.append(struct.pack(f">{len(values)}d", *values))
    return b"".join(out)


# The signature odonata's services append after the LCM payload (common/bus/message_signer.hpp):
# magic, sender id, timestamp (µs, growing per sender), keyed BLAKE2b-256 (libsodium's
# crypto_generichash with the key) over channel + NUL + payload + those 20 bytes.
_SIGNATURE_MAGIC = b"OSG1"


def load_key(path):
    """The 32-byte key from a file of 64 hex digits that only its owner may read."""
    if os.stat(path).st_mode & 0o077:
        raise ValueError(f"key file {path} may be read by others than its owner: chmod 600 it")
    text = "".join(open(path).read().split())
    if len(text) != 64:
        raise ValueError(f"key file {path} must hold 64 hex digits (32 bytes)")
    return bytes.fromhex(text)


class Signer:
    """Signs payloads as one sender: a random id, timestamps that grow with every message."""

    def __init__(self, key):
        self.key = key
        self.sender_id = int.from_bytes(os.urandom(8), "big")
        self.last = 0

    def sign(self, channel, payload, now_us=None):
        now_us = time.time_ns() // 1000 if now_us is None else now_us
        self.last = max(int(now_us), self.last + 1)
        header = _SIGNATURE_MAGIC + struct.pack(">QQ", self.sender_id, self.last)
        tag = hashlib.blake2b(channel.encode("ascii") + b"\0" + payload + header, key=self.key,
                              digest_size=32).digest()
        return payload + header + tag


def parse_udpm_url(url):
    """(group, port, ttl) of an LCM udpm URL such as udpm://239.255.76.67:7667?ttl=0."""
    u = urllib.parse.urlparse(url)
    if u.scheme != "udpm":
        raise ValueError(f"only udpm:// URLs can be published to from Python, not {url!r}")
    ttl = int(urllib.parse.parse_qs(u.query).get("ttl", ["0"])[0])
    return u.hostname or "239.255.76.67", u.port or 7667, ttl


class UdpmPublisher:
    """LCM's udpm provider, publishing only: LC02 for a message that fits, LC03 fragments
    otherwise, one sequence number per message, as LCM 1.3.1 numbers them."""

    def __init__(self, url=None):
        self.url = url or os.environ.get("LCM_DEFAULT_URL") or DEFAULT_URL
        self.group, self.port, ttl = parse_udpm_url(self.url)
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
        self.sock.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, ttl)
        self.sock.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_LOOP, 1)
        self.seqno = 0

    def datagrams(self, channel, payload):
        """The datagrams of one message (also what tests compare against LCM's)."""
        ch = channel.encode("ascii")
        if not 0 < len(ch) <= 63:
            raise ValueError(f"an LCM channel name has 1-63 characters: {channel!r}")
        seq = self.seqno
        self.seqno = (self.seqno + 1) & 0xFFFFFFFF
        if len(ch) + 1 + len(payload) <= _SHORT_MAX:
            return [struct.pack(">II", _MAGIC_SHORT, seq) + ch + b"\0" + payload]
        count = -(-len(payload) // _FRAGMENT_MAX)
        if count > 65535:
            raise ValueError(f"a message of {len(payload)} bytes is too large for LCM")
        out, offset, first = [], 0, _FRAGMENT_MAX - (len(ch) + 1)
        for no in range(count):
            size = min(first if no == 0 else _FRAGMENT_MAX, len(payload) - offset)
            head = struct.pack(">IIIIHH", _MAGIC_LONG, seq, len(payload), offset, no, count)
            out.append(head + (ch + b"\0" if no == 0 else b"") + payload[offset:offset + size])
            offset += size
        if offset != len(payload):  # the first fragment's room went to the channel name
            raise AssertionError("fragmentation lost bytes")
        return out

    def publish(self, channel, payload):
        for d in self.datagrams(channel, payload):
            self.sock.sendto(d, (self.group, self.port))

    def close(self):
        self.sock.close()


class SignalsPublisher:
    """A vehicle's signals, by name, on VEHICLE_SIGNALS: one call per control step."""

    def __init__(self, url=None, source="python-vehicle", channel=CHANNEL, key_path=None):
        self.udpm = UdpmPublisher(url)
        self.source = source
        self.channel = channel
        self.signer = Signer(load_key(key_path)) if key_path else None

    def publish(self, seq, names, values, utime=None):
        if utime is None:
            utime = time.time_ns() // 1000
        payload = encode_signals(utime, seq, self.source, names, values)
        if self.signer:
            payload = self.signer.sign(self.channel, payload)
        self.udpm.publish(self.channel, payload)
