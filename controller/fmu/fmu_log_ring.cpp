// SPDX-License-Identifier: BSD-3-Clause
#include "controller/fmu/fmu_log_ring.hpp"

#include <cstdio>
#include <utility>

namespace flexloop::controller::fmu {

namespace {

const char* status_text(fmi2Status s) {
  static const char* const kStatus[] = {"ok", "warning", "discard", "error", "fatal", "pending"};
  return static_cast<unsigned>(s) < 6 ? kStatus[s] : "?";
}

template <std::size_t N>
void copy_text(std::array<char, N>& to, const char* from) noexcept {
  std::snprintf(to.data(), N, "%s", from ? from : "");
}

}  // namespace

FmuLogRing::FmuLogRing(std::string fmu) : fmu_(std::move(fmu)), slots_(kSlots) {}

void FmuLogRing::logger(fmi2ComponentEnvironment ring, fmi2String instance, fmi2Status status,
                        fmi2String category, fmi2String message, ...) {
  std::va_list args;
  va_start(args, message);
  if (ring) static_cast<FmuLogRing*>(ring)->record(instance, status, category, message, args);
  va_end(args);
}

void FmuLogRing::record(fmi2String instance, fmi2Status status, fmi2String category,
                        fmi2String message, std::va_list args) noexcept {
  const std::uint64_t head = head_.load(std::memory_order_relaxed);
  const bool full = head - tail_.load(std::memory_order_acquire) >= kSlots;
  Slot& slot = slots_[head % kSlots];
  // A full ring keeps its messages; the text is still formatted (into the first warning's slot
  // only) so that a warning is named even when the ring has no room for it.
  std::va_list copy;
  va_copy(copy, args);
  if (!full) {
    slot.status = status;
    copy_text(slot.instance, instance);
    copy_text(slot.category, category);
    std::vsnprintf(slot.text.data(), kSlotChars, message ? message : "", copy);
  }
  va_end(copy);
  if (status == fmi2Warning && !warned_.load(std::memory_order_relaxed)) {
    std::vsnprintf(first_warning_.data(), kSlotChars, message ? message : "", args);
    warned_.store(true, std::memory_order_release);
  }
  if (full) {
    lost_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  head_.store(head + 1, std::memory_order_release);
}

std::vector<std::string> FmuLogRing::take() {
  std::vector<std::string> out;
  const std::uint64_t head = head_.load(std::memory_order_acquire);
  std::uint64_t tail = tail_.load(std::memory_order_relaxed);
  for (; tail < head; ++tail) {
    const Slot& s = slots_[tail % kSlots];
    out.push_back("FMU " + fmu_ + " (" + s.instance.data() + ", " + status_text(s.status) + ", " +
                  s.category.data() + "): " + s.text.data());
  }
  tail_.store(tail, std::memory_order_release);
  return out;
}

std::string FmuLogRing::first_warning() const {
  return warned_.load(std::memory_order_acquire) ? std::string(first_warning_.data())
                                                 : std::string();
}

}  // namespace flexloop::controller::fmu
