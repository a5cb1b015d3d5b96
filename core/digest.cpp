#include "digest.hpp"

#include <openssl/evp.h>

#include <fstream>
#include <memory>
#include <stdexcept>
#include <vector>

#include "input_file.hpp"

namespace tigris {

namespace {

// Hex SHA-256 of what `feed` passes to its update function.
template <class Feed>
std::string sha256_hex(Feed feed) {
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> ctx(EVP_MD_CTX_new(), &EVP_MD_CTX_free);
  if (!ctx || EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("OpenSSL could not start a SHA-256 digest");
  feed([&](const char* data, std::size_t n) { EVP_DigestUpdate(ctx.get(), data, n); });
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int n = 0;
  EVP_DigestFinal_ex(ctx.get(), digest, &n);
  std::string hex;
  static const char* digits = "0123456789abcdef";
  for (unsigned int i = 0; i < n; ++i) {
    hex += digits[digest[i] >> 4];
    hex += digits[digest[i] & 15];
  }
  return hex;
}

}  // namespace

std::string sha256_of_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot read the file to record its SHA-256");
  std::string hex = sha256_hex([&](const auto& update) {
    std::vector<char> buf(1 << 16);
    while (in) {
      in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
      if (in.gcount() > 0) update(buf.data(), static_cast<std::size_t>(in.gcount()));
    }
  });
  if (in.bad()) throw std::invalid_argument(path + ": read error while computing its SHA-256");
  return hex;
}

std::string sha256_of_text(const std::string& text) {
  return sha256_hex([&](const auto& update) { update(text.data(), text.size()); });
}

nlohmann::json input_file(const std::string& role, const std::string& path) {
  const std::uint64_t bytes = check_input(path, "the " + role);  // a FIFO or device: an error, never a hang
  return {{"role", role}, {"path", path}, {"bytes", bytes}, {"sha256", sha256_of_file(path)}};
}

nlohmann::json builtin_input(const std::string& role, const std::string& name) {
  return {{"role", role}, {"builtin", name}};
}

}  // namespace tigris
