// Issue 8: atomic writes (symlinks, modes, failures, signals, concurrent writers), reading any
// input (pipes, size limit, NULs), the OBJ pre-scan, the text format's reader and writer agreeing,
// the bake's memory estimate, and inside-out meshes against their analytic SDF.
#include "core/io/atomic_file.hpp"
#include "core/io/formats/format.hpp"
#include "core/mesh/input_file.hpp"
#include "core/bake/memory_estimate.hpp"
#include "core/runtime/memory.hpp"
#include "core/mesh/obj_scan.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/mesh.hpp"

#include "support/checks.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <thread>
#include <unistd.h>

namespace sdfgen {
namespace {

using test::errorFrom;
namespace fs = std::filesystem;

std::string readAll(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

unsigned modeOf(const fs::path& path) {
    struct stat status {};
    EXPECT_EQ(stat(path.c_str(), &status), 0);
    return unsigned(status.st_mode & 07777);
}

class AtomicFile : public test::ScratchFolderTest {
protected:
    // Files in the folder other than the given ones (left-over temporaries).
    std::vector<std::string> strays(const std::vector<std::string>& expected) {
        std::vector<std::string> found;
        std::error_code ec; // none when a death test's child removed its folder (parentsPath)
        for (const auto& entry : fs::directory_iterator(dir_, ec)) {
            const std::string name = entry.path().filename().string();
            if (std::find(expected.begin(), expected.end(), name) == expected.end()) found.push_back(name);
        }
        return found;
    }
    static auto text(const std::string& content) {
        return [content](std::ostream& out) { out << content; };
    }
};

TEST_F(AtomicFile, WritesAndReplacesLeavingNothingElse) {
    const std::string path = (dir_ / "f.txt").string();
    writeFileAtomically(path, text("first"));
    EXPECT_EQ(readAll(path), "first");
    writeFileAtomically(path, text(std::string(300000, 'x'))); // larger than the stream's buffer
    EXPECT_EQ(readAll(path), std::string(300000, 'x'));
    EXPECT_TRUE(strays({"f.txt"}).empty());
}

TEST_F(AtomicFile, FailingWriterKeepsTheOldFileAndRemovesTheTemporary) {
    const std::string path = write("f.txt", "old");
    const std::string message = errorFrom([&] {
        writeFileAtomically(path, [&](std::ostream& out) {
            out << std::string(200000, 'y');
            throw Error(path + ": encoding failed");
        });
    });
    EXPECT_CONTAINS(message, "encoding failed");
    EXPECT_EQ(readAll(path), "old");
    EXPECT_TRUE(strays({"f.txt"}).empty());
}

// A device of our own (as root), so that a regression replaces a scratch file, not the system's /dev/full.
TEST_F(AtomicFile, FullDeviceIsAnErrorAndStaysADevice) {
    const std::string full = (dir_ / "full").string();
    if (mknod(full.c_str(), S_IFCHR | 0666, makedev(1, 7)) != 0) GTEST_SKIP() << "cannot make a device node here";
    const std::string message = errorFrom([&] { writeFileAtomically(full, text(std::string(100000, 'z'))); });
    EXPECT_CONTAINS(message, full + ": write failed (No space left on device)");
    EXPECT_TRUE(fs::is_character_file(full));
}

TEST_F(AtomicFile, FifoIsWrittenInPlace) {
    const std::string fifo = (dir_ / "fifo").string();
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    std::string received;
    std::thread reader([&] { received = readAll(fifo); });
    writeFileAtomically(fifo, text("through the pipe"));
    reader.join();
    EXPECT_EQ(received, "through the pipe");
    EXPECT_TRUE(fs::is_fifo(fifo));
}

TEST_F(AtomicFile, MissingFolderIsAnError) {
    const std::string path = (dir_ / "no" / "f.txt").string();
    EXPECT_CONTAINS(errorFrom([&] { writeFileAtomically(path, text("x")); }), path + ": cannot create a temporary file");
    EXPECT_CONTAINS(errorFrom([&] { writeFileAtomically("", text("x")); }), "the output path is empty");
    EXPECT_CONTAINS(errorFrom([&] { writeFileAtomically(dir_.string(), text("x")); }), ": is a directory");
}

TEST_F(AtomicFile, WritesThroughSymbolicLinks) {
    fs::create_directory(dir_ / "sub");
    const std::string target = write("sub/target.txt", "old");
    fs::create_symlink("target.txt", dir_ / "sub" / "relative");  // relative to its own folder
    fs::create_symlink(dir_ / "sub" / "relative", dir_ / "chain"); // a link to a link
    writeFileAtomically((dir_ / "chain").string(), text("new"));
    EXPECT_TRUE(fs::is_symlink(dir_ / "chain"));
    EXPECT_TRUE(fs::is_symlink(dir_ / "sub" / "relative"));
    EXPECT_EQ(readAll(target), "new");
    // A dangling link gets its target created.
    fs::create_symlink("made.txt", dir_ / "dangling");
    writeFileAtomically((dir_ / "dangling").string(), text("made"));
    EXPECT_TRUE(fs::is_symlink(dir_ / "dangling"));
    EXPECT_EQ(readAll(dir_ / "made.txt"), "made");
}

TEST_F(AtomicFile, KeepsTheModeOfAnExistingFileAndUsesTheUmaskForANewOne) {
    for (const unsigned mode : {0600u, 0640u, 0755u, 0444u}) {
        const std::string path = write("f" + std::to_string(mode), "old");
        fs::permissions(path, fs::perms(mode));
        writeFileAtomically(path, text("new"));
        EXPECT_EQ(modeOf(path), mode);
        EXPECT_EQ(readAll(path), "new");
    }
    const mode_t previous = umask(027);
    writeFileAtomically((dir_ / "new027").string(), text("x"));
    umask(022);
    writeFileAtomically((dir_ / "new022").string(), text("x"));
    umask(previous);
    EXPECT_EQ(modeOf(dir_ / "new027"), 0640u);
    EXPECT_EQ(modeOf(dir_ / "new022"), 0644u);
}

TEST_F(AtomicFile, ConcurrentWritersLeaveOneCompleteFile) {
    const std::string path = (dir_ / "shared.txt").string();
    std::vector<std::thread> writers;
    for (char c = 'a'; c < 'e'; ++c) {
        writers.emplace_back([&, c] {
            for (int round = 0; round < 10; ++round) writeFileAtomically(path, text(std::string(100000, c)));
        });
    }
    for (std::thread& t : writers) t.join();
    const std::string content = readAll(path);
    ASSERT_EQ(content.size(), 100000u);
    EXPECT_EQ(content, std::string(100000, content[0]));
    EXPECT_TRUE(strays({"shared.txt"}).empty());
}

// For libraries that write to a path themselves, sometimes by making a new file there.
TEST_F(AtomicFile, PathWritersGetATemporaryAndTheSameGuarantees) {
    const std::string path = write("f.zip", "old");
    fs::permissions(path, fs::perms(0640));
    writeFileAtomicallyAt(path, [&](const std::string& temporary) {
        EXPECT_NE(temporary, path);
        const std::string own = temporary + ".lib";
        std::ofstream(own) << "new";
        fs::permissions(own, fs::perms(0600));
        fs::rename(own, temporary); // as libzip does
    });
    EXPECT_EQ(readAll(path), "new");
    EXPECT_EQ(modeOf(path), 0640u);
    EXPECT_CONTAINS(errorFrom([&] {
                        writeFileAtomicallyAt(path, [&](const std::string& temporary) {
                            std::ofstream(temporary) << "partial";
                            throw Error(path + ": library failed");
                        });
                    }),
                    "library failed");
    EXPECT_EQ(readAll(path), "new");
    EXPECT_TRUE(strays({"f.zip"}).empty());
}

// A signal while the temporary is being written: the process dies of that signal, the old file
// is intact and the temporary is gone.
// The path a death test's child is to write: the parent's. A "threadsafe" death test runs the
// whole test again in a new process, whose scratch folder is its own: without this, the child
// would write there and the parent would check a folder nothing was written to.
// The child's own folder is removed (it is killed before its TearDown).
std::string parentsPath(const std::string& path) {
    setenv("SDFGEN_TEST_PARENT_PATH", path.c_str(), /*overwrite=*/0); // the child inherits the parent's
    const std::string parents = std::getenv("SDFGEN_TEST_PARENT_PATH");
    if (parents != path) fs::remove_all(fs::path(path).parent_path());
    return parents;
}

TEST_F(AtomicFile, SignalsRemoveTheTemporary) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    const std::string path = parentsPath(write("f.txt", "old"));
    for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
        EXPECT_EXIT(
            {
                std::signal(signal, SIG_DFL);
                writeFileAtomically(path, [&](std::ostream& out) {
                    out << std::string(100000, 'p');
                    out.flush();
                    std::raise(signal);
                });
            },
            ::testing::KilledBySignal(signal), "");
        EXPECT_EQ(readAll(path), "old");
        EXPECT_TRUE(strays({"f.txt"}).empty()) << "signal " << signal;
    }
    unsetenv("SDFGEN_TEST_PARENT_PATH");
}

TEST_F(AtomicFile, PipeBehindAProcLinkIsWrittenDirectly) {
    // /dev/stdout on a pipe: /proc/self/fd/N, a link to "pipe:[...]" (not a path).
    for (const bool atPath : {false, true}) {
        int fds[2];
        ASSERT_EQ(pipe(fds), 0);
        const std::string path = "/proc/self/fd/" + std::to_string(fds[1]);
        if (atPath) writeFileAtomicallyAt(path, [](const std::string& at) { std::ofstream(at) << "through the pipe"; });
        else writeFileAtomically(path, text("through the pipe"));
        close(fds[1]);
        char buffer[64] = {};
        EXPECT_EQ(read(fds[0], buffer, sizeof buffer - 1), 16);
        EXPECT_STREQ(buffer, "through the pipe");
        close(fds[0]);
        EXPECT_TRUE(strays({}).empty());
    }
}

void limitFileSize(rlim_t bytes) {
    rlimit size{};
    size.rlim_cur = size.rlim_max = bytes;
    setrlimit(RLIMIT_FSIZE, &size);
    rlimit core{};
    setrlimit(RLIMIT_CORE, &core);
}

TEST_F(AtomicFile, FileSizeLimitRemovesTheTemporary) {
    // Killed by SIGXFSZ (ulimit -f) mid-write: the old file stays, and no temporary is left.
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    const std::string path = parentsPath(write("f.txt", "old"));
    EXPECT_EXIT(
        {
            std::signal(SIGXFSZ, SIG_DFL);
            limitFileSize(50000); // no core dump either (SIGXFSZ dumps core by default)
            writeFileAtomically(path, text(std::string(200000, 'p')));
        },
        ::testing::KilledBySignal(SIGXFSZ), "");
    EXPECT_EQ(readAll(path), "old");
    EXPECT_TRUE(strays({"f.txt"}).empty());
    unsetenv("SDFGEN_TEST_PARENT_PATH");
}

TEST_F(AtomicFile, NamesOfEveryValidLengthAreWritten) {
    // The temporary's name is cut short so that it fits where the target's name does.
    for (const std::size_t length : {200, 224, 240, 255}) {
        const std::string name = std::string(length - 4, 'n') + ".sdf";
        const std::string path = (dir_ / name).string();
        writeFileAtomically(path, text("x"));
        EXPECT_EQ(readAll(path), "x") << length;
        writeFileAtomicallyAt(path, [](const std::string& temporary) { std::ofstream(temporary) << "y"; });
        EXPECT_EQ(readAll(path), "y") << length;
        EXPECT_TRUE(strays({name}).empty()) << length;
        fs::remove(path);
    }
}

// ---- Out of memory ---------------------------------------------------------------------------

// The process's address space now (VmSize), in bytes.
rlim_t addressSpaceBytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmSize:", 0) == 0) return rlim_t(std::stoull(line.substr(7))) * 1024;
    }
    return 0;
}

