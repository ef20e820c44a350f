// python/odonata_signals.py writes signals_t byte for byte as lcm-gen's C++ code does (the same
// fingerprint, the same layout), and its LC03 fragments follow LCM 1.3.1's sizes.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include "odonata/signals_t.hpp"

namespace {

std::string Python(const std::string& code) {
  const std::string cmd = "/usr/bin/python3 -c 'import sys; sys.path.insert(0, \"" +
                          std::string(ODONATA_PYTHON_DIR) + "\")\n" + code + "' 2>&1";
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr) return out;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
  pclose(p);
  return out;
}

std::string Hex(const std::vector<unsigned char>& b) {
  static const char* digits = "0123456789abcdef";
  std::string s;
  for (const unsigned char c : b) {
    s += digits[c >> 4];
    s += digits[c & 15];
  }
  return s;
}

TEST(PythonSignals, EncodesAsLcmGenDoes) {
  odonata::signals_t m{};
  m.utime = 1764000000123456;
  m.seq = 42;
  m.source = "python-vehicle";
  m.num_signals = 3;
  m.names = {"vz_mps", "throttle", "battery_v"};
  m.values = {-1.25, 0.6, 12.599999};
  std::vector<unsigned char> buf(static_cast<std::size_t>(m.getEncodedSize()));
  ASSERT_EQ(m.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  const std::string py = Python(
      "import odonata_signals as o\n"
      "sys.stdout.write(o.encode_signals(1764000000123456, 42, \"python-vehicle\", "
      "[\"vz_mps\", \"throttle\", \"battery_v\"], [-1.25, 0.6, 12.599999]).hex())");
  EXPECT_EQ(py, Hex(buf));
  EXPECT_EQ(static_cast<uint64_t>(odonata::signals_t::getHash()),
            std::stoull(Python("import odonata_signals as o\nprint(o.FINGERPRINT)")));
}

TEST(PythonSignals, FragmentsAsLcmDoes) {
  // 65 499 bytes of channel, NUL and payload fit one LC02 datagram; one more byte takes two LC03
  // fragments (20-byte headers), the first with 65 423 bytes of payload minus the channel and
  // its NUL, the second with the remaining 77.
  const std::string py = Python(
      "import odonata_signals as o\n"
      "p = o.UdpmPublisher(\"udpm://239.255.76.67:7667?ttl=0\")\n"
      "print([len(d) for d in p.datagrams(\"CH\", bytes(65499 - 3))])\n"
      "d = p.datagrams(\"CH\", bytes(65499 - 2))\n"
      "print([len(x) for x in d], [x[:4].hex() for x in d], d[0][20:23])\n"
      "print(o.parse_udpm_url(\"udpm://239.255.76.68:7690?ttl=1\"))\n"
      "try:\n  o.encode_signals(0, 0, \"a\\0b\", [], [])\nexcept ValueError as e:\n  "
      "print(\"refused\")");
  EXPECT_NE(py.find("[65507]"), std::string::npos) << py;  // 8 bytes of header + 65 499
  EXPECT_NE(py.find("[65443, 97] ['4c433033', '4c433033'] b'CH\\x00'"), std::string::npos) << py;
  EXPECT_NE(py.find("('239.255.76.68', 7690, 1)"), std::string::npos) << py;
  EXPECT_NE(py.find("refused"), std::string::npos) << py;
}

}  // namespace
