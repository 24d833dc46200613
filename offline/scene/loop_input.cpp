#include "offline/scene/loop_input.hpp"
#include "common/build_info.hpp"
#include "common/input_error.hpp"

#include <openssl/evp.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <memory>

#include "offline/scene/loop_artefact_builder.hpp"
#include "offline/scene/scene_plant.hpp"

namespace flexloop::scene {

namespace {

// SHA-256 (OpenSSL EVP) of what `feed` gives its update function, as lowercase hex.
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
  if (!in) throw common::InputError(path, "cannot open file");
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

artefact::Provenance loop_provenance(const std::string& scene_path, const std::string& model_path) {
  return {scene_path,
          file_sha256(scene_path),
          model_path,
          file_sha256(model_path),
          common::build_info::kVersion,
          common::build_info::kGitHash};
}

artefact::LoopArtefact load_loop(const std::string& path, const LoopInputOptions& o) {
  if (artefact::is_loop_artefact_file(path)) return artefact::read_loop_artefact(path, o);
  Scene sc = load_scene(path);
  if (o.rate_hz > 0) sc.discretisation.rate_hz = o.rate_hz;
  const auto p = build_scene_plant(sc);
  require_stable_loop(p);
  artefact::LoopArtefact a =
      build_loop_artefact(p, sample_scene(p), o.form.value_or(artefact::PlantForm::kDense),
                          loop_provenance(path, sc.model_path));
  if (o.duration_s > 0) a.duration_s = o.duration_s;
  return a;
}

}  // namespace flexloop::scene
