// A program run in a process of its own, its standard output collected, stopped when it runs too long or
// says too much: how twinray reads mesh files without letting a library's crash or hang become its own
// (mesh_file.h). posix_spawn rather than fork: the new process starts clean, whatever threads, locks and
// memory the caller has.
#pragma once

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace twinray::scene {

struct ProcessOutcome {
    enum class End { exited, killed_by_signal, timed_out, too_much_output };
    End end = End::exited;
    int status = 0;      // the exit status, or the signal's number
    std::string output;  // all of its standard output (up to the limit)
    std::string errors;  // the beginning of its standard error, for messages
};

// Runs `program` with `arguments` (argv[1]...), standard input from /dev/null, in the caller's environment,
// and waits until it ends or `time_limit` has passed (then it is killed). Throws std::runtime_error when it
// cannot be started.
ProcessOutcome run_process(const std::filesystem::path& program, const std::vector<std::string>& arguments,
                           std::chrono::milliseconds time_limit, std::size_t max_output);

}  // namespace twinray::scene
