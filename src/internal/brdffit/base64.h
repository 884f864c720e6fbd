// Base64 (RFC 4648, standard alphabet, '=' padding, no line breaks): the one encoder of the data
// URIs brdffit writes (a glTF file's buffer, the report's PNG images).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace brdffit {

std::string base64(const std::vector<uint8_t>& bytes);

}  // namespace brdffit
