// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Fixed-size matrix-vector products for the real-time step, column by column:
//
//   acc = 0;  for j in 0..K-1:  acc += M(:, j) * x_j        (one SIMD broadcast of x_j per column)
//
// with the R rows of acc held in registers as the widest SIMD packets that fit, then narrower
// ones, then scalars, and the columns split over two accumulators (even and odd j) added at the
// end. Why not Eigen's `M.lazyProduct(x)`, which the step used before: it unrolls the sums row
// packet by row packet and broadcasts x_j again for every packet (36 broadcasts for a 12x12 product
// in AVX double instead of 12), for 6-row matrices it uses 2-wide packets only (its packet must
// divide the size), and each row's sum is one chain of K dependent multiply-adds. Measured on
// the closed-loop step in plant/runtime/README.md.
// The two chains change the order of the sums (last-bit differences against lazyProduct).
//
// Built on Eigen's packet primitives (pset1, ploadu, pmadd, padd, pstoreu), so it follows
// whatever SIMD the build enables (scalars without any). For Eigen's default column-major
// storage. No allocation, lock, exception or system call.
#include <Eigen/Core>
#include <complex>
#include <type_traits>

// GCC warns that a SIMD type used as a template argument loses its attributes (alignment and
// aliasing hints of the typedef); the packets here are values in registers, as in Eigen's own
// templates, which silence the same warning.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"

namespace flexloop::numeric {

namespace detail {

namespace ei = Eigen::internal;

// The packet sizes the build offers for Scalar, widest first: AVX-512 double 8, 4, 2; AVX2
// double 4, 2; AVX-512 float 16, 8, 4; without SIMD the scalar alone. Level L's packet type is
// PacketLevel<Scalar, L>::type; the level past the narrowest is the scalar (size 1).
template <typename Scalar, int L>
struct PacketLevel {
  using Wider = typename PacketLevel<Scalar, L - 1>::type;
  using Half = typename ei::unpacket_traits<Wider>::half;
  // The narrowest packet is its own half: below it come scalars, then nothing smaller.
  using type = std::conditional_t<std::is_same_v<Half, Wider>, Scalar, Half>;
};
template <typename Scalar>
struct PacketLevel<Scalar, 0> {
  using type = typename ei::packet_traits<Scalar>::type;
};
template <typename Scalar, int L>
inline constexpr int kPacketSize = ei::unpacket_traits<typename PacketLevel<Scalar, L>::type>::size;

// N values of type T, meant to live in registers. A plain array (std::array of SIMD types drops
// their attributes); one unused slot when N = 0, which the compiler removes.
template <typename T, int N>
struct Registers {
  T v[N > 0 ? N : 1];
  EIGEN_ALWAYS_INLINE T& operator[](int i) { return v[i]; }
  EIGEN_ALWAYS_INLINE const T& operator[](int i) const { return v[i]; }
};

// The R sums of a product in registers, rows Offset .. Offset + R - 1 of the column: as many
// packets of level L as fit, the rest in narrower ones (12 doubles: one 8-wide and one 4-wide
// packet with AVX-512, three 4-wide with AVX2; 12 floats: 8 + 4 with either).
template <typename Scalar, int R, int L = 0, int Offset = 0>
struct Accumulator {
  using Packet = typename PacketLevel<Scalar, L>::type;
  static constexpr int kSize = kPacketSize<Scalar, L>;
  static constexpr int kCount = R / kSize;
  static constexpr int kRest = R - kCount * kSize;
  struct None {  // no narrower rows
    EIGEN_ALWAYS_INLINE void add_column(const Scalar*, Scalar) {}
    EIGEN_ALWAYS_INLINE static None zero_sums() { return {}; }
    EIGEN_ALWAYS_INLINE void store(Scalar*) const {}
    EIGEN_ALWAYS_INLINE void add(const None&) {}
  };
  using Rest = std::conditional_t<kRest == 0, None,
                                  Accumulator<Scalar, kRest, L + 1, Offset + kCount * kSize>>;

  Registers<Packet, kCount> packets;
  Rest rest;

  // acc += column * s, for the R contiguous entries of `column` from Offset on.
  EIGEN_ALWAYS_INLINE void add_column(const Scalar* column, Scalar s) {
    if constexpr (kCount > 0) {
      const Packet b = ei::pset1<Packet>(s);
#pragma GCC unroll 16
      for (int p = 0; p < kCount; ++p)
        packets[p] = ei::pmadd(ei::ploadu<Packet>(column + Offset + p * kSize), b, packets[p]);
    }
    rest.add_column(column, s);
  }

  EIGEN_ALWAYS_INLINE static Accumulator zero_sums() {
    Accumulator a;
#pragma GCC unroll 16
    for (int p = 0; p < kCount; ++p) a.packets[p] = ei::pset1<Packet>(Scalar(0));
    a.rest = Rest::zero_sums();
    return a;
  }

  // Two chains (even and odd columns) summed at the end: each chain is half as long, so the
  // sums of one sample are ready sooner for the next (on the closed-loop step two chains were
  // faster than one and than three, plant/runtime/README.md).
  // x: any Eigen vector expression of K entries, read entry by entry (x.coeff(j)).
  template <int K, typename X>
  EIGEN_ALWAYS_INLINE static Accumulator product(const Scalar* M, const X& x) {
    constexpr int kChains = K < 2 ? K : 2;
    Accumulator chain[kChains];
#pragma GCC unroll 4
    for (int c = 0; c < kChains; ++c) chain[c] = zero_sums();
#pragma GCC unroll 32
    for (int j = 0; j < K; ++j) chain[j % kChains].add_column(M + j * R, x.coeff(j));
#pragma GCC unroll 4
    for (int c = 1; c < kChains; ++c) chain[0].add(chain[c]);
    return chain[0];
  }

