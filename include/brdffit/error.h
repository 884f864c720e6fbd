// brdffit reports every problem with input or options as a brdffit::Error whose message names
// the file (or option) and the problem; the command-line tool prints it and exits non-zero.
#pragma once

#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace brdffit {

// The text with control characters (ESC, NUL, CR, DEL, ...) written as \xHH, so that bytes a
// message quotes from a file neither drive the terminal nor cut the message short at a NUL.
// Newlines and tabs are kept: messages may be laid out on several lines.
inline std::string printable(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if ((byte < 0x20 && c != '\n' && c != '\t') || byte == 0x7f)
      out += fmt::format("\\x{:02x}", byte);
    else
      out += c;
  }
  return out;
}

// Every message goes through printable(), whatever built it.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(printable(message)) {}
  explicit Error(const char* message) : Error(std::string(message)) {}
};

// A fit stopped on request (FitOptions::cancel) before it ended: it has no result.
class Cancelled : public Error {
 public:
  Cancelled() : Error("the fit was cancelled") {}
};

template <class... Args>
[[noreturn]] void fail(fmt::format_string<Args...> format, Args&&... args) {
  throw Error(fmt::format(format, std::forward<Args>(args)...));
}

}  // namespace brdffit
