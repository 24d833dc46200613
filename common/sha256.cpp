// SPDX-License-Identifier: BSD-3-Clause
#include "common/sha256.hpp"

#include <openssl/evp.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <memory>

#include "common/input_error.hpp"

namespace flexloop::common {

namespace {

// SHA-256 of what `feed` gives its update function, as lowercase hex.
template <class Feed>
std::string sha256_hex(Feed&& feed) {
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> ctx(EVP_MD_CTX_new(), EVP_MD_CTX_free);
  EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr);
  feed([&](const char* data, std::size_t n) { EVP_DigestUpdate(ctx.get(), data, n); });
  std::array<unsigned char, EVP_MAX_MD_SIZE> md{};
  unsigned int len = 0;
  EVP_DigestFinal_ex(ctx.get(), md.data(), &len);
  std::string hex;
  char two[3];
  for (unsigned int i = 0; i < len; ++i) {
    std::snprintf(two, sizeof two, "%02x", md[i]);
    hex += two;
  }
  return hex;
}

}  // namespace

std::string file_sha256(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open file");
  return sha256_hex([&](const auto& update) {
    std::array<char, 65536> buf{};
    while (in) {
      in.read(buf.data(), buf.size());
      update(buf.data(), static_cast<std::size_t>(in.gcount()));
    }
  });
}

std::string text_sha256(std::string_view text) {
  return sha256_hex([&](const auto& update) { update(text.data(), text.size()); });
}

}  // namespace flexloop::common
