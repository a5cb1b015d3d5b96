#include "input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "input_error.hpp"

namespace tigris {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what, const std::string& why) {
  throw InputError(path + ": " + (what.empty() ? "" : "cannot read " + what + ": ") + why);
}

const char* kind(mode_t m) {
  if (S_ISDIR(m)) return "a folder";
  if (S_ISFIFO(m)) return "a FIFO (named pipe)";
  if (S_ISCHR(m)) return "a character device";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISSOCK(m)) return "a socket";
  return "not a regular file";
}

std::string size_text(std::uint64_t b) {
  if (b >= (1ull << 30)) return std::to_string(b >> 30) + " GiB";
  if (b >= (1ull << 20)) return std::to_string(b >> 20) + " MiB";
  return std::to_string(b) + " bytes";
}

// stat() through links, with the link's own trouble named.
struct stat stat_input(const std::string& path, const std::string& what) {
  if (path.empty()) fail("(empty path)", what, "no file named");
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) return st;
  const int err = errno;
  struct stat lst {};
  if (err == ELOOP) fail(path, what, "a loop of symbolic links");
  if (err == ENOENT && ::lstat(path.c_str(), &lst) == 0 && S_ISLNK(lst.st_mode)) {
    char target[4096];
    const ssize_t n = ::readlink(path.c_str(), target, sizeof target - 1);
    fail(path, what,
         "a broken symbolic link (to " + std::string(target, n > 0 ? static_cast<std::size_t>(n) : 0) + ")");
  }
  if (err == ENOENT) fail(path, what, "no such file");
  if (err == ENOTDIR) fail(path, what, "a part of the path is not a folder");
  fail(path, what, std::strerror(err));
}

void check_stat(const struct stat& st, const std::string& path, const std::string& what, std::uint64_t max_bytes) {
  if (!S_ISREG(st.st_mode)) fail(path, what, std::string("is ") + kind(st.st_mode) + ", not a regular file");
  if (static_cast<std::uint64_t>(st.st_size) > max_bytes)
    fail(path, what,
         "is " + size_text(static_cast<std::uint64_t>(st.st_size)) + ", more than the " + size_text(max_bytes) +
             " such an input may be (is it the right file?)");
}

}  // namespace

std::uint64_t check_input(const std::string& path, const std::string& what, std::uint64_t max_bytes) {
  const struct stat st = stat_input(path, what);
  check_stat(st, path, what, max_bytes);
  return static_cast<std::uint64_t>(st.st_size);
}

std::string read_input(const std::string& path, const std::string& what, std::uint64_t max_bytes) {
  check_input(path, what, max_bytes);
  // O_NONBLOCK: a FIFO swapped in after the check opens without waiting, and fstat refuses it.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) fail(path, what, std::strerror(errno));
  struct FdCloser {
    int fd;
    ~FdCloser() { ::close(fd); }
  } fd_closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) fail(path, what, std::strerror(errno));
  check_stat(st, path, what, max_bytes);
  std::string bytes(static_cast<std::size_t>(st.st_size), '\0');
  std::size_t got = 0;
  while (got < bytes.size()) {
    const ssize_t n = ::read(fd, &bytes[got], bytes.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(path, what, std::string("read error: ") + std::strerror(errno));
    if (n == 0) fail(path, what, "read error (the file shrank while it was read)");
    got += static_cast<std::size_t>(n);
  }
  char extra;
  if (::read(fd, &extra, 1) > 0) fail(path, what, "read error (the file grew while it was read)");
  return bytes;
}

}  // namespace tigris
