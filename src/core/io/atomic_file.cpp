#include "core/io/atomic_file.hpp"
#include "sdfgen/error.hpp"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fcntl.h>
#include <fstream>
#include <memory>
#include <mutex>
#include <streambuf>
#include <sys/stat.h>
#include <unistd.h>

namespace sdfgen {

namespace {

// Temporary files being written, for the signal handler. A fixed table of plain char arrays,
// because a handler may only touch async-signal-safe state (no allocation, no locks).
constexpr int kTempSlots = 64;
constexpr std::size_t kTempPathMax = 4096;
struct TempSlot {
    std::atomic<int> state{0}; // 0 free, 1 being filled, 2 holds a path to remove on a signal
    char path[kTempPathMax];
};
TempSlot gTempSlots[kTempSlots];

extern "C" void removeTempFilesAndDie(int signal) {
    for (TempSlot& slot : gTempSlots) {
        if (slot.state.load() == 2) unlink(slot.path);
    }
    // Terminate as the signal would have, so the parent sees the real cause (e.g. 130 for ^C).
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

void installSignalHandlers() {
    static std::once_flag once;
    std::call_once(once, [] {
        // SIGXFSZ: a write past the file-size limit (ulimit -f) kills the process the same way.
        for (int signal : {SIGINT, SIGTERM, SIGHUP, SIGXFSZ}) {
            struct sigaction current {};
            // Only a default action is replaced: an ignored SIGHUP (nohup) or a program's own
            // handler stays as it is.
            if (sigaction(signal, nullptr, &current) != 0 || (current.sa_flags & SA_SIGINFO) || current.sa_handler != SIG_DFL) {
                continue;
            }
            struct sigaction action {};
            action.sa_handler = removeTempFilesAndDie;
            sigemptyset(&action.sa_mask);
            sigaction(signal, &action, nullptr);
        }
    });
}

// Registers a temporary file for removal on a signal for as long as it lives.
class TempRegistration {
public:
    explicit TempRegistration(const std::string& path) {
        if (path.size() >= kTempPathMax) return;
        for (TempSlot& slot : gTempSlots) {
            int expected = 0;
            if (slot.state.compare_exchange_strong(expected, 1)) {
                std::memcpy(slot.path, path.c_str(), path.size() + 1);
                slot.state.store(2);
                slot_ = &slot;
                return;
            }
        }
    }
    ~TempRegistration() {
        if (slot_) slot_->state.store(0);
    }
    TempRegistration(const TempRegistration&) = delete;
    TempRegistration& operator=(const TempRegistration&) = delete;

private:
    TempSlot* slot_ = nullptr;
};

// An output stream buffer over a file descriptor that remembers the first write error.
class FdBuffer : public std::streambuf {
public:
    explicit FdBuffer(int fd) : fd_(fd) { setp(buffer_, buffer_ + sizeof(buffer_)); }
    int error() const { return error_; }

protected:
    int_type overflow(int_type ch) override {
        if (!flush()) return traits_type::eof();
        if (!traits_type::eq_int_type(ch, traits_type::eof())) {
            *pptr() = traits_type::to_char_type(ch);
            pbump(1);
        }
        return traits_type::not_eof(ch);
    }
    std::streamsize xsputn(const char* data, std::streamsize n) override {
        if (n <= epptr() - pptr()) {
            std::memcpy(pptr(), data, std::size_t(n));
            pbump(int(n));
            return n;
        }
        if (!flush() || !writeAll(data, std::size_t(n))) return 0;
        return n;
    }
    int sync() override { return flush() ? 0 : -1; }

private:
    bool flush() {
        const std::size_t n = std::size_t(pptr() - pbase());
        setp(buffer_, buffer_ + sizeof(buffer_));
        return writeAll(buffer_, n);
    }
    bool writeAll(const char* data, std::size_t n) {
        if (error_) return false;
        while (n > 0) {
            const ssize_t written = ::write(fd_, data, n);
            if (written < 0 && errno == EINTR) continue;
            if (written <= 0) {
                error_ = written < 0 ? errno : EIO;
                return false;
            }
            data += written;
            n -= std::size_t(written);
        }
        return true;
    }

    int fd_;
    int error_ = 0;
    char buffer_[1 << 16];
};

// The file a path finally names, following symbolic links (relative ones from their folder).
std::string resolveLinks(const std::string& path) {
    std::string current = path;
    for (int hops = 0; hops < 40; ++hops) {
        struct stat status {};
        if (lstat(current.c_str(), &status) != 0 || !S_ISLNK(status.st_mode)) return current;
        std::string target(std::size_t(status.st_size > 0 ? status.st_size : 4096) + 1, '\0');
        const ssize_t n = readlink(current.c_str(), target.data(), target.size());
        if (n < 0 || std::size_t(n) >= target.size()) throw Error(path + ": cannot read the symbolic link " + current);
        target.resize(std::size_t(n));
        if (target.front() != '/') {
            const std::size_t slash = current.rfind('/');
            if (slash != std::string::npos) target = current.substr(0, slash + 1) + target;
        }
        current = target;
    }
    throw Error(path + ": too many levels of symbolic links");
}

mode_t newFileMode() {
    // /proc/self/status reports the umask without changing it (umask() can only be read by setting it).
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("Umask:", 0) == 0) return mode_t(0666 & ~std::stoul(line.substr(6), nullptr, 8));
    }
    const mode_t mask = umask(022);
    umask(mask);
    return mode_t(0666 & ~mask);
}

std::string reason(int error) { return std::strerror(error); }

void writeStream(const std::string& path, int fd, const std::function<void(std::ostream&)>& write) {
    FdBuffer buffer(fd);
    std::ostream out(&buffer);
    write(out);
    out.flush();
    if (buffer.error() || !out) throw Error(path + ": write failed (" + reason(buffer.error() ? buffer.error() : EIO) + ")");
}

} // namespace

