// SPDX-License-Identifier: BSD-3-Clause
#include "plant/superelement/reduction_store.hpp"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "common/atomic_file.hpp"

namespace flexloop::plant::superelement {

namespace {

std::string& store_folder() {
  static std::string folder;
  return folder;
}

constexpr char kMagic[] = "flexloop reduction 2\n";
constexpr double kByteOrderMark = 1.0 + 1.0 / 1024;  // reads back equal on this machine only

// FNV-1a, 64 bits: a file name for a key (the key itself is in the file and checked).
std::string file_for(const std::string& key) {
  std::uint64_t h = 1469598103934665603ull;
  for (const unsigned char c : key) h = (h ^ c) * 1099511628211ull;
  char name[40];
  std::snprintf(name, sizeof name, "%016llx.reduction", static_cast<unsigned long long>(h));
  return (std::filesystem::path(store_folder()) / name).string();
}

struct Writer {
  std::string bytes;
  template <class T>
  void put(const T& v) {
    bytes.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void put_doubles(const double* p, Eigen::Index n) {
    bytes.append(reinterpret_cast<const char*>(p), static_cast<std::size_t>(n) * sizeof(double));
  }
};

struct Reader {
  const std::string& bytes;
  std::size_t at = 0;
  bool ok = true;
  template <class T>
  T get() {
    T v{};
    if (!take(&v, sizeof v)) return T{};
    return v;
  }
  bool take(void* out, std::size_t n) {
    if (!ok || bytes.size() - at < n) return ok = false;
    std::memcpy(out, bytes.data() + at, n);
    at += n;
    return true;
  }
};

// A count read from the file: non-negative and small enough to fit what is left.
bool plausible(std::int64_t count, std::size_t element, const Reader& r) {
  return count >= 0 && static_cast<std::uint64_t>(count) <= (r.bytes.size() - r.at) / element;
}

bool read_matrix(Reader& r, Eigen::MatrixXd& m, std::int64_t n) {
  // n first (n * n of a damaged count could overflow), then the whole matrix.
  if (!plausible(n, sizeof(double), r) || !plausible(n * n, sizeof(double), r)) return false;
  m.resize(n, n);
  return r.take(m.data(), static_cast<std::size_t>(n * n) * sizeof(double)) && m.allFinite();
}

bool read_pads(Reader& r, ReducedSuperelement& s, std::int64_t pads) {
  for (std::int64_t k = 0; k < pads && r.ok; ++k) {
    PadNodes pad;
    pad.kind = static_cast<PadKind>(r.get<std::int32_t>());
    const auto nodes = r.get<std::int64_t>();
    if (!plausible(nodes, 32, r)) return false;
    for (std::int64_t i = 0; i < nodes; ++i) pad.nodes.push_back(r.get<std::int64_t>());
    for (std::int64_t i = 0; i < nodes; ++i) {
      Eigen::Vector3d p;
      r.take(p.data(), sizeof(double) * 3);
      pad.positions.push_back(p);
    }
    s.pads.push_back(std::move(pad));
  }
  return r.ok;
}

bool read_body(Reader& r, ReducedSuperelement& s) {
  const auto n = r.get<std::int64_t>(), dofs = r.get<std::int64_t>(), modes = r.get<std::int64_t>(),
             nodes = r.get<std::int64_t>(), pins = r.get<std::int64_t>(),
             pads = r.get<std::int64_t>();
  s.full_dofs = r.get<std::int64_t>();
  s.reduction.interface_dofs = dofs;
  if (!r.ok || dofs < 0 || modes < 0 || dofs + modes != n || !plausible(pins, 12, r) ||
      !plausible(nodes, 24, r) || !plausible(pads, 12, r))
    return false;
  if (!read_matrix(r, s.reduction.K, n) || !read_matrix(r, s.reduction.M, n)) return false;
  s.reduction.fixed_interface_hz.resize(modes);
  if (!r.take(s.reduction.fixed_interface_hz.data(), static_cast<std::size_t>(modes) * 8))
    return false;
  for (std::int64_t i = 0; i < pins; ++i)
    s.interface_dofs.push_back({static_cast<long>(r.get<std::int64_t>()), r.get<std::int32_t>()});
  for (std::int64_t i = 0; i < nodes; ++i) {
    Eigen::Vector3d p;
    r.take(p.data(), sizeof(double) * 3);
    s.positions.push_back(p);
  }
  return read_pads(r, s, pads) && r.at == r.bytes.size();
}

}  // namespace

void set_reduction_store(const std::string& folder) {
  store_folder() = folder;
}

const std::string& reduction_store() {
  return store_folder();
}

std::shared_ptr<const ReducedSuperelement> load_stored_reduction(const std::string& key) {
  if (store_folder().empty()) return nullptr;
  std::ifstream in(file_for(key), std::ios::binary);
  if (!in) return nullptr;
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Reader r{bytes};
  char magic[sizeof kMagic - 1];
  if (!r.take(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof magic) != 0 ||
      r.get<double>() != kByteOrderMark)
    return nullptr;
  const auto key_size = r.get<std::int64_t>();
  if (!plausible(key_size, 1, r) || bytes.compare(r.at, static_cast<std::size_t>(key_size), key))
    return nullptr;
  r.at += static_cast<std::size_t>(key_size);
  auto s = std::make_shared<ReducedSuperelement>();
  if (!read_body(r, *s)) return nullptr;
  return s;
}

void store_reduction(const std::string& key, const ReducedSuperelement& s) {
  // A reduction with the unkept modes' moments (analyse's error) is its process's alone.
  if (store_folder().empty() || !s.reduction.residual.scaled.empty()) return;
  const auto& c = s.reduction;
  Writer w;
  w.bytes.append(kMagic, sizeof kMagic - 1);
  w.put(kByteOrderMark);
  w.put(static_cast<std::int64_t>(key.size()));
  w.bytes += key;
  for (const std::int64_t v :
       {static_cast<std::int64_t>(c.K.rows()), static_cast<std::int64_t>(c.interface_dofs),
        static_cast<std::int64_t>(c.fixed_interface_hz.size()),
        static_cast<std::int64_t>(s.positions.size()),
        static_cast<std::int64_t>(s.interface_dofs.size()),
        static_cast<std::int64_t>(s.pads.size()), static_cast<std::int64_t>(s.full_dofs)})
    w.put(v);
  w.put_doubles(c.K.data(), c.K.size());
  w.put_doubles(c.M.data(), c.M.size());
  w.put_doubles(c.fixed_interface_hz.data(), c.fixed_interface_hz.size());
  for (const DofLabel& d : s.interface_dofs) {
    w.put(static_cast<std::int64_t>(d.node));
    w.put(static_cast<std::int32_t>(d.direction));
  }
  for (const Eigen::Vector3d& p : s.positions) w.put_doubles(p.data(), 3);
  for (const PadNodes& pad : s.pads) {
    w.put(static_cast<std::int32_t>(pad.kind));
    w.put(static_cast<std::int64_t>(pad.nodes.size()));
    for (const long node : pad.nodes) w.put(static_cast<std::int64_t>(node));
    for (const Eigen::Vector3d& p : pad.positions) w.put_doubles(p.data(), 3);
  }
  std::filesystem::create_directories(store_folder());
  common::write_text_atomically(file_for(key), w.bytes);
}

}  // namespace flexloop::plant::superelement
