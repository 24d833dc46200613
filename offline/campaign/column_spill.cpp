// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/column_spill.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <utility>

namespace flexloop::campaign {

namespace {

[[noreturn]] void fail(const std::string& step) {
  throw std::runtime_error("campaign report: temporary column file: " + step + ": " +
                           std::strerror(errno));
}

// An anonymous file in TMPDIR: removed from the directory at once, freed when closed.
int anonymous_file() {
  std::string path = (std::filesystem::temp_directory_path() / "flexloop-columns.XXXXXX").string();
  const int fd = ::mkstemp(path.data());
  if (fd < 0) fail("create in " + std::filesystem::temp_directory_path().string());
  ::unlink(path.c_str());
  return fd;
}

}  // namespace

ColumnSpill::ColumnSpill(std::size_t columns) : pending_(columns), chunks_(columns) {}

ColumnSpill::~ColumnSpill() {
  if (fd_ >= 0) ::close(fd_);
}

ColumnSpill::ColumnSpill(ColumnSpill&& other) noexcept
    : pending_(std::move(other.pending_)),
      chunks_(std::move(other.chunks_)),
      fd_(std::exchange(other.fd_, -1)),
      end_(other.end_) {}

ColumnSpill& ColumnSpill::operator=(ColumnSpill&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    pending_ = std::move(other.pending_);
    chunks_ = std::move(other.chunks_);
    fd_ = std::exchange(other.fd_, -1);
    end_ = other.end_;
  }
  return *this;
}

void ColumnSpill::push(std::size_t column, double value) {
  std::vector<double>& pending = pending_[column];
  if (pending.capacity() == 0) pending.reserve(kChunk);
  pending.push_back(value);
  if (pending.size() == kChunk) spill(column);
}

void ColumnSpill::spill(std::size_t column) {
  if (fd_ < 0) fd_ = anonymous_file();
  std::vector<double>& pending = pending_[column];
  const auto bytes = static_cast<ssize_t>(pending.size() * sizeof(double));
  if (::pwrite(fd_, pending.data(), static_cast<std::size_t>(bytes), static_cast<off_t>(end_)) !=
      bytes)
    fail("write");
  chunks_[column].push_back(end_);
  end_ += static_cast<std::uint64_t>(bytes);
  pending.clear();
}

std::vector<double> ColumnSpill::column(std::size_t column) const {
  std::vector<double> out(chunks_[column].size() * kChunk);
  const auto bytes = static_cast<ssize_t>(kChunk * sizeof(double));
  for (std::size_t c = 0; c < chunks_[column].size(); ++c)
    if (::pread(fd_, out.data() + c * kChunk, static_cast<std::size_t>(bytes),
                static_cast<off_t>(chunks_[column][c])) != bytes)
      fail("read");
  out.insert(out.end(), pending_[column].begin(), pending_[column].end());
  return out;
}

}  // namespace flexloop::campaign
