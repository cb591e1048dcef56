// The child process of child_process.hpp: fork, a pipe for the reply, poll() for the deadline.
#include "child_process.hpp"

#include <poll.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"

namespace cbps {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Writes all of `size` bytes; false on a broken pipe.
bool write_all(int fd, const void* data, std::size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = ::write(fd, p, size);
    if (n <= 0) {
      if (n < 0 && errno == EINTR) continue;
      return false;
    }
    p += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

/// What the child sends back: the fixed part, then the two texts and lambda.
struct Reply {
  int said_ok = 0;
  int iterations = -1;
  double convert_s = 0.0, solve_s = 0.0;
  std::uint64_t status_size = 0, class_size = 0, rows = 0;
};

[[noreturn]] void child(int fd,
                        pid_t parent,
                        const BoxedProblem& problem,
                        VecX lambda,
                        const SolverOptions& options,
                        PeerSolve run_here) {
  // The child ends with its parent, however the parent ends (Ctrl-C's cleanup, SIGTERM,
  // SIGKILL): the kernel sends SIGKILL when the thread that forked it is gone; a parent gone
  // before this line leaves the child to init, which getppid() then shows.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) std::_Exit(4);
  ::dup2(2, 1);  // a peer may print to stdout: keep cbps's own output (--json) whole
  // The default action for every signal the parent may handle: an abort inside the peer ends the
  // child as SIGABRT (the parent reports it), and Ctrl-C's clean-up is the parent's alone.
  for (const int sig : {SIGABRT, SIGSEGV, SIGFPE, SIGILL, SIGBUS, SIGINT, SIGTERM})
    std::signal(sig, SIG_DFL);
  PeerRun run;
  try {
    run = run_here(problem, lambda, options);
  } catch (const std::exception& e) {
    run.status = std::string("error: ") + e.what();
  }
  Reply r;
  r.said_ok = run.said_ok ? 1 : 0;
  r.iterations = run.iterations;
  r.convert_s = run.convert_s;
  r.solve_s = run.solve_s;
  r.status_size = run.status.size();
  r.class_size = run.problem_class.size();
  r.rows = static_cast<std::uint64_t>(lambda.size());
  const bool ok = write_all(fd, &r, sizeof r) &&
                  write_all(fd, run.status.data(), run.status.size()) &&
                  write_all(fd, run.problem_class.data(), run.problem_class.size()) &&
                  write_all(fd, lambda.data(), sizeof(double) * lambda.size());
  ::close(fd);
  std::_Exit(ok ? 0 : 3);
}

/// Reads the child's reply from `fd` into `bytes` until the child closes its end; true when
/// `deadline` passed first.
bool read_reply(int fd, std::chrono::steady_clock::time_point deadline, std::vector<char>& bytes) {
  char buffer[1 << 16];
  const bool bounded = deadline != std::chrono::steady_clock::time_point::max();
  for (;;) {
    if (bounded) {
      const double left =
          std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
      if (left <= 0.0) return true;
      pollfd p{fd, POLLIN, 0};
      const int ready = ::poll(&p, 1, static_cast<int>(std::ceil(std::min(left, 3600.0) * 1e3)));
      if (ready < 0 && errno == EINTR) continue;
      if (ready == 0) continue;  // the loop's test of the time left ends it
    }
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    bytes.insert(bytes.end(), buffer, buffer + n);
  }
}

/// How a child that sent no whole reply ended, in words.
std::string how_it_ended(int status, const std::string& library) {
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    const std::string name = sig == SIGABRT
                                 ? " SIGABRT (an assertion or abort() inside " + library + ")"
                             : sig == SIGSEGV ? std::string(" SIGSEGV")
                             : sig == SIGFPE  ? std::string(" SIGFPE")
                                              : std::string();
    return "ended the process: signal " + std::to_string(sig) + name;
  }
  if (WIFEXITED(status))
    return "ended the process: exit(" + std::to_string(WEXITSTATUS(status)) + ") inside " +
           library + " (its message is on stderr)";
  return "ended the process";
}

}  // namespace

PeerRun run_in_child(const BoxedProblem& problem,
                     VecX& lambda,
                     const SolverOptions& options,
                     PeerSolve run_here,
                     const char* library) {
  // The child sends back lambda and the peer's own word; the parent reports how the child ended
  // when it sends nothing. The peer's conversion and solve are timed in the child.
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error(std::string(library) + ": pipe() failed");
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t parent = ::getpid();
  const auto started = std::chrono::steady_clock::now();
  // solve() sets the deadline; a caller of solve_peer alone gets the limit from now.
  auto deadline = options.deadline;
  if (deadline == std::chrono::steady_clock::time_point::max() && options.time_limit > 0.0)
    deadline = started + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                             std::chrono::duration<double>(options.time_limit));
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::runtime_error(std::string(library) + ": fork() failed");
  }
  if (pid == 0) {
    ::close(fds[0]);
    child(fds[1], parent, problem, lambda, options, run_here);
  }
  ::close(fds[1]);
  std::vector<char> bytes;
  const bool timed_out = read_reply(fds[0], deadline, bytes);
  ::close(fds[0]);
  if (timed_out) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  PeerRun run;
  if (timed_out) {
    run.timed_out = true;
    run.status = "time limit: the child process was killed after " +
                 number_text(seconds_since(started)) + " s (time limit " +
                 number_text(options.time_limit) + " s)";
    run.solve_s = seconds_since(started);
    run.problem_class = to_string(peer_class(problem));
    return run;  // lambda as it was: the guess
  }
  Reply r;
  const bool exited = WIFEXITED(status) && WEXITSTATUS(status) == 0 && bytes.size() >= sizeof r;
  if (exited) std::memcpy(&r, bytes.data(), sizeof r);
  const std::size_t whole =
      sizeof r + r.status_size + r.class_size + sizeof(double) * static_cast<std::size_t>(r.rows);
  if (!exited || bytes.size() != whole || static_cast<long>(r.rows) != lambda.size()) {
    run.status = how_it_ended(status, library);
    run.problem_class = to_string(peer_class(problem));
    return run;  // lambda as it was: the guess
  }
  const char* p = bytes.data() + sizeof r;
  run.said_ok = r.said_ok != 0;
  run.iterations = r.iterations;
  run.convert_s = r.convert_s;
  run.solve_s = r.solve_s;
  run.status.assign(p, r.status_size);
  p += r.status_size;
  run.problem_class.assign(p, r.class_size);
  p += r.class_size;
  std::memcpy(lambda.data(), p, sizeof(double) * r.rows);
  return run;
}

}  // namespace cbps
