#include "tsuchi/io/csv_table.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/toml_section.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace tsuchi::io {

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  auto trim = [](std::string s) {
    const auto b = s.find_first_not_of(" \t\r");
    const auto e = s.find_last_not_of(" \t\r");
    return b == std::string::npos ? std::string{} : s.substr(b, e - b + 1);
  };
  if (line.find(',') != std::string::npos) {
    std::size_t start = 0;
    while (true) {
      const auto comma = line.find(',', start);
      out.push_back(trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  } else {
    std::istringstream in(line);
    std::string f;
    while (in >> f) out.push_back(f);
  }
  return out;
}

bool blank_or_comment(const std::string& line) {
  const auto b = line.find_first_not_of(" \t\r");
  return b == std::string::npos || line[b] == '#';
}

}  // namespace

int CsvTable::column(const std::string& name) const {
  for (std::size_t k = 0; k < names.size(); ++k)
    if (names[k] == name) return static_cast<int>(k);
  return -1;
}

std::string CsvTable::at(std::size_t r) const { return fmt::format("{}:{}", file, lines[r]); }

std::string input_directory(const std::string& input_file) {
  return std::filesystem::path(input_file).parent_path().string();
}

std::string data_path(const std::string& path, const std::string& directory) {
  const std::filesystem::path p(path);
  if (p.is_absolute() || directory.empty()) return p.string();
  return (std::filesystem::path(directory) / p).string();
}

CsvTable read_csv_table(const std::string& path, const std::string& directory, const std::string& context) {
  CsvTable t;
  t.file = data_path(path, directory);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(t.file, ec))
    throw InputError(fmt::format("{}: cannot read \"{}\": {}", context, t.file,
                                 std::filesystem::exists(t.file, ec) ? "not a regular file" : "no such file"));
  std::ifstream in(t.file, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open \"{}\"", context, t.file));
  std::stringstream whole;
  whole << in.rdbuf();
  const std::string text = whole.str();
  t.digest = 1469598103934665603ull;
  for (unsigned char ch : text) t.digest = (t.digest ^ ch) * 1099511628211ull;

  std::istringstream lines(text);
  std::string line;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    if (blank_or_comment(line)) continue;
    auto fields = split(line);
    if (t.names.empty()) {
      for (const auto& f : fields) {
        double dummy = 0.0;
        const auto r = std::from_chars(f.data(), f.data() + f.size(), dummy);
        if (r.ec == std::errc{} && r.ptr == f.data() + f.size())
          throw InputError(fmt::format("{}: {}:{}: expected a header row of column names first, got the number {}",
                                       context, t.file, number, printable(f)));
        if (f.empty()) throw InputError(fmt::format("{}: {}:{}: a column of the header has no name", context, t.file, number));
        for (const auto& seen : t.names)
          if (seen == f) throw InputError(fmt::format("{}: {}:{}: column \"{}\" appears twice", context, t.file, number, printable(f)));
        t.names.push_back(f);
      }
      continue;
    }
    if (fields.size() != t.names.size())
      throw InputError(fmt::format("{}: {}:{}: expected {} values (columns {}), got {}", context, t.file, number,
                                   t.names.size(), printable(fmt::format("{}", fmt::join(t.names, ", ")), 200),
                                   fields.size()));
    std::vector<double> row(fields.size());
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const auto& f = fields[k];
      const char* b = f.data();
      if (!f.empty() && *b == '+') ++b;
      const auto r = std::from_chars(b, f.data() + f.size(), row[k]);
      if (r.ec != std::errc{} || r.ptr != f.data() + f.size() || !std::isfinite(row[k]))
        throw InputError(fmt::format("{}: {}:{}: column \"{}\": expected a finite number, got \"{}\"", context, t.file,
                                     number, printable(t.names[k]), printable(f)));
    }
    t.rows.push_back(std::move(row));
    t.lines.push_back(number);
  }
  if (t.names.empty()) throw InputError(fmt::format("{}: \"{}\" holds no header row and no data", context, t.file));
  if (t.rows.empty()) throw InputError(fmt::format("{}: \"{}\" holds a header but no row of data", context, t.file));
  return t;
}

}  // namespace tsuchi::io
