#include "offline/report/csv_writer.hpp"

#include "common/atomic_file.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace flexloop::report {

namespace {
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

}  // namespace

std::string format_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);  // shortest round-trip form
  return std::string(buf, res.ptr);
}

void write_csv(const std::string& path, const std::vector<std::string>& header,
               Eigen::Ref<const Eigen::MatrixXd> data) {
  if (static_cast<Eigen::Index>(header.size()) != data.cols())
    throw std::invalid_argument("write_csv " + path + ": " + std::to_string(header.size()) +
                                " column names for " + std::to_string(data.cols()) + " columns");
  std::string text = header_line(header);
  for (Eigen::Index i = 0; i < data.rows(); ++i) {
    for (Eigen::Index j = 0; j < data.cols(); ++j) {
      if (j) text += ',';
      text += format_number(data(i, j));
    }
    text += '\n';
  }
  common::write_text_atomically(path, text);
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
