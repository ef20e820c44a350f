// CSVs as spreadsheets write them outside English locales: ';' between cells, ',' as the decimal
// mark (issue 23 point 7), and a clear hint when the separator is not the one asked for.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "io/csv_table.hpp"

namespace odonata::io {
namespace {

TEST(CsvFormat, SemicolonsAndDecimalCommas) {
  const CsvTable t = CsvTable::Parse("u;y\n1,5;-2,25\n3;4e-1\n", "semi.csv", MissingCells::kReject,
                                     CsvFormat{';', ','});
  EXPECT_EQ(t.Column("u"), (std::vector<double>{1.5, 3.0}));
  EXPECT_EQ(t.Column("y"), (std::vector<double>{-2.25, 0.4}));
  const CsvTable tabs =
      CsvTable::Parse("u\ty\n1.5\t2\n", "tabs.tsv", MissingCells::kReject, CsvFormat{'\t', '.'});
  EXPECT_EQ(tabs.Column("y"), std::vector<double>{2.0});
}

TEST(CsvFormat, TheWrongSeparatorIsNamedWithTheOptionThatReadsIt) {
  try {
    CsvTable::Parse("u;y\n1,5;2\n", "semi.csv");
    ADD_FAILURE() << "read with ','";
  } catch (const CsvError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("semi.csv:2"), std::string::npos) << what;
    EXPECT_NE(what.find("--delimiter ';'"), std::string::npos) << what;
  }
  // And with decimal points: the rows split like the header, so only the cell says it.
  for (const auto& [text, option] :
       {std::pair<std::string, std::string>{"u;y\n1.5;2\n", "';'"}, {"u\ty\n1.5\t2\n", "tab"}}) {
    try {
      CsvTable::Parse(text, "points.csv");
      ADD_FAILURE() << "read with ','";
    } catch (const CsvError& e) {
      EXPECT_NE(std::string(e.what()).find("--delimiter " + option), std::string::npos) << e.what();
    }
  }
  // With a decimal comma a '.' is not a decimal mark: no silent misreading of 1.234 as 1234.
  EXPECT_THROW(CsvTable::Parse("u;y\n1.5;2\n", "x.csv", MissingCells::kReject, CsvFormat{';', ','}),
               CsvError);
  EXPECT_THROW(CsvTable::Parse("u,y\n1,2\n", "x.csv", MissingCells::kReject, CsvFormat{',', ','}),
               std::invalid_argument);
}

// Issue 61: a device or a binary file is an error, not a read that never ends.
TEST(CsvTable, ABinaryFileOrDeviceIsRefusedNotReadForEver) {
  try {
    CsvTable::Read("/dev/zero");
    FAIL() << "read /dev/zero";
  } catch (const CsvError& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/zero: a NUL byte at byte 0"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace odonata::io
