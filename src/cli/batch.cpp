// `sdfgen batch`: many meshes, one output each, resumable, sharded across machines. Each mesh is
// baked in a child process (fork) so that a timeout, a memory budget or a crash ends that mesh
// only; the parent schedules, records and summarises.
#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "cli/batch_plan.hpp"
#include "sdfgen/memory.hpp"
#include "sdfgen/device.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/model.hpp"
#include "sdfgen/sample.hpp"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <fcntl.h>
#include <map>
#include <memory>
#include <mutex>
#include <new>
#include <poll.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace sdfgen::cli {

namespace fs = std::filesystem;

namespace {

struct BatchArgs {
    std::string input;
    std::string outDir;
    std::string format = "npz";
    BakeSettings settings;
    SampleSettings sampling;
    std::size_t samples = 500000;
    int threads = 0;
    int jobs = 1;
    double timeout = 0;     // seconds per mesh, 0 = none
    double memoryMiB = 0;   // address-space budget per mesh, 0 = physical memory / jobs
    bool force = false;
    std::string status;     // JSON lines file; "{shard}" becomes the shard index
    std::string shard;
    int shardCount = 0;
};

// What a finished mesh reports to the status file and the summary.
struct Outcome {
    batch::Task task;
    std::string status; // done, skipped, failed
    double seconds = 0;
    std::string error;
    std::string details; // JSON members from the child: grid, sign, triangles, device
    std::string device;  // where it was baked, briefly: "cpu" or "gpu RENDERER"
    std::vector<std::string> warnings; // from the mesh's load and its bake, one line each
};

const std::map<std::string, std::string> formatExtensions = {
    {"npz", ".npz"}, {"npy", ".npy"}, {"vdb", ".vdb"}, {"sdf", ".sdf"}, {"nrrd", ".nrrd"}, {"samples", ".npz"}};

std::string hostName() {
    char name[256] = {};
    gethostname(name, sizeof(name) - 1);
    return name;
}

// CPUs this process may run on (Slurm and containers restrict the affinity mask, not the core count).
int availableCpus() {
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof(set), &set) == 0) return std::max(1, CPU_COUNT(&set));
    return int(std::max(1u, std::thread::hardware_concurrency()));
}

std::string jsonNumber(double value) {
    char text[40];
    std::snprintf(text, sizeof(text), "%.17g", value);
    return text;
}

std::string secondsText(double seconds) {
    char text[40];
    std::snprintf(text, sizeof(text), "%g s", seconds);
    return text;
}

// The partial file a child writes before renaming it into place. Hidden, with this host and the
// child's pid, so that a later run on this host can remove what a killed child left behind.
std::string partialPrefix(const fs::path& output, const std::string& host) {
    return "." + output.filename().string() + ".partial-" + host + "-";
}

// Whether process `pid` still runs: it exists and is not a zombie (a killed child whose parent
// died too stays one until init reaps it, which a rerun started at once can beat).
bool running(pid_t pid) {
    if (!(kill(pid, 0) == 0 || errno == EPERM)) return false;
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string line;
    if (!std::getline(stat, line)) return true; // no /proc: trust kill()
    const std::size_t end = line.rfind(')'); // "pid (name) state ...": the name may hold anything
    return end == std::string::npos || end + 2 >= line.size() || line[end + 2] != 'Z';
}

// Removes partial files that children on this host left when they were killed, in the folders of
// this shard's outputs. A partial whose child still runs (another batch on this host) is kept.
void removeStalePartials(const std::vector<batch::Task>& tasks, const std::string& host) {
    std::map<fs::path, std::vector<std::string>> prefixes;
    for (const batch::Task& task : tasks) prefixes[fs::path(task.output).parent_path()].push_back(partialPrefix(task.output, host));
    for (auto& [folder, names] : prefixes) {
        std::sort(names.begin(), names.end());
        std::error_code ec;
        for (fs::directory_iterator it(folder.empty() ? fs::path(".") : folder, ec), end; !ec && it != end; it.increment(ec)) {
            const std::string name = it->path().filename().string();
            auto candidate = std::upper_bound(names.begin(), names.end(), name);
            if (candidate == names.begin()) continue;
            const std::string& prefix = *--candidate;
            if (name.compare(0, prefix.size(), prefix) != 0) continue;
            const pid_t pid = pid_t(std::atol(name.c_str() + prefix.size()));
            if (pid > 0 && running(pid)) continue;
            fs::remove(it->path(), ec);
        }
    }
}

