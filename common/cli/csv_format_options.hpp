#pragma once
// --delimiter and --decimal, the same on every program that reads a CSV (odonata-fit,
// odonata-replay): a spreadsheet in a German or French locale writes "1,5;2,25".

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "io/csv_table.hpp"

namespace odonata::cli {

struct CsvFormatOptions {
  std::string delimiter = ",", decimal = ".";
  /// The format, or nothing when the delimiter and the decimal mark are the same (a ',' for
  /// both: the caller says which option to change).
  std::optional<io::CsvFormat> Format() const {
    io::CsvFormat f;
    f.delimiter = delimiter == "tab" || delimiter == "\\t" ? '\t' : delimiter[0];
    f.decimal = decimal[0];
    if (f.delimiter == f.decimal) return std::nullopt;
    return f;
  }
};

/// Adds both options to `app`.
inline void AddCsvFormatOptions(CLI::App* app, CsvFormatOptions* options) {
  app->add_option("--delimiter", options->delimiter,
                  "what separates the cells of the CSV files: ',' ';' or tab (a spreadsheet in a "
                  "German or French locale writes ';')")
      ->capture_default_str()
      ->check(CLI::IsMember({",", ";", "tab", "\t"}));
  app->add_option("--decimal", options->decimal, "the numbers' decimal mark: '.' or ','")
      ->capture_default_str()
      ->check(CLI::IsMember({".", ","}));
}

}  // namespace odonata::cli
