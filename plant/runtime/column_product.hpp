#pragma once
// Fixed-size matrix-vector products for the real-time step, column by column:
//
//   acc = 0;  for j in 0..K-1:  acc += M(:, j) * x_j        (one SIMD broadcast of x_j per column)
//
// with the R rows of acc held in registers as full SIMD packets, then half packets, then
// scalars, and the columns split over two accumulators (even and odd j) added at the end.
// Why not Eigen's `M.lazyProduct(x)`, which the step used before: it unrolls the sums row packet
// by row packet and broadcasts x_j again for every packet (36 broadcasts for a 12x12 product in
// AVX double instead of 12), for 6-row matrices it uses 2-wide packets only (its packet must
// divide the size), and each row's sum is one chain of K dependent multiply-adds. Measured on
// the closed-loop step in plant/runtime/README.md.
// The two chains change the order of the sums (last-bit differences against lazyProduct).
//
// Built on Eigen's packet primitives (pset1, ploadu, pmadd, padd, pstoreu), so it follows
// whatever SIMD the build enables (scalars without any). For Eigen's default column-major
// storage. No allocation, lock, exception or system call.
#include <Eigen/Core>
#include <type_traits>

// GCC warns that a SIMD type used as a template argument loses its attributes (alignment and
// aliasing hints of the typedef); the packets here are values in registers, as in Eigen's own
// templates, which silence the same warning.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"

namespace flexloop::plant::runtime {

namespace detail {

namespace ei = Eigen::internal;

// How R rows split into full packets, half packets and single scalars.
template <typename Scalar, int R>
struct RowPackets {
  using Full = typename ei::packet_traits<Scalar>::type;
  using Half = typename ei::unpacket_traits<Full>::half;
  static constexpr int kFullSize = ei::unpacket_traits<Full>::size;
  static constexpr int kHalfSize =
      std::is_same_v<Half, Full> ? R + 1 : ei::unpacket_traits<Half>::size;  // R + 1: no halves
  static constexpr int kFull = R / kFullSize;
  static constexpr int kHalf = (R - kFull * kFullSize) / kHalfSize;
  static constexpr int kHalfStart = kFull * kFullSize;
  static constexpr int kScalarStart = kHalfStart + kHalf * kHalfSize;
  static constexpr int kScalar = R - kScalarStart;
};

// N values of type T, meant to live in registers. A plain array (std::array of SIMD types drops
// their attributes); one unused slot when N = 0, which the compiler removes.
template <typename T, int N>
struct Registers {
  T v[N > 0 ? N : 1];
  EIGEN_ALWAYS_INLINE T& operator[](int i) { return v[i]; }
  EIGEN_ALWAYS_INLINE const T& operator[](int i) const { return v[i]; }
};

// The R sums of a product, in registers.
template <typename Scalar, int R>
struct Accumulator {
  using Rows = RowPackets<Scalar, R>;
  Registers<typename Rows::Full, Rows::kFull> full;
  Registers<typename Rows::Half, Rows::kHalf> half;
  Registers<Scalar, Rows::kScalar> scalar;

  // acc += column * s, for the R contiguous entries of `column`.
  EIGEN_ALWAYS_INLINE void add_column(const Scalar* column, Scalar s) {
    if constexpr (Rows::kFull > 0) {
      const auto b = ei::pset1<typename Rows::Full>(s);
#pragma GCC unroll 16
      for (int p = 0; p < Rows::kFull; ++p)
        full[p] =
            ei::pmadd(ei::ploadu<typename Rows::Full>(column + p * Rows::kFullSize), b, full[p]);
    }
    if constexpr (Rows::kHalf > 0) {
      const auto b = ei::pset1<typename Rows::Half>(s);
#pragma GCC unroll 16
      for (int p = 0; p < Rows::kHalf; ++p)
        half[p] = ei::pmadd(
            ei::ploadu<typename Rows::Half>(column + Rows::kHalfStart + p * Rows::kHalfSize), b,
            half[p]);
    }
#pragma GCC unroll 16
    for (int i = 0; i < Rows::kScalar; ++i)
      scalar[i] = ei::pmadd(column[Rows::kScalarStart + i], s, scalar[i]);
  }

