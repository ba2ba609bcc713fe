#include "io/isolated_run.hpp"

#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <exception>
#include <filesystem>

#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

void write_all(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

}  // namespace

namespace {
bool g_in_isolated_child = false;
}  // namespace

bool in_isolated_child() { return g_in_isolated_child; }

void run_isolated(const std::string& subject, const std::function<void()>& check, double timeout_s) {
  int fds[2];
  if (::pipe(fds) != 0) {
    check();
    return;
  }
  const pid_t parent = ::getpid();
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    check();
    return;
  }
  if (child == 0) {
    // Child: run the check, report an InputError's message through the pipe, and leave with
    // _exit so that no atexit handler or buffered stream of the parent runs twice.
    // A child spinning in the library must not outlive a parent killed by SIGKILL (no timeout
    // kills it then): the kernel sends it SIGKILL when the parent dies. If the parent died
    // between fork() and prctl(), the child is already someone else's: leave at once.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(4);
    ::close(fds[0]);
    g_in_isolated_child = true;
    int status = 0;
    try {
      check();
    } catch (const InputError& e) {
      write_all(fds[1], e.what());
      status = 2;
    } catch (const std::exception& e) {
      write_all(fds[1], subject + ": internal error while reading: " + e.what());
      status = 3;
    } catch (...) {
      status = 3;
    }
    ::close(fds[1]);
    ::_exit(status);
  }

  ::close(fds[1]);
  std::string message;
  bool timed_out = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      timed_out = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int r = ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 1000)));
    if (r < 0 && errno != EINTR) break;
    if (r <= 0) continue;
    char buffer[4096];
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n > 0) {
      message.append(buffer, static_cast<std::size_t>(n));
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    break;  // EOF: the child closed the pipe (it is exiting)
  }
  ::close(fds[0]);
  if (timed_out) ::kill(child, SIGKILL);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (timed_out)
    throw InputError(subject + ": reading did not finish within " +
                     std::to_string(static_cast<int>(timeout_s)) +
                     " s; the file is probably corrupt (the HDF5 library loops on some damaged files)");
  if (WIFSIGNALED(status))
    throw InputError(subject + ": the file is corrupt: the HDF5 library crashed reading it (signal " +
                     std::to_string(WTERMSIG(status)) + ")");
  if (WIFEXITED(status) && WEXITSTATUS(status) == 2) throw InputError(message);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw InputError(message.empty()
                         ? subject +
                               ": the file is corrupt: the HDF5 library failed reading it (exit status " +
                               std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")"
                         : message);
}

double isolated_read_timeout(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  return 10.0 + (ec ? 0.0 : static_cast<double>(size) / 5e6);
}

}  // namespace trackassoc
