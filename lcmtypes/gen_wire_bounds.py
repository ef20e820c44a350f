#!/usr/bin/python3
"""Writes bus/wire_bounds.hpp and bus/wire_bounds.cpp from the project's .lcm files.

LCM 1.3.1's generated decode() resizes each std::vector to the count a message claims before it
checks that the bytes are there, so SafeDecode first walks the message with CountsFit and rejects
absurd counts before anything is allocated (docs/lcm.md §8). That walk has to follow each type's
wire layout exactly, and the .lcm files already state the layouts: generating the walks from them
at build time leaves one copy, so an edited or a new type cannot leave its bounds behind.

    gen_wire_bounds.py --header OUT/bus/wire_bounds.hpp --source OUT/bus/wire_bounds.cpp A.lcm ...

It understands the part of the LCM grammar the project uses: `package`; `struct`; members of the
primitive types or of structs declared in the given files, several per declaration; arrays of
any rank sized by positive decimal literals or by earlier scalar integer members; `const`
declarations (they take no bytes on the wire); // and /* */ comments. Anything else (an enum, an
unknown type, an array sized by a constant's name, ...) stops the build with FILE:LINE and why.

The output has a Walk_<package>_<type> function per type and one CountsFit overload per top-level
type (one that no other type contains), which skips the fingerprint and walks the type. Nested
structs are inline on the wire, without a fingerprint. The cursor the walks use is hand-written
(common/bus/wire_cursor.hpp).
"""
import argparse
import os
import re
import sys
import textwrap
from dataclasses import dataclass, field

# Bytes on the wire (big-endian) of each fixed-size primitive; a string is an int32 length that
# counts its NUL, then the bytes.
FIXED_BYTES = {"int8_t": 1, "int16_t": 2, "int32_t": 4, "int64_t": 8, "float": 4, "double": 8,
               "boolean": 1, "byte": 1}
DIMENSION_TYPES = ("int8_t", "int16_t", "int32_t", "int64_t")
CONST_TYPES = ("int8_t", "int16_t", "int32_t", "int64_t", "float", "double")
INT_RANGES = {"int8_t": 7, "int16_t": 15, "int32_t": 31, "int64_t": 63}
# decode() takes the message's length as an int: nothing larger can be on the wire.
MAX_BYTES = 2**31 - 1
# Names the generated walks use themselves; a count member of that name gets a trailing _.
RESERVED_LOCALS = ("w", "i", "n")
LINE_WIDTH = 100

TOKEN = re.compile(r"""
    (?P<space>\s+)
  | (?P<comment>//[^\n]*|/\*.*?\*/)
  | (?P<name>[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*)
  | (?P<number>[-+]?(?:0[xX][0-9A-Fa-f]+|(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?))
  | (?P<punct>[{}\[\];,=])
""", re.VERBOSE | re.DOTALL)
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
INT_LITERAL = re.compile(r"[-+]?(?:0[xX][0-9A-Fa-f]+|[0-9]+)")
SIZE_LITERAL = re.compile(r"[1-9][0-9]*")


class LcmError(Exception):
    """Something in a .lcm file this generator does not understand, with its place."""

    def __init__(self, path, line, message):
        super().__init__(f"{path}:{line}: error: {message}")


@dataclass
class Token:
    kind: str  # name, number or punct
    text: str
    line: int


@dataclass
class Member:
    name: str
    type: str  # a primitive, or the struct's full name once resolved
    dims: list  # int for a fixed size, str for the member that holds the size
    line: int


@dataclass
class Struct:
    package: str
    name: str
    path: str
    line: int
    members: list = field(default_factory=list)

    @property
    def full_name(self):
        return f"{self.package}.{self.name}" if self.package else self.name


def tokenize(path, text):
    tokens, pos, line = [], 0, 1
    while pos < len(text):
        match = TOKEN.match(text, pos)
        if not match:
            what = "unterminated /* comment" if text.startswith("/*", pos) else \
                f"unexpected character {text[pos]!r}"
            raise LcmError(path, line, what)
        if match.lastgroup in ("name", "number", "punct"):
            tokens.append(Token(match.lastgroup, match.group(), line))
        line += match.group().count("\n")
        pos = match.end()
    return tokens


