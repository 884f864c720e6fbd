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

// How an output is written, decided by what its path finally names (links followed).
enum class OutputKind { Replace, WriteThrough };

bool is_null_device(const struct stat& info) {
  struct stat null;
  return S_ISCHR(info.st_mode) && ::stat("/dev/null", &null) == 0 && null.st_rdev == info.st_rdev;
}

// Whether `path` is a symbolic link that leads, directly or through other links, into /proc: a
// descriptor of this process (/dev/stdout → /proc/self/fd/1), whatever the descriptor is open on.
bool is_descriptor_link(const std::string& path) {
  std::string at = path;
  for (int hop = 0; hop < 40; ++hop) {
    std::error_code error;
    if (!fs::is_symlink(at, error)) return false;
    const fs::path target = fs::read_symlink(at, error);
    if (error) return false;
    at = (target.is_absolute() ? target : fs::path(at).parent_path() / target).lexically_normal().string();
    if (at.rfind("/proc/", 0) == 0) return true;
  }
  return false;
}

// Replace: a regular file, a link to one, or nothing yet; WriteThrough: a pipe, a socket, a
// terminal or /dev/null, reached directly or through links, and whatever a descriptor link
// (`--csv /dev/stdout`) leads to: written into (appended to), never renamed over. Anything else
// (a folder, a disk, another device) is refused: renaming over a device node would swap a system
// file for ours, and writing into one could do worse.
OutputKind output_kind(const std::string& path) {
  struct stat info;
  if (::stat(path.c_str(), &info) != 0) return OutputKind::Replace;
  if (S_ISREG(info.st_mode)) return is_descriptor_link(path) ? OutputKind::WriteThrough : OutputKind::Replace;
  if (S_ISFIFO(info.st_mode) || S_ISSOCK(info.st_mode) || is_null_device(info)) return OutputKind::WriteThrough;
  if (S_ISCHR(info.st_mode)) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    const bool terminal = fd >= 0 && ::isatty(fd);
    if (fd >= 0) ::close(fd);
    if (terminal) return OutputKind::WriteThrough;
  }
  fail("{}: cannot write: {}, not a regular file", path, file_kind(info.st_mode));
}

// Throws Error naming `path` and why unless a file can be made there now: written into when it
// is one written through, else created in its folder, which must exist (with `folders_made`,
// the command makes the missing ones: the nearest existing folder above must take them) and be
// a folder this process may write into. Read-only file systems count (access() says EROFS).
void check_can_create(const std::string& path, bool folders_made) {
  if (output_kind(path) == OutputKind::WriteThrough) {
    if (::access(path.c_str(), W_OK) != 0) fail("{}: cannot write: {}", path, std::strerror(errno));
    return;
  }
  fs::path folder = fs::path(path).parent_path();
  struct stat info;
  for (;;) {
    const std::string shown = folder.empty() ? "." : folder.string();
    if (::stat(shown.c_str(), &info) == 0) {
      if (!S_ISDIR(info.st_mode))
        fail("{}: cannot write: {} is {}, not a folder", path, shown,
             S_ISREG(info.st_mode) ? "a file" : file_kind(info.st_mode));
      if (::access(shown.c_str(), W_OK | X_OK) != 0)
        fail("{}: cannot write into the folder {}: {}", path, shown, std::strerror(errno));
      return;
    }
    // ENOTDIR: a file on the way, named as such above.
    if (errno != ENOENT && errno != ENOTDIR)
      fail("{}: cannot write: the folder {}: {}", path, shown, std::strerror(errno));
    if ((!folders_made && errno == ENOENT) || folder.empty() || folder == folder.parent_path())
      fail("{}: cannot write: the folder {} does not exist", path, shown);
    folder = folder.parent_path();
  }
}

// Copies the file at `from` into the open descriptor `to`; an error message, empty on success.
std::string copy_into(const std::string& from, int to) {
  const int in = ::open(from.c_str(), O_RDONLY | O_CLOEXEC);
  if (in < 0) return std::strerror(errno);
  std::string problem;
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(in, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n < 0) problem = std::strerror(errno);
      break;
    }
    if (!write_all(to, std::string(buffer, static_cast<size_t>(n)))) {
      problem = std::strerror(errno);
      break;
    }
  }
  ::close(in);
  return problem;
}

