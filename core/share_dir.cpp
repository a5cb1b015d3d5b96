#include "share_dir.hpp"

#include <unistd.h>

#include <climits>
#include <filesystem>

namespace tigris {

std::string self_path() {
  char self[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) return "";
  self[n] = '\0';
  return self;
}

std::string share_dir() {
  namespace fs = std::filesystem;
  return (fs::path(self_path()).parent_path().parent_path() / "share" / "tigris").string();
}

}  // namespace tigris
