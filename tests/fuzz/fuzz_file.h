// For fuzz targets whose reader takes a path: the input written to this process's scratch file.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

namespace brdffit::fuzz {

// Writes the bytes to /tmp/brdffit-fuzz-<name>-<pid><extension> and returns its path.
inline std::string input_file(const char* name, const char* extension, const uint8_t* data, size_t size) {
  static const std::string path =
      "/tmp/brdffit-fuzz-" + std::string(name) + "-" + std::to_string(::getpid()) + extension;
  FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) return path;
  if (size > 0) std::fwrite(data, 1, size, file);
  std::fclose(file);
  return path;
}

}  // namespace brdffit::fuzz
