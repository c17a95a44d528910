#include "cli/conform_command.h"

#include "cli/exit_codes.h"
#include "io/atomic_file.h"
#include "plugin/conformance.h"
#include "plugin/direct_sse.h"
#include "plugin/plugin.h"
#include "scene/loader.h"

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace twinray::cli {
namespace {

struct ConformArguments {
    std::string plugin_path;  // or "sse"
    std::vector<std::string> scene_paths;
    int width = 64;
    int height = 48;
    int watertight_rays = 300;
    double time_limit = 60;
    std::string junit_path;
    std::vector<std::string> suites;  // empty: every suite
};

// --suite's names for the suites of plugin/conformance.h.
const std::map<std::string, std::string> suite_keys{{"hand-solved", "hand-solved"},
                                                    {"primary", "primary rays"},
                                                    {"far", "far from the origin"},
                                                    {"extremes", "extremes"},
                                                    {"watertight", "watertight"}};

// What became of work run in a child process.
struct ChildAnswer {
    enum class Ending { answered, crashed, hung, exited } ending = Ending::answered;
    std::string text;  // what the child wrote
    int code = 0;      // the signal it died of, or the status it exited with
};

// Runs `work` in a child process and returns the text it returns, read through a pipe; a child that dies of a
// signal, exits by itself (a plug-in calling exit) or answers nothing within `time_limit` seconds is reported as
// such (and killed if it hangs). The child leaves by _exit, running no destructor of the parent's state.
ChildAnswer in_child(const std::function<std::string()>& work, double time_limit) {
    int channel[2];
    if (pipe(channel) != 0) {
        throw std::runtime_error("cannot create a pipe for the child process");
    }
    std::fflush(nullptr);
    const pid_t child = fork();
    if (child < 0) {
        throw std::runtime_error("cannot start a child process");
    }
    if (child == 0) {
        close(channel[0]);
        // A crash of the plug-in's is its verdict: the child dies of the signal, whatever handler twinray's build
        // installed (a sanitizer's would turn it into an exit status).
        for (int fatal : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) {
            signal(fatal, SIG_DFL);
        }
        std::string text;
        try {
            text = work();
        } catch (const std::exception& error) {
            text = std::string("fail\t") + error.what();
        }
        text = "=" + text;  // the mark of an answer: a child that wrote nothing did not answer
        for (std::size_t written = 0; written < text.size();) {
            const ssize_t step = write(channel[1], text.data() + written, text.size() - written);
            if (step <= 0) {
                break;
            }
            written += static_cast<std::size_t>(step);
        }
        _exit(0);
    }
    close(channel[1]);
    ChildAnswer answer;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(time_limit);
    bool hung = false;
    for (;;) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) {
            hung = true;
            break;
        }
        pollfd readable{channel[0], POLLIN, 0};
        if (poll(&readable, 1, static_cast<int>(std::min<long long>(left.count(), 1000))) <= 0) {
            continue;
        }
        char buffer[4096];
        const ssize_t got = read(channel[0], buffer, sizeof buffer);
        if (got <= 0) {
            break;
        }
        answer.text.append(buffer, static_cast<std::size_t>(got));
    }
    close(channel[0]);
    if (hung) {
        kill(child, SIGKILL);
    }
    int status = 0;
    waitpid(child, &status, 0);
    if (hung) {
        answer.ending = ChildAnswer::Ending::hung;
    } else if (WIFSIGNALED(status)) {
        answer.ending = ChildAnswer::Ending::crashed;
        answer.code = WTERMSIG(status);
    } else if (answer.text.empty() || answer.text.front() != '=') {
        answer.ending = ChildAnswer::Ending::exited;
        answer.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    } else {
        answer.text.erase(0, 1);
    }
    return answer;
}

// `sse` names twinray's SSE tracer called directly; anything else is a plug-in's library.
std::unique_ptr<plugin::JudgedTracer> judged_tracer(const std::string& name) {
    if (name == "sse") {
        return std::make_unique<plugin::DirectSse>();
    }
    return std::make_unique<plugin::Plugin>(name);
}

std::string xml_escaped(const std::string& text) {
    std::string escaped;
    for (char c : text) {
        switch (c) {
            case '&': escaped += "&amp;"; break;
            case '<': escaped += "&lt;"; break;
            case '>': escaped += "&gt;"; break;
            case '"': escaped += "&quot;"; break;
            default: escaped += c;
        }
    }
    return escaped;
}

struct Judged {
    std::string suite, name;
    plugin::Verdict verdict;
    std::string detail;
    double seconds;
};