// The one way brdffit writes a file: `fill` writes the temporary file (open as fd, named tmp)
// and returns an error message, empty on success; the file is then renamed over `path`, or,
// when `path` names a pipe or a terminal, copied into it.
void replace_file(const std::string& path, const std::string& extension,
                  const std::function<std::string(int fd, const std::string& tmp)>& fill) {
  const OutputKind kind = output_kind(path);
  // mkstemps opens O_CREAT|O_EXCL with a fresh name: a planted file or link is never followed.
  // The name starts with kTempPrefix, so that --resume removes only temporaries of brdffit's. A
  // file written through is staged in the temporary folder, not beside a pipe in /dev.
  const fs::path target(path);
  std::error_code error;
  const fs::path folder = kind == OutputKind::Replace ? target.parent_path() : fs::temp_directory_path(error);
  std::string tmp = (folder / (kTempPrefix + target.filename().string() + ".XXXXXX" + extension)).string();
  const int fd = ::mkstemps(tmp.data(), static_cast<int>(extension.size()));
  if (fd < 0) fail("{}: cannot write: {}", path, std::strerror(errno));
  std::string problem;
  if (::fchmod(fd, new_file_mode()) != 0) problem = std::strerror(errno);
  if (problem.empty()) problem = fill(fd, tmp);
  if (problem.empty() && kind == OutputKind::Replace && ::fsync(fd) != 0) problem = std::strerror(errno);
  if (::close(fd) != 0 && problem.empty()) problem = std::strerror(errno);
  if (problem.empty() && kind == OutputKind::WriteThrough) {
    const int out = ::open(path.c_str(), O_WRONLY | O_APPEND | O_NOCTTY | O_CLOEXEC);
    problem = out < 0 ? std::strerror(errno) : copy_into(tmp, out);
    if (out >= 0) ::close(out);
    ::unlink(tmp.c_str());
    if (problem.empty()) return;
  }
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

void check_outputs(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs,
                   OutputFolders folders) {
  // One entry per path: its identity when it exists, else its normal absolute spelling.
  struct Entry {
    std::string path;
    bool exists;
    dev_t device;
    ino_t inode;
    std::string spelling;
  };
  auto entry = [](const std::string& path) {
    // Not there yet: spelled with its folder's links resolved, so that l/x.json and r/x.json
    // through two links to one folder are one output.
    struct stat info;
    std::error_code error;
    const fs::path resolved = fs::weakly_canonical(absolute_path(path), error);
    Entry e{path, ::stat(path.c_str(), &info) == 0, 0, 0, error ? absolute_path(path) : resolved.string()};
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
    check_can_create(p, folders == OutputFolders::Made);  // refuses what cannot be written
    const Entry e = entry(p);
    for (const Entry& i : in)
      if (same(e, i)) fail("{}: the output is the input {}: refusing to overwrite it", p, i.path);
    for (const Entry& o : out)
      if (same(e, o)) fail("{}: the same file is given as two outputs ({} and {})", p, o.path, p);
    out.push_back(e);
  }
}

void check_output_folder(const std::string& folder) {
  std::error_code error;
  if (fs::exists(folder, error) && !fs::is_directory(folder, error))
    fail("{}: cannot write results into it: not a folder", folder);
  check_can_create((fs::path(folder) / "summary.json").string(), true);
}

int remove_stale_temp_files(const std::string& folder) {
  // replace_file's names: kTempPrefix + <name>.XXXXXX[.ext] (mkstemps); nothing else is touched.
  static const std::regex temp_name(R"(\.brdffit-tmp\..+\.[A-Za-z0-9]{6}(\.[A-Za-z0-9]+)?)");
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

std::string count_of(size_t count, const std::string& noun) {
  return fmt::format("{} {}{}", count, noun, count == 1 ? "" : "s");
}

std::string join_words(const std::vector<std::string>& words, const std::string& conjunction) {
  std::string text;
  for (size_t i = 0; i < words.size(); ++i)
    text += (i == 0 ? "" : i + 1 == words.size() ? " " + conjunction + " " : ", ") + words[i];
  return text;
}

}  // namespace brdffit
