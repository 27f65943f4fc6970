#pragma once
// Printing to the terminal, a log or a pipe that may go away under a run: a closed pipe
// (`tsuchi run ... | head -1`) or a hung-up terminal makes every later write fail (EPIPE, EIO;
// SIGPIPE is ignored, main.cpp). The run must go on and write its files and checkpoint all the
// same, so a failed write is dropped here instead of throwing as fmt::print does.
#include "tsuchi/io/toml_section.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <string_view>
#include <utility>

namespace tsuchi::app {

template <typename... T>
void say(std::FILE* stream, fmt::format_string<T...> format, T&&... args) {
  const std::string text = fmt::format(format, std::forward<T>(args)...);
  if (std::fwrite(text.data(), 1, text.size(), stream) != text.size()) std::clearerr(stream);
}

// A message as the terminal may show it: it can quote a file's bytes (a binary file given as a
// CSV), and an ESC or a bell from there must not reach the terminal. Control characters other
// than the line breaks, invisible characters and bytes that are not UTF-8 are written out as
// \u{XXXX} or \xNN (io::printable), line by line.
inline std::string shown(std::string_view text) {
  std::string r;
  for (std::size_t at = 0; at <= text.size();) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    r += io::printable(text.substr(at, end - at), std::string::npos);
    if (end < text.size()) r += '\n';
    at = end + 1;
  }
  return r;
}

// To standard output.
template <typename... T>
void say(fmt::format_string<T...> format, T&&... args) {
  say(stdout, format, std::forward<T>(args)...);
}

}  // namespace tsuchi::app
