// How twinray render fails: each failure a user can meet gives a clear message and a documented exit
// status, and never leaves a partial or corrupted image behind (docs/reliability.md lists them all).
// The real binary is run, killed and interrupted, as in tests/cli_test.cpp.
#include "run_twinray.h"
#include "sanitized_build.h"
#include "test_output.h"

#include <gtest/gtest.h>

#include <sys/mount.h>
#include <unistd.h>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace fs = std::filesystem;
using twinray::test::CommandResult;
using twinray::test::run_twinray;
using twinray::test::RunningTwinray;
using namespace std::chrono_literals;

// The exit statuses under test (src/cli/exit_codes.h, the README's table).
constexpr int usage_error = 1;
constexpr int invalid_scene = 2;
constexpr int output_error = 3;
constexpr int interrupted = 130;
constexpr int killed = 128 + SIGKILL;

std::string scene(const std::string& name) {
    return std::string(TWINRAY_SOURCE_DIR) + "/scenes/" + name;
}

std::string read_bytes(const fs::path& path) {
    std::ifstream stream(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}

class FailureTest : public ::testing::Test {
protected:
    void SetUp() override {
        folder_ = twinray::test::own_output_path("failure");
        ::umount2(folder_.c_str(), MNT_DETACH);  // a tmpfs left by an earlier run that was killed
        twinray::test::fresh_directory(folder_);
    }
    void TearDown() override {
        std::error_code ignored;
        fs::permissions(folder_, fs::perms::owner_all, fs::perm_options::add, ignored);
    }

    fs::path path(const std::string& name) const { return folder_ / name; }

    // An image already there, which a failed render must leave exactly as it was.
    std::string existing_image(const std::string& name) {
        CommandResult result = run_twinray("render " + scene("spheres.json") + " --width 24 -o " + path(name).string());
        EXPECT_EQ(result.exit_status, 0) << result.output;
        return read_bytes(path(name));
    }

    std::vector<std::string> files() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(folder_)) {
            names.push_back(entry.path().filename().string());
        }
        std::sort(names.begin(), names.end());
        return names;
    }

    fs::path folder_;
};

