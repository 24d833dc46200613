// SPDX-License-Identifier: BSD-3-Clause
#include "offline/campaign/shard_merge.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "offline/campaign/shard_run.hpp"

namespace flexloop::campaign {

namespace {

// Bytes of a file at an offset. @throws std::runtime_error when they cannot be read.
void read_at(int fd, const std::string& file, std::uint64_t offset, char* to, std::size_t size) {
  for (std::size_t done = 0; done < size;) {
    const ssize_t got = ::pread(fd, to + done, size - done, static_cast<off_t>(offset + done));
    if (got <= 0) throw std::runtime_error("campaign report: cannot read " + file + " again");
    done += static_cast<std::size_t>(got);
  }
}

int open_shard(const std::string& file) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw common::InputError(file, "cannot open the shard file");
  return fd;
}

}  // namespace

ShardLines::ShardLines(std::vector<std::string> files, long evaluations)
    : files_(std::move(files)), places_(static_cast<std::size_t>(evaluations)) {}

void ShardLines::record(long index, std::uint32_t file, std::uint64_t offset,
                        std::uint32_t length) {
  places_[static_cast<std::size_t>(index)] = {offset, length, file};
}

std::string ShardLines::line(long index) const {
  const Place& p = places_[static_cast<std::size_t>(index)];
  if (p.length == 0) return "";
  std::string text(p.length, '\0');
  const int fd = open_shard(files_[p.file]);
  try {
    read_at(fd, files_[p.file], p.offset, text.data(), text.size());
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
  return text;
}

std::string ShardLines::place(long index) const {
  const Place& p = places_[static_cast<std::size_t>(index)];
  std::ifstream in(files_[p.file], std::ios::binary);
  long number = 1;
  std::vector<char> chunk(1 << 16);
  for (std::uint64_t left = p.offset; left > 0 && in;) {
    in.read(chunk.data(),
            static_cast<std::streamsize>(std::min<std::uint64_t>(left, chunk.size())));
    number += std::count(chunk.data(), chunk.data() + in.gcount(), '\n');
    left -= static_cast<std::uint64_t>(in.gcount());
  }
  return files_[p.file] + ":" + std::to_string(number);
}

// The lines in index order, copied in pieces of about 1 MiB; the shards stay open while they
// are read (up to a few hundred at once: the rest opened as they are needed).
void ShardLines::write_in_index_order(const std::filesystem::path& file) const {
  constexpr std::size_t kPiece = 1 << 20, kOpenAtMost = 256;
  common::AtomicFileWriter out(file);
  std::vector<int> fds(files_.size(), -1);
  std::size_t open = 0;
  const auto close_all = [&] {
    for (int& fd : fds)
      if (fd >= 0) ::close(fd), fd = -1;
    open = 0;
  };
  std::string piece;
  piece.reserve(kPiece + (1 << 16));
  try {
    for (const Place& p : places_) {
      if (p.length == 0) continue;
      if (fds[p.file] < 0) {
        if (open == kOpenAtMost) close_all();
        fds[p.file] = open_shard(files_[p.file]), ++open;
      }
      const std::size_t at = piece.size();
      piece.resize(at + p.length);
      read_at(fds[p.file], files_[p.file], p.offset, piece.data() + at, p.length);
      if (piece.size() >= kPiece) out.write(piece.data(), piece.size()), piece.clear();
    }
    out.write(piece.data(), piece.size());
  } catch (...) {
    close_all();
    throw;
  }
  close_all();
  out.commit();
}

namespace {

// Per build ("flexloop" {version, build}, as its JSON text) the lowest index it computed and that
// line's place: lines of two builds may differ in their last bits, so a campaign's are not pooled.
struct BuildSeen {
  long index;
  std::string place;
};
using Builds = std::map<std::string, BuildSeen>;

void note_build(const nlohmann::json& sample, long index, const std::string& place,
                Builds& builds) {
  const std::string build = sample.value("flexloop", nlohmann::json()).dump();
  const auto [it, fresh] = builds.emplace(build, BuildSeen{index, place});
  if (!fresh && index < it->second.index) it->second = {index, place};
}

// One build computed every line. Else the error names the line of the lowest index and the
// lowest of another build: what a check in index order finds first.
void require_one_build(const Builds& builds) {
  if (builds.size() < 2) return;
  auto first = builds.begin();
  for (auto it = builds.begin(); it != builds.end(); ++it)
    if (it->second.index < first->second.index) first = it;
  auto other = builds.end();
  for (auto it = builds.begin(); it != builds.end(); ++it)
    if (it != first && (other == builds.end() || it->second.index < other->second.index))
      other = it;
  throw common::InputError(other->second.place,
                           "computed by flexloop " + other->first + ", but " + first->second.place +
                               " by " + first->first +
                               ": a campaign's samples come from one build; run its shards again "
                               "with one flexloop");
}

// One shard file, line by line: each checked, the first line of each index recorded and taken.
void read_shard(const std::string& file, std::uint32_t file_number, const nlohmann::json& plan,
                ShardLines& lines, Builds& builds, const TakeSample& take) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw common::InputError(file, "cannot open the shard file");
  const std::string plan_id = plan.at("plan_id").get<std::string>();
  const long evaluations = plan.at("evaluations").get<long>();
  std::string text;
  std::uint64_t offset = 0;
  for (long number = 1; std::getline(in, text); ++number) {
    const std::string place = file + ":" + std::to_string(number);
    if (in.eof())  // no '\n' before the end
      throw common::InputError(place,
                               "a torn last line (its run was killed): run the shard again "
                               "(`flexloop campaign run` completes it)");
    const nlohmann::json sample = plan_line(text, place, plan_id);
    const long index = sample.value("index", -1L);
    if (index < 0 || index >= evaluations)
      throw common::InputError(place, "index " + std::to_string(index) +
                                          " is not in the plan (0.." +
                                          std::to_string(evaluations - 1) + ")");
    text += '\n';
    if (lines.has(index)) {
      if (lines.line(index) != text)
        throw common::InputError(
            place, "index " + std::to_string(index) + " differs from " + lines.place(index));
    } else {
      lines.record(index, file_number, offset, static_cast<std::uint32_t>(text.size()));
      note_build(sample, index, place, builds);
      take(index, sample);
    }
    offset += text.size();
  }
}

}  // namespace

