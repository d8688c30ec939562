// Running the cullproof program from a test as a user would, with the faults a user's system has:
// a time limit (a hang is a failure, not a stuck test), a limit on file size (writes past it fail
// as on a full disk), and, for a test running as root, file permissions that apply (root's
// CAP_DAC_OVERRIDE would let it write into a read-only directory).
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <linux/capability.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace cullproof::testing {

/// A fresh, empty folder under the system's temporary folder (`name` and the process id), removed
/// with everything in it when the object goes, after giving back the permissions a test took
/// from its folders.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name)
      : path_(std::filesystem::temp_directory_path() / (name + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    for (const auto& e : std::filesystem::recursive_directory_iterator(path_, ec))
      if (e.is_directory())
        std::filesystem::permissions(e.path(), std::filesystem::perms::owner_all, std::filesystem::perm_options::add, ec);
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const noexcept { return path_; }

 private:
  std::filesystem::path path_;
};

struct RunOptions {
  std::vector<std::string> args;                   ///< the program and its arguments
  std::chrono::milliseconds timeout{60000};        ///< then the program is killed and timed_out set
  std::optional<rlim_t> file_size_limit;           ///< RLIMIT_FSIZE in bytes, SIGXFSZ ignored (EFBIG)
  bool permissions_apply = false;                  ///< as root: drop the capabilities that bypass them
  std::string stdout_path;                         ///< stdout to this file (e.g. /dev/full); else captured
};

struct RunResult {
  int exit_code = -1;  ///< when it exited
  int signal = 0;      ///< when a signal ended it
  bool timed_out = false;
  bool could_not_drop_capabilities = false;  ///< permissions_apply asked and this system refused
  std::string out, err;
};

/// The exit status 125 with this text on stderr: the child could not drop its capabilities.
inline constexpr const char* kNoCapabilityDrop = "run_program: cannot drop CAP_DAC_OVERRIDE";

inline RunResult run_program(const RunOptions& o) {
  // Everything the child needs is made before fork(): between fork and exec it only calls the
  // system.
  std::vector<char*> argv;
  for (const std::string& a : o.args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  int out[2], err[2];
  if (::pipe(out) != 0 || ::pipe(err) != 0) return {};
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(out[1], 1);
    ::dup2(err[1], 2);
    ::close(out[0]), ::close(out[1]), ::close(err[0]), ::close(err[1]);
    if (!o.stdout_path.empty()) {
      const int fd = ::open(o.stdout_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd < 0) ::_exit(127);
      ::dup2(fd, 1);
      ::close(fd);
    }
    if (o.file_size_limit) {
      ::signal(SIGXFSZ, SIG_IGN);  // inherited across exec: a write past the limit fails with EFBIG
      const rlimit r{*o.file_size_limit, *o.file_size_limit};
      ::setrlimit(RLIMIT_FSIZE, &r);
    }
    if (o.permissions_apply && ::geteuid() == 0) {
      // Out of the bounding set, these capabilities are not given back by exec.
      for (int cap : {CAP_DAC_OVERRIDE, CAP_DAC_READ_SEARCH, CAP_FOWNER})
        if (::prctl(PR_CAPBSET_DROP, cap, 0, 0, 0) != 0) {
          (void)!::write(2, kNoCapabilityDrop, std::strlen(kNoCapabilityDrop));
          ::_exit(125);
        }
    }
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(out[1]);
  ::close(err[1]);
  RunResult r;
  const auto deadline = std::chrono::steady_clock::now() + o.timeout;
  pollfd fds[2] = {{out[0], POLLIN, 0}, {err[0], POLLIN, 0}};
  int open_fds = 2;
  while (open_fds > 0) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      r.timed_out = true;
      ::kill(pid, SIGKILL);
      break;
    }
    if (::poll(fds, 2, int(left.count())) < 0) continue;
    for (pollfd& p : fds) {
      if (p.fd < 0 || !(p.revents & (POLLIN | POLLHUP))) continue;
      char buf[65536];
      const ssize_t n = ::read(p.fd, buf, sizeof buf);
      if (n <= 0) {
        ::close(p.fd);
        p.fd = -1;
        --open_fds;
      } else {
        (p.fd == out[0] ? r.out : r.err).append(buf, std::size_t(n));
      }
    }
  }
  for (const pollfd& p : fds)
    if (p.fd >= 0) ::close(p.fd);
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.could_not_drop_capabilities = r.exit_code == 125 && r.err.find(kNoCapabilityDrop) != std::string::npos;
  return r;
}

/// Starts the program with stdout and stderr to /dev/null, without waiting (to kill it).
inline pid_t start_program(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

}  // namespace cullproof::testing
