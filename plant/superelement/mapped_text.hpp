// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Text files of an FE tool read where they lie (issue 58): a whole file memory-mapped read-only,
// its lines numbered for error messages (file:line), and numbers taken with std::from_chars (no
// iostreams: a 10^6-DOF model is about a gigabyte of text, read at disk speed).
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>

#include "common/input_error.hpp"

namespace flexloop::plant::superelement::text {

using common::InputError;

// A whole file mapped read-only: the text is parsed where it lies, at disk speed.
class MappedText {
 public:
  explicit MappedText(const std::string& path) : path_(path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw InputError(path, std::string("cannot read: ") + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
      ::close(fd);
      throw InputError(path, "not a regular file");
    }
    size_ = static_cast<std::size_t>(st.st_size);
    if (size_ > 0) {
      data_ = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
      if (data_ == MAP_FAILED) {
        ::close(fd);
        throw InputError(path, std::string("cannot map: ") + std::strerror(errno));
      }
      ::madvise(data_, size_, MADV_SEQUENTIAL);
    }
    ::close(fd);
  }
  ~MappedText() {
    if (data_ && data_ != MAP_FAILED) ::munmap(data_, size_);
  }
  MappedText(const MappedText&) = delete;
  MappedText& operator=(const MappedText&) = delete;

  std::string_view text() const {
    return size_ ? std::string_view(static_cast<const char*>(data_), size_) : std::string_view();
  }

 private:
  std::string path_;
  void* data_ = nullptr;
  std::size_t size_ = 0;
};

// The lines of a text, numbered from 1, blank ones included in the count.
class Lines {
 public:
  Lines(std::string_view text, std::string file) : rest_(text), file_(std::move(file)) {}
  bool next(std::string_view& line) {
    if (rest_.empty()) return false;
    const std::size_t end = rest_.find('\n');
    line = rest_.substr(0, end);
    rest_ = end == std::string_view::npos ? std::string_view() : rest_.substr(end + 1);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    ++number_;
    return true;
  }
  InputError error(const std::string& what) const {
    return InputError(file_ + ":" + std::to_string(number_), what);
  }

 private:
  std::string_view rest_;
  std::string file_;
  long number_ = 0;
};

inline bool blank(std::string_view s) {
  return s.find_first_not_of(" \t") == std::string_view::npos;
}

// The next whitespace- (or comma-) separated field of `s` as a T, consuming it; false when
// there is none or it is not a T.
template <class T>
inline bool take(std::string_view& s, T& value, bool comma = false) {
  const std::size_t start = s.find_first_not_of(comma ? " \t," : " \t");
  if (start == std::string_view::npos) return false;
  s.remove_prefix(start);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || (end != s.data() + s.size() && !std::strchr(" \t,", *end))) return false;
  s.remove_prefix(static_cast<std::size_t>(end - s.data()));
  return true;
}

}  // namespace flexloop::plant::superelement::text
