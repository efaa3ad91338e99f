#include "owval/base/contained.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <stdexcept>

#include "owval/base/errors.hpp"

namespace owval {
namespace {

constexpr int kExitRefused = 2, kExitOtherError = 3;

// Set by a sanitizer runtime (and libFuzzer registers its crash report through it); absent
// otherwise.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

[[noreturn]] void RunChild(int pipe_out, const std::function<void()>& work, int timeout_s) {
  // Libraries' own diagnostics (and a sanitizer's report) stay out of owval's one-line output.
  const int null = ::open("/dev/null", O_WRONLY);
  if (null >= 0) ::dup2(null, STDERR_FILENO);
  // A crash ends the child, and the parent reports it: the handlers inherited from the parent
  // (a sanitizer's, libFuzzer's) would otherwise report it as the parent's own, and libFuzzer
  // would save the input as a crash of the fuzz target that contained it.
  for (const int deadly : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT}) std::signal(deadly, SIG_DFL);
  if (__sanitizer_set_death_callback) __sanitizer_set_death_callback(nullptr);
  std::signal(SIGALRM, SIG_DFL);
  ::alarm(static_cast<unsigned>(timeout_s));
  int code = 0;
  std::string message;
  try {
    work();
  } catch (const InputError& e) {
    code = kExitRefused, message = e.what();
  } catch (const std::exception& e) {
    code = kExitOtherError, message = e.what();
  }
  for (std::size_t done = 0; done < message.size();) {
    const ssize_t n = ::write(pipe_out, message.data() + done, message.size() - done);
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  ::_exit(code);  // no atexit handlers, no flushing of the parent's buffers twice
}

std::string ReadAll(int fd) {
  std::string text;
  char buffer[4096];
  for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) != 0;) {
    if (n < 0) {
      if (errno == EINTR) continue;
      break;
    }
    text.append(buffer, static_cast<std::size_t>(n));
  }
  return text;
}

}  // namespace

void RunContained(const std::string& file, const std::string& what,
                  const std::function<void()>& work, const ContainedOptions& options) {
  int fds[2];
  if (::pipe(fds) != 0)
    throw std::runtime_error("cannot create a pipe: " + std::string(std::strerror(errno)));
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(fds[0]), ::close(fds[1]);
    throw std::runtime_error("cannot fork: " + std::string(std::strerror(errno)));
  }
  if (child == 0) {
    ::close(fds[0]);
    RunChild(fds[1], work, options.timeout_s);
  }
  ::close(fds[1]);
  const std::string message = ReadAll(fds[0]);
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  if (WIFEXITED(status) && WEXITSTATUS(status) == kExitRefused) throw InputError(message);
  if (WIFEXITED(status) && WEXITSTATUS(status) == kExitOtherError)
    throw std::runtime_error(message);
  const std::string how = WIFSIGNALED(status)
                              ? (WTERMSIG(status) == SIGALRM
                                     ? "ran past " + std::to_string(options.timeout_s) + " s"
                                     : "crashed (" + std::string(strsignal(WTERMSIG(status))) + ")")
                              : "crashed (exit " + std::to_string(WEXITSTATUS(status)) + ")";
  throw InputError(file, 0, what + " " + how + ": corrupt or hostile file");
}

}  // namespace owval