std::string index_ranges(const std::vector<long>& sorted, std::size_t at_most) {
  std::string out;
  std::size_t ranges = 0;
  for (std::size_t i = 0; i < sorted.size();) {
    std::size_t j = i;
    while (j + 1 < sorted.size() && sorted[j + 1] == sorted[j] + 1) ++j;
    if (++ranges > at_most) return out + ", ...";
    out += (out.empty() ? "" : ", ") + std::to_string(sorted[i]) +
           (j > i ? "-" + std::to_string(sorted[j]) : "");
    i = j + 1;
  }
  return out;
}

ShardLines merge_shards(const nlohmann::json& plan, const std::vector<std::string>& files,
                        const TakeSample& take) {
  const long evaluations = plan.at("evaluations").get<long>();
  ShardLines lines(files, evaluations);
  Builds builds;
  for (std::size_t f = 0; f < files.size(); ++f)
    read_shard(files[f], static_cast<std::uint32_t>(f), plan, lines, builds, take);
  require_one_build(builds);
  std::vector<long> missing;
  for (long i = 0; i < evaluations; ++i)
    if (!lines.has(i)) missing.push_back(i);
  if (!missing.empty())
    throw common::InputError(
        "plan " + plan.at("plan_id").get<std::string>().substr(0, 12),
        std::to_string(missing.size()) + " of " + std::to_string(evaluations) +
            " samples missing: " + index_ranges(missing) +
            " (run the shards that hold them again with `flexloop campaign run`, or pass their "
            "files)");
  return lines;
}

MergedSamples merge_shards(const nlohmann::json& plan, const std::vector<std::string>& files) {
  MergedSamples m;
  m.samples.resize(plan.at("evaluations").get<std::size_t>());
  const ShardLines lines = merge_shards(plan, files, [&](long index, const nlohmann::json& sample) {
    m.samples[static_cast<std::size_t>(index)] = sample;
  });
  for (long i = 0; i < static_cast<long>(m.samples.size()); ++i) m.jsonl += lines.line(i);
  return m;
}

}  // namespace flexloop::campaign