// Every write primitive in src/ and reference/ must sit in the atomic writer (src/io/atomic_file.cpp)
// or write the temporary file it hands out (src/image/image_file.cpp, called inside write_atomically).
// Anything else that creates a file bypasses temporary + rename and could leave half a file behind; a
// new one fails here until it goes through src/io/atomic_file.h or is allowed below with its reason.
TEST_F(FailureTest, EveryFileTwinrayWritesGoesThroughTheAtomicWriter) {
    const std::vector<std::pair<std::string, std::regex>> primitives = {
        {"std::ofstream / fstream", std::regex(R"(\bofstream\b|\bstd::fstream\b)")},
        {"fopen for writing", std::regex(R"(fopen\s*\([^;]*"[wa])")},
        {"OpenImageIO ImageOutput", std::regex(R"(ImageOutput::create)")},
        {"OpenImageIO ImageBuf::write",
         std::regex(R"(\bImageBuf\b[^;]*\.write\s*\(|\b\w+\s*\.\s*write\s*\(\s*[\w.]*(path|file|output))")},
        {"POSIX open/creat for writing", std::regex(R"(\bO_(CREAT|WRONLY|RDWR)\b|\bcreat\s*\()")},
        {"file copy or rename", std::regex(R"(\b(copy_file|rename)\s*\()")},
    };
    const std::map<std::string, std::vector<std::string>> allowed = {
        {"src/io/atomic_file.cpp", {"fopen for writing", "file copy or rename"}},
        {"src/image/image_file.cpp", {"fopen for writing"}},
        // POV-Ray's own inputs (the .pov text, an empty .ini) in a scratch folder (diff's povray_work/),
        // read back by POV-Ray at once: not an output a user keeps.
        {"src/pov/povray_runner.cpp", {"std::ofstream / fstream"}},
        // The whole-process bench sends its child processes' output to /dev/null: no file is written.
        {"src/cli/bench_process.cpp", {"POSIX open/creat for writing"}},
    };
    int files_read = 0;
    for (const char* top : {"src", "reference"}) {
        for (const auto& entry : fs::recursive_directory_iterator(fs::path(TWINRAY_SOURCE_DIR) / top)) {
            std::string extension = entry.path().extension().string();
            if (extension != ".cpp" && extension != ".h") {
                continue;
            }
            ++files_read;
            std::string relative = fs::relative(entry.path(), TWINRAY_SOURCE_DIR).generic_string();
            std::string text = read_bytes(entry.path());
            for (const auto& [what, pattern] : primitives) {
                if (!std::regex_search(text, pattern)) {
                    continue;
                }
                auto allowance = allowed.find(relative);
                bool ok = allowance != allowed.end() && std::find(allowance->second.begin(), allowance->second.end(),
                                                                  what) != allowance->second.end();
                EXPECT_TRUE(ok)
                    << relative << " uses " << what
                    << ": write through io::write_atomically / write_text_atomically (src/io/atomic_file.h) "
                       "or write_image, so that a failure never leaves a partial file";
            }
        }
    }
    EXPECT_GT(files_read, 10);
    // The two allowed writers do write through the temporary.
    EXPECT_NE(read_bytes(fs::path(TWINRAY_SOURCE_DIR) / "src/image/image_file.cpp").find("io::write_atomically"),
              std::string::npos);
}

TEST_F(FailureTest, RenderKilledMidwayLeavesTheExistingImageIntactAndNoTemporaryFile) {
    std::string before = existing_image("showcase.png");
    RunningTwinray render({"render", scene("showcase.json"), "--width", "3000", "--tracer", "reference", "--threads",
                           "2", "-o", path("showcase.png").string()});
    ASSERT_TRUE(render.started());
    // Rendering: the render command has begun (its SIGINT handler is in) and two workers are busy.
    ASSERT_TRUE(render.wait_until([&] { return render.catches_sigint() && render.running_threads() >= 2; }, 20s))
        << "the render never started: " << render.wait().output;
    std::this_thread::sleep_for(100ms);
    ASSERT_FALSE(render.has_exited()) << "the render should take a minute, not 0.1 s: " << render.wait().output;
    render.send(SIGKILL);
    EXPECT_EQ(render.wait().exit_status, killed);
    EXPECT_EQ(read_bytes(path("showcase.png")), before) << "the old image must be untouched";
    EXPECT_EQ(files(), std::vector<std::string>{"showcase.png"}) << "no temporary file may be left";
}

// Named for the threads so that `ctest --preset tsan` (tests with "Thread" in their name) runs it: under
// that preset twinray itself is built with ThreadSanitizer and the cancellation is checked for races.
class CtrlCTest : public FailureTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(CtrlCTest, StopsAllRenderThreadsWithinASecondWithStatus130AndWritesNothing) {
    std::string tracer = GetParam();
    // Long renders (seconds, minutes under sanitizers) whose items are short: SSE 16 x 16 tiles,
    // reference rows of 800 pixels.
    std::string width = tracer == "sse" ? "3000" : "800";
    std::string before = existing_image("showcase.png");
    RunningTwinray render({"render", scene("showcase.json"), "--width", width, "--tracer", tracer, "--threads", "2",
                           "-o", path("showcase.png").string()});
    ASSERT_TRUE(render.started());
    ASSERT_TRUE(render.wait_until([&] { return render.catches_sigint() && render.running_threads() >= 2; }, 20s))
        << "the render never started: " << render.wait().output;
    auto sent = std::chrono::steady_clock::now();
    render.send(SIGINT);
    CommandResult result = render.wait();
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
    EXPECT_EQ(result.exit_status, interrupted) << result.output;
    EXPECT_LT(seconds, 1.0) << "Ctrl-C must stop the render promptly";
    EXPECT_NE(result.output.find("interrupted"), std::string::npos) << result.output;
    EXPECT_EQ(read_bytes(path("showcase.png")), before) << "the old image must be untouched";
    EXPECT_EQ(files(), std::vector<std::string>{"showcase.png"}) << "no temporary file may be left";
}

INSTANTIATE_TEST_SUITE_P(Tracers, CtrlCTest, ::testing::Values("sse", "reference"),
                         [](const auto& param_info) { return std::string(param_info.param); });

TEST_F(FailureTest, OutputUnderAFileIsRefusedWithStatusThree) {
    // Root may write anywhere, but not below something that is not a folder (/dev/full/x.png alike).
    write_bytes(path("not_a_folder"), "x");
    CommandResult result =
        run_twinray("render " + scene("spheres.json") + " -o " + path("not_a_folder/s.png").string());
    EXPECT_EQ(result.exit_status, output_error) << result.output;
    EXPECT_NE(result.output.find("cannot write"), std::string::npos) << result.output;
    EXPECT_EQ(files(), std::vector<std::string>{"not_a_folder"});
}

TEST_F(FailureTest, FolderThatRefusesNewFilesFailsWithStatusThreeEvenForRoot) {
    // /proc is a folder that passes the writable check (access(W_OK) is true for root) but refuses to
    // create any file: this is the write itself failing, after the render, not the check before it.
    if (!fs::is_directory("/proc/self")) {
        GTEST_SKIP() << "no procfs at /proc";
    }
    CommandResult result =
        run_twinray("render " + scene("spheres.json") + " --width 16 -o /proc/twinray-failure-test.png");
    EXPECT_EQ(result.exit_status, output_error) << result.output;
    EXPECT_NE(result.output.find("cannot write /proc/twinray-failure-test.png"), std::string::npos) << result.output;
}

// Root may write into a mode 555 folder, so as root the folder is given to `nobody` and twinray runs as
// `nobody` (setpriv, util-linux): the folder's owner, refused only by its mode. The scene is copied
// into the folder, beside the build tree's binary, so only the build tree need be reachable by nobody.
TEST_F(FailureTest, ReadOnlyFolderIsRefusedWithStatusThree) {
    fs::copy_file(scene("spheres.json"), path("spheres.json"));
    std::string run_as;
    if (::geteuid() == 0) {
        run_as = "setpriv --reuid=65534 --regid=65534 --clear-groups";
        if (std::system((run_as + " test -x " + folder_.string()).c_str()) != 0) {
            GTEST_SKIP() << "running as root, and nobody cannot reach " << folder_.string()
                         << " (a private folder above the build tree?)";
        }
        constexpr uid_t nobody = 65534;
        ASSERT_EQ(::chown(folder_.c_str(), nobody, nobody), 0) << std::strerror(errno);
    }
    fs::permissions(folder_, fs::perms::owner_write | fs::perms::group_write | fs::perms::others_write,
                    fs::perm_options::remove);
    CommandResult result =
        run_twinray("render " + path("spheres.json").string() + " -o " + path("s.png").string(), run_as);
    EXPECT_EQ(result.exit_status, output_error) << result.output;
    EXPECT_NE(result.output.find("not writable"), std::string::npos) << result.output;
    EXPECT_EQ(files(), std::vector<std::string>{"spheres.json"}) << "nothing written beside the scene";
}

// A folder that may not be entered hides whether the output's folder exists: that is an output error
// (status 3, with the system's reason), not an internal one. As root, twinray runs as nobody.
TEST_F(FailureTest, OutputBelowAFolderThatMayNotBeEnteredIsRefusedWithStatusThree) {
    std::string run_as = ::geteuid() == 0 ? "setpriv --reuid=65534 --regid=65534 --clear-groups" : "";
    if (!run_as.empty() && std::system((run_as + " test -x " + folder_.string()).c_str()) != 0) {
        GTEST_SKIP() << "running as root, and nobody cannot reach " << folder_.string();
    }
    fs::create_directory(path("locked"));
    fs::permissions(path("locked"), fs::perms::none);
    fs::path output = path("locked") / "inner" / "x.png";
    CommandResult result = run_twinray("render " + scene("spheres.json") + " -o " + output.string(), run_as);
    fs::permissions(path("locked"), fs::perms::owner_all);
    EXPECT_EQ(result.exit_status, output_error) << result.output;
    EXPECT_NE(result.output.find("cannot be reached: Permission denied"), std::string::npos) << result.output;
}

TEST_F(FailureTest, MissingOrUnreadableSceneFailsWithStatusTwoAndKeepsTheOldImage) {
    std::string before = existing_image("out.png");
    CommandResult missing =
        run_twinray("render " + path("no_such_scene.json").string() + " -o " + path("out.png").string());
    EXPECT_EQ(missing.exit_status, invalid_scene) << missing.output;
    EXPECT_NE(missing.output.find("no_such_scene.json: cannot open file"), std::string::npos) << missing.output;
    CommandResult folder = run_twinray("render " + folder_.string() + " -o " + path("out.png").string());
    EXPECT_EQ(folder.exit_status, invalid_scene) << folder.output;
    EXPECT_NE(folder.output.find("cannot read file"), std::string::npos) << folder.output;
    EXPECT_EQ(read_bytes(path("out.png")), before);
    EXPECT_EQ(files(), std::vector<std::string>{"out.png"});
}

// A full disk, without privileges: RLIMIT_FSIZE (ulimit -f) makes every write past 1 KiB fail (EFBIG,
// with SIGXFSZ ignored), which is what a full disk does to a writer (ENOSPC) part-way through a file.
// The next test uses a real full filesystem where mounting one is allowed.
class DiskFullTest : public FailureTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(DiskFullTest, WriteFailingPartWayFailsWithStatusThreeAndKeepsTheOldImage) {
    std::string name = std::string("out") + GetParam();
    write_bytes(path(name), "the old image");
    RunningTwinray render({"render", scene("showcase.json"), "-o", path(name).string()}, {.file_size_bytes = 1024});
    CommandResult result = render.wait();
    EXPECT_EQ(result.exit_status, output_error) << result.output;
    EXPECT_NE(result.output.find("cannot write " + path(name).string()), std::string::npos) << result.output;
    if (std::string(GetParam()) == ".png") {
        // OpenEXR reports the failure in its own words; for PNG our check of the stream gives errno's.
        EXPECT_NE(result.output.find("File too large"), std::string::npos) << result.output;
    }
    EXPECT_EQ(read_bytes(path(name)), "the old image");
    EXPECT_EQ(files(), std::vector<std::string>{name}) << "the truncated temporary must be removed";
}

INSTANTIATE_TEST_SUITE_P(Formats, DiskFullTest, ::testing::Values(".png", ".exr"),
                         [](const auto& param_info) { return std::string(param_info.param + 1); });

TEST_F(FailureTest, FullFilesystemFailsWithStatusThreeAndKeepsTheOldImage) {
    // 16 KiB of tmpfs: room for the old image, not for showcase's 58 KB PNG.
    if (::mount("tmpfs", folder_.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, "size=16k,mode=0755") != 0) {
        GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno)
                     << "; needs CAP_SYS_ADMIN): DiskFullTest covers a write failing part-way";
    }
    struct Unmount {
        const fs::path& folder;
        ~Unmount() { ::umount2(folder.c_str(), MNT_DETACH); }
    } unmount{folder_};
    write_bytes(path("out.png"), "the old image");
    CommandResult result = run_twinray("render " + scene("showcase.json") + " -o " + path("out.png").string());
    EXPECT_EQ(result.exit_status, output_error) << result.output;
    EXPECT_NE(result.output.find("No space left on device"), std::string::npos) << result.output;
    EXPECT_EQ(read_bytes(path("out.png")), "the old image");
    EXPECT_EQ(files(), std::vector<std::string>{"out.png"});
}

