#include "scene/reader_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <stdexcept>
#include <system_error>
#include <thread>

extern char** environ;

namespace twinray::scene {
namespace {

constexpr std::size_t max_error_text = 2000;

std::string errno_text(int error) {
    return std::error_code(error, std::generic_category()).message();
}

// Both ends close on exec: only the ends dup2'ed onto the child's 1 and 2 reach it, also when other threads
// spawn processes at the same time.
struct Pipe {
    std::array<int, 2> ends{-1, -1};
    Pipe() {
        if (::pipe2(ends.data(), O_CLOEXEC) != 0) {
            throw std::runtime_error("cannot create a pipe: " + errno_text(errno));
        }
    }
    Pipe(const Pipe&) = delete;
    Pipe& operator=(const Pipe&) = delete;
    ~Pipe() {
        close_end(0);
        close_end(1);
    }
    void close_end(int end) {
        if (ends[end] >= 0) {
            ::close(ends[end]);
            ends[end] = -1;
        }
    }
};

// The child's descriptors, and its signals as a fresh process has them: none blocked, none ignored (the caller
// may block or ignore some, and a reader must die of the signal a crash raises, not be stopped by SIGPIPE).
struct Spawn {
    posix_spawn_file_actions_t actions{};
    posix_spawnattr_t attributes{};
    Spawn() {
        posix_spawn_file_actions_init(&actions);
        posix_spawnattr_init(&attributes);
        sigset_t signals;
        sigemptyset(&signals);
        posix_spawnattr_setsigmask(&attributes, &signals);
        sigfillset(&signals);
        posix_spawnattr_setsigdefault(&attributes, &signals);
        posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    }
    Spawn(const Spawn&) = delete;
    Spawn& operator=(const Spawn&) = delete;
    ~Spawn() {
        posix_spawnattr_destroy(&attributes);
        posix_spawn_file_actions_destroy(&actions);
    }
};

using Clock = std::chrono::steady_clock;

int milliseconds_until(Clock::time_point deadline) {
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()).count();
    return static_cast<int>(std::max<decltype(left)>(left, 0));
}

}  // namespace

ProcessOutcome run_process(const std::filesystem::path& program, const std::vector<std::string>& arguments,
                           std::chrono::milliseconds time_limit, std::size_t max_output) {
    Pipe output;
    Pipe errors;
    Spawn spawn;
    posix_spawn_file_actions_addopen(&spawn.actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&spawn.actions, output.ends[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&spawn.actions, errors.ends[1], STDERR_FILENO);
    std::vector<std::string> words{program.string()};
    words.insert(words.end(), arguments.begin(), arguments.end());
    std::vector<char*> argv;
    for (std::string& word : words) {
        argv.push_back(word.data());
    }
    argv.push_back(nullptr);
    const Clock::time_point deadline = Clock::now() + time_limit;
    pid_t child = 0;
    if (const int error =
            posix_spawn(&child, program.c_str(), &spawn.actions, &spawn.attributes, argv.data(), environ)) {
        throw std::runtime_error("cannot start " + program.string() + ": " + errno_text(error));
    }
    output.close_end(1);
    errors.close_end(1);

    ProcessOutcome outcome;
    bool stopped = false;
    std::array<char, 65536> buffer;
    std::array<pollfd, 2> streams{pollfd{output.ends[0], POLLIN, 0}, pollfd{errors.ends[0], POLLIN, 0}};
    while (!stopped && (streams[0].fd >= 0 || streams[1].fd >= 0)) {
        const int ready = ::poll(streams.data(), streams.size(), milliseconds_until(deadline));
        if (ready < 0 && errno == EINTR) {
            continue;
        }
        if (ready <= 0) {
            outcome.end = ProcessOutcome::End::timed_out;
            stopped = true;
            break;
        }
        for (std::size_t s = 0; s < streams.size(); ++s) {
            if (streams[s].fd < 0 || streams[s].revents == 0) {
                continue;
            }
            const ssize_t got = ::read(streams[s].fd, buffer.data(), buffer.size());
            if (got < 0 && errno == EINTR) {
                continue;
            }
            if (got <= 0) {
                streams[s].fd = -1;  // closed: poll passes over negative descriptors
                continue;
            }
            std::string& text = s == 0 ? outcome.output : outcome.errors;
            const std::size_t room = s == 0 ? max_output + 1 : max_error_text;
            text.append(buffer.data(), std::min(static_cast<std::size_t>(got), room - std::min(room, text.size())));
            if (s == 0 && outcome.output.size() > max_output) {
                outcome.end = ProcessOutcome::End::too_much_output;
                stopped = true;
            }
        }
    }
    // Both streams closed: the child is ending, or has closed them and goes on; it gets until the deadline.
    int status = 0;
    pid_t waited = 0;
    while (!stopped && (waited = ::waitpid(child, &status, WNOHANG)) == 0) {
        if (Clock::now() >= deadline) {
            outcome.end = ProcessOutcome::End::timed_out;
            stopped = true;
        } else {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
    }
    if (stopped) {
        ::kill(child, SIGKILL);
        while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
        }
        return outcome;
    }
    if (waited < 0) {
        throw std::runtime_error("cannot wait for " + program.string() + ": " + errno_text(errno));
    }
    if (WIFSIGNALED(status)) {
        outcome.end = ProcessOutcome::End::killed_by_signal;
        outcome.status = WTERMSIG(status);
    } else {
        outcome.status = WEXITSTATUS(status);
    }
    return outcome;
}

}  // namespace twinray::scene
