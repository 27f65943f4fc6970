#pragma once
// A table of numbers from a CSV file (a ground-motion record, particles to start from): a header
// row of column names, then one row of numbers per line. Fields are separated by commas, or by
// spaces and tabs when a line has no comma; blank lines and lines starting with '#' are skipped.
// Errors name the input key that pointed at the file, the CSV file, its line and the column.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tsuchi::io {

struct CsvTable {
  std::string file;                       // the path as opened
  std::vector<std::string> names;         // header
  std::vector<std::vector<double>> rows;  // each names.size() long
  std::vector<int> lines;                 // the file's line number of each row
  std::uint64_t digest = 0;               // FNV-1a of the file's bytes: a restart checks the data too

  // Index of column `name`, or -1.
  int column(const std::string& name) const;
  // "FILE:LINE" of row r.
  std::string at(std::size_t r) const;
};

// `context` is how the error starts: "INPUT:LINE:COL: key 'functions.0.file'". A relative `path` is
// taken against `directory` (the folder of the input file). Throws InputError.
CsvTable read_csv_table(const std::string& path, const std::string& directory, const std::string& context);

// The path of a data file named in an input: absolute, or relative to the input file's folder.
std::string data_path(const std::string& path, const std::string& directory);
// The folder of an input file ("" for the current one).
std::string input_directory(const std::string& input_file);

}  // namespace tsuchi::io
