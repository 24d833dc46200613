// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Unit designs of a campaign: where in [0,1)^d each model evaluation lies. Every point is a pure
// function of (kind, n, d, seed, index), the same bytes on every machine
// (doc/campaign_statistics.md):
//
//  - random: coordinate k of evaluation i is unit_from_bits(counter_bits(seed, i, k)).
//  - lhs (Latin hypercube): per dimension k a permutation pi_k of the n strata (Fisher-Yates
//    driven by CounterStream(seed, k)), and a jitter inside the stratum:
//    x_ik = (pi_k(i) + u_ik) / n with the jitter u_ik = unit_from_bits(counter_bits(seed, i, k))
//    (the random design's coordinate); the permutations use streams of a seed tagged apart.
//  - sobol: the unscrambled Sobol sequence with Joe and Kuo's direction numbers (Boost's table),
//    evaluation i = point i + 1 (point 0, the origin, is skipped); the seed is not used.
//  - saltelli: A_b and B_b are the first and last d coordinates of point b + 1 of the
//    2d-dimensional Sobol sequence; evaluation index b*(d+2) + j is A_b (j = 0), B_b (j = 1) or
//    A_b with column i taken from B_b (j = 2 + i).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace flexloop::campaign {

enum class DesignKind { kRandom, kLatinHypercube, kSobol, kSaltelli };

/// "random" | "lhs" | "sobol" | "saltelli"; anything else is a common::InputError naming the
/// valid names.
DesignKind design_kind_from_name(const std::string& name);
std::string design_name(DesignKind kind);

/// Model evaluations for n base samples of d parameters: n, or n*(d+2) for Saltelli.
long evaluation_count(DesignKind kind, long n, int d);

/// The points of one design. Building it costs O(n d) for a Latin hypercube (its permutations)
/// and O(d) otherwise; a point then costs O(d) (Sobol: O(d * 64), the Gray-code jump). point()
/// may be called from several threads at once.
class DesignPoints {
 public:
  /// std::invalid_argument for n < 1, d < 1 or d beyond the Sobol table (3667, 1833 for Saltelli).
  DesignPoints(DesignKind kind, long n, int d, std::uint64_t seed);
  long size() const { return evaluation_count(kind_, n_, d_); }
  /// Evaluation `index` (0 <= index < size(), else std::out_of_range) as a point of [0,1)^d.
  std::vector<double> point(long index) const;

  DesignKind kind() const { return kind_; }
  long n() const { return n_; }
  int d() const { return d_; }
  std::uint64_t seed() const { return seed_; }

 private:
  struct SobolEngine;  // Boost's engine with its direction numbers, built once per design
  std::vector<double> sobol_point(long point) const;
  DesignKind kind_;
  long n_;
  int d_;
  std::uint64_t seed_;
  std::vector<std::vector<std::uint32_t>> strata_;  // LHS: strata_[k][i] = pi_k(i)
  std::shared_ptr<const SobolEngine> sobol_;        // Sobol and Saltelli
};

/// Evaluation `index` (0 <= index < evaluation_count) as a point of [0,1)^d: a pure function of
/// (kind, n, d, seed, index). Keeps the last design built (per thread), so that asking for the
/// points of one design in turn costs O(d) each, not O(n d).
std::vector<double> unit_point(DesignKind kind, long n, int d, std::uint64_t seed, long index);

}  // namespace flexloop::campaign