std::string junit_xml(const std::string& tracer, const std::vector<Judged>& judged) {
    std::vector<std::string> suites;
    for (const Judged& each : judged) {
        if (suites.empty() || suites.back() != each.suite) {
            suites.push_back(each.suite);
        }
    }
    std::ostringstream xml;
    xml << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"twinray conform " << xml_escaped(tracer)
        << "\">\n";
    for (const std::string& suite : suites) {
        int tests = 0, failures = 0, skipped = 0;
        for (const Judged& each : judged) {
            if (each.suite == suite) {
                ++tests;
                failures += each.verdict == plugin::Verdict::fail ? 1 : 0;
                skipped += each.verdict == plugin::Verdict::skipped ? 1 : 0;
            }
        }
        xml << "  <testsuite name=\"" << xml_escaped(suite) << "\" tests=\"" << tests << "\" failures=\"" << failures
            << "\" skipped=\"" << skipped << "\">\n";
        for (const Judged& each : judged) {
            if (each.suite != suite) {
                continue;
            }
            xml << "    <testcase classname=\"conform." << xml_escaped(suite) << "\" name=\"" << xml_escaped(each.name)
                << "\" time=\"" << each.seconds << "\">";
            if (each.verdict == plugin::Verdict::fail) {
                xml << "<failure message=\"" << xml_escaped(each.detail) << "\"/>";
            } else if (each.verdict == plugin::Verdict::skipped) {
                xml << "<skipped message=\"" << xml_escaped(each.detail) << "\"/>";
            } else {
                xml << "<system-out>" << plugin::verdict_name(each.verdict) << ": " << xml_escaped(each.detail)
                    << "</system-out>";
            }
            xml << "</testcase>\n";
        }
        xml << "  </testsuite>\n";
    }
    xml << "</testsuites>\n";
    return xml.str();
}

// A case's answer, "VERDICT\tDETAIL", or what became of the child.
std::pair<plugin::Verdict, std::string> verdict_of(const ChildAnswer& answer, double time_limit) {
    switch (answer.ending) {
        case ChildAnswer::Ending::hung: {
            char limit[32];
            std::snprintf(limit, sizeof limit, "%g", time_limit);
            return {plugin::Verdict::fail, std::string("the tracer gave no answer within ") + limit +
                                               " s (killed: it hangs, or is that slow)"};
        }
        case ChildAnswer::Ending::crashed:
            return {plugin::Verdict::fail, std::string("the tracer crashed (") + strsignal(answer.code) + ", signal " +
                                               std::to_string(answer.code) + ")"};
        case ChildAnswer::Ending::exited:
            return {plugin::Verdict::fail,
                    "the tracer ended the process (exit status " + std::to_string(answer.code) + ") before answering"};
        case ChildAnswer::Ending::answered: break;
    }
    const std::size_t tab = answer.text.find('\t');
    const std::string verdict = answer.text.substr(0, tab);
    const std::string detail = tab == std::string::npos ? "" : answer.text.substr(tab + 1);
    for (plugin::Verdict each :
         {plugin::Verdict::pass, plugin::Verdict::warn, plugin::Verdict::fail, plugin::Verdict::skipped}) {
        if (verdict == plugin::verdict_name(each)) {
            return {each, detail};
        }
    }
    return {plugin::Verdict::fail, "an answer twinray cannot read: " + answer.text};
}

