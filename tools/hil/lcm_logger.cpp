#include "tools/hil/lcm_logger.hpp"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stdexcept>
#include <vector>

extern char** environ;

namespace flexloop::hil {

LcmLogger::LcmLogger(const std::string& url, const std::string& path) {
  std::vector<std::string> args{"lcm-logger", "-f", "--lcm-url=" + url, path};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  if (posix_spawnp(&pid_, "lcm-logger", nullptr, nullptr, argv.data(), environ) != 0) {
    pid_ = -1;
    throw std::runtime_error("cannot start lcm-logger (is the lcm package installed?)");
  }
  usleep(200'000);  // let it subscribe before the run starts
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
