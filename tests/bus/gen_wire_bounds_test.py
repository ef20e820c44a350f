#!/usr/bin/python3
"""lcmtypes/gen_wire_bounds.py: the walks it writes for the LCM grammar it supports, and that
anything else in a .lcm file stops it with FILE:LINE and the reason, before it writes a file."""
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.environ["ODONATA_SOURCE"], "lcmtypes/gen_wire_bounds.py")

SUPPORTED = """package p.q;  // a dotted package
/* a block
   comment */
struct inner_t {
  int8_t k;
  string tag[k];
  byte raw[2][k];
}
struct outer_t
{
  int64_t rows;
  int16_t cols, fixed[3];
  boolean flags[rows];
  float grid[2][rows][cols];
  inner_t one, many[rows];
  p.q.inner_t pair[2];
  const int32_t A = -0x10, B = 5;
  const double PI = 3.14159;
  string names[cols][2];
  double tail;
}
"""


def generate(text):
    """(exit status, stderr, header, source) for one file t.lcm holding `text`."""
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, "t.lcm"), "w", encoding="utf-8") as f:
            f.write(text)
        hpp, cpp = os.path.join(d, "bus/wire_bounds.hpp"), os.path.join(d, "bus/wire_bounds.cpp")
        r = subprocess.run([sys.executable, SCRIPT, "--header", hpp, "--source", cpp,
                            os.path.join(d, "t.lcm")], capture_output=True, text=True, check=False)
        return r.returncode, r.stderr, read(hpp), read(cpp)


def read(path):
    """The file's text, or None when it was not written."""
    if not os.path.exists(path):
        return None
    with open(path, encoding="utf-8") as f:
        return f.read()


class Supported(unittest.TestCase):
    def test_walks_follow_the_declarations(self):
        status, err, header, source = generate(SUPPORTED)
        self.assertEqual(status, 0, err)
        for line in ["const int64_t k = w.Count<int8_t>();",
                     "w.Strings(k);  // tag[k]",
                     "w.Array(w.Elements({2, k}), 1);  // raw[2][k]",
                     "const int64_t rows = w.Count<int64_t>();",
                     "const int64_t cols = w.Count<int16_t>();",
                     "w.Skip(6);  // fixed[3]",
                     "w.Array(rows, 1);  // flags[rows]",
                     "w.Array(w.Elements({2, rows, cols}), 4);  // grid[2][rows][cols]",
                     "Walk_p_q_inner_t(w);  // one",
                     "for (int64_t i = 0, n = rows; i < n && w.ok(); ++i) Walk_p_q_inner_t(w);",
                     "for (int64_t i = 0, n = 2; i < n && w.ok(); ++i) Walk_p_q_inner_t(w);",
                     "w.Strings(w.Elements({cols, 2}));  // names[cols][2]",
                     "w.Skip(8);  // tail",
                     "w.Skip(8);  // fingerprint"]:
            self.assertIn(line, source)
        # Only the type no other type contains gets a CountsFit.
        self.assertIn('#include "p/q/outer_t.hpp"', header)
        self.assertIn("bool CountsFit(const p::q::outer_t*, const void* data, int64_t size);",
                      header)
        self.assertNotIn("inner_t*", header)


class Rejected(unittest.TestCase):
    CASES = [
        ("package p;\nenum e_t { A = 1 }", 2, "enums are not supported"),
        ("package p;\nstruct a_t {\n  foo_t x;\n}", 3, "unknown type 'foo_t'"),
        ("package p;\nstruct a_t {\n  const int32_t N = 3;\n  double x[N];\n}", 4,
         "array size 'N' is not an earlier member"),
        ("package p;\nstruct a_t {\n  double x[n];\n  int32_t n;\n}", 3,
         "array size 'n' is not an earlier member"),
        ("package p;\nstruct a_t {\n  double n;\n  double x[n];\n}", 4,
         "not a scalar integer member"),
        ("package p;\nstruct a_t {\n  double x[0];\n}", 3, "not a positive decimal literal"),
        ("package p;\nstruct a_t {\n  int32_t a;\n  int64_t a;\n}", 4, "'a' is declared twice"),
        ("package p;\nstruct a_t {\n  b_t b;\n}\nstruct b_t {\n  a_t a;\n}", 2, "contains itself"),
        ("package p;\nstruct a_t {\n  int32_t x;\n};", 4, "expected 'package' or 'struct'"),
        ("package p;\nstruct a_t {\n  int32_t x\n}", 4, "expected ';'"),
        ("package p;\nstruct a_t {\n  int8_t x; /* never closed\n}", 3, "unterminated /* comment"),
        ("package p;\nstruct a_t {\n  const int8_t X = 300;\n}", 3, "does not fit in int8_t"),
        ("package p;\nstruct a_t {\n  int32_t x @;\n}", 3, "unexpected character '@'"),
        ("package p;\nstruct a_t {\n  int32_t x;\n", 3, "end of file"),
    ]

    def test_each_stops_with_its_place_and_reason(self):
        for text, line, reason in self.CASES:
            with self.subTest(reason=reason):
                status, err, header, source = generate(text)
                self.assertEqual(status, 1)
                self.assertIn(f"t.lcm:{line}: error: ", err)
                self.assertIn(reason, err)
                self.assertIsNone(header)
                self.assertIsNone(source)


if __name__ == "__main__":
    unittest.main()