class Parser:
    """Recursive descent over one file's tokens."""

    def __init__(self, path, tokens):
        self.path, self.tokens, self.pos = path, tokens, 0

    def error(self, token, message):
        line = token.line if token else (self.tokens[-1].line if self.tokens else 1)
        return LcmError(self.path, line, message)

    def at_end(self):
        return self.pos == len(self.tokens)

    def next(self, what):
        if self.at_end():
            raise self.error(None, f"end of file, expected {what}")
        self.pos += 1
        return self.tokens[self.pos - 1]

    def accept(self, text):
        if not self.at_end() and self.tokens[self.pos].text == text:
            self.pos += 1
            return True
        return False

    def expect(self, text):
        token = self.next(f"'{text}'")
        if token.text != text:
            raise self.error(token, f"expected '{text}', found '{token.text}'")

    def name(self, what, dotted=False):
        token = self.next(what)
        if token.kind != "name" or (not dotted and not IDENTIFIER.fullmatch(token.text)):
            raise self.error(token, f"expected {what}, found '{token.text}'")
        return token

    def parse_file(self):
        package, structs = "", []
        while not self.at_end():
            token = self.next("'package' or 'struct'")
            if token.text == "package":
                package = self.name("a package name", dotted=True).text
                self.expect(";")
            elif token.text == "struct":
                structs.append(self.parse_struct(package))
            else:
                hint = " (enums are not supported)" if token.text == "enum" else ""
                raise self.error(token,
                                 f"expected 'package' or 'struct', found '{token.text}'{hint}")
        return structs

    def parse_struct(self, package):
        token = self.name("a struct name", dotted=True)
        if "." in token.text:
            package, name = token.text.rsplit(".", 1)
        else:
            name = token.text
        struct = Struct(package, name, self.path, token.line)
        names = set()
        self.expect("{")
        while not self.accept("}"):
            if self.accept("const"):
                self.parse_consts(names)
            else:
                self.parse_members(struct, names)
        return struct

    def declare(self, names, token):
        if token.text in names:
            raise self.error(token, f"'{token.text}' is declared twice")
        names.add(token.text)

    def parse_consts(self, names):
        type_token = self.name("a const type")
        if type_token.text not in CONST_TYPES:
            raise self.error(type_token, f"a const cannot be of type '{type_token.text}'")
        while True:
            self.declare(names, self.name("a const name"))
            self.expect("=")
            value = self.next("a constant value")
            integral = type_token.text in INT_RANGES
            if value.kind != "number" or (integral and not INT_LITERAL.fullmatch(value.text)):
                raise self.error(value, f"'{value.text}' is not a {type_token.text} literal")
            if integral:
                bits = INT_RANGES[type_token.text]
                number = int(value.text, 16 if "x" in value.text.lower() else 10)
                if not -2**bits <= number < 2**bits:
                    raise self.error(value, f"{value.text} does not fit in {type_token.text}")
            if not self.accept(","):
                break
        self.expect(";")

    def parse_members(self, struct, names):
        type_token = self.name("a member type", dotted=True)
        if type_token.text in ("struct", "enum"):
            raise self.error(type_token, f"nested {type_token.text} declarations are not supported")
        while True:
            name_token = self.name("a member name")
            self.declare(names, name_token)
            member = Member(name_token.text, type_token.text, [], name_token.line)
            while self.accept("["):
                member.dims.append(self.parse_dimension(struct))
                self.expect("]")
            struct.members.append(member)
            if not self.accept(","):
                break
        self.expect(";")

    def parse_dimension(self, struct):
        token = self.next("an array size")
        if token.kind == "number":
            if not SIZE_LITERAL.fullmatch(token.text):
                raise self.error(token,
                                 f"array size '{token.text}' is not a positive decimal literal")
            if int(token.text) > MAX_BYTES:
                raise self.error(token, f"array size {token.text} cannot fit in a message")
            return int(token.text)
        if token.kind != "name":
            raise self.error(token, f"expected an array size, found '{token.text}'")
        sizer = next((m for m in struct.members if m.name == token.text), None)
        if sizer is None:
            raise self.error(token, f"array size '{token.text}' is not an earlier member of "
                             f"{struct.name} (a const's name is not accepted as a size either)")
        if sizer.dims or sizer.type not in DIMENSION_TYPES:
            raise self.error(token, f"array size '{token.text}' is not a scalar integer member")
        return token.text