// The format allows 16384 x 16384, but that image alone is 3 GiB of float pixels. render refuses more
// than 8192 x 8192 pixels (67108864) before allocating anything.
TEST_F(FailureTest, HugeImageIsRefusedBeforeAllocatingWithStatusOne) {
    RunningTwinray render(
        {"render", scene("spheres.json"), "--width", "16384", "--height", "16384", "-o", path("huge.png").string()});
    CommandResult result = render.wait();
    EXPECT_EQ(result.exit_status, usage_error) << result.output;
    EXPECT_NE(result.output.find("16384 x 16384"), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("limit of 67108864 (8192 x 8192"), std::string::npos) << result.output;
    // Had it allocated the image first, its peak memory would be 3 GiB.
    EXPECT_LT(render.peak_memory_bytes(), 1L << 30) << "refused only after allocating";
    EXPECT_TRUE(files().empty());
}

// The loader reserves its arrays of primitives for as many as the file's size could hold: a file of 2 GiB
// could hold 53 million, 5.8 GB of reserve. The reserve stops at the primitive limit (4194304, 450 MB), and
// where the parser stops before the end (here at the first zero byte after the scene, where the document
// ends) the text is read again only up to there for the error's wording, not all 2 GiB. So under a 1 GiB
// address space the scene renders (both used to fail with std::bad_alloc, an internal error, status 70).
// The zero bytes are a hole: the file takes no disk space.
TEST_F(FailureTest, AHugeSceneFileIsReadWithinTheMemoryOfASceneAtThePrimitiveLimit) {
#ifdef TWINRAY_SANITIZED_BUILD
    GTEST_SKIP() << "the sanitizers reserve terabytes of shadow memory: no address-space limit can hold";
#endif
    const fs::path huge = path("huge.json");
    write_bytes(huge, read_bytes(scene("spheres.json")));
    fs::resize_file(huge, std::uintmax_t{2} << 30);
    RunningTwinray render({"render", huge.string(), "--width", "32", "-o", path("huge.png").string()},
                          {.address_space_bytes = rlim_t{1} << 30});
    CommandResult result = render.wait();
    EXPECT_EQ(result.exit_status, 0) << result.output;
    EXPECT_TRUE(fs::exists(path("huge.png")));
    fs::remove(huge);
}