// ---- The child: bakes one mesh and reports on a pipe. ----

// Raises `cancel` when the deadline passes (the cooperative stop; the parent kills later if a
// phase does not check the flag).
void cancelAt(std::chrono::steady_clock::time_point deadline, std::atomic<bool>& cancel) {
    std::thread([deadline, &cancel] {
        std::this_thread::sleep_until(deadline);
        cancel = true;
    }).detach();
}

// Where a bake ran, in a few words for the status lines: "cpu", or the device's name and its
// renderer ("gpu llvmpipe (...)").
std::string deviceUsed(const BakeResult& result, const std::string& asked) {
    if (!result.onDevice) return "cpu";
    std::string why;
    const ComputeDevice* device = selectComputeDevice(asked, &why);
    return why.substr(0, why.find(':')) + " " + device->renderer(); // why starts with the device's name
}

// Bakes one mesh into its output; returns the status line's JSON members, sets `device` and adds
// the warnings of the load and the bake to `warnings` as they arise (kept when the bake fails).
std::string bakeOne(const batch::Task& task, const BatchArgs& args, int threads, const std::atomic<bool>& cancel, std::string& device,
                    std::vector<std::string>& warnings) {
    refuseOverwritingInput(task.output, {task.mesh});
    RunControl control;
    control.threads = threads;
    control.cancel = &cancel;
    control.warn = [&warnings](const std::string& warning) { warnings.push_back(warning); };
    const Model model = Model::load(task.mesh, control);
    const Mesh& mesh = model.mesh();
    std::string details = "\"triangles\":" + std::to_string(mesh.triangleCount());

    fs::create_directories(fs::path(task.output).parent_path().empty() ? fs::path(".") : fs::path(task.output).parent_path());
    const fs::path output(task.output);
    const fs::path partial = output.parent_path() / (partialPrefix(output, hostName()) + std::to_string(getpid()) + output.extension().string());
    if (args.format == "samples") {
        SampleSettings sampling = args.sampling;
        sampling.padding = args.settings.padding;
        const Samples samples = sampleSdf(model, args.samples, sampling, control);
        saveSamples(samples, partial.string());
        details += ",\"samples\":" + std::to_string(samples.size()) + ",\"seed\":" + std::to_string(sampling.seed) +
                   ",\"dims\":null,\"origin\":null,\"voxel\":null,\"sign\":null,\"sign_reason\":null";
        device = "cpu"; // point queries
    } else {
        BakeResult result = model.bake(args.settings, control);
        // A band bake's field is sparse: .vdb and .npz keep it so, the dense formats get its dense
        // form where it fits; the save gives its bricks up.
        const Grid g = result.field.header().grid;
        const std::string sign = result.field.header().parameter("sign");
        try {
            saveAnyField(std::move(result.field), partial.string());
        } catch (const Error& e) {
            // The writer names the hidden partial file; the user named the output.
            std::string message = e.what();
            for (std::size_t at; (at = message.find(partial.string())) != std::string::npos;) message.replace(at, partial.string().size(), task.output);
            throw Error(message);
        }
        details += ",\"dims\":[" + std::to_string(g.dims.x) + "," + std::to_string(g.dims.y) + "," + std::to_string(g.dims.z) +
                   "],\"origin\":[" + jsonNumber(g.origin.x) + "," + jsonNumber(g.origin.y) + "," + jsonNumber(g.origin.z) +
                   "],\"voxel\":" + jsonNumber(g.voxel) + ",\"sign\":" + batch::jsonString(sign) +
                   ",\"sign_reason\":" + (result.signReason.empty() ? "null" : batch::jsonString(result.signReason));
        device = deviceUsed(result, args.settings.device);
    }
    details += ",\"device\":" + batch::jsonString(device);
    // The rename is what makes the output complete: a resumed batch skips exactly the renamed ones.
    if (std::rename(partial.c_str(), output.c_str()) != 0) {
        const std::string why = std::strerror(errno);
        fs::remove(partial);
        throw Error(task.output + ": cannot rename the finished file into place: " + why);
    }
    return details;
}

