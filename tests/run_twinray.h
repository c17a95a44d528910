// Running the real twinray binary from a test, as a user would: to completion through the shell
// (run_twinray), or as a child process the test can watch, signal and reap (RunningTwinray).
#pragma once

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace twinray::test {

struct CommandResult {
    int exit_status;     // the exit status; 128 + N if killed by signal N (as a shell reports it)
    std::string output;  // stdout and stderr together
};

inline int shell_status(int wait_status) {
    if (WIFEXITED(wait_status)) {
        return WEXITSTATUS(wait_status);
    }
    return WIFSIGNALED(wait_status) ? 128 + WTERMSIG(wait_status) : -1;
}

// `arguments` and `environment` (e.g. "NAME=value") are pasted into a shell command line.
inline CommandResult run_twinray(const std::string& arguments, const std::string& environment = "") {
    std::string command = environment + " " + std::string(TWINRAY_BINARY) + " " + arguments + " 2>&1";
    FILE* pipe = ::popen(command.c_str(), "r");
    if (pipe == nullptr) {
        return {-1, "popen failed"};
    }
    std::string output;
    std::array<char, 4096> buffer{};
    while (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe) != nullptr) {
        output += buffer.data();
    }
    int status = ::pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

// twinray as a child process (no shell): the test can look at it through /proc while it runs, send it
// signals, and reap it with its resource usage. Its stdout and stderr go to a pipe, read once it exits
// (twinray prints a few lines, far less than a pipe holds). The destructor kills a child still running.
class RunningTwinray {
public:
    struct Limits {
        std::optional<rlim_t> file_size_bytes = {};      // RLIMIT_FSIZE, with SIGXFSZ ignored: writes fail with EFBIG
        std::optional<rlim_t> address_space_bytes = {};  // RLIMIT_AS: reserving more fails, touched or not
    };

    explicit RunningTwinray(const std::vector<std::string>& arguments) : RunningTwinray(arguments, Limits{}) {}

    RunningTwinray(const std::vector<std::string>& arguments, Limits limits) {
        int fds[2];
        if (::pipe2(fds, O_CLOEXEC) != 0) {
            return;
        }
        std::vector<std::string> argv_strings{TWINRAY_BINARY};
        argv_strings.insert(argv_strings.end(), arguments.begin(), arguments.end());
        std::vector<char*> argv;
        for (std::string& argument : argv_strings) {
            argv.push_back(argument.data());
        }
        argv.push_back(nullptr);
        pid_ = ::fork();
        if (pid_ == 0) {
            // In the child: only async-signal-safe calls until exec.
            ::dup2(fds[1], STDOUT_FILENO);
            ::dup2(fds[1], STDERR_FILENO);
            ::signal(SIGINT, SIG_DFL);
            if (limits.file_size_bytes) {
                ::signal(SIGXFSZ, SIG_IGN);
                struct rlimit limit {
                    *limits.file_size_bytes, *limits.file_size_bytes
                };
                ::setrlimit(RLIMIT_FSIZE, &limit);
            }
            if (limits.address_space_bytes) {
                struct rlimit limit {
                    *limits.address_space_bytes, *limits.address_space_bytes
                };
                ::setrlimit(RLIMIT_AS, &limit);
            }
            ::execv(argv[0], argv.data());
            ::_exit(127);
        }
        ::close(fds[1]);
        output_fd_ = fds[0];
    }

    ~RunningTwinray() {
        if (pid_ > 0 && !reaped_) {
            ::kill(pid_, SIGKILL);
            wait();
        }
        if (output_fd_ >= 0) {
            ::close(output_fd_);
        }
    }
    RunningTwinray(const RunningTwinray&) = delete;
    RunningTwinray& operator=(const RunningTwinray&) = delete;

    bool started() const { return pid_ > 0; }
    pid_t pid() const { return pid_; }

    // Whether the process has a handler for SIGINT (SigCgt in /proc/PID/status): twinray render
    // installs one before it loads the scene.
    bool catches_sigint() const {
        std::ifstream status("/proc/" + std::to_string(pid_) + "/status");
        std::string line;
        while (std::getline(status, line)) {
            if (line.rfind("SigCgt:", 0) == 0) {
                unsigned long long mask = std::stoull(line.substr(7), nullptr, 16);
                return (mask >> (SIGINT - 1)) & 1u;
            }
        }
        return false;
    }

    // Threads in state R (running or ready to run). Library threads that sleep (a logging pool that
    // OpenImageIO's dependencies start) are not counted, so two of them mean two render workers busy.
    int running_threads() const {
        int running = 0;
        std::error_code error;
        for (const auto& task : std::filesystem::directory_iterator("/proc/" + std::to_string(pid_) + "/task", error)) {
            std::ifstream stat(task.path() / "stat");
            std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
            // The state follows the command name, which is in parentheses: "TID (comm) S ...".
            std::size_t close = text.rfind(')');
            if (close != std::string::npos && close + 2 < text.size() && text[close + 2] == 'R') {
                ++running;
            }
        }
        return running;
    }

    bool has_exited() {
        if (reaped_) {
            return true;
        }
        int status = 0;
        struct rusage usage {};
        pid_t result = ::wait4(pid_, &status, WNOHANG, &usage);
        if (result == pid_) {
            record(status, usage);
        }
        return reaped_;
    }

    // Polls `condition` every millisecond until it holds (true), the child exits or `timeout` passes (false).
    bool wait_until(const std::function<bool()>& condition, std::chrono::milliseconds timeout) {
        auto deadline = std::chrono::steady_clock::now() + timeout;
        while (std::chrono::steady_clock::now() < deadline) {
            if (has_exited()) {
                return false;
            }
            if (condition()) {
                return true;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        return false;
    }

    void send(int signal) const { ::kill(pid_, signal); }

    CommandResult wait() {
        if (!reaped_) {
            int status = 0;
            struct rusage usage {};
            pid_t result;
            do {
                result = ::wait4(pid_, &status, 0, &usage);
            } while (result < 0 && errno == EINTR);
            if (result == pid_) {
                record(status, usage);
            } else {
                reaped_ = true;
                exit_status_ = -1;
            }
        }
        std::string output;
        if (output_fd_ >= 0) {
            std::array<char, 4096> buffer{};
            ssize_t count;
            while ((count = ::read(output_fd_, buffer.data(), buffer.size())) > 0) {
                output.append(buffer.data(), static_cast<std::size_t>(count));
            }
            ::close(output_fd_);
            output_fd_ = -1;
            output_ = output;
        }
        return {exit_status_, output_};
    }

    // Valid once reaped: the child's peak resident memory, in bytes.
    long peak_memory_bytes() const { return peak_memory_kib_ * 1024; }

private:
    void record(int status, const struct rusage& usage) {
        reaped_ = true;
        exit_status_ = shell_status(status);
        peak_memory_kib_ = usage.ru_maxrss;
    }

    pid_t pid_ = -1;
    int output_fd_ = -1;
    bool reaped_ = false;
    int exit_status_ = -1;
    long peak_memory_kib_ = 0;
    std::string output_;
};

}  // namespace twinray::test
