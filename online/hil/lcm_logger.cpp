#include "online/hil/lcm_logger.hpp"

#include <sched.h>
#include <signal.h>
#include <spawn.h>
#include <sys/sysinfo.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <sstream>
#include <stdexcept>
#include <vector>

extern char** environ;

namespace flexloop::hil {

namespace {

// "exit code N" / "killed by signal N".
std::string describe_status(int status) {
  if (WIFEXITED(status)) return "exit code " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return "killed by signal " + std::to_string(WTERMSIG(status));
  return "status " + std::to_string(status);
}

}  // namespace

LcmLogger::LcmLogger(const std::string& url, const std::string& path) : url_(url) {
  std::string tmp = "/tmp/flexloop-lcm-logger-XXXXXX";
  const int out_fd = mkstemp(tmp.data());
  if (out_fd < 0) throw std::runtime_error("cannot create a file for lcm-logger's output in /tmp");
  output_path_ = tmp;
  std::vector<std::string> args{"lcm-logger", "-f", "--lcm-url=" + url, path};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_adddup2(&files, out_fd, STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&files, out_fd, STDERR_FILENO);
  // The caller may run pinned to the plant's CPU at real-time priority (the baselines); the
  // logger must not inherit that, or a spinning plant starves it and the log stays empty.
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sched_param normal{};
  posix_spawnattr_setschedpolicy(&attr, SCHED_OTHER);
  posix_spawnattr_setschedparam(&attr, &normal);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSCHEDULER);
  const int spawned = posix_spawnp(&pid_, "lcm-logger", &files, &attr, argv.data(), environ);
  posix_spawnattr_destroy(&attr);
  posix_spawn_file_actions_destroy(&files);
  close(out_fd);
  if (spawned != 0) {
    pid_ = -1;
    unlink(output_path_.c_str());
    throw std::runtime_error("cannot start lcm-logger (is the lcm package installed?)");
  }
  cpu_set_t every{};
  CPU_ZERO(&every);
  for (int cpu = 0; cpu < get_nprocs_conf() && cpu < CPU_SETSIZE; ++cpu) CPU_SET(cpu, &every);
  sched_setaffinity(pid_, sizeof every, &every);  // best effort: a failure leaves it pinned
  usleep(200'000);                                // let it subscribe before the run starts
  int status = 0;
  if (waitpid(pid_, &status, WNOHANG) == pid_) {
    pid_ = -1;
    const std::string words = output();
    unlink(output_path_.c_str());
    throw std::runtime_error("lcm-logger " + path + ": ended at start (" + describe_status(status) +
                             "): " + words);
  }
}

std::string LcmLogger::output() const {
  std::ifstream in(output_path_);
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  if (s.size() > 2000) s = "..." + s.substr(s.size() - 2000);
  return s.empty() ? "(it printed nothing)" : s;
}

void LcmLogger::record(const std::string& channel, const std::string& text) const {
  lcm::LCM lcm(url_);
  if (!lcm.good()) throw std::runtime_error("cannot open LCM on " + url_ + " to record " + channel);
  if (lcm.publish(channel, text.data(), static_cast<unsigned int>(text.size())) != 0)
    throw std::runtime_error("cannot publish " + channel + " on " + url_);
  usleep(50'000);  // the logger writes it before the loop's traffic starts
}

std::string LcmLogger::stop() {
  if (pid_ <= 0) return {};
  int status = 0;
  const bool ended_early = waitpid(pid_, &status, WNOHANG) == pid_;
  if (!ended_early) {
    kill(pid_, SIGINT);
    bool reaped = false;
    for (int i = 0; i < 200 && !reaped; ++i) {
      reaped = waitpid(pid_, &status, WNOHANG) == pid_;
      if (!reaped) usleep(10'000);
    }
    if (!reaped) {
      kill(pid_, SIGKILL);
      while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
      }
    }
  }
  pid_ = -1;
  std::string problem;
  if (ended_early)
    problem = "lcm-logger ended during the run (" + describe_status(status) + "): " + output();
  else if (!(WIFEXITED(status) && WEXITSTATUS(status) == 0) &&
           !(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT))
    problem = "lcm-logger did not end cleanly (" + describe_status(status) + "): " + output();
  unlink(output_path_.c_str());
  return problem;
}

LcmLogger::~LcmLogger() {
  stop();
}

}  // namespace flexloop::hil
