// SPDX-License-Identifier: BSD-3-Clause
#include "common/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "common/input_error.hpp"

namespace flexloop::common {

namespace {

// The hidden temporary name beside `file` (a mkstemp template).
std::string temporary_beside(const std::filesystem::path& file) {
  const auto dir = file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  std::string name = ".";  // appended piecewise: GCC 12 -O3 warns falsely (-Wrestrict) on a + chain
  name += file.filename().string();
  name += ".tmp.XXXXXX";
  return (dir / name).string();
}

}  // namespace

void require_writable(const std::filesystem::path& file) {
  if (file.empty()) throw InputError("(empty file name)", "cannot be written");
  // A folder of that name: a file cannot replace it (a run would end in a failed rename).
  std::error_code is_folder;
  if (std::filesystem::is_directory(file, is_folder))
    throw InputError(file.string(), "cannot be written: Is a directory");
  std::error_code ec;
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), ec);
  if (ec) throw InputError(file.string(), "cannot be written: " + ec.message());
  std::string tmp = temporary_beside(file);
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0)
    throw InputError(file.string(), std::string("cannot be written: ") + std::strerror(errno));
  ::close(fd);
  ::unlink(tmp.c_str());
}

void require_creatable(const std::filesystem::path& file) {
  if (file.empty()) throw InputError("(empty file name)", "cannot be written");
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec))
    throw InputError(file.string(), "cannot be written: Is a directory");
  std::filesystem::path folder = std::filesystem::absolute(file, ec).parent_path();
  while (!folder.empty() && !std::filesystem::exists(folder, ec) && folder != folder.root_path())
    folder = folder.parent_path();
  if (!std::filesystem::is_directory(folder, ec))
    throw InputError(file.string(), "cannot be written: " + folder.string() + " is not a folder");
  if (::access(folder.c_str(), W_OK) != 0)
    throw InputError(file.string(), std::string("cannot be written: ") + std::strerror(errno));
}

AtomicFileWriter::AtomicFileWriter(std::filesystem::path file)
    : file_(std::move(file)), tmp_(temporary_beside(file_)) {
  if (file_.empty()) throw std::runtime_error("cannot write a file with an empty name");
  fd_ = ::mkstemp(tmp_.data());
  if (fd_ < 0) {
    tmp_.clear();  // nothing to remove
    const auto dir = file_.has_parent_path() ? file_.parent_path() : std::filesystem::path(".");
    fail("cannot create a temporary file in " + dir.string());
  }
}

AtomicFileWriter::~AtomicFileWriter() {
  if (fd_ >= 0) ::close(fd_);
  if (!tmp_.empty()) ::unlink(tmp_.c_str());
}

void AtomicFileWriter::fail(const std::string& step) {
  const int err = errno;
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (!tmp_.empty()) ::unlink(tmp_.c_str());
  tmp_.clear();
  throw std::runtime_error("cannot write " + file_.string() + ": " + step + ": " +
                           std::strerror(err));
}

void AtomicFileWriter::write(const char* data, std::size_t size) {
  if (fd_ < 0) throw std::logic_error("AtomicFileWriter::write after commit or failure");
  const off_t start = ::lseek(fd_, 0, SEEK_CUR);
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(fd_, data + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("write " + tmp_);
    done += static_cast<std::size_t>(n);
  }
  // Start the disk on these bytes now, not all at fsync(): advice, so a refusal is no error.
  if (start >= 0 && size > 0)
    ::sync_file_range(fd_, start, static_cast<off_t>(size), SYNC_FILE_RANGE_WRITE);
}

void AtomicFileWriter::commit() {
  if (fd_ < 0) throw std::logic_error("AtomicFileWriter::commit twice or after failure");
  // mkstemp creates 0600; artefacts and reports are ordinary readable files.
  if (::fchmod(fd_, 0644) != 0) fail("set permissions on " + tmp_);
  if (::fsync(fd_) != 0) fail("flush " + tmp_);
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail("close " + tmp_);
  if (std::rename(tmp_.c_str(), file_.c_str()) != 0) fail("rename " + tmp_);
  tmp_.clear();  // it is the target now
  // Make the rename itself durable; failure here leaves a complete file, so it is not an error.
  const auto dir = file_.has_parent_path() ? file_.parent_path() : std::filesystem::path(".");
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

void write_text_atomically(const std::filesystem::path& file, const std::string& text) {
  AtomicFileWriter out(file);
  out.write(text.data(), text.size());
  out.commit();
}

}  // namespace flexloop::common
