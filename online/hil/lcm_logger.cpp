#include "online/hil/lcm_logger.hpp"

#include <sched.h>
#include <signal.h>
#include <spawn.h>
#include <sys/sysinfo.h>
#include <sys/wait.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>
#include <stdexcept>
#include <vector>

extern char** environ;

namespace flexloop::hil {

LcmLogger::LcmLogger(const std::string& url, const std::string& path) : url_(url) {
  std::vector<std::string> args{"lcm-logger", "-f", "--lcm-url=" + url, path};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // The caller may run pinned to the plant's CPU at real-time priority (the baselines); the
  // logger must not inherit that, or a spinning plant starves it and the log stays empty.
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sched_param normal{};
  posix_spawnattr_setschedpolicy(&attr, SCHED_OTHER);
  posix_spawnattr_setschedparam(&attr, &normal);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSCHEDULER);
  const int spawned = posix_spawnp(&pid_, "lcm-logger", nullptr, &attr, argv.data(), environ);
  posix_spawnattr_destroy(&attr);
  if (spawned != 0) {
    pid_ = -1;
    throw std::runtime_error("cannot start lcm-logger (is the lcm package installed?)");
  }
  cpu_set_t every{};
  CPU_ZERO(&every);
  for (int cpu = 0; cpu < get_nprocs_conf() && cpu < CPU_SETSIZE; ++cpu) CPU_SET(cpu, &every);
  sched_setaffinity(pid_, sizeof every, &every);  // best effort: a failure leaves it pinned
  usleep(200'000);                                // let it subscribe before the run starts
}

void LcmLogger::record(const std::string& channel, const std::string& text) const {
  lcm::LCM lcm(url_);
  if (!lcm.good()) throw std::runtime_error("cannot open LCM on " + url_ + " to record " + channel);
  if (lcm.publish(channel, text.data(), static_cast<unsigned int>(text.size())) != 0)
    throw std::runtime_error("cannot publish " + channel + " on " + url_);
  usleep(50'000);  // the logger writes it before the loop's traffic starts
}

LcmLogger::~LcmLogger() {
  if (pid_ <= 0) return;
  kill(pid_, SIGINT);
  int status = 0;
  for (int i = 0; i < 200; ++i) {
    if (waitpid(pid_, &status, WNOHANG) == pid_) return;
    usleep(10'000);
  }
  kill(pid_, SIGKILL);
  waitpid(pid_, &status, 0);
}

}  // namespace flexloop::hil
