// Compressed measured inputs: the field ships MERL tables as .binary.xz or .binary.gz, and
// brdffit reads them as they are. Recognised by content (the xz and gzip magic bytes), so a
// misnamed file still opens; the name without .xz/.gz then says what is inside.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace brdffit {

enum class Compression { None, Xz, Gzip };

// From a file's first bytes (six are enough).
Compression compression_of(const std::string& head);

// How many bytes a decompressed input may hold, from its first kHeadBytes (all of them when it is
// shorter): a MERL header implies its table's size exactly. Decompression stops there, so a
// small bomb costs no more than the header it starts with allows.
constexpr size_t kHeadBytes = 16;
using SizeFromHead = std::function<uint64_t(const std::string& head)>;

// The file's bytes decompressed (every stream of a multi-stream file), streamed and stopped at
// the limit. A file that is corrupt or truncated, or that decompresses to more than the limit
// (a bomb, or not a table), is an Error naming the file.
std::string decompress_file(const std::string& path, Compression compression, const SizeFromHead& limit_of);
// The same with a fixed limit.
std::string decompress_file(const std::string& path, Compression compression, uint64_t max_bytes);

// "gold.binary.xz" -> "gold.binary"; any other name unchanged.
std::string without_compression_suffix(const std::string& path);

}  // namespace brdffit
