#include "tsuchi/io/stl_reader.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace tsuchi::io {

namespace {

// Little-endian float and integer, whatever the machine.
std::uint32_t u32_at(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | static_cast<unsigned char>(b[at + static_cast<std::size_t>(k)]);
  return v;
}

float f32_at(const std::string& b, std::size_t at) {
  const std::uint32_t bits = u32_at(b, at);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

StlSurface read_binary(const std::string& b) {
  StlSurface s;
  s.binary = true;
  const std::uint32_t n = u32_at(b, 80);
  s.triangles.resize(n);
  s.start.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    const std::size_t at = 84 + 50 * t;
    s.start[t] = at;
    for (int c = 0; c < 3; ++c)
      for (int d = 0; d < 3; ++d)
        s.triangles[t][c][d] = f32_at(b, at + 12 + 12 * static_cast<std::size_t>(c) + 4 * static_cast<std::size_t>(d));
  }
  return s;
}

// Words of an ASCII file, each with its line.
class Words {
 public:
  explicit Words(const std::string& text) : t_(text) {}

  // The next word, or "" at the end.
  std::string next() {
    while (i_ < t_.size() && std::isspace(static_cast<unsigned char>(t_[i_]))) {
      if (t_[i_] == '\n') ++line_;
      ++i_;
    }
    const std::size_t from = i_;
    while (i_ < t_.size() && !std::isspace(static_cast<unsigned char>(t_[i_]))) ++i_;
    word_line_ = line_;
    // Keywords in any case ("FACET", as some exporters write them); numbers do not mind.
    std::string w = t_.substr(from, i_ - from);
    for (char& ch : w) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return w;
  }

  void skip_line() {
    while (i_ < t_.size() && t_[i_] != '\n') ++i_;
  }

  std::size_t line() const { return word_line_; }

  void expect(const char* want) {
    const std::string w = next();
    if (w != want)
      throw StlError(
          fmt::format("line {}: expected '{}', got {}", word_line_, want,
                      w.empty() ? std::string("the end of the file") : fmt::format("'{}'", w.substr(0, 40))));
  }

  double number(const char* what) {
    const std::string w = next();
    char* end = nullptr;
    const double v = w.empty() ? 0.0 : std::strtod(w.c_str(), &end);
    if (w.empty() || end != w.c_str() + w.size())
      throw StlError(
          fmt::format("line {}: expected {}, got {}", word_line_, what,
                      w.empty() ? std::string("the end of the file") : fmt::format("'{}'", w.substr(0, 40))));
    if (!std::isfinite(v)) throw StlError(fmt::format("line {}: {} '{}' is not a finite number", word_line_, what, w));
    return v;
  }

 private:
  const std::string& t_;
  std::size_t i_ = 0, line_ = 1, word_line_ = 1;
};

StlSurface read_ascii(const std::string& text) {
  StlSurface s;
  Words w(text);
  w.expect("solid");
  w.skip_line();  // the solid's name
  for (;;) {
    std::string word = w.next();
    if (word == "endsolid") {
      w.skip_line();
      word = w.next();
      if (word.empty()) break;
      if (word != "solid")
        throw StlError(fmt::format("line {}: expected 'solid' or the end of the file after 'endsolid', got '{}'",
                                   w.line(), word.substr(0, 40)));
      w.skip_line();
      continue;
    }
    if (word != "facet")
      throw StlError(fmt::format("line {}: expected 'facet' or 'endsolid', got {}", w.line(),
                                 word.empty() ? std::string("the end of the file (the file is cut short)")
                                              : fmt::format("'{}'", word.substr(0, 40))));
    s.start.push_back(w.line());
    w.expect("normal");
    for (int d = 0; d < 3; ++d) w.number("a normal component");
    w.expect("outer");
    w.expect("loop");
    geometry::Triangle t;
    for (int c = 0; c < 3; ++c) {
      w.expect("vertex");
      for (int d = 0; d < 3; ++d) t[c][d] = w.number("a vertex coordinate");
    }
    w.expect("endloop");
    w.expect("endfacet");
    s.triangles.push_back(t);
  }
  return s;
}

}  // namespace

std::string StlSurface::name(std::size_t k) const {
  if (k >= start.size()) return fmt::format("triangle {}", k + 1);
  return fmt::format("triangle {} ({} {})", k + 1, binary ? "byte" : "line", start[k]);
}

StlSurface read_stl(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw StlError("no such file (or not a regular file)");
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw StlError(fmt::format("cannot read its size: {}", ec.message()));
  if (size > max_stl_bytes) throw StlError(fmt::format("{} bytes is more than the {} accepted", size, max_stl_bytes));
  std::ifstream in(path, std::ios::binary);
  if (!in.is_open()) throw StlError("cannot be opened (is it readable?)");
  std::string b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw StlError("cannot be read");
  if (b.size() != size) throw StlError("changed while it was read");
  if (b.size() >= 84 && 84 + std::uint64_t{50} * u32_at(b, 80) == b.size()) return read_binary(b);
  std::size_t i = 0;
  while (i < b.size() && std::isspace(static_cast<unsigned char>(b[i]))) ++i;
  if ((b.compare(i, 5, "solid") == 0 || b.compare(i, 5, "SOLID") == 0) && b.find('\0') == std::string::npos)
    return read_ascii(b);
  if (b.size() < 84) throw StlError(fmt::format("{} bytes is too short for a binary STL file (84 at least)", b.size()));
  throw StlError(
      fmt::format("a binary STL file announcing {} triangles has 84 + 50 x {} = {} bytes, this one has {}: "
                  "it is cut short or not an STL file",
                  u32_at(b, 80), u32_at(b, 80), 84 + std::uint64_t{50} * u32_at(b, 80), b.size()));
}

}  // namespace tsuchi::io
