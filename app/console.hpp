#pragma once
// Printing to the terminal, a log or a pipe that may go away under a run: a closed pipe
// (`tsuchi run ... | head -1`) or a hung-up terminal makes every later write fail (EPIPE, EIO;
// SIGPIPE is ignored, main.cpp). The run must go on and write its files and checkpoint all the
// same, so a failed write is dropped here instead of throwing as fmt::print does.
#include <fmt/format.h>

#include <cstdio>
#include <string>
#include <utility>

namespace tsuchi::app {

template <typename... T>
void say(std::FILE* stream, fmt::format_string<T...> format, T&&... args) {
  const std::string text = fmt::format(format, std::forward<T>(args)...);
  if (std::fwrite(text.data(), 1, text.size(), stream) != text.size()) std::clearerr(stream);
}

// To standard output.
template <typename... T>
void say(fmt::format_string<T...> format, T&&... args) {
  say(stdout, format, std::forward<T>(args)...);
}

}  // namespace tsuchi::app