class OutOfMemory : public test::ScratchFolderTest {};

TEST_F(OutOfMemory, ErrorsNameTheFile) {
    // An allocation that fails (the address space limited to 16 MiB more than is in use: the 64 MiB
    // files cannot be read) is an Error naming the file, not a bare std::bad_alloc.
#ifdef SDFGEN_TEST_ASAN
    GTEST_SKIP() << "AddressSanitizer's allocator aborts on a failed allocation instead of throwing std::bad_alloc "
                    "(allocator_may_return_null=0); the release build runs this test";
#endif
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    const std::string field = write("big.sdf", std::string(64 << 20, ' '));
    const std::string mesh = write("big.obj", std::string(64 << 20, ' '));
    const auto namesBoth = [&] {
        rlimit space{};
        space.rlim_cur = space.rlim_max = addressSpaceBytes() + (16 << 20);
        setrlimit(RLIMIT_AS, &space);
        const std::string a = errorFrom([&] { loadField(field); });
        const std::string b = errorFrom([&] { loadMesh(mesh); });
        std::fprintf(stderr, "%s\n%s\n", a.c_str(), b.c_str());
        fs::remove_all(dir_); // the child's own folder (it ends before its TearDown)
        return a == field + ": out of memory while reading it" && b == mesh + ": out of memory while reading it";
    };
    EXPECT_EXIT(std::_Exit(namesBoth() ? 0 : 1), ::testing::ExitedWithCode(0), "");
}

