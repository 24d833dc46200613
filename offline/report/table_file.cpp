#include "offline/report/table_file.hpp"

#include <fcntl.h>
#include <matio.h>
#include <unistd.h>

#include <filesystem>
#include <stdexcept>

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

}  // namespace

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
