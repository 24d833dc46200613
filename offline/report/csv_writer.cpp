// SPDX-License-Identifier: BSD-3-Clause
#include "offline/report/csv_writer.hpp"

#include "common/atomic_file.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <future>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

namespace flexloop::report {

namespace {

constexpr std::size_t kNumberRoom = 32;             // "-1.2345678901234567e-308" is 24
constexpr std::size_t kBlockBytes = 4 << 20;        // bytes handed to the kernel at once
constexpr Eigen::Index kParallelNumbers = 1 << 20;  // from here on every CPU formats

std::string csv_field(const std::string& name) {
  if (name.find_first_of(",\"\r\n") == std::string::npos) return name;
  std::string q = "\"";
  for (char c : name) {
    if (c == '"') q += '"';  // RFC 4180: a quote inside a quoted field is doubled
    q += c;
  }
  return q + "\"";
}

std::string header_line(const std::vector<std::string>& header) {
  std::string s;
  for (std::size_t j = 0; j < header.size(); ++j) {
    if (j) s += ',';
    s += csv_field(header[j]);
  }
  return s + '\n';
}

// The shortest text that reads back to exactly `v` (std::to_chars), or nan / inf / -inf, at `out`
// (room for 32 characters); returns the end.
char* put_number(char* out, double v) {
  if (std::isnan(v)) return std::copy_n("nan", 3, out);
  if (std::isinf(v)) return v > 0 ? std::copy_n("inf", 3, out) : std::copy_n("-inf", 4, out);
  return std::to_chars(out, out + kNumberRoom, v).ptr;  // shortest round-trip form
}

// Rows [first, last) of `data` as CSV lines at `out` (room for 32 + 1 bytes a number and 1 a
// row); returns the end.
char* put_rows(char* out, const Eigen::Ref<const Eigen::MatrixXd>& data, Eigen::Index first,
               Eigen::Index last) {
  for (Eigen::Index i = first; i < last; ++i) {
    for (Eigen::Index j = 0; j < data.cols(); ++j) {
      if (j) *out++ = ',';
      out = put_number(out, data(i, j));
    }
    *out++ = '\n';
  }
  return out;
}

}  // namespace

std::string format_number(double v) {
  char buf[kNumberRoom];
  return std::string(buf, put_number(buf, v));
}

void write_csv(const std::string& path, const std::vector<std::string>& header,
               Eigen::Ref<const Eigen::MatrixXd> data) {
  if (static_cast<Eigen::Index>(header.size()) != data.cols())
    throw std::invalid_argument("write_csv " + path + ": " + std::to_string(header.size()) +
                                " column names for " + std::to_string(data.cols()) + " columns");
  // Formatted in blocks handed to the kernel one by one: no allocation per number or row, and a
  // 100 s log at 10 kHz (600 MB of text) never held whole. The shortest round-trip formatting is
  // most of the time (~70 ns a number, the kernel's copy a tenth of that), so a large table is
  // formatted on every CPU, a block each, and the blocks written in order.
  common::AtomicFileWriter out(path);
  const std::string names = header_line(header);
  out.write(names.data(), names.size());
  const Eigen::Index rows = data.rows();
  const std::size_t row_room = static_cast<std::size_t>(data.cols()) * (kNumberRoom + 1) + 1;
  const Eigen::Index chunk = std::clamp<Eigen::Index>(  // rows a block; a small table's own
      static_cast<Eigen::Index>(kBlockBytes / row_room), 1, std::max<Eigen::Index>(rows, 1));
  const unsigned workers =
      data.size() >= kParallelNumbers ? std::max(std::thread::hardware_concurrency(), 1u) : 1u;
  std::vector<std::vector<char>> blocks(
      workers, std::vector<char>(static_cast<std::size_t>(chunk) * row_room));
  std::vector<std::future<char*>> helped(workers);
  for (Eigen::Index first = 0; first < rows; first += workers * chunk) {
    const auto rows_of = [&](unsigned w) {
      return std::pair{std::min(rows, first + w * chunk), std::min(rows, first + (w + 1) * chunk)};
    };
    for (unsigned w = 1; w < workers; ++w)
      helped[w] = std::async(std::launch::async, [&, w, range = rows_of(w)] {
        return put_rows(blocks[w].data(), data, range.first, range.second);
      });
    const auto [from, to] = rows_of(0);
    char* end = put_rows(blocks[0].data(), data, from, to);
    for (unsigned w = 0; w < workers; ++w) {
      if (w > 0) end = helped[w].get();
      out.write(blocks[w].data(), static_cast<std::size_t>(end - blocks[w].data()));
    }
  }
  out.commit();
}

void write_csv_columns(const std::string& path, const std::vector<std::string>& header,
                       const std::vector<std::vector<double>>& columns) {
  if (header.size() != columns.size())
    throw std::invalid_argument("write_csv " + path + ": " + std::to_string(header.size()) +
                                " column names for " + std::to_string(columns.size()) + " columns");
  const std::size_t rows = columns.empty() ? 0 : columns.front().size();
  Eigen::MatrixXd data(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(columns.size()));
  for (std::size_t j = 0; j < columns.size(); ++j) {
    if (columns[j].size() != rows)
      throw std::invalid_argument("write_csv " + path + ": column '" + header[j] + "' has " +
                                  std::to_string(columns[j].size()) + " values, the first has " +
                                  std::to_string(rows));
    for (std::size_t i = 0; i < rows; ++i)
      data(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = columns[j][i];
  }
  write_csv(path, header, data);
}

}  // namespace flexloop::report
