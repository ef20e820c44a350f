#!/usr/bin/env python3
"""A vehicle for odonata-mavlink's tests: sends a real .tlog's frames over UDP or a serial port
at the recording's own pace (or faster), optionally losing a share of them, and answers the
commands it is sent as an autopilot does. Written apart from odonata's C++ (Python's struct and a
CRC of its own), so the bridge and this script meet only on the wire.

  send: each record's frame (or the whole record, --stamped: its 8-byte stamp, then the frame) in
        one datagram to --udp HOST:PORT, or written to --serial PATH (a pty socat made), at the
        record's time / --speed. --loss P drops that share of records (seeded; never the first).
  answer: a COMMAND_LONG (id 76) that arrives, checked against its CRC (CRC_EXTRA 152), is
        recorded and answered with COMMAND_ACK (id 77, CRC_EXTRA 143) from 1:1, result 0.
  junk (--junk N): after each record sent, N datagrams of what a link must drop, in turn: an
        ATTITUDE from 1:1 with a bad checksum, a message odonata does not know (from 3:1), an
        ATTITUDE from another vehicle (2:1: it joins once the recording's first ATTITUDE is sent,
        for a plain field name follows the first sender heard), half a frame, noise (no start byte in it), a frame
        with unknown incompat flags (from 4:1). Each carries pitchspeed 1e6 where it has one, a
        value the recording never holds, so a log shows whether any got through.
  report (--report FILE, JSON): records sent and dropped, the sequence numbers skipped per sender
        over what was sent (what the bridge must count as lost: pymavlink's rule), commands.

Usage: mavlink_vehicle.py TLOG (--udp HOST:PORT | --serial PATH) [--stamped] [--speed S]
         [--seconds T] [--loss P] [--seed N] [--junk N] [--linger S] [--report FILE]
"""
import argparse
import json
import os
import random
import select
import socket
import struct
import sys
import time


def crc_x25(data, crc=0xFFFF):
    for b in data:
        tmp = (b ^ (crc & 0xFF)) & 0xFF
        tmp = (tmp ^ (tmp << 4)) & 0xFF
        crc = ((crc >> 8) ^ (tmp << 8) ^ (tmp << 3) ^ (tmp >> 4)) & 0xFFFF
    return crc


def records(path):
    """[(t_us, frame bytes)] of a .tlog of MAVLink 2 frames."""
    data = open(path, 'rb').read()
    out, pos = [], 0
    while pos + 8 + 12 <= len(data):
        (t_us,) = struct.unpack_from('>Q', data, pos)
        if data[pos + 8] != 0xFD:
            raise ValueError('not a MAVLink 2 frame at byte %d' % (pos + 8))
        length, incompat = data[pos + 9], data[pos + 10]
        size = 10 + length + 2 + (13 if incompat & 1 else 0)
        out.append((t_us, data[pos + 8:pos + 8 + size]))
        pos += 8 + size
    return out


def frame_v2(msgid, payload, seq, sysid=1, compid=1, crc_extra=0):
    while len(payload) > 1 and payload[-1] == 0:
        payload = payload[:-1]
    head = struct.pack('<BBBBBBB', len(payload), 0, 0, seq, sysid, compid, msgid & 0xFF) + \
        struct.pack('<H', msgid >> 8)
    crc = crc_x25(bytes([crc_extra]), crc_x25(head + payload))
    return b'\xfd' + head + payload + struct.pack('<H', crc)


JUNK_KINDS = ['bad_crc', 'unknown', 'other_sender', 'cut', 'noise', 'incompatible']