int run_conform(const ConformArguments& arguments) {
    std::vector<plugin::NamedScene> scenes;
    if (arguments.scene_paths.empty()) {
        scenes = plugin::built_in_conformance_scenes();
    }
    for (const std::string& path : arguments.scene_paths) {
        try {
            scenes.push_back({path, scene::load_scene(path)});
        } catch (const scene::SceneError& error) {
            std::cerr << "twinray conform: invalid scene: " << error.what() << "\n";
            return exit_invalid_scene;
        }
    }
    const std::string& path = arguments.plugin_path;
    const ChildAnswer described = in_child(
        [&] {
            try {
                return "pass\t" + judged_tracer(path)->description();
            } catch (const std::runtime_error& unusable) {
                return std::string("fail\t") + unusable.what();
            }
        },
        arguments.time_limit);
    const auto [loadable, description] = verdict_of(described, arguments.time_limit);
    if (loadable != plugin::Verdict::pass) {
        std::cerr << "twinray conform: " << description << "\n";
        return exit_plugin_unusable;
    }
    std::printf("tracer:  %s\nlibrary: %s\n", description.c_str(), path == "sse" ? "(built in)" : path.c_str());
    std::printf(
        "hand-solved rays: t, point and normal within %g unit roundoffs times the size scale %g, else fail (warn on a "
        "rule of twinray's own); "
        "primary rays at %d x %d; thresholds: t error within %g unit roundoffs of |o|+t passes, within %g "
        "warns; any disagreement warns, more than %g of the rays fails; every case in a child process, at "
        "most %g s each\n\n",
        plugin::ieee_roundings, plugin::hand_solved_size_scale, arguments.width, arguments.height, plugin::t_error_pass,
        plugin::t_error_warn, plugin::disagreement_warn, arguments.time_limit);
    std::vector<Judged> judged;
    std::map<plugin::Verdict, int> counts;
    std::string suite;
    for (const plugin::ConformCase& conform_case :
         plugin::conformance_cases(scenes, arguments.width, arguments.height, arguments.watertight_rays)) {
        if (!arguments.suites.empty() &&
            std::none_of(arguments.suites.begin(), arguments.suites.end(),
                         [&](const std::string& key) { return suite_keys.at(key) == conform_case.suite; })) {
            continue;
        }
        if (conform_case.suite != suite) {
            suite = conform_case.suite;
            std::printf("%s%s\n", judged.empty() ? "" : "\n", suite.c_str());
        }
        const auto start = std::chrono::steady_clock::now();
        const ChildAnswer answer = in_child(
            [&] {
                try {
                    const plugin::CaseResult result = conform_case.run(*judged_tracer(path));
                    return std::string(plugin::verdict_name(result.verdict)) + "\t" + result.detail;
                } catch (const plugin::UnsupportedKind& refusal) {
                    return std::string("skipped\t") + refusal.what();
                } catch (const plugin::PluginUnusable& unusable) {
                    return std::string("fail\t") + unusable.what();
                } catch (const plugin::PluginFault& fault) {
                    return std::string("fail\t") + fault.what();
                }
            },
            arguments.time_limit);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const auto [verdict, detail] = verdict_of(answer, arguments.time_limit);
        std::printf("  %-7s %s: %s\n", plugin::verdict_name(verdict), conform_case.name.c_str(), detail.c_str());
        std::fflush(stdout);
        judged.push_back({conform_case.suite, conform_case.name, verdict, detail, seconds});
        ++counts[verdict];
    }
    std::printf("\n%d pass, %d warn, %d fail, %d skipped\n", counts[plugin::Verdict::pass],
                counts[plugin::Verdict::warn], counts[plugin::Verdict::fail], counts[plugin::Verdict::skipped]);
    if (!arguments.junit_path.empty()) {
        try {
            io::write_text_atomically(arguments.junit_path, junit_xml(description, judged));
        } catch (const std::exception& error) {
            std::cerr << "twinray conform: " << error.what() << "\n";
            return exit_output_error;
        }
    }
    return counts[plugin::Verdict::fail] == 0 ? exit_success : exit_conformance_failed;
}

}  // namespace

void add_conform_command(CLI::App& app, std::function<int()>& run) {
    auto arguments = std::make_shared<ConformArguments>();
    CLI::App* command = app.add_subcommand(
        "conform",
        "Judge a tracer behind the tracer ABI (docs/plugins.md), or with `sse` twinray's own SSE tracer called "
        "directly, ray by ray: the hand-solved expectations, then against the double-precision oracle the "
        "primary rays of each scene (a built-in pair without any), the same moved far from the origin, and the "
        "watertightness rays (exit 0: no case failed; 10: some did; 7: the plug-in cannot be used)");
    command->add_option("tracer", arguments->plugin_path, "The tracer's shared library, or sse")->required();
    command->add_option("scenes", arguments->scene_paths,
                        "Scene files (default: 300 spheres and a tessellated sphere)");
    command->add_option("--width", arguments->width, "Primary rays per row")
        ->check(CLI::Range(1, 4096))
        ->capture_default_str();
    command->add_option("--height", arguments->height, "Rows of primary rays")
        ->check(CLI::Range(1, 4096))
        ->capture_default_str();
    command
        ->add_option("--watertight-rays", arguments->watertight_rays,
                     "Watertightness rays per family, distance and size")
        ->check(CLI::Range(1, 1'000'000))
        ->capture_default_str();
    command
        ->add_option("--time-limit", arguments->time_limit,
                     "Seconds each case may take before the tracer is called hung")
        ->check(CLI::Range(0.1, 86400.0))
        ->capture_default_str();
    command
        ->add_option("--suite", arguments->suites,
                     "Only these suites: hand-solved, primary, far, extremes, watertight (repeatable)")
        ->check(CLI::IsMember({"hand-solved", "primary", "far", "extremes", "watertight"}));
    command->add_option("--junit", arguments->junit_path, "Also write the verdicts as JUnit XML here (atomically)");
    command->callback([arguments, &run] { run = [arguments] { return run_conform(*arguments); }; });
}

}  // namespace twinray::cli