// ---- Reading input ------------------------------------------------------------------------------

class InputFile : public test::ScratchFolderTest {};

TEST_F(InputFile, ReadsAPipe) {
    int fds[2];
    ASSERT_EQ(pipe(fds), 0);
    const std::string data(300000, 'q');
    std::thread writer([&] {
        std::size_t done = 0;
        while (done < data.size()) {
            const ssize_t n = ::write(fds[1], data.data() + done, data.size() - done);
            if (n <= 0) break;
            done += std::size_t(n);
        }
        close(fds[1]);
    });
    const std::string read = readInputFile("/proc/self/fd/" + std::to_string(fds[0]), InputKind::Text);
    writer.join();
    close(fds[0]);
    EXPECT_EQ(read, data);
}

TEST_F(InputFile, SizeLimitIsAnErrorBeforeReading) {
    const std::string path = write("big.txt", std::string(3 << 20, 'a'));
    EXPECT_CONTAINS(errorFrom([&] { readInputFile(path, InputKind::Text, 2 << 20); }),
                    path + ": larger than the input limit of 2 MiB");
    EXPECT_EQ(readInputFile(path, InputKind::Text, 3 << 20).size(), std::size_t(3 << 20));
}

TEST_F(InputFile, SizeLimitOnAnEndlessDevice) {
    EXPECT_CONTAINS(errorFrom([&] { readInputFile("/dev/zero", InputKind::Binary, 1 << 20); }),
                    "/dev/zero: larger than the input limit of 1 MiB");
    EXPECT_CONTAINS(errorFrom([&] { readInputFile("/dev/zero", InputKind::Text); }), "/dev/zero:1: NUL byte");
}