class Junk:
    """Datagrams a link must drop, each kind from a sender of its own with consecutive numbers,
    so that none moves another sender's sequence count."""

    def __init__(self, rng):
        self.rng = rng
        self.seq = {k: 0 for k in JUNK_KINDS}
        self.counts = {k: 0 for k in JUNK_KINDS}
        self.turn = 0

    def next(self, vehicle_attitude_sent):
        kind = JUNK_KINDS[self.turn % len(JUNK_KINDS)]
        self.turn += 1
        if kind == 'other_sender' and not vehicle_attitude_sent:
            kind = 'noise'
        seq = self.seq[kind]
        self.seq[kind] = (seq + 1) & 0xFF
        self.counts[kind] += 1
        attitude = struct.pack('<Iffffff', 1, 0.0, 0.0, 0.0, 0.0, 1e6, 0.0)
        if kind == 'bad_crc':
            f = bytearray(frame_v2(30, attitude, seq, 1, 1, crc_extra=39))
            f[-1] ^= 0x55
            return bytes(f)
        if kind == 'unknown':
            return frame_v2(178, bytes(24), seq, 3, 1, crc_extra=47)
        if kind == 'other_sender':
            return frame_v2(30, attitude, seq, 2, 1, crc_extra=39)
        if kind == 'cut':
            f = frame_v2(30, attitude, seq, 2, 9, crc_extra=39)
            return f[:len(f) // 2]
        if kind == 'noise':
            return bytes(self.rng.choice([b for b in range(256) if b not in (0xFD, 0xFE)])
                         for _ in range(self.rng.randint(1, 40)))
        f = bytearray(frame_v2(30, attitude, seq, 4, 1, crc_extra=39))
        f[2] = 0x02  # an incompat flag no receiver knows; the checksum made after
        crc = crc_x25(bytes([39]), crc_x25(bytes(f[1:-2])))
        f[-2:] = struct.pack('<H', crc)
        return bytes(f)


class Answerer:
    """Finds COMMAND_LONG frames in what the bridge sends and answers each."""

    def __init__(self):
        self.buf = b''
        self.commands = []
        self.bad = 0
        self.seq = 0

    def feed(self, data):
        self.buf += data
        answers = []
        while True:
            start = self.buf.find(b'\xfd')
            if start < 0 or len(self.buf) - start < 12:
                break
            self.buf = self.buf[start:]
            length = self.buf[1]
            if len(self.buf) < 12 + length:
                break
            frame, self.buf = self.buf[:12 + length], self.buf[12 + length:]
            msgid = frame[7] | frame[8] << 8 | frame[9] << 16
            if msgid != 76:
                continue
            (crc,) = struct.unpack_from('<H', frame, 10 + length)
            if crc != crc_x25(bytes([152]), crc_x25(frame[1:10 + length])):
                self.bad += 1
                continue
            payload = frame[10:10 + length] + b'\0' * (33 - length)
            params = struct.unpack_from('<7f', payload, 0)
            command, target_system, target_component, confirmation = struct.unpack_from(
                '<HBBB', payload, 28)
            self.commands.append({'sysid': frame[5], 'compid': frame[6], 'command': command,
                                  'target': [target_system, target_component],
                                  'param1': params[0], 'param2': params[1]})
            ack = struct.pack('<HBBiBB', command, 0, 0, 0, frame[5], frame[6])
            answers.append(frame_v2(77, ack, self.seq, crc_extra=143))
            self.seq = (self.seq + 1) & 0xFF
        return answers


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('tlog')
    ap.add_argument('--udp')
    ap.add_argument('--serial')
    ap.add_argument('--stamped', action='store_true')
    ap.add_argument('--speed', type=float, default=1.0)
    ap.add_argument('--seconds', type=float, default=float('inf'),
                    help='send the records of the recording\'s first SECONDS only')
    ap.add_argument('--loss', type=float, default=0.0)
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--junk', type=int, default=0)
    ap.add_argument('--linger', type=float, default=0.5,
                    help='seconds to keep answering after the last record')
    ap.add_argument('--report')
    a = ap.parse_args()
    recs = records(a.tlog)
    first_us = recs[0][0]
    recs = [r for r in recs if (r[0] - first_us) / 1e6 <= a.seconds]
    if a.udp:
        host, port = a.udp.rsplit(':', 1)
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        sock.connect((host, int(port)))
        fd = sock.fileno()
        write = sock.send
    else:
        fd = os.open(a.serial, os.O_RDWR | os.O_NOCTTY)
        write = lambda b: os.write(fd, b)
    rng = random.Random(a.seed)
    answerer = Answerer()
    junk = Junk(random.Random(a.seed + 1))
    attitude_sent = False
    last_seq, lost, sent, dropped = {}, [0], 0, 0
    stamp = [first_us]

    def track(frame):  # pymavlink's rule: numbers skipped since the sender's last frame
        key = (frame[5], frame[6])
        if key in last_seq:
            lost[0] += (frame[4] - last_seq[key] - 1) & 0xFF
        last_seq[key] = frame[4]

    def poll(timeout):
        r, _, _ = select.select([fd], [], [], max(timeout, 0.0))
        if not r:
            return
        try:
            data = os.read(fd, 65536) if not a.udp else sock.recv(65536)
        except (ConnectionRefusedError, BlockingIOError):
            return
        # Stamped, the bridge takes records only: an answer is stamped as the latest record sent.
        for answer in answerer.feed(data):
            track(answer)
            write(struct.pack('>Q', stamp[0]) + answer if a.stamped else answer)

    start = time.monotonic()
    for i, (t_us, frame) in enumerate(recs):
        due = start + (t_us - first_us) / 1e6 / a.speed
        while time.monotonic() < due:
            poll(due - time.monotonic())
        if i > 0 and rng.random() < a.loss:
            dropped += 1
            continue
        track(frame)
        write(struct.pack('>Q', t_us) + frame if a.stamped else frame)
        stamp[0] = t_us
        attitude_sent = attitude_sent or (frame[7] == 30 and frame[8] == 0 and frame[9] == 0)
        for _ in range(a.junk):
            j = junk.next(attitude_sent)
            write(struct.pack('>Q', t_us) + j if a.stamped else j)
        sent += 1
    end = time.monotonic() + a.linger
    while time.monotonic() < end:
        poll(end - time.monotonic())
    report = {'sent': sent, 'dropped': dropped, 'sequence_lost': lost[0],
              'junk': junk.counts, 'commands': answerer.commands, 'bad_commands': answerer.bad}
    if a.report:
        with open(a.report, 'w') as f:
            json.dump(report, f)
    print(json.dumps({k: v for k, v in report.items() if k != 'commands'}))


if __name__ == '__main__':
    sys.exit(main())
