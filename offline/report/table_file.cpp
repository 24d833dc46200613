// SPDX-License-Identifier: BSD-3-Clause
#include "offline/report/table_file.hpp"

#include <fcntl.h>
#include <matio.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "offline/report/csv_writer.hpp"

namespace flexloop::report {

namespace {

// Where stage_table() writes before commit_table() renames.
std::string staged_name(const std::string& path) {
  return path + ".tmp";
}

std::string extension(const std::string& path) {
  return std::filesystem::path(path).extension().string();
}

// The column names as a 1 x n cell array of strings (views of `names`, not copies).
matvar_t* name_cells(const std::vector<std::string>& names) {
  std::size_t dims[2] = {1, names.size()};
  matvar_t* cells = Mat_VarCreate("columns", MAT_C_CELL, MAT_T_CELL, 2, dims, nullptr, 0);
  for (std::size_t j = 0; cells && j < names.size(); ++j) {
    std::size_t char_dims[2] = {1, names[j].size()};
    matvar_t* s = Mat_VarCreate(nullptr, MAT_C_CHAR, MAT_T_UTF8, 2, char_dims,
                                const_cast<char*>(names[j].data()), MAT_F_DONT_COPY_DATA);
    if (!s) {
      Mat_VarFree(cells);
      return nullptr;
    }
    Mat_VarSetCell(cells, static_cast<int>(j), s);
  }
  return cells;
}

// `data` must be contiguous (outer stride = rows).
bool write_mat_file(const std::string& file, const std::vector<std::string>& names,
                    Eigen::Ref<const Eigen::MatrixXd> data) {
  mat_t* mat = Mat_CreateVer(file.c_str(), nullptr, MAT_FT_MAT5);
  if (!mat) return false;
  // Eigen stores column-major, as MATLAB does: the data is written as it is, not copied.
  std::size_t dims[2] = {static_cast<std::size_t>(data.rows()),
                         static_cast<std::size_t>(data.cols())};
  matvar_t* d = Mat_VarCreate("data", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims,
                              const_cast<double*>(data.data()), MAT_F_DONT_COPY_DATA);
  matvar_t* cells = name_cells(names);
  bool ok = d && cells && Mat_VarWrite(mat, d, MAT_COMPRESSION_NONE) == 0 &&
            Mat_VarWrite(mat, cells, MAT_COMPRESSION_NONE) == 0;
  if (d) Mat_VarFree(d);
  if (cells) Mat_VarFree(cells);
  ok = Mat_Close(mat) == 0 && ok;
  if (ok) {  // on disk before it replaces the target, as plant/lti/atomic_file.hpp does
    const int fd = ::open(file.c_str(), O_RDONLY);
    ok = fd >= 0 && ::fsync(fd) == 0;
    if (fd >= 0) ::close(fd);
  }
  return ok;
}

// One CSV line split at the commas outside quotes; quoted fields unquoted (RFC 4180).
std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '"' && quoted && i + 1 < line.size() && line[i + 1] == '"')
      fields.back() += '"', ++i;  // a doubled quote inside a quoted field
    else if (c == '"')
      quoted = !quoted;
    else if (c == ',' && !quoted)
      fields.emplace_back();
    else if (c != '\r')
      fields.back() += c;
  }
  return fields;
}

// Rows of numbers into row-major values; every row as long as the header.
Table read_csv_table(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw common::InputError(path, "cannot open the table");
  std::string line;
  if (!std::getline(in, line)) throw common::InputError(path + ":1", "no header row");
  Table t;
  t.names = csv_fields(line);
  const std::size_t cols = t.names.size();
  std::vector<double> values;  // row-major
  for (long number = 2; std::getline(in, line); ++number) {
    if (line.empty() || line == "\r") continue;
    const char* p = line.c_str();
    for (std::size_t j = 0; j < cols; ++j) {
      char* end = nullptr;
      values.push_back(std::strtod(p, &end));  // exact for the shortest form the writer uses
      const char want = j + 1 < cols ? ',' : '\0';
      if (end == p || (*end != want && !(want == '\0' && *end == '\r')))
        throw common::InputError(path + ":" + std::to_string(number),
                                 "column " + std::to_string(j + 1) + " (" + t.names[j] +
                                     "): not a number, or not " + std::to_string(cols) +
                                     " columns as the header has");
      p = end + 1;
    }
  }
  const auto rows = static_cast<Eigen::Index>(values.size() / std::max<std::size_t>(cols, 1));
  t.data = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      values.data(), rows, static_cast<Eigen::Index>(cols));
  return t;
}

