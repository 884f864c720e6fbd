#include "brdffit/io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>

#include "brdffit/error.h"

namespace brdffit {

namespace fs = std::filesystem;

namespace {

// The permissions a plain open(..., 0666) would give, as files written before mkstemp had;
// mkstemp itself creates 0600. The umask is read once, before any thread writes.
mode_t new_file_mode() {
  static const mode_t mode = [] {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    return static_cast<mode_t>(0666 & ~mask);
  }();
  return mode;
}

const char* file_kind(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

// Writes all of `contents` to fd; false with errno set on failure.
bool write_all(int fd, const std::string& contents) {
  size_t written = 0;
  while (written < contents.size()) {
    const ssize_t n = ::write(fd, contents.data() + written, contents.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    written += static_cast<size_t>(n);
  }
  return true;
}

}  // namespace

namespace {

// The one way brdffit replaces a file: `fill` writes the temporary file (open as fd, named tmp)
// and returns an error message, empty on success; the file is then renamed over `path`.
void replace_file(const std::string& path, const std::string& extension,
                  const std::function<std::string(int fd, const std::string& tmp)>& fill) {
  // Only a regular file (or nothing) is replaced: renaming over a device node or a FIFO would
  // swap a system file for ours. A symbolic link is replaced itself (rename does not follow it).
  struct stat target;
  if (::lstat(path.c_str(), &target) == 0 && !S_ISREG(target.st_mode) && !S_ISLNK(target.st_mode))
    fail("{}: cannot write: {}, not a regular file", path, file_kind(target.st_mode));
  // mkstemps opens O_CREAT|O_EXCL with a fresh name: a planted file or link is never followed.
  std::string tmp = path + kTempInfix + "XXXXXX" + extension;
  const int fd = ::mkstemps(tmp.data(), static_cast<int>(extension.size()));
  if (fd < 0) fail("{}: cannot write: {}", path, std::strerror(errno));
  std::string problem;
  if (::fchmod(fd, new_file_mode()) != 0) problem = std::strerror(errno);
  if (problem.empty()) problem = fill(fd, tmp);
  if (problem.empty() && ::fsync(fd) != 0) problem = std::strerror(errno);
  if (::close(fd) != 0 && problem.empty()) problem = std::strerror(errno);
  if (problem.empty() && std::rename(tmp.c_str(), path.c_str()) != 0) problem = std::strerror(errno);
  if (!problem.empty()) {
    ::unlink(tmp.c_str());
    fail("{}: cannot write: {}", path, problem);
  }
}

}  // namespace

void write_file_atomic(const std::string& path, const std::string& contents) {
  replace_file(path, "", [&](int fd, const std::string&) {
    return write_all(fd, contents) ? std::string() : std::string(std::strerror(errno));
  });
}

void replace_file_atomic(const std::string& path, const std::string& extension,
                         const std::function<std::string(const std::string& temp_path)>& write) {
  replace_file(path, extension, [&](int, const std::string& tmp) { return write(tmp); });
}

std::string read_file(const std::string& path, uint64_t max_bytes) {
  // O_NONBLOCK: opening a FIFO must not wait for a writer; it is refused just below.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) fail("{}: cannot open: {}", path, std::strerror(errno));
  struct stat info;
  if (::fstat(fd, &info) != 0) {
    const int err = errno;
    ::close(fd);
    fail("{}: cannot open: {}", path, std::strerror(err));
  }
  if (!S_ISREG(info.st_mode)) {
    ::close(fd);
    fail("{}: cannot read: {}, not a regular file", path, file_kind(info.st_mode));
  }
  if (static_cast<uint64_t>(info.st_size) > max_bytes) {
    ::close(fd);
    fail("{}: cannot read: {} bytes, more than the limit of {} bytes", path, info.st_size, max_bytes);
  }
  std::string bytes(static_cast<size_t>(info.st_size), '\0');
  size_t got = 0;
  while (got < bytes.size()) {
    const ssize_t n = ::read(fd, bytes.data() + got, bytes.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int err = errno;
      ::close(fd);
      fail("{}: read error: {}", path, std::strerror(err));
    }
    if (n == 0) break;  // the file shrank while we read it
    got += static_cast<size_t>(n);
  }
  ::close(fd);
  bytes.resize(got);
  return bytes;
}

uint64_t check_input_file(const std::string& path, uint64_t max_bytes) {
  struct stat info;
  if (::stat(path.c_str(), &info) != 0) fail("{}: cannot open: {}", path, std::strerror(errno));
  if (!S_ISREG(info.st_mode)) fail("{}: cannot read: {}, not a regular file", path, file_kind(info.st_mode));
  if (static_cast<uint64_t>(info.st_size) > max_bytes)
    fail("{}: cannot read: {} bytes, more than the limit of {} bytes", path, info.st_size, max_bytes);
  return static_cast<uint64_t>(info.st_size);
}

std::string absolute_path(const std::string& path) {
  if (path.empty()) return path;
  std::error_code error;
  const fs::path absolute = fs::absolute(path, error);
  return (error ? fs::path(path) : absolute).lexically_normal().string();
}

void check_outputs(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs) {
  // One entry per path: its identity when it exists, else its normal absolute spelling.
  struct Entry {
    std::string path;
    bool exists;
    dev_t device;
    ino_t inode;
    std::string spelling;
  };
  auto entry = [](const std::string& path) {
    struct stat info;
    Entry e{path, ::stat(path.c_str(), &info) == 0, 0, 0, absolute_path(path)};
    if (e.exists) e.device = info.st_dev, e.inode = info.st_ino;
    return e;
  };
  auto same = [](const Entry& a, const Entry& b) {
    return a.exists && b.exists ? a.device == b.device && a.inode == b.inode : a.spelling == b.spelling;
  };
  std::vector<Entry> in, out;
  for (const std::string& p : inputs)
    if (!p.empty()) in.push_back(entry(p));
  for (const std::string& p : outputs) {
    if (p.empty()) continue;
    struct stat info;
    if (::lstat(p.c_str(), &info) == 0 && !S_ISREG(info.st_mode) && !S_ISLNK(info.st_mode))
      fail("{}: cannot write: {}, not a regular file", p, file_kind(info.st_mode));
    const Entry e = entry(p);
    for (const Entry& i : in)
      if (same(e, i)) fail("{}: the output is the input {}: refusing to overwrite it", p, i.path);
    for (const Entry& o : out)
      if (same(e, o)) fail("{}: the same file is given as two outputs ({} and {})", p, o.path, p);
    out.push_back(e);
  }
}

int remove_stale_temp_files(const std::string& folder) {
  // replace_file's names: <name>.tmp.XXXXXX[.ext] (mkstemps), or <name>.tmp.<pid> (older versions).
  static const std::regex temp_name(R"(.+\.tmp\.([A-Za-z0-9]{6}(\.[A-Za-z0-9]+)?|[0-9]+))");
  int removed = 0;
  std::error_code error;
  for (const fs::directory_entry& e : fs::directory_iterator(folder, error)) {
    if (!e.is_regular_file(error) || e.is_symlink(error)) continue;
    if (!std::regex_match(e.path().filename().string(), temp_name)) continue;
    if (fs::remove(e.path(), error)) ++removed;
  }
  return removed;
}

}  // namespace brdffit

#include <openssl/evp.h>

namespace brdffit {

std::string sha256_file(const std::string& path) {
  // Checked before opening: a folder opens as a stream that reads nothing, a FIFO blocks.
  check_input_file(path, UINT64_MAX);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("{}: cannot open: {}", path, std::strerror(errno));
  EVP_MD_CTX* ctx = EVP_MD_CTX_new();
  EVP_DigestInit_ex(ctx, EVP_sha256(), nullptr);
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0)
    EVP_DigestUpdate(ctx, buffer, static_cast<size_t>(in.gcount()));
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  EVP_DigestFinal_ex(ctx, digest, &length);
  EVP_MD_CTX_free(ctx);
  std::string hex;
  for (unsigned int i = 0; i < length; ++i) hex += fmt::format("{:02x}", digest[i]);
  return hex;
}

std::string escape_markup(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string count_of(size_t count, const std::string& noun) {
  return fmt::format("{} {}{}", count, noun, count == 1 ? "" : "s");
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char ch : text) quoted += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return quoted + "\"";
}

std::string escape_markdown(const std::string& text) {
  std::string out;
  for (const char c : escape_markup(text)) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      out += ' ';
    else if (std::strchr("\\`*_[]|", c))
      out += std::string("\\") + c;
    else
      out += c;
  }
  return out;
}

}  // namespace brdffit