// The report's warning lines: "warning:TEXT\n" each, TEXT on one line.
std::string warningLines(const std::vector<std::string>& warnings) {
    std::string lines;
    for (std::string warning : warnings) {
        std::replace_if(warning.begin(), warning.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
        lines += "warning:" + warning + "\n";
    }
    return lines;
}

// The budget counts from the size the process already has (the program and its libraries).
void limitAddressSpace(double budgetMiB) {
    std::ifstream statm("/proc/self/statm");
    std::uint64_t pages = 0;
    statm >> pages;
    const rlim_t bytes = rlim_t(double(pages) * double(sysconf(_SC_PAGESIZE)) + budgetMiB * 1024.0 * 1024.0);
    const rlimit limit{bytes, bytes};
    setrlimit(RLIMIT_AS, &limit);
}

[[noreturn]] void runChild(const batch::Task& task, const BatchArgs& args, int threads, double memoryMiB, int reportFd) {
    static std::atomic<bool> cancel{false};
    std::string report;
    std::vector<std::string> warnings;
    int code = 0;
    try {
        if (memoryMiB > 0) limitAddressSpace(memoryMiB);
        if (args.timeout > 0) {
            cancelAt(std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                           std::chrono::duration<double>(args.timeout)),
                     cancel);
        }
        std::string device;
        const std::string details = bakeOne(task, args, threads, cancel, device, warnings);
        report = "ok\n" + device + "\n" + warningLines(warnings) + details;
    } catch (const Cancelled&) {
        report = "failed\ntimed out after " + secondsText(args.timeout) + "\n" + warningLines(warnings);
        code = 1;
    } catch (const std::bad_alloc&) {
        report = "failed\nout of memory: over the budget of " + std::to_string(std::llround(memoryMiB)) + " MiB (--memory)\n" +
                 warningLines(warnings);
        code = 1;
    } catch (const OutOfMemoryError& e) { // the file named
        report = std::string("failed\n") + e.what() + ": over the budget of " + std::to_string(std::llround(memoryMiB)) +
                 " MiB (--memory)\n" + warningLines(warnings);
        code = 1;
    } catch (const Error& e) {
        report = std::string("failed\n") + e.what() + "\n" + warningLines(warnings);
        code = 1;
    } catch (const std::exception& e) {
        report = std::string("failed\ninternal error: ") + e.what() + "\n" + warningLines(warnings);
        code = 1;
    } catch (...) {
        report = "failed\ninternal error: an unknown exception\n"; // the child must never return into the parent's code
        code = 1;
    }
    for (std::size_t done = 0; done < report.size();) {
        const ssize_t n = ::write(reportFd, report.data() + done, report.size() - done);
        if (n <= 0 && errno != EINTR) break;
        if (n > 0) done += std::size_t(n);
    }
    _exit(code); // no atexit handlers or static destructors of the parent's copy
}

// ---- The parent: schedules children, records outcomes. ----

struct Running {
    batch::Task task;
    pid_t pid;
    int fd;
    std::string report;
    Stopwatch clock;
    bool killed = false;
};

class Scheduler {
public:
    Scheduler(const BatchArgs& args, int threadsPerJob, double memoryMiB)
        : args_(args), threadsPerJob_(threadsPerJob), memoryMiB_(memoryMiB) {}

    void start(const batch::Task& task) {
        int fds[2];
        if (pipe2(fds, O_CLOEXEC) != 0) throw Error(std::string("cannot create a pipe: ") + std::strerror(errno));
        std::fflush(nullptr); // the child must not flush the parent's buffered output again
        const pid_t pid = fork();
        if (pid < 0) throw Error(std::string("cannot start a process: ") + std::strerror(errno));
        if (pid == 0) {
            ::close(fds[0]);
            runChild(task, args_, threadsPerJob_, memoryMiB_, fds[1]);
        }
        ::close(fds[1]);
        running_.push_back({task, pid, fds[0], {}, {}, false});
    }

