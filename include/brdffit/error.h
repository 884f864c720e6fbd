// brdffit reports every problem with input or options as a brdffit::Error whose message names
// the file (or option) and the problem; the command-line tool prints it and exits non-zero.
#pragma once

#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace brdffit {

// The one path for text from files and names to the terminal: control characters (ESC, NUL,
// CR, ...; newlines and tabs are kept, messages may be laid out on several lines), DEL, C1
// controls and bytes that are not UTF-8 written as \xHH, so that bytes a message or a table
// quotes from a file or a name neither drive the terminal nor cut the text short at a NUL.
std::string printable(const std::string& text);

// Every message goes through printable(), whatever built it.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(printable(message)) {}
  explicit Error(const char* message) : Error(std::string(message)) {}
};

// A request that cannot be what was meant, whatever the files hold: an unknown name (model,
// metric, command), an option value out of its range, options that exclude each other, an input
// of the wrong kind for the command. The command line exits 2 for it (1 for an Error about a
// file or a fit), so that scripts tell a typo from bad data.
class UsageError : public Error {
 public:
  using Error::Error;
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

template <class... Args>
[[noreturn]] void fail_usage(fmt::format_string<Args...> format, Args&&... args) {
  throw UsageError(fmt::format(format, std::forward<Args>(args)...));
}

}  // namespace brdffit
