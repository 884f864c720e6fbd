// File helpers: whole-or-nothing writes and whole-file reads with clear errors, checksums, and
// escaping text for the HTML and XML files brdffit writes.
#pragma once

#include <string>

namespace brdffit {

// Writes to a temporary file beside `path`, flushes it and renames it over `path`, so readers
// see the old file or the complete new one, never a partial one. Throws Error on failure.
void write_file_atomic(const std::string& path, const std::string& contents);

// Reads a whole file into memory; throws Error naming the file when it cannot.
std::string read_file(const std::string& path);

// SHA-256 of a file's bytes as lowercase hex.
std::string sha256_file(const std::string& path);

// Text escaped to stand in HTML or XML content and attribute values (& < > " ').
std::string escape_markup(const std::string& text);

}  // namespace brdffit