    std::size_t runningCount() const { return running_.size(); }

    // Waits until at least one child has finished (or 100 ms passed); returns the finished ones.
    std::vector<Outcome> wait() {
        std::vector<pollfd> fds;
        for (const Running& r : running_) fds.push_back({r.fd, POLLIN, 0});
        poll(fds.data(), fds.size(), 100);
        std::vector<Outcome> finished;
        for (auto it = running_.begin(); it != running_.end();) {
            drain(*it);
            if (args_.timeout > 0 && !it->killed && it->clock.seconds() > args_.timeout + killGraceSeconds()) {
                kill(it->pid, SIGKILL); // a phase ignored the cancel flag
                it->killed = true;
            }
            int status = 0;
            const pid_t done = waitpid(it->pid, &status, WNOHANG);
            if (done == it->pid) {
                drain(*it);
                ::close(it->fd);
                finished.push_back(outcomeOf(*it, status));
                it = running_.erase(it);
            } else {
                ++it;
            }
        }
        return finished;
    }

private:
    // Time a child gets to notice its cancel flag before it is killed.
    double killGraceSeconds() const { return 2.0 + 0.1 * args_.timeout; }

    static void drain(Running& r) {
        char buffer[4096];
        for (;;) {
            pollfd p{r.fd, POLLIN, 0};
            if (poll(&p, 1, 0) <= 0 || !(p.revents & (POLLIN | POLLHUP))) return;
            const ssize_t n = ::read(r.fd, buffer, sizeof(buffer));
            if (n <= 0) return;
            r.report.append(buffer, std::size_t(n));
        }
    }

    Outcome outcomeOf(const Running& r, int status) const {
        Outcome outcome;
        outcome.task = r.task;
        outcome.seconds = r.clock.seconds();
        // The report: "ok" or "failed", the device or the error, warning lines, the details.
        const std::size_t first = r.report.find('\n');
        const std::size_t second = first == std::string::npos ? std::string::npos : r.report.find('\n', first + 1);
        std::size_t rest = second == std::string::npos ? r.report.size() : second + 1;
        for (std::size_t end; r.report.compare(rest, 8, "warning:") == 0 && (end = r.report.find('\n', rest)) != std::string::npos; rest = end + 1) {
            outcome.warnings.push_back(r.report.substr(rest + 8, end - rest - 8));
        }
        if (second != std::string::npos && r.report.compare(0, first, "ok") == 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0) {
            outcome.status = "done";
            outcome.device = r.report.substr(first + 1, second - first - 1);
            outcome.details = r.report.substr(rest);
            return outcome;
        }
        outcome.status = "failed";
        if (second != std::string::npos && r.report.compare(0, first, "failed") == 0) {
            outcome.error = r.report.substr(first + 1, second - first - 1);
        } else if (r.killed) {
            outcome.error = "timed out after " + secondsText(args_.timeout) + " and did not stop when cancelled: killed";
        } else if (WIFSIGNALED(status)) {
            const int sig = WTERMSIG(status);
            outcome.error = "crashed: signal " + std::to_string(sig) + " (" + strsignal(sig) + ")" +
                            (sig == SIGKILL ? ", perhaps the kernel's out-of-memory killer" : "");
        } else {
            outcome.error = "the baking process exited with status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                            " without a report";
        }
        return outcome;
    }

    const BatchArgs& args_;
    int threadsPerJob_;
    double memoryMiB_;
    std::vector<Running> running_;
};

std::string statusLine(const Outcome& o, double band, const batch::Shard& shard, const std::string& host) {
    std::string line = "{\"mesh\":" + batch::jsonString(o.task.mesh) + ",\"output\":" + batch::jsonString(o.task.output) +
                       ",\"status\":\"" + o.status + "\",\"seconds\":" + jsonNumber(std::round(o.seconds * 1000.0) / 1000.0) +
                       ",\"error\":" + (o.error.empty() ? "null" : batch::jsonString(o.error));
    std::string warnings;
    for (const std::string& warning : o.warnings) warnings += (warnings.empty() ? "" : ",") + batch::jsonString(warning);
    line += ",\"warnings\":[" + warnings + "]";
    line += "," + (o.details.empty() ? std::string("\"triangles\":null,\"dims\":null,\"origin\":null,\"voxel\":null,\"sign\":null,\"sign_reason\":null,\"device\":null")
                                     : o.details);
    line += std::string(",\"band\":") + (band > 0 ? jsonNumber(band) : "null");
    line += ",\"shard\":\"" + std::to_string(shard.index) + "/" + std::to_string(shard.count) + "\",\"host\":" + batch::jsonString(host) + "}";
    return line;
}

