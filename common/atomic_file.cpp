#include "common/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

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

void write_text_atomically(const std::filesystem::path& file, const std::string& text) {
  if (file.empty()) throw std::runtime_error("cannot write a file with an empty name");
  const auto dir = file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  std::string tmp = temporary_beside(file);
  const auto fail = [&](const std::string& step, int fd, bool remove_tmp) {
    const int err = errno;
    if (fd >= 0) ::close(fd);
    if (remove_tmp) ::unlink(tmp.c_str());
    throw std::runtime_error("cannot write " + file.string() + ": " + step + ": " +
                             std::strerror(err));
  };
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) fail("cannot create a temporary file in " + dir.string(), -1, false);
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("write " + tmp, fd, true);
    done += static_cast<std::size_t>(n);
  }
  // mkstemp creates 0600; artefacts and reports are ordinary readable files.
  if (::fchmod(fd, 0644) != 0) fail("set permissions on " + tmp, fd, true);
  if (::fsync(fd) != 0) fail("flush " + tmp, fd, true);
  if (::close(fd) != 0) fail("close " + tmp, -1, true);
  if (std::rename(tmp.c_str(), file.c_str()) != 0) fail("rename " + tmp, -1, true);
  // Make the rename itself durable; failure here leaves a complete file, so it is not an error.
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

}  // namespace flexloop::common
