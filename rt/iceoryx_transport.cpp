// SPDX-License-Identifier: BSD-3-Clause
#include "rt/iceoryx_transport.hpp"

#include <unistd.h>

#include <iceoryx_hoofs/log/logmanager.hpp>
#include <iceoryx_hoofs/platform/platform_settings.hpp>
#include <iceoryx_posh/mepoo/chunk_header.hpp>
#include <iceoryx_posh/runtime/posh_runtime.hpp>
#include <stdexcept>

#include "rt/roudi_process.hpp"

namespace flexloop::rt {

namespace {

iox::capro::IdString_t id_string(const std::string& text) {
  if (text.size() > iox::capro::IdString_t::capacity())
    throw std::runtime_error("iceoryx: the name '" + text + "' is longer than " +
                             std::to_string(iox::capro::IdString_t::capacity()) + " characters");
  return iox::capro::IdString_t(iox::cxx::TruncateToCapacity, text.c_str());
}

}  // namespace

iox::capro::ServiceDescription iceoryx_service(const std::string& channel) {
  return {id_string("flexloop"), id_string(channel), id_string("lcm")};
}

std::string IceoryxTransport::registered_name(const std::string& runtime_name) {
  return runtime_name + "_" + std::to_string(getpid());
}

std::vector<std::string> IceoryxTransport::runtime_files(const std::string& registered_name) {
  return {iox::platform::IOX_UDS_SOCKET_PATH_PREFIX + registered_name,
          iox::platform::IOX_LOCK_FILE_PATH_PREFIX + registered_name + ".lock"};
}

IceoryxTransport::IceoryxTransport(const std::string& runtime_name) {
  // iceoryx logs to stdout; a loop's output is its own report, so only warnings and worse.
  iox::log::LogManager::GetLogManager().SetDefaultLogLevel(iox::log::LogLevel::kWarn,
                                                           iox::log::LogLevelOutput::kHideLogLevel);
  // iceoryx's runtime would wait a minute for a RouDi and then abort: say at once that none runs.
  if (!running_roudi_pid())
    throw RoudiError(
        "iceoryx: no RouDi runs on this host (start one: flexloop roudi, or iox-roudi)");
  const std::string name = registered_name(runtime_name);
  iox::runtime::PoshRuntime::initRuntime(
      iox::RuntimeName_t(iox::cxx::TruncateToCapacity, id_string(name).c_str()));
  waitset_ = std::make_unique<iox::popo::WaitSet<>>();
}

// The wait set goes first (declared last): it detaches the subscribers it watches.
IceoryxTransport::~IceoryxTransport() = default;

void IceoryxTransport::subscribe_bytes(const std::string& channel, Deliver deliver, void* inbox,
                                       int queue_capacity) {
  iox::popo::SubscriberOptions o;
  o.queueCapacity = static_cast<std::uint64_t>(queue_capacity);
  o.historyRequest = 0;
  Subscription s{std::make_unique<iox::popo::UntypedSubscriber>(iceoryx_service(channel), o),
                 deliver, inbox, recorder_ ? recorder_->channel(channel) : -1};
  if (waitset_->attachState(*s.subscriber, iox::popo::SubscriberState::HAS_DATA).has_error())
    throw std::runtime_error("iceoryx: cannot attach the subscriber of " + channel +
                             " to the wait set");
  subscriptions_.push_back(std::move(s));
}

int IceoryxTransport::poll_ready(std::int64_t timeout_ns) noexcept {
  for (const Subscription& s : subscriptions_)
    if (s.subscriber->hasData()) return 1;
  if (timeout_ns <= 0) return 0;
  return waitset_->timedWait(iox::units::Duration::fromNanoseconds(timeout_ns)).empty() ? 0 : 1;
}

bool IceoryxTransport::subscriptions_connected() const noexcept {
  for (const Subscription& s : subscriptions_)
    if (s.subscriber->getSubscriptionState() != iox::SubscribeState::SUBSCRIBED) return false;
  return true;
}

int IceoryxTransport::handle_pending() noexcept {
  int handled = 0;
  for (Subscription& s : subscriptions_) {
    while (s.subscriber->hasData()) {
      const void* chunk = nullptr;
      s.subscriber->take().and_then([&](const void* p) { chunk = p; });
      if (!chunk) break;  // the queue's chunk was dropped as the oldest meanwhile
      const std::int64_t now = monotonic_now_ns();
      const int size =
          static_cast<int>(iox::mepoo::ChunkHeader::fromUserPayload(chunk)->userPayloadSize());
      if (recorder_) recorder_->record(s.recorder_channel, chunk, size, now);
      s.deliver(s.inbox, chunk, size, now);
      s.subscriber->release(chunk);
      ++handled;
    }
  }
  return handled;
}

}  // namespace flexloop::rt
