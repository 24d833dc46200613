#include "tools/report/csv_writer.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

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

[[noreturn]] void fail(const std::string& path, const std::string& what, int err) {
  throw std::runtime_error("cannot write " + path + ": " + what +
                           (err ? std::string(": ") + std::strerror(err) : std::string()));
}
}  // namespace

std::string format_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);  // shortest round-trip form
  return std::string(buf, res.ptr);
}

void write_file_atomic(const std::string& path, const std::string& contents) {
  if (path.empty()) throw std::runtime_error("cannot write a file with an empty name");
  std::string tmpl = path + ".tmp.XXXXXX";
  const int fd = ::mkstemp(tmpl.data());
  if (fd < 0) fail(path, "cannot create a temporary file beside it", errno);
  auto abandon = [&](const std::string& what, int err) {
    ::close(fd);
    ::unlink(tmpl.c_str());
    fail(path, what, err);
  };
  // mkstemp creates the file 0600; a report is meant to be read by others.
  if (::fchmod(fd, 0644) != 0) abandon("fchmod", errno);
  std::size_t done = 0;
  while (done < contents.size()) {
    const ssize_t w = ::write(fd, contents.data() + done, contents.size() - done);
    if (w < 0) {
      if (errno == EINTR) continue;
      abandon("write", errno);
    }
    done += static_cast<std::size_t>(w);
  }
  if (::fsync(fd) != 0) abandon("fsync", errno);
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(tmpl.c_str());
    fail(path, "close", err);
  }
  if (std::rename(tmpl.c_str(), path.c_str()) != 0) {
    const int err = errno;
    ::unlink(tmpl.c_str());
    fail(path, "rename from " + tmpl, err);
  }
}

void write_csv(const std::string& path, const std::vector<std::string>& header,
               const Eigen::MatrixXd& data) {
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
  write_file_atomic(path, text);
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
