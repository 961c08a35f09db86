#include "cli/batch_plan.hpp"
#include "sdfgen/error.hpp"
#include "core/runtime/file_extension.hpp"
#include "sdfgen/mesh.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sys/stat.h>
#include <unistd.h>

namespace sdfgen::batch {

namespace fs = std::filesystem;

namespace {

bool endsWith(const std::string& text, const std::string& suffix) {
    return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// `mesh` relative to `base`, when it lies inside it (lexically); empty otherwise.
fs::path insideOf(const fs::path& mesh, const fs::path& base) {
    const fs::path relative = mesh.lexically_normal().lexically_relative(base.lexically_normal());
    if (relative.empty() || *relative.begin() == "..") return {};
    return relative;
}

// Where each output came from, to name both meshes when two would write the same file.
class OutputNames {
public:
    void add(const Task& task, const std::string& where) {
        const auto [it, inserted] = owners_.emplace(task.output, task.mesh);
        if (!inserted && it->second != task.mesh) {
            throw Error(where + ": meshes " + it->second + " and " + task.mesh + " would both be saved as " + task.output +
                        "; give explicit output names in a list (MESH<TAB>OUTPUT)");
        }
    }

private:
    std::map<std::string, std::string> owners_;
};

std::vector<Task> sortedUnique(std::vector<Task> tasks) {
    std::sort(tasks.begin(), tasks.end());
    tasks.erase(std::unique(tasks.begin(), tasks.end()), tasks.end());
    return tasks;
}

// The mesh files below `folder`, following symbolic links to folders but reading each folder (by
// device and inode) once: a link back up the tree, or a second link to a folder already read, is
// skipped, so that loops end and no mesh is baked twice. Entries are visited in name order, so the
// path a folder is read under does not depend on the file system's order.
void findMeshes(const fs::path& folder, const fs::path& top, std::set<std::pair<dev_t, ino_t>>& visited, std::vector<fs::path>& meshes) {
    struct stat info{};
    if (::stat(folder.c_str(), &info) != 0 || !visited.insert({info.st_dev, info.st_ino}).second) return;
    std::error_code ec;
    std::vector<fs::path> entries;
    for (fs::directory_iterator it(folder, ec), end; it != end; it.increment(ec)) {
        if (ec) break;
        entries.push_back(it->path());
    }
    if (ec) throw Error(folder == top ? top.string() + ": cannot read the folder: " + ec.message()
                                      : folder.string() + ": cannot read the folder (below " + top.string() + "): " + ec.message());
    std::sort(entries.begin(), entries.end());
    for (const fs::path& entry : entries) {
        const fs::file_status status = fs::status(entry, ec); // through links; a dangling link is skipped
        if (fs::is_directory(status)) findMeshes(entry, top, visited, meshes);
        else if (fs::is_regular_file(status) && isMeshFile(entry.string())) meshes.push_back(entry);
    }
}

std::vector<Task> planFolder(const fs::path& folder, const fs::path& outDir, const std::string& extension) {
    std::vector<Task> tasks;
    std::set<std::pair<dev_t, ino_t>> visited;
    std::vector<fs::path> meshes;
    findMeshes(folder, folder, visited, meshes);
    for (const fs::path& mesh : meshes) {
        fs::path relative = insideOf(mesh, folder);
        relative.replace_extension(extension);
        tasks.push_back({mesh.lexically_normal().string(), (outDir / relative).lexically_normal().string()});
    }
    tasks = sortedUnique(std::move(tasks));
    OutputNames names;
    for (const Task& task : tasks) names.add(task, folder.string());
    if (tasks.empty()) throw Error(folder.string() + ": no mesh files in the folder");
    return tasks;
}

std::vector<Task> planList(const fs::path& list, const fs::path& outDir, const std::string& extension) {
    std::ifstream in(list);
    if (!in) throw Error(list.string() + ": cannot open: " + std::strerror(errno));
    const fs::path base = list.parent_path().empty() ? fs::path(".") : list.parent_path();
    std::vector<std::pair<Task, std::string>> tasks; // with where each came from
    std::string line;
    for (std::size_t number = 1; std::getline(in, line); ++number) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const std::string where = list.string() + ":" + std::to_string(number);
        const std::size_t first = line.find_first_not_of(" \t");
        if (first == std::string::npos || line[first] == '#') continue;
        if (line.find('\0') != std::string::npos) throw Error(where + ": the line holds a NUL byte (not a text list)");
        const std::size_t tab = line.find('\t');
        const fs::path given = line.substr(0, tab);
        if (given.empty()) throw Error(where + ": no mesh path before the TAB");
        const fs::path mesh = (given.is_absolute() ? given : base / given).lexically_normal();
        fs::path output;
        if (tab != std::string::npos) {
            const std::string name = line.substr(tab + 1);
            if (name.empty() || name.find('\t') != std::string::npos) {
                throw Error(where + ": expected MESH or MESH<TAB>OUTPUT, got more than one TAB or an empty output");
            }
            if (!endsWith(name, extension)) throw Error(where + ": output name " + name + " does not end with " + extension);
            // Outputs stay inside the output folder: no absolute path, no way up out of it.
            const fs::path relative(name);
            if (relative.is_absolute() || relative.has_root_name() || relative.has_root_directory()) {
                throw Error(where + ": output name " + name + " is an absolute path; give it relative to the output folder");
            }
            if (std::any_of(relative.begin(), relative.end(), [](const fs::path& part) { return part == ".."; })) {
                throw Error(where + ": output name " + name + " has a '..' part; it must stay inside the output folder");
            }
            output = outDir / relative;
        } else {
            fs::path relative = insideOf(mesh, base);
            if (relative.empty()) relative = mesh.filename();
            relative.replace_extension(extension);
            output = outDir / relative;
        }
        tasks.push_back({{mesh.string(), output.lexically_normal().string()}, where});
    }
    if (in.bad()) throw Error(list.string() + ": read error");
    std::sort(tasks.begin(), tasks.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    OutputNames names;
    std::vector<Task> unique;
    for (const auto& [task, where] : tasks) {
        if (!unique.empty() && unique.back() == task) continue;
        names.add(task, where);
        unique.push_back(task);
    }
    if (unique.empty()) throw Error(list.string() + ": the list names no meshes");
    return unique;
}

int parsePositive(const char* text, const std::string& what, bool allowZero) {
    char* end = nullptr;
    errno = 0;
    const long value = std::strtol(text, &end, 10);
    if (end == text || *end != '\0' || errno != 0 || value < (allowZero ? 0 : 1) || value > (1 << 30)) {
        throw Error(what + " must be " + (allowZero ? "a whole number >= 0" : "a whole number >= 1") + " (got '" + text + "')");
    }
    return int(value);
}

} // namespace

bool isMeshFile(const std::string& path) {
    // The formats loadMesh names in its errors (its own readers', and the common ones it reads
    // through Assimp); a folder scan must not pick up textures, materials or glTF buffers.
    static const std::vector<std::string> extensions = meshFormatExtensions();
    return std::find(extensions.begin(), extensions.end(), lowerExtension(path)) != extensions.end();
}

std::vector<Task> planBatch(const std::string& input, const std::string& outDir, const std::string& extension) {
    std::error_code ec;
    const fs::file_status status = fs::status(input, ec);
    if (!fs::exists(status)) throw Error(input + ": no such file or folder");
    if (fs::is_directory(status)) return planFolder(input, outDir, extension);
    if (isMeshFile(input)) throw Error(input + ": a mesh, not a list of meshes (give a list file or a folder)");
    return planList(input, outDir, extension);
}

Shard parseShard(const std::string& text) {
    const std::size_t slash = text.find('/');
    if (slash == std::string::npos) throw Error("--shard must be I/N, e.g. 0/4 (got '" + text + "')");
    Shard shard;
    shard.index = parsePositive(text.substr(0, slash).c_str(), "--shard's index", true);
    shard.count = parsePositive(text.substr(slash + 1).c_str(), "--shard's count", false);
    if (shard.index >= shard.count) throw Error("--shard " + text + ": the index must be below the count (shards are 0 to N-1)");
    return shard;
}

Shard resolveShard(const std::string& shardOption, int shardCount, const std::function<const char*(const char*)>& getenv) {
    if (!shardOption.empty()) return parseShard(shardOption);
    if (const char* id = getenv("SLURM_ARRAY_TASK_ID")) {
        const char* count = getenv("SLURM_ARRAY_TASK_COUNT");
        if (!count) throw Error("SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not");
        const char* min = getenv("SLURM_ARRAY_TASK_MIN");
        const char* step = getenv("SLURM_ARRAY_TASK_STEP");
        // --array=A-B:S numbers the tasks A, A+S, ...; the shard is the task's position in that range.
        const int taskId = parsePositive(id, "SLURM_ARRAY_TASK_ID", true);
        const int first = min ? parsePositive(min, "SLURM_ARRAY_TASK_MIN", true) : 0;
        const int stride = step ? parsePositive(step, "SLURM_ARRAY_TASK_STEP", false) : 1;
        Shard shard;
        shard.count = parsePositive(count, "SLURM_ARRAY_TASK_COUNT", false);
        if (taskId < first || (taskId - first) % stride != 0 || (taskId - first) / stride >= shard.count) {
            throw Error("the Slurm array task " + std::string(id) + " is not one of " + count + " tasks from " +
                        std::to_string(first) + " in steps of " + std::to_string(stride) +
                        " (use --array=0-N or --array=A-B:S, without gaps)");
        }
        shard.index = (taskId - first) / stride;
        return shard;
    }
    if (const char* index = getenv("JOB_COMPLETION_INDEX")) {
        if (shardCount < 1) throw Error("JOB_COMPLETION_INDEX is set: give --shard-count N (the Indexed Job's completions)");
        Shard shard{parsePositive(index, "JOB_COMPLETION_INDEX", true), shardCount};
        if (shard.index >= shard.count) {
            throw Error("JOB_COMPLETION_INDEX " + std::string(index) + " is not below --shard-count " + std::to_string(shardCount));
        }
        return shard;
    }
    if (shardCount > 1) throw Error("--shard-count needs JOB_COMPLETION_INDEX (a Kubernetes Indexed Job); otherwise use --shard I/N");
    return {};
}

std::vector<Task> tasksOfShard(const std::vector<Task>& tasks, Shard shard) {
    std::vector<Task> mine;
    for (std::size_t i = std::size_t(shard.index); i < tasks.size(); i += std::size_t(shard.count)) mine.push_back(tasks[i]);
    return mine;
}

std::string jsonString(const std::string& text) {
    std::string out = "\"";
    for (const char c : text) {
        switch (c) {
        case '"': out += "\\\""; break;
        case '\\': out += "\\\\"; break;
        case '\n': out += "\\n"; break;
        case '\r': out += "\\r"; break;
        case '\t': out += "\\t"; break;
        default:
            if (static_cast<unsigned char>(c) < 0x20) {
                char escaped[8];
                std::snprintf(escaped, sizeof(escaped), "\\u%04x", unsigned(static_cast<unsigned char>(c)));
                out += escaped;
            } else {
                out += c;
            }
        }
    }
    return out + "\"";
}

void appendLine(const std::string& path, const std::string& line) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0) throw Error(path + ": cannot open for appending: " + std::strerror(errno));
    const std::string text = line + "\n";
    const ssize_t written = ::write(fd, text.data(), text.size());
    const int writeError = errno;
    ::close(fd);
    if (written != ssize_t(text.size())) {
        throw Error(path + ": cannot append: " + (written < 0 ? std::strerror(writeError) : "short write"));
    }
}

} // namespace sdfgen::batch
