#pragma once
// Reading TOML input: one table at a time through Section, which hands out typed, range-checked
// values, remembers which keys were read and rejects the rest, and words every error as
// "FILE:LINE:COL: key 'a.b': expected ..., got ...". Shared by the run input and the element input.
#include "tsuchi/core/errors.hpp"
#include "tsuchi/model/config.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace tsuchi::io {

inline constexpr const char* axis_name[3] = {"x", "y", "z"};

// "a", "b", "c": how messages list the names a key accepts; `name` picks each item's name.
template <class Range, class Name = std::identity>
std::string quoted_list(const Range& items, Name name = {}) {
  std::string r;
  for (const auto& item : items) r += fmt::format("{}\"{}\"", r.empty() ? "" : ", ", std::invoke(name, item));
  return r;
}

// Text from the input as it goes into a message: control characters and invisible ones (zero-width
// spaces, a byte-order mark, a no-break space) shown as \u{XXXX}, bytes that are not UTF-8 as
// \xNN, and at most `max` characters, so that a stray character can be seen and a 1 MB key does not
// fill the terminal.
inline std::string printable(std::string_view s, std::size_t max = 80) {
  std::string r;
  std::size_t shown = 0, i = 0;
  while (i < s.size() && shown < max) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t len = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
    char32_t cp = len == 1 ? c : len == 2 ? c & 0x1f : len == 3 ? c & 0x0f : c & 0x07;
    for (std::size_t k = 1; k < len; ++k) {
      const auto cc = i + k < s.size() ? static_cast<unsigned char>(s[i + k]) : 0;
      if ((cc >> 6) != 2) len = 0;
      cp = (cp << 6) | (cc & 0x3f);
    }
    if (len == 0) {
      r += fmt::format("\\x{:02x}", c);
      ++i;
    } else {
      const bool invisible = cp < 0x20 || (cp >= 0x7f && cp <= 0xa0) || cp == 0xad || (cp >= 0x200b && cp <= 0x200f) ||
                             (cp >= 0x2028 && cp <= 0x202e) || (cp >= 0x2060 && cp <= 0x2064) || cp == 0xfeff;
      if (invisible) r += fmt::format("\\u{{{:04X}}}", static_cast<std::uint32_t>(cp));
      else r.append(s.substr(i, len));
      i += len;
    }
    ++shown;
  }
  if (i < s.size()) r += fmt::format("... ({} bytes in all)", s.size());
  return r;
}

inline std::string describe(const toml::node& n) {
  if (auto v = n.as_integer()) return fmt::format("{}", v->get());
  if (auto v = n.as_floating_point()) {
    // Keep the decimal point: "got 2" for a 2.0 where a whole number is wanted would mislead.
    std::string r = fmt::format("{}", v->get());
    if (r.find_first_of(".eEn") == std::string::npos) r += ".0";
    return r;
  }
  if (auto v = n.as_string()) return fmt::format("\"{}\"", printable(v->get()));
  if (auto v = n.as_boolean()) return v->get() ? "true" : "false";
  if (n.is_array()) return "an array";
  if (n.is_table()) return "a table";
  return "a value of another type";
}

inline std::string where(const std::string& file, const toml::source_region& r) {
  if (r.begin.line == 0) return fmt::format("{}: (command-line override)", file);
  return fmt::format("{}:{}:{}", file, r.begin.line, r.begin.column);
}

// One TOML table being read: hands out typed values, remembers which keys were asked for, and
// on finish() reports any key nobody asked for.
class Section {
 public:
  Section(const toml::table& t, std::string path, const std::string& file)
      : t_(t), path_(std::move(path)), file_(file) {}

  std::string key_path(std::string_view key) const {
    return path_.empty() ? printable(key) : fmt::format("{}.{}", path_, printable(key));
  }

  // "FILE:LINE:COLUMN: key 'PATH': msg", at the key's value, or at the table when it is absent.
  std::string located(std::string_view key, const std::string& msg) const {
    const toml::node* n = t_.get(key);
    const auto& region = n ? n->source() : t_.source();
    return fmt::format("{}: key '{}': {}", where(file_, region), key_path(key), msg);
  }

  [[noreturn]] void fail(std::string_view key, const std::string& msg) const {
    throw InputError(located(key, msg));
  }

  [[noreturn]] void fail_here(const std::string& msg) const {
    throw InputError(fmt::format("{}: {}{}", where(file_, t_.source()),
                                 path_.empty() ? "" : fmt::format("in '{}': ", path_), msg));
  }

