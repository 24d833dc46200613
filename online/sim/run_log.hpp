// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The log of an in-process run: one row per logged sample (t, floor, performance, performance
// sensors, sensors, commands), column-major as MATLAB stores it, so that a .mat file is written
// straight from it (offline/report/table_file.hpp).
//
// Sized once before the loop and not cleared: the loop writes every row. Its memory is asked of
// the kernel in 2 MB pages (transparent huge pages, madvise mode): a 20 s log at 10 kHz is
// 50 MB, which first touched in 4 KB pages costs 12 800 page faults -- on this project's VMs
// three times the run that fills it -- and 25 in 2 MB pages. Where the kernel has none to give,
// it is ordinary memory.
#include <sys/mman.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstdlib>
#include <memory>
#include <new>

namespace flexloop::sim {

class RunLog {
 public:
  using View = Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>>;
  using ConstView = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>;

  RunLog() = default;
  /// Uninitialised: every entry must be written before it is read.
  RunLog(Eigen::Index rows, Eigen::Index cols) : rows_(rows), cols_(cols), stride_(rows) {
    const std::size_t bytes = static_cast<std::size_t>(rows * cols) * sizeof(double);
    if (bytes == 0) return;
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    data_.reset(static_cast<double*>(std::aligned_alloc(kHugePage, rounded)));
    if (!data_) throw std::bad_alloc();
    ::madvise(data_.get(), rounded, MADV_HUGEPAGE);  // advice only: refused is fine
  }

  Eigen::Index rows() const noexcept { return rows_; }
  Eigen::Index cols() const noexcept { return cols_; }
  View matrix() noexcept { return {data_.get(), rows_, cols_, Eigen::OuterStride<>(stride_)}; }
  ConstView matrix() const noexcept {
    return {data_.get(), rows_, cols_, Eigen::OuterStride<>(stride_)};
  }
  /// Keeps the first `rows` rows (a run that stopped early).
  void keep_rows(Eigen::Index rows) noexcept { rows_ = std::min(rows, rows_); }

 private:
  static constexpr std::size_t kHugePage = std::size_t{2} << 20;
  struct Free {
    void operator()(double* p) const noexcept { std::free(p); }
  };
  std::unique_ptr<double, Free> data_;
  Eigen::Index rows_ = 0, cols_ = 0, stride_ = 0;
};

}  // namespace flexloop::sim