// ", band 3 voxels" for a band bake, "" for a dense one.
std::string bandText(double band) {
    if (!(band > 0)) return "";
    char text[48];
    std::snprintf(text, sizeof(text), ", band %g voxels", band);
    return text;
}

void printSummary(const std::vector<Outcome>& outcomes, std::size_t allTasks, const batch::Shard& shard, double band, double seconds) {
    std::map<std::string, std::size_t> counts{{"done", 0}, {"skipped", 0}, {"failed", 0}};
    for (const Outcome& o : outcomes) ++counts[o.status];
    std::printf("\nbatch summary: shard %d/%d, %zu of %zu meshes%s, %.1f s\n", shard.index, shard.count, outcomes.size(), allTasks,
                bandText(band).c_str(), seconds);
    std::printf("  %-8s %6zu\n  %-8s %6zu\n  %-8s %6zu\n", "done", counts["done"], "skipped", counts["skipped"], "failed", counts["failed"]);
    if (counts["done"] > 0) std::printf("  %.0f meshes per hour (baked meshes / wall time)\n", double(counts["done"]) * 3600.0 / seconds);
    std::vector<const Outcome*> baked;
    for (const Outcome& o : outcomes) {
        if (o.status == "done") baked.push_back(&o);
    }
    std::sort(baked.begin(), baked.end(), [](const Outcome* a, const Outcome* b) { return a->seconds > b->seconds; });
    for (std::size_t i = 0; i < std::min<std::size_t>(3, baked.size()); ++i) {
        std::printf("  %s %8.2f s  %s\n", i == 0 ? "slowest" : "       ", baked[i]->seconds, baked[i]->task.mesh.c_str());
    }
    for (const Outcome& o : outcomes) {
        if (o.status == "failed") std::printf("  failed   %s: %s\n", o.task.mesh.c_str(), o.error.c_str());
    }
}

int runBatch(const BatchArgs& args) {
    Stopwatch clock;
    checkBakeSettings(args.settings); // here, before any work, rather than by every mesh's bake
    if (args.settings.band > 0 && args.format == "samples") {
        throw Error("--band makes a field; --format samples makes samples without a grid (choose one)");
    }
    const std::string extension = formatExtensions.at(args.format);
    const std::vector<batch::Task> all = batch::planBatch(args.input, args.outDir, extension);
    const batch::Shard shard = batch::resolveShard(args.shard, args.shardCount, [](const char* name) { return std::getenv(name); });
    const std::vector<batch::Task> tasks = batch::tasksOfShard(all, shard);
    std::string statusPath = args.status;
    if (const std::size_t at = statusPath.find("{shard}"); at != std::string::npos) statusPath.replace(at, 7, std::to_string(shard.index));
    const std::string host = hostName();
    const int cpus = args.threads > 0 ? args.threads : availableCpus();
    const int threadsPerJob = std::max(1, cpus / args.jobs);
    const double memoryMiB = args.memoryMiB > 0 ? args.memoryMiB : double(usableMemoryBytes() >> 20) / args.jobs;
    removeStalePartials(tasks, host);
    std::printf("batch: %zu of %zu meshes in shard %d/%d, %d at a time with %d threads each%s\n", tasks.size(), all.size(),
                shard.index, shard.count, args.jobs, threadsPerJob, bandText(args.settings.band).c_str());
    std::fflush(stdout);

    std::vector<Outcome> outcomes;
    auto record = [&](const Outcome& o) {
        outcomes.push_back(o);
        std::printf("[%zu/%zu] %-7s %s -> %s (%.2f s%s%s)%s%s\n", outcomes.size(), tasks.size(), o.status.c_str(), o.task.mesh.c_str(),
                    o.task.output.c_str(), o.seconds, o.device.empty() ? "" : ", ", o.device.c_str(), o.error.empty() ? "" : ": ",
                    o.error.c_str());
        std::fflush(stdout);
        for (const std::string& warning : o.warnings) std::printf("  warning: %s\n", warning.c_str());
        std::fflush(stdout);
        if (!statusPath.empty()) batch::appendLine(statusPath, statusLine(o, args.settings.band, shard, host));
    };
    Scheduler scheduler(args, threadsPerJob, memoryMiB);
    std::size_t next = 0;
    while (next < tasks.size() || scheduler.runningCount() > 0) {
        while (next < tasks.size() && scheduler.runningCount() < std::size_t(args.jobs)) {
            const batch::Task& task = tasks[next++];
            std::error_code ec;
            if (!args.force && fs::is_regular_file(task.output, ec)) {
                record({task, "skipped", 0.0, "", "", "", {}});
                continue;
            }
            scheduler.start(task);
        }
        for (const Outcome& o : scheduler.wait()) record(o);
    }
    printSummary(outcomes, all.size(), shard, args.settings.band, clock.seconds());
    return std::any_of(outcomes.begin(), outcomes.end(), [](const Outcome& o) { return o.status == "failed"; }) ? 1 : 0;
}

} // namespace

