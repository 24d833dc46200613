#include "offline/campaign/shard_run.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>

#include "common/input_error.hpp"

namespace flexloop::campaign {

Shard parse_shard(const std::string& text) {
  Shard s;
  char slash = 0;
  char rest = 0;
  if (std::sscanf(text.c_str(), "%ld%c%ld%c", &s.k, &slash, &s.m, &rest) != 3 || slash != '/' ||
      s.m < 1 || s.k < 0 || s.k >= s.m)
    throw common::InputError("--shard", "'" + text + "' is not K/M with 0 <= K < M");
  return s;
}

std::vector<long> shard_indices(const Shard& shard, long evaluations) {
  std::vector<long> out;
  for (long i = shard.k; i < evaluations; i += shard.m) out.push_back(i);
  return out;
}

nlohmann::json plan_line(const std::string& text, const std::string& place,
                         const std::string& plan_id) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error&) {
    throw common::InputError(place, "not a JSON line: the shard file is damaged");
  }
  if (!j.is_object() || j.value("plan_id", std::string()) != plan_id)
    throw common::InputError(
        place, "this line belongs to another plan (plan_id " +
                   (j.is_object() ? j.value("plan_id", std::string("none")) : std::string("none")) +
                   "; this plan's is " + plan_id + ")");
  return j;
}

std::vector<long> completed_indices(const std::string& file, const std::string& plan_id,
                                    const Shard& shard, long evaluations) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return {};
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  std::vector<long> done;
  std::set<long> seen;
  std::size_t start = 0;
  long line_number = 0;
  for (std::size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1) {
    const std::string place = file + ":" + std::to_string(++line_number);
    const nlohmann::json j = plan_line(text.substr(start, end - start), place, plan_id);
    const long index = j.value("index", -1L);
    if (index < 0 || index >= evaluations || index % shard.m != shard.k)
      throw common::InputError(place, "index " + std::to_string(index) + " is not one of shard " +
                                          std::to_string(shard.k) + "/" + std::to_string(shard.m));
    if (!seen.insert(index).second)
      throw common::InputError(place, "index " + std::to_string(index) + " is there twice");
    done.push_back(index);
  }
  // A last line without its newline was being written when the run was killed: cut it off.
  if (start < text.size()) std::filesystem::resize_file(file, start);
  return done;
}

ShardRunResult run_shard(const std::string& file, const std::string& plan_id, const Shard& shard,
                         long evaluations, const std::function<nlohmann::json(long)>& line_of,
                         const std::function<void(long, long)>& progress) {
  const std::vector<long> all = shard_indices(shard, evaluations);
  const std::vector<long> done_list = completed_indices(file, plan_id, shard, evaluations);
  const std::set<long> done(done_list.begin(), done_list.end());
  ShardRunResult r;
  r.already = static_cast<long>(done.size());
  const long total = static_cast<long>(all.size());
  if (progress) progress(r.already, total);
  std::FILE* out = std::fopen(file.c_str(), "ab");
  if (!out) throw common::InputError(file, "cannot be written");
  try {
    for (long index : all) {
      if (done.count(index)) continue;
      const std::string text = line_of(index).dump() + "\n";
      // One write, flushed: a kill leaves at most this line torn, which the next run cuts off.
      if (std::fwrite(text.data(), 1, text.size(), out) != text.size() || std::fflush(out) != 0)
        throw std::runtime_error("cannot write " + file);
      ++r.computed;
      if (progress) progress(r.already + r.computed, total);
    }
  } catch (...) {
    std::fclose(out);
    throw;
  }
  if (std::fclose(out) != 0) throw std::runtime_error("cannot write " + file);
  return r;
}

long complete_lines(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return 0;
  return static_cast<long>(
      std::count(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>(), '\n'));
}

}  // namespace flexloop::campaign
