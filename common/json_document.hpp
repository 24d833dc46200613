// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Reading and writing flexloop's JSON documents (artefacts), shared by the offline and the online
// side: a reader that names the file and key of everything wrong (`file: key 'A' row 3 column 2:
// expected a number, found string "x"`), matrices as lists of rows, and a writer that lays
// matrices out one row per line and never leaves a half-written file (atomic_file.hpp).
// Errors: flexloop::InputError.
#include <Eigen/Core>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace flexloop::common {

/// "string \"x\"", "number", "array", ... for messages.
std::string json_type_of(const nlohmann::json& v);

/// Parses a file. @throws InputError naming the file when it cannot be read or is not JSON.
nlohmann::json parse_json_file(const std::filesystem::path& file);

/// A matrix as a list of rows.
nlohmann::json matrix_to_json(const Eigen::MatrixXd& m);

/// Writes `j` atomically: matrices one row per line, label lists on one line, `first_keys` in
/// that order first, then the rest. @throws std::runtime_error when the file cannot be written.
void write_json_atomically(const std::filesystem::path& file, const nlohmann::json& j,
                           const std::vector<std::string>& first_keys = {});

/// One JSON object of a document, and where it is ("file: key 'plant'").
class JsonReader {
 public:
  /// @throws InputError unless j is an object.
  JsonReader(const nlohmann::json& j, std::string place);

  bool has(const std::string& key) const { return j_.contains(key); }
  const nlohmann::json& get(const std::string& key) const;
  /// The object at `key`, as a reader of its own.
  JsonReader object(const std::string& key) const;
  double number(const std::string& key) const;
  /// An integer in [min, max].
  long integer(const std::string& key, long min, long max) const;
  bool boolean(const std::string& key) const;
  std::string string(const std::string& key) const;
  /// Non-empty, unique names.
  std::vector<std::string> labels(const std::string& key) const;
  /// rows x cols, each row a list of finite numbers; what_row / what_col name one of each.
  Eigen::MatrixXd matrix(const std::string& key, std::size_t rows, std::size_t cols,
                         const char* what_row, const char* what_col) const;
  /// A list of finite numbers of any length.
  Eigen::VectorXd vector(const std::string& key) const;

  std::string place(const std::string& key) const;
  const std::string& place() const { return place_; }
  const nlohmann::json& value() const { return j_; }

 private:
  const nlohmann::json& j_;
  std::string place_;
};

}  // namespace flexloop::common