// The matio variable `name`, read whole; freed when it goes.
struct MatVar {
  matvar_t* var = nullptr;
  ~MatVar() { Mat_VarFree(var); }
};

// A MATLAB char array as UTF-8: as it is when stored as bytes (matio, scipy), else (MATLAB's
// own UTF-16 code units) each unit of the Basic Multilingual Plane encoded.
std::string char_text(const matvar_t& s) {
  if (s.data_type != MAT_T_UINT16 && s.data_type != MAT_T_UTF16)
    return {static_cast<const char*>(s.data), s.nbytes};
  std::string out;
  const auto* units = static_cast<const std::uint16_t*>(s.data);
  for (std::size_t k = 0; k < s.nbytes / 2; ++k) {
    const unsigned u = units[k];
    if (u < 0x80) {
      out += static_cast<char>(u);
    } else if (u < 0x800) {
      out += static_cast<char>(0xC0 | (u >> 6));
      out += static_cast<char>(0x80 | (u & 0x3F));
    } else {
      out += static_cast<char>(0xE0 | (u >> 12));
      out += static_cast<char>(0x80 | ((u >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (u & 0x3F));
    }
  }
  return out;
}

Table read_mat_table(const std::string& path) {
  mat_t* mat = Mat_Open(path.c_str(), MAT_ACC_RDONLY);
  if (!mat) throw common::InputError(path, "cannot be read as a MATLAB .mat file");
  const MatVar data{Mat_VarRead(mat, "data")}, columns{Mat_VarRead(mat, "columns")};
  Mat_Close(mat);
  const matvar_t* d = data.var;
  if (!d || d->class_type != MAT_C_DOUBLE || d->isComplex || d->rank != 2)
    throw common::InputError(path + ":data", "no real double matrix `data`");
  Table t;
  t.data = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(d->data),
                                             static_cast<Eigen::Index>(d->dims[0]),
                                             static_cast<Eigen::Index>(d->dims[1]));
  const matvar_t* c = columns.var;
  const std::size_t names = c && c->class_type == MAT_C_CELL ? c->dims[0] * c->dims[1] : 0;
  for (std::size_t j = 0; j < names; ++j) {
    const matvar_t* s = Mat_VarGetCell(const_cast<matvar_t*>(c), static_cast<int>(j));
    if (!s || s->class_type != MAT_C_CHAR || !s->data) break;
    t.names.push_back(char_text(*s));
  }
  if (static_cast<Eigen::Index>(t.names.size()) != t.data.cols())
    throw common::InputError(path + ":columns", "not a cell array of " +
                                                    std::to_string(t.data.cols()) +
                                                    " column names (one per column of `data`)");
  return t;
}

}  // namespace

Table read_table(const std::string& path) {
  if (!std::filesystem::exists(path)) throw common::InputError(path, "cannot open the table");
  if (extension(path) == ".csv") return read_csv_table(path);
  if (extension(path) == ".mat") return read_mat_table(path);
  throw common::InputError(path, "a table is read from .csv or .mat");
}

bool is_table_file(const std::string& path) {
  const std::string ext = extension(path);
  return ext == ".csv" || ext == ".mat";
}

void stage_table(const std::string& path, const std::vector<std::string>& names,
                 Eigen::Ref<const Eigen::MatrixXd> data) {
  const std::string ext = extension(path);
  if (!is_table_file(path))
    throw common::InputError(path, "a table is written as .csv or .mat (got '" + ext + "')");
  if (static_cast<Eigen::Index>(names.size()) != data.cols())
    throw std::invalid_argument(path + ": " + std::to_string(names.size()) + " column names for " +
                                std::to_string(data.cols()) + " columns");
  const std::string staged = staged_name(path);
  if (ext == ".csv") {
    write_csv(staged, names, data);  // itself atomic: staged appears whole or not at all
    return;
  }
  const bool contiguous = data.outerStride() == data.rows();
  if (!(contiguous ? write_mat_file(staged, names, data)
                   : write_mat_file(staged, names, Eigen::MatrixXd(data)))) {
    discard_table(path);
    throw std::runtime_error(path + ": cannot be written");
  }
}

void commit_table(const std::string& path) {
  std::filesystem::rename(staged_name(path), path);
}

void discard_table(const std::string& path) noexcept {
  std::error_code ignored;
  std::filesystem::remove(staged_name(path), ignored);
}

void write_table(const std::string& path, const std::vector<std::string>& names,
                 Eigen::Ref<const Eigen::MatrixXd> data) {
  stage_table(path, names, data);
  commit_table(path);
}

}  // namespace flexloop::report