  EIGEN_ALWAYS_INLINE static Accumulator zero_sums() {
    Accumulator a;
#pragma GCC unroll 16
    for (int p = 0; p < Rows::kFull; ++p) a.full[p] = ei::pset1<typename Rows::Full>(Scalar(0));
#pragma GCC unroll 16
    for (int p = 0; p < Rows::kHalf; ++p) a.half[p] = ei::pset1<typename Rows::Half>(Scalar(0));
#pragma GCC unroll 16
    for (int i = 0; i < Rows::kScalar; ++i) a.scalar[i] = Scalar(0);
    return a;
  }

  // Two chains (even and odd columns) summed at the end: each chain is half as long, so the
  // sums of one sample are ready sooner for the next (on the closed-loop step two chains were
  // faster than one and than three, plant/runtime/README.md).
  template <int K>
  EIGEN_ALWAYS_INLINE static Accumulator product(const Scalar* M, const Scalar* x) {
    constexpr int kChains = K < 2 ? K : 2;
    Accumulator chain[kChains];
#pragma GCC unroll 4
    for (int c = 0; c < kChains; ++c) chain[c] = zero_sums();
#pragma GCC unroll 32
    for (int j = 0; j < K; ++j) chain[j % kChains].add_column(M + j * R, x[j]);
#pragma GCC unroll 4
    for (int c = 1; c < kChains; ++c) chain[0].add(chain[c]);
    return chain[0];
  }

  // out = the sums.
  EIGEN_ALWAYS_INLINE void store(Scalar* out) const {
#pragma GCC unroll 16
    for (int p = 0; p < Rows::kFull; ++p) ei::pstoreu(out + p * Rows::kFullSize, full[p]);
#pragma GCC unroll 16
    for (int p = 0; p < Rows::kHalf; ++p)
      ei::pstoreu(out + Rows::kHalfStart + p * Rows::kHalfSize, half[p]);
#pragma GCC unroll 16
    for (int i = 0; i < Rows::kScalar; ++i) out[Rows::kScalarStart + i] = scalar[i];
  }
  // this += o, packet by packet.
  EIGEN_ALWAYS_INLINE void add(const Accumulator& o) {
#pragma GCC unroll 16
    for (int p = 0; p < Rows::kFull; ++p) full[p] = ei::padd(full[p], o.full[p]);
#pragma GCC unroll 16
    for (int p = 0; p < Rows::kHalf; ++p) half[p] = ei::padd(half[p], o.half[p]);
#pragma GCC unroll 16
    for (int i = 0; i < Rows::kScalar; ++i) scalar[i] += o.scalar[i];
  }
};

}  // namespace detail

/// N rounded up to whole SIMD packets of Scalar: a vector of 6 doubles is padded to 8, two AVX
/// registers, instead of one 4-wide and one 2-wide packet (N itself without SIMD).
template <typename Scalar, int N>
inline constexpr int kPaddedRows =
    (N + detail::RowPackets<Scalar, N>::kFullSize - 1) /
    detail::RowPackets<Scalar, N>::kFullSize* detail::RowPackets<Scalar, N>::kFullSize;

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

/// M x, summed column by column (see the header comment). x: any contiguous vector of K entries
/// (e.g. a head() of a longer one).
template <typename Scalar, int R, int K, typename V>
EIGEN_ALWAYS_INLINE Eigen::Matrix<Scalar, R, 1> column_product(const Eigen::Matrix<Scalar, R, K>& M,
                                                               const Eigen::MatrixBase<V>& x) {
  static_assert(V::SizeAtCompileTime == K && V::InnerStrideAtCompileTime == 1,
                "column_product: x must be a contiguous vector of M.cols() entries");
  Eigen::Matrix<Scalar, R, 1> y;
  detail::Accumulator<Scalar, R>::template product<K>(M.data(), x.derived().data()).store(y.data());
  return y;
}

/// A a + B b: the two products summed separately (two independent chains), then added.
template <typename Scalar, int R, int KA, int KB>
EIGEN_ALWAYS_INLINE Eigen::Matrix<Scalar, R, 1> product_sum(const Eigen::Matrix<Scalar, R, KA>& A,
                                                            const Eigen::Matrix<Scalar, KA, 1>& a,
                                                            const Eigen::Matrix<Scalar, R, KB>& B,
                                                            const Eigen::Matrix<Scalar, KB, 1>& b) {
  using Acc = detail::Accumulator<Scalar, R>;
  Acc sum = Acc::template product<KA>(A.data(), a.data());
  sum.add(Acc::template product<KB>(B.data(), b.data()));
  Eigen::Matrix<Scalar, R, 1> y;
  sum.store(y.data());
  return y;
}

}  // namespace flexloop::plant::runtime

#pragma GCC diagnostic pop