TEST_F(FailureTest, OnePixelRowPastTheLimitIsRefusedAndSoIsASceneThatAsksTooMuch) {
    CommandResult past =
        run_twinray("render " + scene("spheres.json") + " --width 8192 --height 8193 -o " + path("a.png").string());
    EXPECT_EQ(past.exit_status, usage_error) << past.output;
    EXPECT_NE(past.output.find("67117056 pixels"), std::string::npos) << past.output;
    // A scene may ask for 16384 x 16384 (the format allows it); render still refuses it.
    std::string text = read_bytes(scene("spheres.json"));
    text = std::regex_replace(text, std::regex(R"("image"\s*:\s*\{[^}]*\})"),
                              R"("image": { "width": 16384, "height": 16384 })");
    write_bytes(path("huge_scene.json"), text);
    CommandResult huge = run_twinray("render " + path("huge_scene.json").string() + " -o " + path("b.png").string());
    EXPECT_EQ(huge.exit_status, usage_error) << huge.output;
    EXPECT_NE(huge.output.find("16384 x 16384"), std::string::npos) << huge.output;
    EXPECT_EQ(files(), std::vector<std::string>{"huge_scene.json"});
}

TEST_F(FailureTest, DerivedSideBeyondTheFormatsLimitIsAUsageError) {
    // A tall scene: --width 8000 alone keeps the aspect ratio, so the height would be 32000.
    std::string text = read_bytes(scene("spheres.json"));
    text = std::regex_replace(text, std::regex(R"("image"\s*:\s*\{[^}]*\})"),
                              R"("image": { "width": 100, "height": 400 })");
    write_bytes(path("tall.json"), text);
    CommandResult result =
        run_twinray("render " + path("tall.json").string() + " --width 8000 -o " + path("t.png").string());
    EXPECT_EQ(result.exit_status, usage_error) << result.output;
    EXPECT_NE(result.output.find("height"), std::string::npos) << result.output;
    EXPECT_EQ(files(), std::vector<std::string>{"tall.json"});
}

}  // namespace