def resolve(structs):
    """Full type names for struct members; the types in containment order (contained first),
    and the set of top-level types."""
    by_name = {}
    for s in structs:
        if s.full_name in by_name:
            raise LcmError(s.path, s.line, f"{s.full_name} is also declared in "
                           f"{by_name[s.full_name].path}")
        by_name[s.full_name] = s
    contained = set()
    for s in structs:
        for m in s.members:
            if m.type in FIXED_BYTES or m.type == "string":
                continue
            full = m.type if "." in m.type or not s.package else f"{s.package}.{m.type}"
            if full not in by_name:
                raise LcmError(s.path, m.line, f"unknown type '{m.type}' of member '{m.name}'")
            m.type = full
            contained.add(full)

    ordered, state = [], {}

    def visit(s, chain):
        if state.get(s.full_name) == "done":
            return
        if state.get(s.full_name) == "visiting":
            raise LcmError(s.path, s.line, f"{s.full_name} contains itself: "
                           + " -> ".join(chain + [s.full_name]))
        state[s.full_name] = "visiting"
        for m in s.members:
            if m.type in by_name:
                visit(by_name[m.type], chain + [s.full_name])
        state[s.full_name] = "done"
        ordered.append(s)

    for name in sorted(by_name):
        visit(by_name[name], [])
    top_level = [s for s in ordered if s.full_name not in contained]
    return ordered, sorted(top_level, key=lambda s: s.full_name)


def cpp_type(s):
    return "::".join(s.package.split(".") + [s.name]) if s.package else f"::{s.name}"


def cpp_header(s):
    return "/".join(s.package.split(".") + [f"{s.name}.hpp"]) if s.package else f"{s.name}.hpp"


def walker_name(full_name):
    return "Walk_" + full_name.replace(".", "_")


def local(name):
    return name + "_" if name in RESERVED_LOCALS else name


def statement(code, comment, indent="  "):
    """`code` with its comment on the same line, or above it when that line would be too long."""
    line = f"{indent}{code}  // {comment}"
    if len(line) <= LINE_WIDTH:
        return [line]
    wrapped = textwrap.wrap(comment, LINE_WIDTH - len(indent) - 3, break_on_hyphens=False)
    return [f"{indent}// {text}" for text in wrapped] + [f"{indent}{code}"]


def label(m):
    return m.name + "".join(f"[{d}]" for d in m.dims)


def product(values):
    result = 1
    for v in values:
        result *= v
    return result


def element_count(s, m):
    """A C++ expression for the number of elements of array member `m`."""
    if all(isinstance(d, int) for d in m.dims):
        count = product(m.dims)
        if count > MAX_BYTES:
            raise LcmError(s.path, m.line, f"{label(m)} cannot fit in a message")
        return str(count)
    if len(m.dims) == 1:
        return local(m.dims[0])  # a count, already no larger than the message
    return "w.Elements({" + ", ".join(str(d) if isinstance(d, int) else local(d)
                                      for d in m.dims) + "})"