namespace {

// What a path finally names: the file to replace (links followed), and its status if it exists.
struct Target {
    std::string path;
    bool exists = false;
    struct stat status {};
    bool regular() const { return !exists || S_ISREG(status.st_mode); }
};

Target inspect(const std::string& path) {
    if (path.empty()) throw Error("the output path is empty");
    installSignalHandlers();
    Target target;
    // What is not a regular file is written through the path as given: /dev/stdout on a pipe
    // leads to /proc/self/fd/1, a link to "pipe:[N]", which names no file to resolve.
    struct stat status {};
    if (stat(path.c_str(), &status) == 0 && !S_ISREG(status.st_mode) && !S_ISDIR(status.st_mode)) {
        target.path = path;
        target.exists = true;
        target.status = status;
        return target;
    }
    target.path = resolveLinks(path);
    target.exists = stat(target.path.c_str(), &target.status) == 0;
    if (target.exists && S_ISDIR(target.status.st_mode)) throw Error(path + ": is a directory");
    return target;
}

// Gives the file the permissions the result must have: the old file's (and, as root, its owner),
// else the umask's default.
void applyMode(const std::string& path, int fd, const Target& target) {
    if (target.exists) {
        // chown first: it clears set-id bits. Not allowed unless root; then the writer owns it.
        if (fchown(fd, target.status.st_uid, target.status.st_gid) != 0) { /* keep the writer as owner */ }
        if (fchmod(fd, target.status.st_mode & 07777) != 0) throw Error(path + ": cannot set permissions (" + reason(errno) + ")");
    } else if (fchmod(fd, newFileMode()) != 0) {
        throw Error(path + ": cannot set permissions (" + reason(errno) + ")");
    }
}

// A suffix no other writer is using: the process id and 64 bits mixed from a clock and a counter.
std::string uniqueSuffix() {
    static std::atomic<std::uint64_t> counter{0};
    std::uint64_t x = std::uint64_t(std::chrono::steady_clock::now().time_since_epoch().count()) ^
                      (counter.fetch_add(1) * 0x9E3779B97F4A7C15ull);
    x ^= x >> 30; x *= 0xBF58476D1CE4E5B9ull; x ^= x >> 27; x *= 0x94D049BB133111EBull; x ^= x >> 31; // splitmix64
    char text[40];
    std::snprintf(text, sizeof(text), "%ld-%016llx", long(getpid()), static_cast<unsigned long long>(x));
    return text;
}

// The temporary's name for `target`: its name + ".tmp-" + `suffix`, the name cut short where the
// whole would exceed the longest file name (NAME_MAX, 255 bytes), so that every valid output name
// has a temporary.
std::string temporaryName(const std::string& target, const std::string& suffix) {
    const std::size_t slash = target.rfind('/');
    const std::size_t nameStart = slash == std::string::npos ? 0 : slash + 1;
    const std::string tail = ".tmp-" + suffix;
    std::size_t nameMax = 255;
    const long limit = pathconf(nameStart == 0 ? "." : target.substr(0, nameStart).c_str(), _PC_NAME_MAX);
    if (limit > 0) nameMax = std::size_t(limit);
    const std::size_t keep = nameMax > tail.size() ? nameMax - tail.size() : 1;
    return target.substr(0, nameStart) + target.substr(nameStart, keep) + tail;
}

// A temporary file beside the target, removed (and unregistered from the signal handler) when
// this goes out of scope before commit().
class Temporary {
public:
    // The name is registered with the signal handler before the file exists (O_EXCL), so a signal
    // landing at any moment after creation finds it; mkstemp would leave a window in between.
    Temporary(const std::string& path, const Target& target) : path_(path), target_(target) {
        for (int attempt = 0; fd_ < 0; ++attempt) {
            name_ = temporaryName(target.path, uniqueSuffix());
            registration_ = std::make_unique<TempRegistration>(name_);
            fd_ = ::open(name_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
            if (fd_ >= 0) break;
            const int error = errno;
            registration_.reset();
            if (error != EEXIST || attempt == 100) {
                throw Error(path + ": cannot create a temporary file beside it (" + reason(error) + ")");
            }
        }
    }
    ~Temporary() {
        if (fd_ >= 0) close(fd_);
        if (!committed_) unlink(name_.c_str());
    }
    Temporary(const Temporary&) = delete;
    Temporary& operator=(const Temporary&) = delete;

    int fd() const { return fd_; }
    const std::string& name() const { return name_; }
    void closeFd() {
        const int fd = fd_;
        fd_ = -1;
        if (close(fd) != 0) throw Error(path_ + ": write failed (" + reason(errno) + ")");
    }
    // fsync, close, rename over the target, then make the rename durable (a failure of that last
    // step cannot undo a complete, visible file).
    void commit() {
        if (fsync(fd_) != 0) throw Error(path_ + ": write failed (" + reason(errno) + ")");
        closeFd();
        if (std::rename(name_.c_str(), target_.path.c_str()) != 0) {
            throw Error(path_ + ": cannot replace the file (" + reason(errno) + ")");
        }
        committed_ = true;
        const std::size_t slash = target_.path.rfind('/');
        const std::string folder = slash == std::string::npos ? "." : slash == 0 ? "/" : target_.path.substr(0, slash);
        const int dir = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        if (dir >= 0) {
            fsync(dir);
            close(dir);
        }
    }
    // Reopens the temporary by name, for writers that were given the name and may have replaced it.
    void reopen() {
        fd_ = ::open(name_.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd_ < 0) throw Error(path_ + ": the writer left no file (" + reason(errno) + ")");
    }

private:
    const std::string& path_;
    const Target& target_;
    std::string name_;
    int fd_ = -1;
    bool committed_ = false;
    std::unique_ptr<TempRegistration> registration_;
};

} // namespace

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
    const Target target = inspect(path);
    if (!target.regular()) {
        const int fd = open(target.path.c_str(), O_WRONLY | O_CLOEXEC);
        if (fd < 0) throw Error(path + ": cannot open for writing (" + reason(errno) + ")");
        try {
            writeStream(path, fd, write);
        } catch (...) {
            close(fd);
            throw;
        }
        if (close(fd) != 0 && errno != EINTR) throw Error(path + ": write failed (" + reason(errno) + ")");
        return;
    }
    Temporary temporary(path, target);
    applyMode(path, temporary.fd(), target);
    writeStream(path, temporary.fd(), write);
    temporary.commit();
}

