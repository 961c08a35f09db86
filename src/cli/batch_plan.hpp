#pragma once
// Planning a batch: which meshes, which output each gets, which shard bakes it, and the status
// file's JSON lines. Running the plan (one child process per mesh) is the CLI's part (batch.cpp).
#include <functional>
#include <string>
#include <vector>

namespace sdfgen::batch {

// One mesh and the path of its output.
struct Task {
    std::string mesh;
    std::string output;
    bool operator<(const Task& other) const { return mesh < other.mesh || (mesh == other.mesh && output < other.output); }
    bool operator==(const Task& other) const { return mesh == other.mesh && output == other.output; }
};

// Whether `path` names a mesh file sdfgen reads (an extension meshFormatExtensions lists,
// case-insensitive).
bool isMeshFile(const std::string& path);

// The tasks for `input`, sorted by mesh path, duplicates removed:
// - a folder: every mesh file below it (recursively, through symbolic links to folders, each
//   folder read once, so link loops end); the output keeps its path relative to the folder, with
//   `extension` in place of the mesh's (chairs/a/model.obj -> OUT/a/model.npz);
// - a list file: one mesh per line (blank lines and lines starting with '#' are skipped), relative
//   paths taken from the list's folder; optionally a TAB and an explicit output name relative to
//   `outDir`, which must end with `extension` and stay inside `outDir` (no absolute path, no '..'). Without one, the output keeps the mesh's path
//   relative to the list's folder, or only its file name for a mesh outside that folder.
// Throws Error naming the list (and line) or folder for anything wrong, including two meshes that
// would write the same output.
std::vector<Task> planBatch(const std::string& input, const std::string& outDir, const std::string& extension);

// Shard `index` of `count` (0 <= index < count).
struct Shard {
    int index = 0;
    int count = 1;
};

// Parses "I/N"; Error for anything else.
Shard parseShard(const std::string& text);

// The shard this process bakes: `--shard I/N` when given; else a Slurm job array's task
// (SLURM_ARRAY_TASK_ID, _MIN, _STEP and _COUNT); else a Kubernetes Indexed Job's
// JOB_COMPLETION_INDEX with `shardCount` (which it needs); else the whole list (0/1). `getenv`
// reads the environment (a parameter for tests).
Shard resolveShard(const std::string& shardOption, int shardCount, const std::function<const char*(const char*)>& getenv);

// The tasks of `shard` in a list sorted by planBatch: the i-th task belongs to shard i mod count.
// Every task is in exactly one shard, the shards' sizes differ by at most one, and the split
// depends only on the set of meshes, not on the order they were listed in.
std::vector<Task> tasksOfShard(const std::vector<Task>& tasks, Shard shard);

// `text` as a JSON string literal, quotes included (control characters escaped, UTF-8 kept).
std::string jsonString(const std::string& text);

// Appends `line` and a newline to `path` with one write() on a file opened with O_APPEND, so lines
// from concurrent processes on one machine never interleave. Throws Error naming the file.
void appendLine(const std::string& path, const std::string& line);

} // namespace sdfgen::batch
