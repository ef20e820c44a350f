#!/usr/bin/env python3
"""MAVLink values decoded apart from odonata's reader, with Python's struct module.

Walks the records of the real telemetry log (an 8-byte big-endian microsecond timestamp, then one
MAVLink 2 frame: 0xFD, the payload length, flags, seq, sysid, compid, a 24-bit message id, the
payload, 2 bytes of CRC, 13 of signature when incompat bit 0 is set) and prints the fields of the
first two ATTITUDE (id 30) and SERVO_OUTPUT_RAW (id 36) frames, with their times in seconds from
the first record. The struct formats below are the messages' wire order written out by hand from
common.xml (fields by type size, largest first; extensions after), not taken from the C++ table.
The C++ real-file test (tlog_real_file_test.cpp) holds these numbers; with --check it is read and
every number there must equal the one decoded here, so the two decoders meet only in the file.

Usage: tlog_values_test.py [--check CPP_TEST] MAVLINK_DIR
"""
import re
import struct
import sys

FILE = 'ardusub_small.tlog'
# id -> (array stem, struct format of the whole payload, field names in that order)
WANTED = {
    30: ('kAttitude', '<Iffffff',
         ['time_boot_ms', 'roll', 'pitch', 'yaw', 'rollspeed', 'pitchspeed', 'yawspeed']),
    36: ('kServoOutputRaw', '<I8HB8H',
         ['time_usec'] + ['servo%d_raw' % i for i in range(1, 9)] + ['port'] +
         ['servo%d_raw' % i for i in range(9, 17)]),
}
COUNT = 2


def decode(data):
    """{id: [(time_s, {field: value}), ...]} of the first COUNT frames of each wanted id."""
    out = {i: [] for i in WANTED}
    first_us = None
    pos = 0
    while pos + 18 <= len(data):
        (t_us,) = struct.unpack_from('>Q', data, pos)
        if first_us is None:
            first_us = t_us
        if data[pos + 8] != 0xFD:
            raise ValueError('not a MAVLink 2 frame at byte %d' % pos)
        length = data[pos + 9]
        incompat = data[pos + 10]
        msgid = data[pos + 15] | data[pos + 16] << 8 | data[pos + 17] << 16
        size = 10 + length + 2 + (13 if incompat & 1 else 0)
        if msgid in out and len(out[msgid]) < COUNT:
            _, fmt, names = WANTED[msgid]
            payload = data[pos + 18:pos + 18 + length]
            payload += b'\0' * (struct.calcsize(fmt) - len(payload))  # truncated: zero-extended
            values = struct.unpack(fmt, payload)
            out[msgid].append(((t_us - first_us) / 1e6, dict(zip(names, values))))
        pos += 8 + size
    return out


def arrays(decoded):
    """{C++ array name: [numbers]}: per message, the times, then one array per field."""
    result = {}
    for msgid, frames in decoded.items():
        stem, _, names = WANTED[msgid]
        result[stem + 'TimeS'] = [t for t, _ in frames]
        for name in names:
            camel = ''.join(p.capitalize() for p in name.split('_'))
            result[stem + camel] = [float(values[name]) for _, values in frames]
    return result


def main(argv):
    check = None
    if len(argv) > 1 and argv[1] == '--check':
        check = open(argv[2]).read()
        argv = argv[:1] + argv[3:]
    if len(argv) != 2:
        print(__doc__)
        return 2
    with open(argv[1] + '/' + FILE, 'rb') as f:
        decoded = arrays(decode(f.read()))
    if check is None:
        for stem, numbers in decoded.items():
            print('constexpr double %s[] = {%s};' % (stem, ', '.join(repr(v) for v in numbers)))
        return 0
    found = dict(re.findall(r'constexpr double (k\w+)\[\] = \{([^}]*)\};', check))
    failures = 0
    for stem, numbers in decoded.items():
        if stem not in found:
            print('missing in the C++ test:', stem)
            failures += 1
            continue
        theirs = [float(x) for x in found[stem].replace('\n', ' ').split(',') if x.strip()]
        if theirs != numbers:
            print('%s: the C++ test holds %s, Python decodes %s' % (stem, theirs, numbers))
            failures += 1
    print('%d of %d arrays differ' % (failures, len(decoded)))
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