void addBatchCommand(CLI::App& app, int& exitCode) {
    auto args = std::make_shared<BatchArgs>();
    CLI::App* batch = app.add_subcommand("batch", "Bake every mesh of a list or folder, one output each; resumable and sharded");
    batch->add_option("input", args->input, "A folder (every mesh below it) or a list file (one mesh per line, optionally MESH<TAB>OUTPUT)")
        ->required();
    batch->add_option("--out", args->outDir, "Output folder")->required();
    std::vector<std::string> formats;
    for (const auto& [name, ext] : formatExtensions) formats.push_back(name);
    batch->add_option("--format", args->format, "Output: a field (npz, npy, vdb, sdf, nrrd) or DeepSDF samples (samples, .npz)")
        ->check(CLI::IsMember(formats))
        ->capture_default_str();
    addBakeOptions(*batch, args->settings, args->threads);
    batch->add_option("--band", args->settings.band,
                      "A narrow-band bake: exact distances only within this many voxels of the surface (0 = dense); "
                      "vdb and npz keep it sparse, npy, sdf and nrrd get its dense form where it fits in memory")
        ->capture_default_str();
    addSampleOptions(*batch, args->sampling);
    batch->add_option("--samples", args->samples, "Samples per mesh for --format samples")->check(wholeNumber(1, std::uint64_t(1) << 34))->capture_default_str();
    batch->add_option("--jobs", args->jobs, "Meshes baked at a time; each gets threads / jobs threads")->check(CLI::Range(1, 1024))->capture_default_str();
    batch->add_option("--timeout", args->timeout, "Seconds per mesh before it is cancelled and recorded as failed (0 = none)")
        ->check(finiteRange(0.0, 1e9))
        ->capture_default_str();
    batch->add_option("--memory", args->memoryMiB, "Memory budget per mesh in MiB: address space beyond the program's own (0 = the memory this process may use / jobs)")
        ->check(finiteRange(0.0, 1e12))
        ->capture_default_str();
    batch->add_flag("--force", args->force, "Bake again even when the output exists");
    batch->add_option("--status", args->status, "Append one JSON line per mesh to this file ({shard} becomes the shard index)");
    batch->add_option("--shard", args->shard, "Bake only shard I of N (I/N, 0-based); default from SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX");
    batch->add_option("--shard-count", args->shardCount, "Shards for JOB_COMPLETION_INDEX (a Kubernetes Indexed Job's completions)")
        ->check(CLI::Range(1, 1 << 30));
    batch->footer("Meshes are sorted by path; the i-th belongs to shard i mod N. An output exists only once complete (written "
                  "beside it, then renamed), so a rerun skips finished meshes and redoes the rest. Exit status 1 if any mesh failed.");
    batch->callback([args, &exitCode] { exitCode = runBatch(*args); });
}

} // namespace sdfgen::cli