TEST_F(InputFile, NulByteIsReportedWithItsLine) {
    const std::string path = write("nul.txt", std::string("a\nb\r\nc\rd \0 e\n", 13));
    EXPECT_CONTAINS(errorFrom([&] { readInputFile(path, InputKind::Text); }), path + ":4: NUL byte");
    EXPECT_EQ(readInputFile(path, InputKind::Binary).size(), 13u);
}

TEST_F(InputFile, DirectoryIsAnError) {
    EXPECT_CONTAINS(errorFrom([&] { readInputFile(dir_.string(), InputKind::Text); }), ": is a directory");
}

// ---- OBJ pre-scan -------------------------------------------------------------------------------

std::string scanError(const std::string& text) {
    return errorFrom([&] { scanObj("m.obj", text); });
}

TEST(ObjScan, RefusesWhatTinyobjloaderWouldMisread) {
    EXPECT_CONTAINS(scanError("v 0x1p0 0 0\n"), "m.obj:1: vertex coordinate '0x1p0' is not a decimal number");
    EXPECT_CONTAINS(scanError("v 0 0 0\nv 1 1.5f 0\n"), "m.obj:2: vertex coordinate '1.5f' is not a decimal number");
    EXPECT_CONTAINS(scanError("v 0 0 1e39\n"), "'1e39' is not a finite number");
    EXPECT_CONTAINS(scanError("v 0 0 -inf\n"), "'-inf' is not a finite number");
    EXPECT_CONTAINS(scanError("v 0 0\n"), "m.obj:1: vertex has fewer than 3 coordinates");
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    EXPECT_CONTAINS(scanError(tri + "f 2 3 4294967300\n"), "m.obj:4: face refers to vertex 4294967300");
    EXPECT_CONTAINS(scanError(tri + "f 1 2 99999999999999999999999\n"), "m.obj:4: face refers to vertex 99999999999999999999999");
    EXPECT_CONTAINS(scanError(tri + "f 1 2 4\n"), "m.obj:4: face refers to vertex 4 but the file has 3 vertices");
    EXPECT_CONTAINS(scanError(tri + "f -1 -2 -4\n"), "m.obj:4: face refers to vertex -4 but only 3 vertices precede it");
    EXPECT_CONTAINS(scanError(tri + "f 1 0 2\n"), "m.obj:4: face vertex index is zero");
    EXPECT_CONTAINS(scanError(tri + "f 1 2\n"), "m.obj:4: face has 2 vertices (a face needs at least 3)");
    EXPECT_CONTAINS(scanError(tri + "f\t1\n"), "m.obj:4: face has 1 vertex");
    EXPECT_CONTAINS(scanError(tri + "f 1 2 x\n"), "m.obj:4: face vertex 'x' is not a whole number");
    EXPECT_CONTAINS(scanError(tri + "f 1 2 3/a\n"), "m.obj:4: face vertex '3/a' is not of the form");
}

