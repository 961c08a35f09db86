// Batch planning: output names from folders and lists, collisions, sharding from options and the
// Slurm / Kubernetes environment, JSON strings and concurrent appends to the status file.
#include "cli/batch_plan.hpp"
#include "sdfgen/error.hpp"

#include "support/checks.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <sys/wait.h>
#include <unistd.h>

namespace sdfgen {
namespace {

using test::errorFrom;
namespace fs = std::filesystem;

class BatchPlan : public test::ScratchFolderTest {
protected:
    std::string touch(const std::string& relative) {
        fs::create_directories((dir_ / relative).parent_path());
        return write(relative, "v 0 0 0\n");
    }
    std::string out() const { return (dir_ / "out").string(); }
};

TEST_F(BatchPlan, FolderKeepsRelativePathsAndSorts) {
    touch("meshes/b.obj");
    touch("meshes/a/model.obj");
    touch("meshes/c/model.OBJ");
    touch("meshes/notes.txt");
    touch("meshes/a/model.mtl");
    touch("meshes/d.PLY");
    const auto tasks = batch::planBatch((dir_ / "meshes").string(), out(), ".npz");
    ASSERT_EQ(tasks.size(), 4u);
    EXPECT_EQ(tasks[0].mesh, (dir_ / "meshes/a/model.obj").string());
    EXPECT_EQ(tasks[0].output, (dir_ / "out/a/model.npz").string());
    EXPECT_EQ(tasks[1].output, (dir_ / "out/b.npz").string());
    EXPECT_EQ(tasks[2].output, (dir_ / "out/c/model.npz").string());
    EXPECT_EQ(tasks[3].output, (dir_ / "out/d.npz").string());
}

TEST_F(BatchPlan, FolderCollisionNamesBothMeshes) {
    touch("m/chair.obj");
    touch("m/chair.Obj");
    const std::string message = errorFrom([&] { batch::planBatch((dir_ / "m").string(), out(), ".npz"); });
    EXPECT_CONTAINS(message, "chair.obj");
    EXPECT_CONTAINS(message, "chair.Obj");
    EXPECT_CONTAINS(message, "would both be saved as");
}

TEST_F(BatchPlan, ListWithExplicitNamesCommentsAndDuplicates) {
    touch("data/x/model.obj");
    touch("data/y/model.obj");
    const std::string list = write("data/list.txt",
                                   "# dataset\n\nx/model.obj\ty-is-x.sdf\ny/model.obj\r\n" +
                                   (dir_ / "data/x/model.obj").string() + "\ty-is-x.sdf\n");
    const auto tasks = batch::planBatch(list, out(), ".sdf");
    ASSERT_EQ(tasks.size(), 2u); // the third line repeats the first
    EXPECT_EQ(tasks[0].mesh, (dir_ / "data/x/model.obj").string());
    EXPECT_EQ(tasks[0].output, (dir_ / "out/y-is-x.sdf").string());
    EXPECT_EQ(tasks[1].output, (dir_ / "out/y/model.sdf").string());
}

TEST_F(BatchPlan, ListErrorsNameTheLine) {
    const std::string clash = write("clash.txt", "a/m.obj\nb/m.obj\tm.npz\n/elsewhere/m.obj\n");
    // a/m.obj -> out/a/m.npz; b/m.obj -> out/m.npz; /elsewhere/m.obj (outside the list's folder) -> out/m.npz.
    const std::string message = errorFrom([&] { batch::planBatch(clash, out(), ".npz"); });
    EXPECT_CONTAINS(message, "/elsewhere/m.obj");
    EXPECT_CONTAINS(message, "b/m.obj");
    EXPECT_CONTAINS(message, "clash.txt:");
    EXPECT_CONTAINS(errorFrom([&] { batch::planBatch(write("ext.txt", "a.obj\ta.vdb\n"), out(), ".npz"); }),
                    "ext.txt:1: output name a.vdb does not end with .npz");
    EXPECT_CONTAINS(errorFrom([&] { batch::planBatch(write("tabs.txt", "\n\na.obj\tb.npz\tc\n"), out(), ".npz"); }), "tabs.txt:3:");
    EXPECT_CONTAINS(errorFrom([&] { batch::planBatch(write("empty.txt", "# nothing\n\n"), out(), ".npz"); }), "names no meshes");
    EXPECT_CONTAINS(errorFrom([&] { batch::planBatch((dir_ / "missing.txt").string(), out(), ".npz"); }), "missing.txt: no such file");
    EXPECT_CONTAINS(errorFrom([&] { batch::planBatch(touch("one.obj"), out(), ".npz"); }), "a mesh, not a list");
    fs::create_directories(dir_ / "empty");
    EXPECT_CONTAINS(errorFrom([&] { batch::planBatch((dir_ / "empty").string(), out(), ".npz"); }), "no mesh files");
}

TEST_F(BatchPlan, ListOutputsStayInsideTheOutputFolder) {
    touch("a.obj");
    EXPECT_CONTAINS(errorFrom([&] { batch::planBatch(write("up.txt", "# up\na.obj\t../x.npz\n"), out(), ".npz"); }),
                    "up.txt:2: output name ../x.npz has a '..' part");
    EXPECT_CONTAINS(errorFrom([&] { batch::planBatch(write("deep.txt", "a.obj\tsub/../../x.npz\n"), out(), ".npz"); }),
                    "deep.txt:1: output name sub/../../x.npz has a '..' part");
    EXPECT_CONTAINS(errorFrom([&] { batch::planBatch(write("abs.txt", "a.obj\t/abs/x.npz\n"), out(), ".npz"); }),
                    "abs.txt:1: output name /abs/x.npz is an absolute path");
    // Below --out, '..'-free names are kept as given.
    const auto tasks = batch::planBatch(write("ok.txt", "a.obj\tsub/x.npz\n"), out(), ".npz");
    ASSERT_EQ(tasks.size(), 1u);
    EXPECT_EQ(tasks[0].output, (dir_ / "out/sub/x.npz").string());
}

TEST_F(BatchPlan, FolderLinksAreFollowedOnceAndLoopsEnd) {
    touch("m/a.obj");
    touch("m/sub/b.obj");
    fs::create_directory_symlink("..", dir_ / "m/sub/loop");    // back up the tree
    fs::create_directory_symlink("../m", dir_ / "m/sub/again"); // a second loop, by another path
    fs::create_directories(dir_ / "elsewhere");
    touch("elsewhere/c.obj");
    fs::create_directory_symlink("../elsewhere", dir_ / "m/linked");   // a folder outside: followed
    fs::create_directory_symlink("../elsewhere", dir_ / "m/linked2");  // the same folder again: skipped
    const auto tasks = batch::planBatch((dir_ / "m").string(), out(), ".npz");
    std::vector<std::string> outputs;
    for (const batch::Task& task : tasks) outputs.push_back(task.output);
    EXPECT_EQ(outputs, (std::vector<std::string>{(dir_ / "out/a.npz").string(), (dir_ / "out/linked/c.npz").string(),
                                                 (dir_ / "out/sub/b.npz").string()}));
}

TEST(BatchShard, EveryTaskInExactlyOneBalancedShard) {
    std::vector<batch::Task> tasks;
    for (int i = 0; i < 103; ++i) tasks.push_back({"m" + std::to_string(1000 + i) + ".obj", "o" + std::to_string(i)});
    for (const int count : {1, 2, 4, 7, 200}) {
        std::map<std::string, int> owner;
        std::size_t smallest = tasks.size(), largest = 0;
        for (int index = 0; index < count; ++index) {
            const auto mine = batch::tasksOfShard(tasks, {index, count});
            smallest = std::min(smallest, mine.size());
            largest = std::max(largest, mine.size());
            for (const auto& task : mine) EXPECT_TRUE(owner.emplace(task.mesh, index).second) << task.mesh << " in two shards";
        }
        EXPECT_EQ(owner.size(), tasks.size());
        EXPECT_LE(largest - smallest, 1u);
    }
}

TEST(BatchShard, FromOptionSlurmAndKubernetes) {
    std::map<std::string, std::string> env;
    auto getenv = [&](const char* name) -> const char* {
        const auto it = env.find(name);
        return it == env.end() ? nullptr : it->second.c_str();
    };
    auto same = [](batch::Shard a, int index, int count) { return a.index == index && a.count == count; };
    EXPECT_TRUE(same(batch::resolveShard("", 0, getenv), 0, 1));
    EXPECT_TRUE(same(batch::resolveShard("2/5", 0, getenv), 2, 5));
    for (const char* bad : {"5/5", "-1/3", "1", "a/b", "1/0", "1/2/3"}) {
        EXPECT_CONTAINS(errorFrom([&] { batch::resolveShard(bad, 0, getenv); }), "--shard");
    }
    env = {{"SLURM_ARRAY_TASK_ID", "3"}, {"SLURM_ARRAY_TASK_COUNT", "4"}};
    EXPECT_TRUE(same(batch::resolveShard("", 0, getenv), 3, 4));
    EXPECT_TRUE(same(batch::resolveShard("0/2", 0, getenv), 0, 2)); // the option wins
    env = {{"SLURM_ARRAY_TASK_ID", "14"}, {"SLURM_ARRAY_TASK_COUNT", "4"}, {"SLURM_ARRAY_TASK_MIN", "10"}, {"SLURM_ARRAY_TASK_STEP", "2"}};
    EXPECT_TRUE(same(batch::resolveShard("", 0, getenv), 2, 4)); // --array=10-16:2
    env["SLURM_ARRAY_TASK_ID"] = "15";
    EXPECT_CONTAINS(errorFrom([&] { batch::resolveShard("", 0, getenv); }), "Slurm array task 15");
    env = {{"SLURM_ARRAY_TASK_ID", "1"}};
    EXPECT_CONTAINS(errorFrom([&] { batch::resolveShard("", 0, getenv); }), "SLURM_ARRAY_TASK_COUNT");
    env = {{"JOB_COMPLETION_INDEX", "6"}};
    EXPECT_TRUE(same(batch::resolveShard("", 8, getenv), 6, 8));
    EXPECT_CONTAINS(errorFrom([&] { batch::resolveShard("", 0, getenv); }), "--shard-count");
    EXPECT_CONTAINS(errorFrom([&] { batch::resolveShard("", 6, getenv); }), "not below --shard-count 6");
    env.clear();
    EXPECT_CONTAINS(errorFrom([&] { batch::resolveShard("", 4, getenv); }), "JOB_COMPLETION_INDEX");
}

TEST(BatchJson, StringsAreEscaped) {
    EXPECT_EQ(batch::jsonString("a\"b\\c\nd\te\x01 é"), "\"a\\\"b\\\\c\\nd\\te\\u0001 é\"");
}

TEST_F(BatchPlan, ConcurrentAppendsNeverInterleave) {
    const std::string path = (dir_ / "status.jsonl").string();
    constexpr int processes = 4, lines = 200;
    std::vector<pid_t> children;
    for (int p = 0; p < processes; ++p) {
        const pid_t pid = fork();
        ASSERT_GE(pid, 0);
        if (pid == 0) {
            for (int i = 0; i < lines; ++i) {
                batch::appendLine(path, "{\"writer\":" + std::to_string(p) + ",\"i\":" + std::to_string(i) + ",\"pad\":\"" +
                                            std::string(std::size_t(100 + 37 * p), char('a' + p)) + "\"}");
            }
            _exit(0);
        }
        children.push_back(pid);
    }
    for (const pid_t pid : children) {
        int status = 0;
        waitpid(pid, &status, 0);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    }
    std::ifstream in(path);
    std::set<std::string> seen;
    std::string line;
    while (std::getline(in, line)) {
        const int writer = line[10] - '0';
        const std::string expected = std::string(std::size_t(100 + 37 * writer), char('a' + writer)) + "\"}";
        ASSERT_GE(line.size(), expected.size());
        EXPECT_EQ(line.substr(line.size() - expected.size()), expected) << line;
        EXPECT_TRUE(seen.insert(line).second);
    }
    EXPECT_EQ(seen.size(), std::size_t(processes * lines));
    EXPECT_CONTAINS(errorFrom([&] { batch::appendLine((dir_ / "no/such/folder/s.jsonl").string(), "x"); }), "cannot open for appending");
}

} // namespace
} // namespace sdfgen
