#pragma once
// Records a run with the distribution's `lcm-logger` (DESIGN.md §10: LCM's own logging), started
// in the caller's network namespace on the loop's URL, so `lcm-spy` / `lcm-logplayer` can replay
// the channels (FLEXLOOP_SENSOR, FLEXLOOP_COMMAND, FLEXLOOP_STATS) afterwards:
//   lcm-logplayer-gui OUT.lcmlog   or   lcm-logplayer OUT.lcmlog & lcm-spy   (same URL)
// The logger is one more LCM receiver on the machine (its own process and socket): it costs CPU
// time in the same namespace, which the report mentions. A logger that fails (cannot open its
// file, dies during the run) fails the run with its own words. Orchestration only.
//
// A log describes itself: record() publishes one text message (the loop's channel map as JSON,
// kChannelMapChannel) once the logger listens, so a reader of the log finds what each entry of
// FLEXLOOP_SENSOR and FLEXLOOP_COMMAND is (name, unit, order) beside the traffic.
#include <sys/types.h>

#include <string>

namespace flexloop::hil {

/// The LCM channel of the loop's channel map in a log (UTF-8 JSON, not an lcm-gen type).
inline constexpr const char* kChannelMapChannel = "FLEXLOOP_CHANNEL_MAP";

class LcmLogger {
 public:
  /// Starts `lcm-logger -f --lcm-url=URL path`; std::runtime_error when it cannot be started or
  /// ends at once (e.g. it cannot open `path`), with its own words.
  LcmLogger(const std::string& url, const std::string& path);
  /// Publishes `text` on `channel` (to the logger's URL), for the log. std::runtime_error when
  /// LCM cannot publish.
  void record(const std::string& channel, const std::string& text) const;
  /// Stops it (SIGINT, then waits; SIGKILL after 2 s) and says how it went: empty when it was
  /// still recording and ended cleanly, else what went wrong, with its own words.
  std::string stop();
  /// Stops it if stop() was not called.
  ~LcmLogger();
  LcmLogger(const LcmLogger&) = delete;
  LcmLogger& operator=(const LcmLogger&) = delete;

 private:
  // What it printed (its stdout and stderr go to a file of their own), last lines.
  std::string output() const;

  std::string url_;
  std::string output_path_;
  pid_t pid_ = -1;
};

}  // namespace flexloop::hil