TEST(Printable, EscapesEveryByteThatIsNotValidUtf8) {
    // Valid sequences of 2, 3 and 4 bytes are kept.
    EXPECT_EQ(printable("caf\xC3\xA9 \xE4\xB8\xAD \xF0\x9F\x98\x80 \xF4\x8F\xBF\xBF"), "caf\xC3\xA9 \xE4\xB8\xAD \xF0\x9F\x98\x80 \xF4\x8F\xBF\xBF");
    // Overlong forms, surrogates, code points past U+10FFFF, stray and cut sequences: \xNN, byte by byte.
    EXPECT_EQ(printable("a\xC0\x80z"), "a\\xc0\\x80z");
    EXPECT_EQ(printable("\xC1\xBF"), "\\xc1\\xbf");
    EXPECT_EQ(printable("\xE0\x80\x80"), "\\xe0\\x80\\x80");
    EXPECT_EQ(printable("\xED\xA0\x80"), "\\xed\\xa0\\x80");
    EXPECT_EQ(printable("\xF0\x80\x80\x80"), "\\xf0\\x80\\x80\\x80");
    EXPECT_EQ(printable("\xF4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");
    EXPECT_EQ(printable("\xF5\x80\x80\x80"), "\\xf5\\x80\\x80\\x80");
    EXPECT_EQ(printable("\x80\xE4\xB8"), "\\x80\\xe4\\xb8");
}

TEST(ObjScan, QuotesTheFileThroughPrintable) {
    EXPECT_EQ(errorFrom([] { scanObj("m.obj", "v 0 0 \xC0\x80\n"); }), "m.obj:1: vertex coordinate '\\xc0\\x80' is not a decimal number");
    EXPECT_EQ(errorFrom([] { scanObj("m.obj", "v 0 0 0\nf 1 2 \xFF\n"); }), "m.obj:2: face vertex '\\xff' is not a whole number");
}

TEST(ObjScan, ReadsWhatIsValid) {
    const ObjScan scan = scanObj("m.obj", "# c\nv 0.1 +2 -3e-2\r\nvn 0 0 1\rv 1e-400 .5 7 1\nv 1 1 1\nf 1//1 2/1 -1\nl 1 2\nf 3 2 1 2\n");
    ASSERT_EQ(scan.vertices.size(), 3u);
    EXPECT_EQ(scan.vertices[0], glm::dvec3(0.1, 2.0, -0.03)); // exactly the doubles written
    EXPECT_EQ(scan.vertices[1], glm::dvec3(0.0, 0.5, 7.0));   // underflow reads as zero
    EXPECT_EQ(scan.faces, 2u);
    EXPECT_FALSE(scan.trianglesOnly); // a quad and a line: tinyobjloader reads the faces
    EXPECT_EQ(withoutByteOrderMark("\xEF\xBB\xBFv 1 2 3"), "v 1 2 3");
}

TEST(ObjScan, ReadsTrianglesAsTinyobjloaderDoes) {
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
    const ObjScan scan = scanObj("m.obj", tri + "f 1 2 3\nf -1 -2/5 -3//2\ng part\nf 4/1/1 1 2\nvn 0 0 1\n");
    EXPECT_TRUE(scan.trianglesOnly);
    EXPECT_EQ(scan.triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {3, 2, 1}, {3, 0, 1}}));
    // What tinyobjloader reads its own way (polygons it triangulates, lines and corners it may
    // refuse) is left to it.
    for (const char* rest : {"f 1 2 3 4\n", "l 1 2\n", "p 1\n", "vw 0 0 1\n", "f 1/- 2 3\n", "f 1/2/ 2 3\n",
                             "f 1/0 2 3\n", "f 1/2/3/4 2 3\n", "f 1/1234567890 2 3\n"}) {
        const ObjScan other = scanObj("m.obj", tri + "f 1 2 3\n" + rest);
        EXPECT_FALSE(other.trianglesOnly) << rest;
        EXPECT_TRUE(other.triangles.empty()) << rest;
    }
}

TEST(ObjScan, PiecesReadAsOnePass) {
    // Vertices, relative and forward indices, every line ending: the same scan, and the same first
    // problem at the same line, whatever the size of the pieces read in parallel.
    const std::string text = "# c\r\nv 0 0 0\nv 1 0 0\r\nv 0 1 0\rf 1 2 5\nv 0 0 1\n\nf -1 -2 -3\r\nv 2 2 2\nf -1 1 2\n";
    const ObjScan whole = scanObj("m.obj", text, text.size());
    ASSERT_EQ(whole.vertices.size(), 5u);
    EXPECT_EQ(whole.triangles, (std::vector<glm::uvec3>{{0, 1, 4}, {3, 2, 1}, {4, 0, 1}}));
    for (std::size_t piece : {1, 2, 3, 5, 8, 13}) {
        const ObjScan scan = scanObj("m.obj", text, piece);
        EXPECT_EQ(scan.vertices, whole.vertices) << piece;
        EXPECT_EQ(scan.triangles, whole.triangles) << piece;
        EXPECT_EQ(scan.faces, 3u) << piece;
        EXPECT_CONTAINS(errorFrom([&] { scanObj("m.obj", text + "v 1 x 0\nf 0 1 2\n", piece); }),
                        "m.obj:11: vertex coordinate 'x' is not a decimal number");
        EXPECT_CONTAINS(errorFrom([&] { scanObj("m.obj", text + "f -7 1 2\n", piece); }),
                        "m.obj:11: face refers to vertex -7 but only 5 vertices precede it");
        EXPECT_CONTAINS(errorFrom([&] { scanObj("m.obj", "f 1 2 9\n" + text, piece); }),
                        "m.obj:1: face refers to vertex 9 but the file has 5 vertices");
    }
}

class LoadObjHygiene : public test::ScratchFolderTest {};