  // "Give exactly one of these keys" failed. When none of them is there, a key one letter off
  // one of them (`young_modulus`) is the likely cause: named with its line, as for a missing key.
  [[noreturn]] void fail_one_of(std::initializer_list<std::string_view> keys, const std::string& msg) const {
    std::string hint;
    if (std::none_of(keys.begin(), keys.end(), [&](std::string_view k) { return has(k); }))
      for (const std::string_view k : keys)
        if (hint.empty()) hint = misspelt(k);
    fail_here(msg + hint);
  }

  bool has(std::string_view key) const { return t_.get(key) != nullptr; }

  const toml::node* get(std::string_view key) {
    used_.insert(std::string(key));
    return t_.get(key);
  }

  const toml::node& need(std::string_view key, const std::string& expected) {
    const toml::node* n = get(key);
    if (!n) {
      throw InputError(fmt::format("{}: missing key '{}': expected {}{}", where(file_, t_.source()),
                                   key_path(key), expected, misspelt(key)));
    }
    return *n;
  }

  double number_of(std::string_view key, const toml::node& n, const std::string& expected) const {
    if (auto i = n.as_integer()) return static_cast<double>(i->get());
    if (auto f = n.as_floating_point()) {
      if (!std::isfinite(f->get())) fail(key, fmt::format("expected {}, got {}", expected, describe(n)));
      return f->get();
    }
    fail(key, fmt::format("expected {}, got {}", expected, describe(n)));
  }

  // A number; `ok` is the range check and `expected` says it in words (with the unit).
  double number(std::string_view key, const std::string& expected,
                const std::function<bool(double)>& ok, std::optional<double> fallback = {}) {
    const toml::node* n = get(key);
    if (!n) {
      if (fallback) return *fallback;
      need(key, expected);
    }
    const double v = number_of(key, *n, expected);
    if (ok && !ok(v)) fail(key, fmt::format("expected {}, got {}", expected, describe(*n)));
    return v;
  }

  std::optional<double> optional_number(std::string_view key, const std::string& expected,
                                        const std::function<bool(double)>& ok) {
    if (!has(key)) {
      get(key);
      return std::nullopt;
    }
    return number(key, expected, ok);
  }

  std::int64_t integer(std::string_view key, const std::string& expected,
                       const std::function<bool(std::int64_t)>& ok, std::int64_t fallback) {
    const toml::node* n = get(key);
    if (!n) return fallback;
    auto i = n->as_integer();
    if (!i || (ok && !ok(i->get()))) fail(key, fmt::format("expected {}, got {}", expected, describe(*n)));
    return i->get();
  }

  std::string string(std::string_view key, const std::string& expected,
                     std::optional<std::string> fallback = {}) {
    const toml::node* n = get(key);
    if (!n) {
      if (fallback) return *fallback;
      need(key, expected);
    }
    auto s = n->as_string();
    if (!s) fail(key, fmt::format("expected {}, got {}", expected, describe(*n)));
    return s->get();
  }

  // A string written on one line of an output (a title in a CSV header): no line break or other
  // control character.
  std::string one_line(std::string_view key, const std::string& expected, std::optional<std::string> fallback = {}) {
    std::string v = string(key, expected, std::move(fallback));
    if (std::any_of(v.begin(), v.end(), [](unsigned char ch) { return ch < 0x20 || ch == 0x7f; }))
      fail(key, fmt::format("expected {} on one line, got a string with a line break or another control character",
                            expected));
    return v;
  }

  bool boolean(std::string_view key, bool fallback) {
    const toml::node* n = get(key);
    if (!n) return fallback;
    auto b = n->as_boolean();
    if (!b) fail(key, fmt::format("expected true or false, got {}", describe(*n)));
    return b->get();
  }

  // One of `choices` (compared case-insensitively); returns its index.
  int choice(std::string_view key, const std::vector<std::string>& choices, int fallback) {
    const toml::node* n = get(key);
    if (!n) return fallback;
    auto s = n->as_string();
    if (s) {
      std::string v = s->get();
      std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
      for (std::size_t i = 0; i < choices.size(); ++i)
        if (v == choices[i]) return static_cast<int>(i);
    }
    fail(key, fmt::format("expected one of {}, got {}", quoted_list(choices), describe(*n)));
  }

  // An array of exactly `dim` numbers, each passing `ok`.
  Triple vector(std::string_view key, int dim, const std::string& expected,
                const std::function<bool(double)>& ok, std::optional<Triple> fallback = {}) {
    const toml::node* n = get(key);
    if (!n) {
      if (fallback) return *fallback;
      need(key, expected);
    }
    return vector_of(key, *n, dim, expected, ok);
  }

