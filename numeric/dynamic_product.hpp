// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Matrix-vector products for the general path's step (sizes known at start-up), column by column
// as column_product.hpp does for compiled sizes:
//
//   out = init + A a + B b        A: rows x ka, B: rows x kb, column-major
//
// The rows are taken in blocks of up to four widest SIMD packets held in registers; within a
// block every column costs one broadcast of its vector entry and one multiply-add per packet, and
// the columns are dealt round independent chains of sums (8 packets in flight), added at the end.
// Why not Eigen's dynamic-size product, which the general path used before: for the small matrices
// of a loop (6 to 30 rows) its run-time dispatch and blocking cost more than the arithmetic.
//
// Storage: every matrix has a whole number of widest packets of rows (padded_row_count(): zeros
// below the real rows), so that no block has a scalar tail; `init` and `out` have as many entries.
// The padding rows of `out` are then init's padding (zero when init's is). The vectors a and b are
// read entry by entry. No allocation, lock, exception or system call.
#include <Eigen/Core>
#include <type_traits>

#include "numeric/column_product.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"

namespace flexloop::numeric {

/// The widest SIMD packet of Scalar the build offers (1 without SIMD).
template <typename Scalar>
inline constexpr Eigen::Index kWidestPacket = detail::kPacketSize<Scalar, 0>;

/// Start-up: `rows` rounded up to whole widest packets, the row count of the matrices and
/// vectors product_sum() reads and writes.
template <typename Scalar>
constexpr Eigen::Index padded_row_count(Eigen::Index rows) {
  return (rows + kWidestPacket<Scalar> - 1) / kWidestPacket<Scalar> * kWidestPacket<Scalar>;
}

namespace detail {

// Independent chains of sums a block keeps: a multiply-add waits ~4 cycles for its sum, and a
// core issues two a cycle, so about 8 packets of sums in flight keep it busy. A block of one
// packet of rows (an output product: a few outputs over many states) needs 8 chains; wider
// blocks get the same from their own packets with fewer.
template <int Packets>
inline constexpr int kChains = Packets == 1   ? 8
                               : Packets == 2 ? 4
                                              : 2;

// sums[c] += M(:, j) m_j over the columns j of M, the columns dealt round the Chains chains.
template <typename Packet, int P, int Packets, int Chains, typename Scalar>
EIGEN_ALWAYS_INLINE void add_columns(Registers<Packet, Packets> (&sums)[Chains], const Scalar* M,
                                     Eigen::Index k, const Scalar* m, Eigen::Index ld) {
  Eigen::Index j = 0;
  for (; j + Chains <= k; j += Chains) {
#pragma GCC unroll 8
    for (int c = 0; c < Chains; ++c) {
      const Packet x = ei::pset1<Packet>(m[j + c]);
      const Scalar* column = M + (j + c) * ld;
#pragma GCC unroll 4
      for (int p = 0; p < Packets; ++p)
        sums[c][p] = ei::pmadd(ei::ploadu<Packet>(column + p * P), x, sums[c][p]);
    }
  }
  for (int c = 0; j < k; ++j, ++c) {
    const Packet x = ei::pset1<Packet>(m[j]);
    const Scalar* column = M + j * ld;
#pragma GCC unroll 4
    for (int p = 0; p < Packets; ++p)
      sums[c][p] = ei::pmadd(ei::ploadu<Packet>(column + p * P), x, sums[c][p]);
  }
}

// Rows [0, Packets * P) of out = init + A a + B b; A and B start at the block's first row, with
// `ld` entries from one column to the next. kChains<Packets> chains of sums, so that a product
// of k columns waits on k / Chains dependent multiply-adds, not k; added pairwise at the end.
template <typename Scalar, int Packets>
EIGEN_ALWAYS_INLINE void product_sum_block(const Scalar* A, Eigen::Index ka, const Scalar* a,
                                           const Scalar* B, Eigen::Index kb, const Scalar* b,
                                           Eigen::Index ld, const Scalar* init, Scalar* out) {
  using Packet = typename PacketLevel<Scalar, 0>::type;
  constexpr int P = kPacketSize<Scalar, 0>;
  constexpr int Chains = kChains<Packets>;
  Registers<Packet, Packets> sums[Chains];
#pragma GCC unroll 8
  for (int c = 0; c < Chains; ++c)
#pragma GCC unroll 4
    for (int p = 0; p < Packets; ++p)
      sums[c][p] = c == 0 && init ? ei::ploadu<Packet>(init + p * P) : ei::pset1<Packet>(Scalar(0));
  add_columns<Packet, P>(sums, A, ka, a, ld);
  add_columns<Packet, P>(sums, B, kb, b, ld);
#pragma GCC unroll 3
  for (int width = Chains / 2; width > 0; width /= 2)
#pragma GCC unroll 4
    for (int c = 0; c < width; ++c)
#pragma GCC unroll 4
      for (int p = 0; p < Packets; ++p) sums[c][p] = ei::padd(sums[c][p], sums[c + width][p]);
#pragma GCC unroll 4
  for (int p = 0; p < Packets; ++p) ei::pstoreu(out + p * P, sums[0][p]);
}

}  // namespace detail

/// out = init + A a + B b over `ld` rows (a whole number of widest packets, see
/// padded_row_count()): A is ld x ka and B ld x kb, column-major with leading dimension ld; a has
/// ka entries, b kb (kb = 0 and B = b = nullptr: no second product); init (nullptr: zero) and out
/// have ld entries (they may be the same).
template <typename Scalar>
EIGEN_ALWAYS_INLINE void product_sum(const Scalar* A, Eigen::Index ka, const Scalar* a,
                                     std::type_identity_t<const Scalar*> B, Eigen::Index kb,
                                     std::type_identity_t<const Scalar*> b, Eigen::Index ld,
                                     std::type_identity_t<const Scalar*> init,
                                     Scalar* out) noexcept {
  constexpr Eigen::Index P = kWidestPacket<Scalar>;
  const auto at = [](const Scalar* v, Eigen::Index r) { return v ? v + r : nullptr; };
  Eigen::Index r = 0;
  for (; r + 4 * P <= ld; r += 4 * P)
    detail::product_sum_block<Scalar, 4>(A + r, ka, a, at(B, r), kb, b, ld, at(init, r), out + r);
  switch ((ld - r) / P) {
    case 3:
      detail::product_sum_block<Scalar, 3>(A + r, ka, a, at(B, r), kb, b, ld, at(init, r), out + r);
      break;
    case 2:
      detail::product_sum_block<Scalar, 2>(A + r, ka, a, at(B, r), kb, b, ld, at(init, r), out + r);
      break;
    case 1:
      detail::product_sum_block<Scalar, 1>(A + r, ka, a, at(B, r), kb, b, ld, at(init, r), out + r);
      break;
    default:
      break;
  }
}

/// out = init + A a (see product_sum).
template <typename Scalar>
EIGEN_ALWAYS_INLINE void product(const Scalar* A, Eigen::Index k, const Scalar* a, Eigen::Index ld,
                                 std::type_identity_t<const Scalar*> init, Scalar* out) noexcept {
  product_sum<Scalar>(A, k, a, nullptr, 0, nullptr, ld, init, out);
}

/// out[i] = v(i) for the entries of a vector expression. v was usually written just before as part
/// of a longer vector (the plant's output, by whole SIMD packets): read entry by entry, because a
/// wider load that spans two of those stores cannot be forwarded from the store buffer and waits
/// for them to reach the cache. A run-time stride keeps the compiler from widening the loop.
template <typename Scalar, typename V>
EIGEN_ALWAYS_INLINE void read_entries(const Eigen::MatrixBase<V>& v, Scalar* out) noexcept {
  if constexpr (V::ColsAtCompileTime == 1 && requires { v.derived().data(); }) {
    const Eigen::Map<const Eigen::Matrix<Scalar, Eigen::Dynamic, 1>, 0, Eigen::InnerStride<>>
        entries(v.derived().data(), v.size(), Eigen::InnerStride<>(v.derived().innerStride()));
    for (Eigen::Index i = 0; i < entries.size(); ++i) out[i] = entries.coeff(i);
  } else {
    for (Eigen::Index i = 0; i < v.size(); ++i) out[i] = static_cast<Scalar>(v.coeff(i));
  }
}

/// Start-up: m with its rows padded to padded_row_count() with zeros, in the step's scalar.
template <typename Scalar>
Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> padded_matrix(const Eigen::MatrixXd& m) {
  Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> p =
      Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>::Zero(
          padded_row_count<Scalar>(m.rows()), m.cols());
  p.topRows(m.rows()) = m.cast<Scalar>();
  return p;
}

}  // namespace flexloop::numeric

#pragma GCC diagnostic pop
