#include "tsuchi/io/toml_section.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <cctype>
#include <sstream>

namespace tsuchi::io {

namespace {

// Puts `value` (TOML syntax) at a dotted path; numeric parts index arrays of tables.
void apply_override(toml::table& root, const std::string& assignment, const std::string& file) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(fmt::format("{}: override '{}': expected key=value", file, printable(assignment)));
  std::string path = assignment.substr(0, eq);
  path.erase(path.find_last_not_of(" \t") + 1);
  // Only blanks before the '=' (found by fuzzing: parts.back() below read past an empty list).
  if (path.empty()) throw InputError(fmt::format("{}: override '{}': expected key=value", file, printable(assignment)));
  const std::string value = assignment.substr(eq + 1);
  // toml++ would read a second line as another key of its own little document, which is dropped.
  if (assignment.find_first_of("\n\r") != std::string::npos)
    throw InputError(fmt::format("{}: override '{}': expected key=value on one line, got a line break in the value",
                                 file, printable(assignment)));
  toml::table parsed;
  try {
    parsed = toml::parse(std::string_view(std::string("v = ") + value), std::string_view("override"));
  } catch (const toml::parse_error& e) {
    // A bare word is the usual slip: a string needs TOML's quotes, which the shell eats unless the
    // whole assignment is quoted too.
    const auto first = value.find_first_not_of(" \t");
    const bool bare_word = first != std::string::npos && std::isalpha(static_cast<unsigned char>(value[first])) &&
                           value.find_first_of("\"'[{") == std::string::npos;
    throw InputError(fmt::format("{}: override '{}': the value is not valid TOML ({}){}", file, printable(assignment),
                                 e.description(),
                                 bare_word ? fmt::format("; a string needs quotes, in the shell: --set '{}=\"{}\"'",
                                                         path, value.substr(first))
                                           : std::string{}));
  }
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string p; std::getline(ss, p, '.');) parts.push_back(p);
  toml::node* here = &root;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    toml::node* next = nullptr;
    if (auto t = here->as_table()) {
      next = t->get(parts[i]);
      if (!next) next = &t->insert_or_assign(parts[i], toml::table{}).first->second;
    } else if (auto a = here->as_array()) {
      char* end = nullptr;
      const long k = std::strtol(parts[i].c_str(), &end, 10);
      if (*end == '\0' && k >= 0 && static_cast<std::size_t>(k) < a->size()) next = a->get(static_cast<std::size_t>(k));
    }
    if (!next || !(next->is_table() || next->is_array()))
      throw InputError(fmt::format("{}: override '{}': '{}' does not name a table", file, printable(assignment), parts[i]));
    here = next;
  }
  auto t = here->as_table();
  if (!t) throw InputError(fmt::format("{}: override '{}': cannot set an array entry", file, printable(assignment)));
  t->insert_or_assign(parts.back(), *parsed.get("v"));
}

// toml++ reports a string left open by what it meets next: the line break ("unescaped control
// characters") or the end of the file. Both mean a missing closing quote, which is what a user
// needs to hear; other control characters inside a string keep toml++'s own words.
std::string describe_parse_error(const std::string& text, const toml::parse_error& e) {
  const std::string what(e.description());
  if (what.find("parsing") == std::string::npos || what.find("string") == std::string::npos) return what;
  if (what.find("end-of-file") != std::string::npos)
    return "a string is not closed: the file ends before its closing quote";
  if (what.find("control characters") == std::string::npos) return what;
  // The column of the error against the length of its line, in code points (toml++ counts so).
  std::size_t begin = 0;
  for (std::size_t line = 1; line < e.source().begin.line && begin != std::string::npos; ++line) {
    begin = text.find('\n', begin);
    if (begin != std::string::npos) ++begin;
  }
  if (begin == std::string::npos) return what;
  std::size_t end = text.find_first_of("\r\n", begin);
  if (end == std::string::npos) end = text.size();
  const auto points = static_cast<std::size_t>(std::count_if(
      text.begin() + static_cast<std::ptrdiff_t>(begin), text.begin() + static_cast<std::ptrdiff_t>(end),
      [](char ch) { return (static_cast<unsigned char>(ch) & 0xC0) != 0x80; }));
  if (e.source().begin.column <= points) return what;
  return "a string is not closed on its line: its closing quote is missing (a string over several lines needs "
         "triple quotes, \"\"\" or \'\'\')";
}

}  // namespace

toml::table parse_toml(const std::string& text, const std::string& file, const std::vector<std::string>& overrides) {
  // toml++ would name the first byte it cannot decode, which tells the user of a binary file
  // (a results file, an executable given by mistake) nothing.
  if (const auto nul = text.find('\0'); nul != std::string::npos) {
    const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(nul), '\n');
    throw InputError(fmt::format("{}:{}: not a text file (byte {} is NUL); expected a TOML input file", file,
                                 line, nul + 1));
  }
  toml::table root;
  try {
    root = toml::parse(std::string_view(text), std::string_view(file));
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}:{}: {}", file, e.source().begin.line, e.source().begin.column,
                                 describe_parse_error(text, e)));
  }
  for (const auto& o : overrides) apply_override(root, o, file);
  return root;
}

std::string read_input_file(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    throw InputError(fmt::format("{}: cannot read the input file: it is {}, not a regular file", path,
                                 std::filesystem::is_directory(status) ? "a directory" : "a device, pipe or socket"));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open the input file", path));
  in.seekg(0, std::ios::end);
  const auto size = static_cast<std::uint64_t>(in.tellg());
  if (size > max_input_bytes)
    throw InputError(fmt::format("{}: the input file is {} bytes long; input files above {} MB are refused (an input "
                                 "is a few kB of TOML)",
                                 path, size, max_input_bytes >> 20));
  in.seekg(0);
  std::string text(static_cast<std::size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  if (!in) throw InputError(fmt::format("{}: cannot read the input file", path));
  return text;
}

}  // namespace tsuchi::io