void writeFileAtomicallyAt(const std::string& path, const std::function<void(const std::string&)>& writeTo) {
    const Target target = inspect(path);
    if (!target.regular()) {
        writeTo(target.path);
        return;
    }
    Temporary temporary(path, target);
    temporary.closeFd();
    writeTo(temporary.name());
    temporary.reopen();
    applyMode(path, temporary.fd(), target); // again: the writer may have made a new file
    temporary.commit();
}

void refuseOverwritingInput(const std::string& output, const std::vector<std::string>& inputs) {
    struct stat outputStat{};
    const bool outputExists = ::stat(output.c_str(), &outputStat) == 0;
    for (const std::string& input : inputs) {
        if (input.empty()) continue;
        struct stat inputStat{};
        bool same;
        if (outputExists && ::stat(input.c_str(), &inputStat) == 0) {
            same = outputStat.st_dev == inputStat.st_dev && outputStat.st_ino == inputStat.st_ino;
        } else {
            std::error_code ec, ec2;
            const std::filesystem::path a = std::filesystem::weakly_canonical(output, ec), b = std::filesystem::weakly_canonical(input, ec2);
            same = !ec && !ec2 && a == b;
        }
        if (same) throw Error(output + ": is the input file " + input + "; refusing to overwrite it");
    }
}

} // namespace sdfgen