  Triple vector_of(std::string_view key, const toml::node& n, int dim, const std::string& expected,
                   const std::function<bool(double)>& ok) const {
    auto a = n.as_array();
    if (!a || static_cast<int>(a->size()) != dim)
      fail(key, fmt::format("expected an array of {} numbers ({}), got {}", dim, expected,
                            a ? fmt::format("{} entries", a->size()) : describe(n)));
    Triple r{};
    for (int d = 0; d < dim; ++d) {
      const toml::node& e = *a->get(static_cast<std::size_t>(d));
      r[d] = number_of(key, e, expected);
      if (ok && !ok(r[d]))
        fail(key, fmt::format("expected {} in every entry, got {} in entry {}", expected,
                              describe(e), d));
    }
    return r;
  }

  const toml::table* table(std::string_view key) {
    const toml::node* n = get(key);
    if (!n) return nullptr;
    if (!n->is_table()) fail(key, fmt::format("expected a table, got {}", describe(*n)));
    return n->as_table();
  }

  // [[key]] array of tables; an absent key gives an empty list.
  std::vector<const toml::table*> tables(std::string_view key) {
    std::vector<const toml::table*> r;
    const toml::node* n = get(key);
    if (!n) return r;
    auto a = n->as_array();
    if (!a) fail(key, fmt::format("expected an array of tables ([[{}]]), got {}", key, describe(*n)));
    for (const auto& e : *a) {
      if (!e.is_table()) fail(key, fmt::format("expected an array of tables ([[{}]]), got an entry that is {}", key, describe(e)));
      r.push_back(e.as_table());
    }
    return r;
  }

  // [[key]] array of tables that must hold at least one entry: an absent key and an empty array
  // (`bodies = []`, in the file or from --set) are both refused.
  std::vector<const toml::table*> need_tables(std::string_view key, const std::string& expected) {
    auto r = tables(key);
    if (r.empty()) {
      if (!has(key)) need(key, expected);
      fail(key, fmt::format("expected {}, got an empty array", expected));
    }
    return r;
  }

  void finish() const {
    for (auto&& [k, v] : t_) {
      if (!used_.count(std::string(k.str()))) {
        throw InputError(fmt::format("{}: unknown key '{}'{}", where(file_, k.source()),
                                     key_path(k.str()), hint(k.str())));
      }
    }
  }

  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }
  const toml::table& raw() const { return t_; }

 private:
  // A required key is read before finish() looks for unknown ones, so a typo of it would be reported
  // as missing while the user sees it in the file: point at the near miss. Only one letter off:
  // a sibling that has not been read yet ('max' while 'min' is missing) is not a typo.
  std::string misspelt(std::string_view key) const {
    for (auto&& [k, v] : t_) {
      if (used_.count(std::string(k.str())) || edit_distance(k.str(), key) > 1) continue;
      const auto line = k.source().begin.line;
      return fmt::format(" (did you misspell it as '{}' {}?)", key_path(k.str()),
                         line == 0 ? std::string("in a command-line override") : fmt::format("on line {}", line));
    }
    return {};
  }

  std::string hint(std::string_view k) const {
    // Suggest a known key that differs only slightly (a typo).
    std::string best;
    std::size_t best_d = 3;
    for (const auto& u : used_) {
      const std::size_t d = edit_distance(k, u);
      if (d < best_d) best_d = d, best = u;
    }
    return best.empty() ? std::string{} : fmt::format(" (did you mean '{}'?)", best);
  }

  // Case does not count: "ZZ" is a typo of "zz", not of "xx".
  static bool same_letter(char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
  }

  static std::size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
      cur[0] = i;
      for (std::size_t j = 1; j <= b.size(); ++j)
        cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + !same_letter(a[i - 1], b[j - 1])});
      std::swap(prev, cur);
    }
    return prev[b.size()];
  }

  const toml::table& t_;
  std::string path_;
  const std::string& file_;
  std::set<std::string> used_;
};

inline const auto positive = [](double v) { return v > 0.0; };
inline const auto non_negative = [](double v) { return v >= 0.0; };
inline const auto any = [](double) { return true; };

// Parses TOML text and applies "dotted.key=value" overrides (value in TOML syntax; numeric
// parts index arrays of tables). Syntax errors become InputError with the file and position.
toml::table parse_toml(const std::string& text, const std::string& file, const std::vector<std::string>& overrides);

// The whole file, or InputError naming it; anything but a regular file of at most
// max_input_bytes is refused before it is read.
inline constexpr std::uint64_t max_input_bytes = std::uint64_t{16} << 20;
std::string read_input_file(const std::string& path);

}  // namespace tsuchi::io