def walker(s):
    """The Walk_ function of struct `s`: its members in wire order."""
    sizers = {d for m in s.members for d in m.dims if isinstance(d, str)}
    body, run = [], []  # run: consecutive fixed-size members, skipped at once

    def flush():
        if run:
            total = sum(size for _, size in run)
            if total > MAX_BYTES:
                raise LcmError(s.path, s.line, f"{s.full_name} cannot fit in a message")
            body.extend(statement(f"w.Skip({total});", ", ".join(name for name, _ in run)))
            run.clear()

    for m in s.members:
        if m.name in sizers:
            flush()
            body.append(f"  const int64_t {local(m.name)} = w.Count<{m.type}>();")
        elif m.type in FIXED_BYTES and all(isinstance(d, int) for d in m.dims):
            run.append((label(m), FIXED_BYTES[m.type] * product(m.dims)))
        else:
            flush()
            if m.type in FIXED_BYTES:
                code = f"w.Array({element_count(s, m)}, {FIXED_BYTES[m.type]});"
            elif m.type == "string":
                code = f"w.Strings({element_count(s, m)});" if m.dims else "w.String();"
            elif m.dims:
                code = (f"for (int64_t i = 0, n = {element_count(s, m)}; i < n && w.ok(); ++i) "
                        f"{walker_name(m.type)}(w);")
            else:
                code = f"{walker_name(m.type)}(w);"
            body.extend(statement(code, label(m)))
    flush()
    cursor = "WireCursor& w" if body else "WireCursor&"
    return [f"// {s.full_name} ({os.path.basename(s.path)})",
            f"void {walker_name(s.full_name)}({cursor}) {{", *body, "}"]


GENERATED_NOTE = ("// Generated by lcmtypes/gen_wire_bounds.py from the .lcm files: edit those, "
                  "not this file.")


def header(top_level):
    lines = ["#pragma once", GENERATED_NOTE, """//
// Checks an encoded message's array counts before lcm-gen's decode() sees them. LCM 1.3.1's
// generated decode() resizes each std::vector to the count the message claims before it checks
// that the bytes are there: a 100-byte packet claiming 2^31 strings makes it allocate ~64 GB
// (std::bad_alloc at best, an OOM kill or a sanitizer abort at worst). Walking the wire format
// first bounds every allocation by the packet's own size.
//
// There is one overload per top-level type (one that no other type contains), walked as its
// .lcm file lays it out, and deliberately no generic fallback.

#include <cstdint>
"""]
    lines += [f'#include "{cpp_header(s)}"' for s in top_level]
    lines += ["", "namespace odonata::bus {", "", """\
/// True when the `size` bytes at `data` hold a message whose every string length and array count
/// is non-negative and fits in the bytes that remain (fingerprint included, top level).
/// The pointer argument only selects the type."""]
    lines += [f"bool CountsFit(const {cpp_type(s)}*, const void* data, int64_t size);"
              for s in top_level]
    lines += ["", "}  // namespace odonata::bus", ""]
    return "\n".join(lines)


def source(structs, top_level):
    lines = [GENERATED_NOTE, '#include "bus/wire_bounds.hpp"', "",
             '#include "bus/wire_cursor.hpp"', "", "namespace odonata::bus {", "namespace {", ""]
    for s in structs:
        lines += walker(s) + [""]
    lines += ["}  // namespace", ""]
    for s in top_level:
        lines += [f"bool CountsFit(const {cpp_type(s)}*, const void* data, int64_t size) {{",
                  "  WireCursor w(data, size);", "  w.Skip(8);  // fingerprint",
                  f"  {walker_name(s.full_name)}(w);", "  return w.ok();", "}", ""]
    lines += ["}  // namespace odonata::bus", ""]
    return "\n".join(lines)


def write(path, text):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w", encoding="utf-8") as out:
        out.write(text)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--header", required=True, help="bus/wire_bounds.hpp to write")
    parser.add_argument("--source", required=True, help="bus/wire_bounds.cpp to write")
    parser.add_argument("lcm_files", nargs="+", metavar="FILE.lcm")
    args = parser.parse_args()
    try:
        structs = []
        for path in args.lcm_files:
            with open(path, encoding="utf-8") as f:
                structs += Parser(path, tokenize(path, f.read())).parse_file()
        ordered, top_level = resolve(structs)
        if not top_level:
            raise LcmError(args.lcm_files[0], 1, "no struct to check")
        header_text, source_text = header(top_level), source(ordered, top_level)
    except (LcmError, OSError, UnicodeDecodeError) as e:
        print(f"gen_wire_bounds.py: {e}", file=sys.stderr)
        return 1
    write(args.header, header_text)
    write(args.source, source_text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
