#!/usr/bin/env python3
"""ArduPilot DataFlash values decoded apart from odonata's reader, with Python's struct module.

Walks the records of each real log (0xA3 0x95, a type, the payload FMT gives the length of) and
prints ATT.Pitch, ATT.Yaw and IMU.GyrX of the first five records of each file, with their times.
The C++ real-file test (dataflash_real_files_test.cpp) holds these numbers; with --check it is
read and every number there must equal the one decoded here, so the two decoders meet only in the
file.

Usage: dataflash_values_test.py [--check CPP_TEST] ARDUPILOT_DIR MAVLINK_DIR
"""
import re
import struct
import sys

# Format character -> (struct code, scale), as ArduPilot's LogStructure.h and pymavlink define them.
CODES = {
    'a': ('32h', None), 'b': ('b', None), 'B': ('B', None), 'h': ('h', None), 'H': ('H', None),
    'i': ('i', None), 'I': ('I', None), 'f': ('f', None), 'd': ('d', None), 'n': ('4s', None),
    'N': ('16s', None), 'Z': ('64s', None), 'c': ('h', 0.01), 'C': ('H', 0.01), 'e': ('i', 0.01),
    'E': ('I', 0.01), 'L': ('i', 1e-7), 'M': ('B', None), 'q': ('q', None), 'Q': ('Q', None),
}
FILES = {'arduplane': 'arduplane_test.BIN', 'ardusub': 'ardusub_small.BIN'}
WANTED = [('ATT', 'Pitch'), ('ATT', 'Yaw'), ('IMU', 'GyrX')]
COUNT = 5


def decode(data, wanted, count):
    """{(message, field): [(time_s, value), ...]} of the first `count` records of each."""
    formats = {128: ('FMT', 89, 'BBnNZ', ['Type', 'Length', 'Name', 'Format', 'Columns'])}
    out = {w: [] for w in wanted}
    pos = 0
    while pos + 3 <= len(data) and data[pos] == 0xA3 and data[pos + 1] == 0x95:
        name, length, fmt, labels = formats[data[pos + 2]]
        if pos + length > len(data):
            break  # the cut last record
        codes = '<' + ''.join(CODES[c][0] for c in fmt)
        values = struct.unpack_from(codes, data, pos + 3)
        if name == 'FMT':
            text = [v.split(b'\0')[0].decode() for v in values[2:]]
            formats[values[0]] = (text[0], values[1], text[1], text[2].split(','))
        for message, field in wanted:
            if name == message and len(out[(message, field)]) < count:
                k = labels.index(field)
                scale = CODES[fmt[k]][1]
                value = values[k] * scale if scale else values[k]
                out[(message, field)].append((values[labels.index('TimeUS')] / 1e6, value))
        pos += length
    return out


def main(argv):
    check = None
    if len(argv) > 1 and argv[1] == '--check':
        check = open(argv[2]).read()
        argv = argv[:1] + argv[3:]
    if len(argv) != 3:
        print(__doc__)
        return 2
    dirs = {'arduplane': argv[1], 'ardusub': argv[2]}
    decoded = {}
    for key, name in FILES.items():
        with open(dirs[key] + '/' + name, 'rb') as f:
            values = decode(f.read(), WANTED, COUNT)
        for (message, field), samples in values.items():
            stem = 'k' + key.capitalize() + message.capitalize() + field
            decoded[stem + 'TimeS'] = [t for t, _ in samples]
            decoded[stem] = [v for _, v in samples]
            print(key, message + '.' + field, samples)
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