  // out = the sums.
  EIGEN_ALWAYS_INLINE void store(Scalar* out) const {
#pragma GCC unroll 16
    for (int p = 0; p < kCount; ++p) ei::pstoreu(out + Offset + p * kSize, packets[p]);
    rest.store(out);
  }
  // this += o, packet by packet.
  EIGEN_ALWAYS_INLINE void add(const Accumulator& o) {
#pragma GCC unroll 16
    for (int p = 0; p < kCount; ++p) packets[p] = ei::padd(packets[p], o.packets[p]);
    rest.add(o.rest);
  }
};

// p with its entries 2i and 2i+1 exchanged: an in-lane permute, done with Eigen's complex packet
// of the same register (pcplxflip exchanges real and imaginary parts). Real: a packet type of the
// cascade of at least two entries.
template <typename Scalar, typename Real, int L = 0>
EIGEN_ALWAYS_INLINE Real swap_neighbours(const Real& p) {
  using Complex = typename PacketLevel<std::complex<Scalar>, L>::type;
  if constexpr (requires { typename ei::unpacket_traits<Complex>::as_real; }) {
    if constexpr (std::is_same_v<typename ei::unpacket_traits<Complex>::as_real, Real>)
      return ei::pcplxflip(Complex(p)).v;
    else
      return swap_neighbours<Scalar, Real, L + 1>(p);
  } else {
    static_assert(!std::is_same_v<Real, Real>, "swap_neighbours: no complex packet of this width");
  }
}

// The smallest packet size of the cascade that holds N rows in one packet, else N rounded up to
// whole widest packets.
template <typename Scalar, int N, int L = 0>
constexpr int padded_size() {
  if constexpr (L == 0 && N > kPacketSize<Scalar, 0>)
    return (N + kPacketSize<Scalar, 0> - 1) / kPacketSize<Scalar, 0> * kPacketSize<Scalar, 0>;
  else if constexpr (kPacketSize<Scalar, L + 1> < N || kPacketSize<Scalar, L> == 1)
    return kPacketSize<Scalar, L>;
  else
    return padded_size<Scalar, N, L + 1>();
}

}  // namespace detail

/// N padded to one SIMD packet, or to whole widest packets when N is wider: a vector of 6
/// doubles takes 8 lanes (two AVX2 registers, or one AVX-512 register) instead of a 4-wide and a
/// 2-wide packet; 6 floats take one 8-wide packet (N itself without SIMD).
template <typename Scalar, int N>
inline constexpr int kPaddedRows = detail::padded_size<Scalar, N>();

/// m with its rows padded to NP with zeros (start-up and the step's short vectors; the padding
/// lanes of a product stay zero when the padded rows of its matrix are zero).
template <int NP, typename Derived>
EIGEN_ALWAYS_INLINE auto padded_rows(const Eigen::MatrixBase<Derived>& m) {
  static_assert(NP >= Derived::RowsAtCompileTime, "padded_rows: NP must not be below the rows");
  using Padded = Eigen::Matrix<typename Derived::Scalar, NP, Derived::ColsAtCompileTime>;
  Padded p = Padded::Zero();
  p.template topRows<Derived::RowsAtCompileTime>() = m;
  return p;
}

/// M x, summed column by column (see the header comment). x: any vector expression of K entries,
/// evaluated entry by entry as the columns need them: a head() of a longer vector, or a
/// difference y - u that then never exists as a vector in memory.
template <typename Scalar, int R, int K, typename V>
EIGEN_ALWAYS_INLINE Eigen::Matrix<Scalar, R, 1> column_product(const Eigen::Matrix<Scalar, R, K>& M,
                                                               const Eigen::MatrixBase<V>& x) {
  static_assert(V::SizeAtCompileTime == K && V::ColsAtCompileTime == 1,
                "column_product: x must be a column vector of M.cols() entries");
  Eigen::Matrix<Scalar, R, 1> y;
  detail::Accumulator<Scalar, R>::template product<K>(M.data(), x.derived()).store(y.data());
  return y;
}

/// A a + B b: the two products summed separately (two independent chains), then added.
template <typename Scalar, int R, int KA, int KB>
EIGEN_ALWAYS_INLINE Eigen::Matrix<Scalar, R, 1> product_sum(const Eigen::Matrix<Scalar, R, KA>& A,
                                                            const Eigen::Matrix<Scalar, KA, 1>& a,
                                                            const Eigen::Matrix<Scalar, R, KB>& B,
                                                            const Eigen::Matrix<Scalar, KB, 1>& b) {
  using Acc = detail::Accumulator<Scalar, R>;
  Acc sum = Acc::template product<KA>(A.data(), a);
  sum.add(Acc::template product<KB>(B.data(), b));
  Eigen::Matrix<Scalar, R, 1> y;
  sum.store(y.data());
  return y;
}

}  // namespace flexloop::numeric

#pragma GCC diagnostic pop
