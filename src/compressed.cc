// Decompressing .xz (liblzma) and .gz (zlib) inputs into memory.
#include "brdffit/compressed.h"

#include <lzma.h>
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "brdffit/error.h"
#include "brdffit/io.h"

namespace brdffit {

namespace {

constexpr size_t kChunk = size_t{1} << 20;

// Appends up to kChunk bytes of room to `out` and returns where they start, refusing to grow
// past max_bytes.
uint8_t* grow(std::string& out, size_t& used, uint64_t max_bytes, const std::string& path) {
  if (used >= max_bytes) fail("{}: decompresses to more than {} bytes: not a measured table", path, max_bytes);
  out.resize(std::min<uint64_t>(used + kChunk, max_bytes));
  return reinterpret_cast<uint8_t*>(out.data()) + used;
}

// The decoders' states, ended however the decoding ends: grow() and fail() throw.
struct XzDecoder {
  lzma_stream stream = LZMA_STREAM_INIT;
  ~XzDecoder() { lzma_end(&stream); }
};

struct GzipDecoder {
  z_stream stream{};
  bool started = false;
  ~GzipDecoder() {
    if (started) inflateEnd(&stream);
  }
};

std::string decompress_xz(const std::string& path, const std::string& in, uint64_t max_bytes) {
  XzDecoder decoder;
  lzma_stream& stream = decoder.stream;
  // LZMA_CONCATENATED: `xz` appends streams when files are concatenated; read them all.
  if (lzma_stream_decoder(&stream, UINT64_MAX, LZMA_CONCATENATED) != LZMA_OK)
    fail("{}: cannot start the xz decoder", path);
  std::string out;
  size_t used = 0;
  stream.next_in = reinterpret_cast<const uint8_t*>(in.data());
  stream.avail_in = in.size();
  lzma_ret status = LZMA_OK;
  while (status == LZMA_OK) {
    stream.next_out = grow(out, used, max_bytes, path);
    stream.avail_out = out.size() - used;
    // All the input is there: LZMA_FINISH says so, and a truncated file ends in LZMA_BUF_ERROR.
    status = lzma_code(&stream, LZMA_FINISH);
    used = out.size() - stream.avail_out;
  }
  if (status != LZMA_STREAM_END) {
    const char* why = status == LZMA_BUF_ERROR      ? "truncated"
                      : status == LZMA_DATA_ERROR   ? "corrupt data"
                      : status == LZMA_FORMAT_ERROR ? "not in the xz format"
                                                    : "cannot be decompressed";
    fail("{}: xz: {}", path, why);
  }
  out.resize(used);
  return out;
}

std::string decompress_gzip(const std::string& path, const std::string& in, uint64_t max_bytes) {
  std::string out;
  size_t used = 0, consumed = 0;
  // One member after another: `cat a.gz b.gz` is a valid gzip file of both.
  while (consumed < in.size()) {
    GzipDecoder decoder;
    z_stream& stream = decoder.stream;
    if (inflateInit2(&stream, 16 + MAX_WBITS) != Z_OK) fail("{}: cannot start the gzip decoder", path);
    decoder.started = true;
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data() + consumed));
    stream.avail_in = static_cast<uInt>(std::min<size_t>(in.size() - consumed, UINT32_MAX));
    int status = Z_OK;
    while (status == Z_OK) {
      stream.next_out = grow(out, used, max_bytes, path);
      stream.avail_out = static_cast<uInt>(out.size() - used);
      status = inflate(&stream, Z_NO_FLUSH);
      used = out.size() - stream.avail_out;
      if (status == Z_BUF_ERROR && stream.avail_in == 0) break;  // the input ended inside the stream
    }
    consumed = static_cast<size_t>(reinterpret_cast<const char*>(stream.next_in) - in.data());
    if (status != Z_STREAM_END) fail("{}: gzip: {}", path, status == Z_DATA_ERROR ? "corrupt data" : "truncated");
  }
  out.resize(used);
  return out;
}

}  // namespace

Compression compression_of(const std::string& head) {
  if (head.compare(0, 6,
                   "\xFD"
                   "7zXZ\0",
                   6) == 0)
    return Compression::Xz;
  if (head.size() >= 2 && head[0] == '\x1F' && head[1] == '\x8B') return Compression::Gzip;
  return Compression::None;
}

std::string decompress_file(const std::string& path, Compression compression, uint64_t max_bytes) {
  const std::string compressed = read_file(path, kMaxInputBytes);
  switch (compression) {
    case Compression::Xz: return decompress_xz(path, compressed, max_bytes);
    case Compression::Gzip: return decompress_gzip(path, compressed, max_bytes);
    case Compression::None: break;
  }
  return compressed;
}

std::string without_compression_suffix(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return extension == ".xz" || extension == ".gz" ? path.substr(0, path.size() - extension.size()) : path;
}

}  // namespace brdffit
