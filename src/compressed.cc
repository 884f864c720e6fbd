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

// The decompressed bytes so far and how many there may be: unknown until the first kHeadBytes
// are out, then what `limit_of` says they imply. One byte more than the limit is let through,
// so that a stream of exactly the limit ends normally and one byte more is caught.
class Output {
 public:
  Output(const std::string& path, const SizeFromHead& limit_of) : path_(path), limit_of_(limit_of) {}

  // Appends room to the buffer and returns where it starts; throws once past the limit.
  uint8_t* grow() {
    decide();
    if (used_ > limit_) fail("{}: decompresses to more than {} bytes: not a measured table", path_, limit_);
    const uint64_t end = decided_ ? std::min<uint64_t>(used_ + kChunk, limit_ + 1) : used_ + kHeadBytes;
    bytes_.resize(static_cast<size_t>(std::max<uint64_t>(end, used_ + 1)));
    return reinterpret_cast<uint8_t*>(bytes_.data()) + used_;
  }
  size_t room() const { return bytes_.size() - used_; }
  void produced(size_t left) { used_ = bytes_.size() - left; }

  std::string finish() {
    decide();
    if (used_ > limit_) fail("{}: decompresses to more than {} bytes: not a measured table", path_, limit_);
    bytes_.resize(used_);
    return std::move(bytes_);
  }

 private:
  void decide() {
    if (decided_ || used_ < kHeadBytes) return;
    limit_ = limit_of_(bytes_.substr(0, used_));
    decided_ = true;
  }

  const std::string& path_;
  const SizeFromHead& limit_of_;
  std::string bytes_;
  size_t used_ = 0;
  uint64_t limit_ = UINT64_MAX - 1;
  bool decided_ = false;
};

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

std::string decompress_xz(const std::string& path, const std::string& in, Output& out) {
  XzDecoder decoder;
  lzma_stream& stream = decoder.stream;
  // LZMA_CONCATENATED: `xz` appends streams when files are concatenated; read them all.
  if (lzma_stream_decoder(&stream, UINT64_MAX, LZMA_CONCATENATED) != LZMA_OK)
    fail("{}: cannot start the xz decoder", path);
  stream.next_in = reinterpret_cast<const uint8_t*>(in.data());
  stream.avail_in = in.size();
  lzma_ret status = LZMA_OK;
  while (status == LZMA_OK) {
    stream.next_out = out.grow();
    stream.avail_out = out.room();
    // All the input is there: LZMA_FINISH says so, and a truncated file ends in LZMA_BUF_ERROR.
    status = lzma_code(&stream, LZMA_FINISH);
    out.produced(stream.avail_out);
  }
  if (status != LZMA_STREAM_END) {
    const char* why = status == LZMA_BUF_ERROR      ? "truncated"
                      : status == LZMA_DATA_ERROR   ? "corrupt data"
                      : status == LZMA_FORMAT_ERROR ? "not in the xz format"
                                                    : "cannot be decompressed";
    fail("{}: xz: {}", path, why);
  }
  return out.finish();
}

std::string decompress_gzip(const std::string& path, const std::string& in, Output& out) {
  size_t consumed = 0;
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
      stream.next_out = out.grow();
      stream.avail_out = static_cast<uInt>(out.room());  // at most kChunk
      status = inflate(&stream, Z_NO_FLUSH);
      out.produced(stream.avail_out);
      if (status == Z_BUF_ERROR && stream.avail_in == 0) break;  // the input ended inside the stream
    }
    consumed = static_cast<size_t>(reinterpret_cast<const char*>(stream.next_in) - in.data());
    if (status != Z_STREAM_END) fail("{}: gzip: {}", path, status == Z_DATA_ERROR ? "corrupt data" : "truncated");
  }
  return out.finish();
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

std::string decompress_file(const std::string& path, Compression compression, const SizeFromHead& limit_of) {
  const std::string compressed = read_file(path, kMaxInputBytes);
  Output out(path, limit_of);
  switch (compression) {
    case Compression::Xz: return decompress_xz(path, compressed, out);
    case Compression::Gzip: return decompress_gzip(path, compressed, out);
    case Compression::None: break;
  }
  return compressed;
}

std::string decompress_file(const std::string& path, Compression compression, uint64_t max_bytes) {
  return decompress_file(path, compression, [max_bytes](const std::string&) { return max_bytes; });
}

std::string without_compression_suffix(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return extension == ".xz" || extension == ".gz" ? path.substr(0, path.size() - extension.size()) : path;
}

}  // namespace brdffit