TEST_F(LoadObjHygiene, ByteOrderMarkAndLoneCarriageReturns) {
    const Mesh bom = loadObj(write("bom.obj", "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    ASSERT_EQ(bom.positions.size(), 3u);
    EXPECT_EQ(bom.triangleCount(), 1u);
    // tinyobjloader ends a line at a lone \r too; the scan agrees with it.
    const Mesh cr = loadObj(write("cr.obj", "v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r"));
    EXPECT_EQ(cr.triangleCount(), 1u);
    EXPECT_EQ(cr.toWorld(glm::dvec3(cr.positions[1])), glm::dvec3(1, 0, 0));
}

TEST_F(LoadObjHygiene, NulInAFaceLineIsAnError) {
    const std::string path = write("nul.obj", std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 \0 2 3\n", 35));
    EXPECT_CONTAINS(errorFrom([&] { loadObj(path); }), path + ":4: NUL byte");
}

// ---- The text format: reader and writer agree ------------------------------------------------------

// What the writer would write, without its checks: how a file with these parts would look.
std::string rawField(const Field& f) {
    std::ostringstream out;
    out << "sdfgen-text 1\nsource " << f.source << "\ndims " << f.grid.dims.x << ' ' << f.grid.dims.y << ' '
        << f.grid.dims.z << "\norigin 0 0 0\nvoxel 1\nmethod " << f.method;
    for (const auto& [k, v] : f.parameters) out << ' ' << k << '=' << v;
    out << "\nvalues\n";
    for (float v : f.values) out << v << '\n';
    return out.str();
}

bool sameField(const Field& a, const Field& b) {
    return a.source == b.source && a.method == b.method && a.parameters == b.parameters && a.grid.dims == b.grid.dims &&
           a.grid.origin == b.grid.origin && a.grid.voxel == b.grid.voxel && a.values == b.values;
}

class FieldTextAgreement : public test::ScratchFolderTest {};

TEST_F(FieldTextAgreement, ByteOrderMarkIsSkipped) {
    Field field;
    field.source = "m.obj";
    field.method = "exact";
    field.grid.dims = {2, 1, 1};
    field.values = {-1.0f, 2.0f};
    const std::string path = (dir_ / "f.sdf").string();
    saveFieldText(field, path);
    const std::string marked = write("bom.sdf", "\xEF\xBB\xBF" + readAll(path));
    const Field read = loadFieldText(marked);
    EXPECT_EQ(read.values, field.values);
    EXPECT_EQ(read.source, "m.obj");
}

TEST_F(FieldTextAgreement, WhatOneAcceptsTheOtherDoes) {
    std::mt19937 random(8);
    const std::string pieces[] = {"a", "b", "x1", " ", "\t", "=", "\r", "\n", std::string(1, '\0'), "\xC3\xA9", "/", "-", ""};
    auto word = [&] {
        std::string s;
        const int n = int(random() % 4);
        for (int i = 0; i < n; ++i) s += pieces[random() % std::size(pieces)];
        return s;
    };
    int saved = 0, refused = 0, readBack = 0;
    for (int trial = 0; trial < 600; ++trial) {
        Field field;
        field.source = word();
        field.method = random() % 2 ? "exact" : word();
        for (int p = int(random() % 3); p > 0; --p) field.parameters.emplace_back(word(), word());
        field.grid.dims = {1 + int(random() % 2), 1, 1};
        field.grid.origin = glm::vec3(0.0f);
        field.grid.voxel = 1.0f;
        for (std::size_t i = 0; i < field.grid.sampleCount(); ++i) field.values.push_back(float(int(random() % 9)) - 4.0f);

        const std::string path = (dir_ / "f.sdf").string();
        bool writable = true;
        try {
            saveFieldText(field, path);
        } catch (const Error&) {
            writable = false;
        }
        if (writable) {
            ++saved;
            EXPECT_TRUE(sameField(loadFieldText(path), field)) << "round trip changed trial " << trial;
            continue;
        }
        ++refused;
        // The writer refused these parts; a file made of them either fails to load or reads as a
        // different field that the writer does write back unchanged.
        const std::string raw = write("raw.sdf", rawField(field));
        Field loaded;
        try {
            loaded = loadFieldText(raw);
        } catch (const Error&) {
            continue;
        }
        ++readBack;
        EXPECT_FALSE(sameField(loaded, field)) << "the reader accepted parts the writer refuses, trial " << trial;
        const std::string again = (dir_ / "again.sdf").string();
        EXPECT_NO_THROW(saveFieldText(loaded, again)) << "trial " << trial;
        EXPECT_TRUE(sameField(loadFieldText(again), loaded)) << "trial " << trial;
    }
    EXPECT_GT(saved, 40);
    EXPECT_GT(refused, 40);
    RecordProperty("read_back", readBack);
}

TEST_F(FieldTextAgreement, DeclaredSizeIsCheckedBeforeAllocating) {
    const std::string path = write("huge.sdf", "sdfgen-text 1\nsource a\ndims 500 500 400\norigin 0 0 0\nvoxel 1\nmethod exact\nvalues\n0\n1\n");
    EXPECT_CONTAINS(errorFrom([&] { loadFieldText(path); }), path + ":9: file ends after 2 of 100000000 values");
}

// ---- Memory estimate ----------------------------------------------------------------------------

TEST(BakeMemory, EstimateCountsEveryBufferOfTheMethodAndSign) {
    const Mesh mesh = test::icosphere(1.0f, 2);
    const Grid grid = makeGrid(mesh.worldBounds(), 40, 0.1f);
    const double samples = double(grid.sampleCount());
    auto perSample = [&](DistanceMethod method, SignMethod sign) {
        BakeSettings s;
        s.method = method;
        s.sign = sign;
        return double(estimateBakeBytes(mesh, grid, s)) / samples;
    };
    // Exact distances go straight into the field (result 4), signed there by the pseudonormal or
    // negated in place by the winding sign, which adds the topology and crossings.
    EXPECT_GE(perSample(DistanceMethod::Exact, SignMethod::Pseudonormal), 4.0);
    EXPECT_GT(perSample(DistanceMethod::Exact, SignMethod::Winding), 4.0);
    EXPECT_GE(perSample(DistanceMethod::Exact, SignMethod::Auto), perSample(DistanceMethod::Exact, SignMethod::Pseudonormal));
    EXPECT_GE(perSample(DistanceMethod::Exact, SignMethod::Auto), perSample(DistanceMethod::Exact, SignMethod::Winding));
    // The ray field is the result (4); with pseudonormal signs, plus the inside flags of a
    // closest-feature pass (1); exact distances signed by rays need a ray field beside them (4).
    EXPECT_GE(perSample(DistanceMethod::Rays, SignMethod::Rays), 4.0);
    EXPECT_GE(perSample(DistanceMethod::Rays, SignMethod::Pseudonormal), 5.0);
    EXPECT_GE(perSample(DistanceMethod::Exact, SignMethod::Rays), 8.0);
    EXPECT_GE(perSample(DistanceMethod::Brute, SignMethod::Winding), 4.0);
    EXPECT_LT(perSample(DistanceMethod::Exact, SignMethod::Auto), 12.0); // not wildly over: no per-sample side arrays
    EXPECT_GT(availableMemoryBytes(), 0u);
    // On a compute device: its host-side tables per triangle (its tree's triangles at least), and
    // for the winding sign the crossing counts and sides per sample (5 bytes).
    BakeSettings exact;
    exact.sign = SignMethod::Winding;
    const double cpu = double(estimateBakeBytes(mesh, grid, exact)), device = double(estimateBakeBytes(mesh, grid, exact, true));
    // (The CPU's estimate counts its closest-point tree, 130 bytes per triangle, which the device does without.)
    const double cpuTree = 130.0 * double(mesh.triangleCount());
    EXPECT_GE(device - cpu + cpuTree, std::max(144.0 * double(mesh.triangleCount()), 5.0 * samples));
    exact.sign = SignMethod::Pseudonormal;
    EXPECT_GE(double(estimateBakeBytes(mesh, grid, exact, true)) - double(estimateBakeBytes(mesh, grid, exact)),
              (144.0 + 2 * 168.0) * double(mesh.triangleCount()));
}

TEST(BakeMemory, GridBeyondAvailableMemoryIsRefusedWithTheFigure) {
    const Mesh mesh = test::box(glm::vec3(1.0f));
    BakeSettings settings;
    // The field's 4 bytes per sample fit in the physical memory; with the ray field that exact
    // distances signed by rays need beside it (4 more), they do not fit what is free.
    settings.sign = SignMethod::Rays;
    settings.res = int(std::cbrt(double(availableMemoryBytes()) / 6.0));
    settings.padding = 0.0f;
    const std::string message = errorFrom([&] { test::bakeMesh(mesh, settings); });
    EXPECT_CONTAINS(message, "needs about ");
    EXPECT_CONTAINS(message, " MiB of memory is available");
}

// ---- Inside-out meshes ----------------------------------------------------------------------------

Mesh flipped(const Mesh& mesh) {
    std::vector<glm::uvec3> triangles = mesh.triangles;
    for (glm::uvec3& t : triangles) std::swap(t[1], t[2]);
    return buildMesh(mesh.source + "-flipped", mesh.worldPositions(), std::move(triangles));
}

Mesh combined(const Mesh& a, const Mesh& b, const glm::vec3& offset) {
    std::vector<glm::dvec3> positions = a.worldPositions();
    std::vector<glm::uvec3> triangles = a.triangles;
    const unsigned base = unsigned(positions.size());
    for (const glm::dvec3& p : b.worldPositions()) positions.push_back(p + glm::dvec3(offset));
    for (const glm::uvec3& t : b.triangles) triangles.push_back(t + base);
    return buildMesh("two", std::move(positions), std::move(triangles));
}

// Counts samples whose sign disagrees with the analytic distance, away from the surface.
template <class Distance>
std::size_t wrongSigns(const Field& field, Distance&& truth, float margin) {
    std::size_t wrong = 0;
    const Grid& g = field.grid;
    for (int k = 0; k < g.dims.z; ++k)
        for (int j = 0; j < g.dims.y; ++j)
            for (int i = 0; i < g.dims.x; ++i) {
                const float d = truth(glm::vec3(g.position(i, j, k)));
                if (std::fabs(d) > margin && (d < 0.0f) != (field.at(i, j, k) < 0.0f)) ++wrong;
            }
    return wrong;
}

TEST(InsideOut, DetectedBySignedVolume) {
    const Mesh sphere = test::icosphere(1.0f, 3);
    BakeSettings settings;
    settings.res = 8;
    const BakeResult right = test::bakeMesh(sphere, settings);
    EXPECT_FALSE(right.check.insideOut);
    EXPECT_NEAR(right.check.signedVolume, 4.0 / 3.0 * M_PI, 0.1);
    const BakeResult wrong = test::bakeMesh(flipped(sphere), settings);
    EXPECT_TRUE(wrong.check.insideOut);
    EXPECT_NEAR(wrong.check.signedVolume, -4.0 / 3.0 * M_PI, 0.1);
    EXPECT_CONTAINS(wrong.check.describe(), "inside out");
    // An open mesh is never called inside out, whatever its orientation.
    std::vector<glm::uvec3> open = flipped(sphere).triangles;
    open.pop_back();
    EXPECT_FALSE(test::bakeMesh(buildMesh("open", sphere.positions, open), settings).check.insideOut);
}

TEST(InsideOut, AutoFixesTheSignsOfAFlippedSphereAndBox) {
    const float sag = test::icosphereSag(1.0f, 3);
    BakeSettings settings;
    settings.res = 24;
    const BakeResult sphere = test::bakeMesh(flipped(test::icosphere(1.0f, 3)), settings);
    EXPECT_EQ(sphere.sign, SignMethod::Pseudonormal);
    EXPECT_CONTAINS(sphere.signReason, "inside out");
    EXPECT_EQ(wrongSigns(sphere.field.dense(), [](glm::vec3 p) { return test::sphereDistance(p, 1.0f); }, sag + 1e-4f), 0u);

    const glm::vec3 half(0.5f, 0.3f, 0.2f);
    const BakeResult box = test::bakeMesh(flipped(test::box(half)), settings);
    EXPECT_TRUE(box.check.insideOut);
    EXPECT_EQ(wrongSigns(box.field.dense(), [&](glm::vec3 p) { return test::boxDistance(p, half); }, 1e-5f), 0u);
}

TEST(InsideOut, AutoFixesTheWindingSignToo) {
    // Two overlapping flipped spheres: closed and consistent but self-intersecting, so auto uses
    // the winding number (-2 in the overlap); the union is inside.
    const Mesh one = flipped(test::icosphere(1.0f, 3));
    const Mesh two = combined(one, one, glm::vec3(1.0f, 0.0f, 0.0f));
    const float sag = test::icosphereSag(1.0f, 3);
    BakeSettings settings;
    settings.res = 24;
    const BakeResult result = test::bakeMesh(two, settings);
    EXPECT_TRUE(result.check.insideOut);
    EXPECT_EQ(result.sign, SignMethod::Winding);
    EXPECT_CONTAINS(result.signReason, "inside out");
    auto unionDistance = [](glm::vec3 p) {
        return std::min(test::sphereDistance(p, 1.0f), test::sphereDistance(p - glm::vec3(1, 0, 0), 1.0f));
    };
    EXPECT_EQ(wrongSigns(result.field.dense(), unionDistance, sag + 1e-4f), 0u);
}

TEST(InsideOut, ExplicitPseudonormalFollowsTheFacesWithAWarning) {
    const float sag = test::icosphereSag(1.0f, 3);
    BakeSettings settings;
    settings.res = 16;
    settings.sign = SignMethod::Pseudonormal;
    const BakeResult result = test::bakeMesh(flipped(test::icosphere(1.0f, 3)), settings);
    ASSERT_EQ(result.warnings.size(), 1u);
    EXPECT_CONTAINS(result.warnings[0], "inside out");
    // Every sign inverted: negative outside.
    EXPECT_EQ(wrongSigns(result.field.dense(), [](glm::vec3 p) { return -test::sphereDistance(p, 1.0f); }, sag + 1e-4f), 0u);
}

TEST(InsideOut, ExplicitWindingSignNeedsNoFlip) {
    // The winding number is -1 inside and 0 outside: |w| > 1/2 is the sphere's inside, no warning.
    const float sag = test::icosphereSag(1.0f, 3);
    BakeSettings settings;
    settings.res = 16;
    settings.sign = SignMethod::Winding;
    const BakeResult result = test::bakeMesh(flipped(test::icosphere(1.0f, 3)), settings);
    EXPECT_TRUE(result.warnings.empty());
    EXPECT_EQ(wrongSigns(result.field.dense(), [](glm::vec3 p) { return test::sphereDistance(p, 1.0f); }, sag + 1e-4f), 0u);
    EXPECT_LT(*std::min_element(result.field.dense().values.begin(), result.field.dense().values.end()), 0.0f);
}

} // namespace
} // namespace sdfgen
