// core/atomic_file: a writer killed with SIGKILL at any moment leaves the old
// file or none, never a truncated one. The writers here are real child
// processes (fork) killed with a real SIGKILL.
#include "pheromesh/core/atomic_file.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <thread>

#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

namespace fs = std::filesystem;

class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    dir_ = fs::temp_directory_path() / ("pheromesh-atomic-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    fs::create_directories(dir_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] std::string file(const std::string& name) const { return (dir_ / name).string(); }
  [[nodiscard]] const fs::path& path() const { return dir_; }

 private:
  fs::path dir_;
};

using test::slurp;

// 1 MiB that differs from `old` everywhere, so any prefix is told apart.
std::string new_content() { return std::string(1 << 20, 'N'); }
const std::string kOld = "the previous metrics.json\n";

// Runs `body` in a child process that writes one byte to a pipe when `body`
// calls `ready()`, then waits to be killed. The parent kills it with SIGKILL
// once ready (or after `delay` when `delay` is set and ready never comes).
// Returns true if the child died of SIGKILL.
bool run_and_kill(const std::function<void(const std::function<void()>&)>& body) {
  int fds[2];
  if (::pipe(fds) != 0) return false;
  const pid_t pid = ::fork();
  if (pid < 0) return false;
  if (pid == 0) {
    ::close(fds[0]);
    body([&] {
      const char b = 'r';
      (void)!::write(fds[1], &b, 1);
      for (int i = 0; i < 300; ++i) ::usleep(100000);  // bounded: 30 s, the parent kills it long before
    });
    ::_exit(0);
  }
  ::close(fds[1]);
  char b = 0;
  const bool ready = ::read(fds[0], &b, 1) == 1;
  ::close(fds[0]);
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return ready && WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
}

TEST(AtomicFile, WriteThenCommitReplacesTheFileAndLeavesNoTemporary) {
  TempDir dir;
  const std::string path = dir.file("metrics.json");
  ASSERT_TRUE(write_file_atomically(path, kOld).ok());
  const auto n = write_file_atomically(path, "new\n");
  ASSERT_TRUE(n.ok()) << n.error().message;
  EXPECT_EQ(n.value(), 4U);
  EXPECT_EQ(slurp(path), "new\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);
}

TEST(AtomicFile, AnUncommittedFileLeavesTheOldOneAndRemovesItsTemporary) {
  TempDir dir;
  const std::string path = dir.file("report.md");
  ASSERT_TRUE(write_file_atomically(path, kOld).ok());
  std::string temp;
  {
    auto f = AtomicFile::create(path);
    ASSERT_TRUE(f.ok()) << f.error().message;
    temp = f->temp_path();
    EXPECT_EQ(fs::path(temp).parent_path(), fs::path(path).parent_path());
    f->write("half a rep");
    f->flush();
    EXPECT_TRUE(fs::exists(temp));
  }
  EXPECT_FALSE(fs::exists(temp));
  EXPECT_EQ(slurp(path), kOld);
}

TEST(AtomicFile, ErrorsNameTheFile) {
  TempDir dir;
  const std::string blocked = dir.file("not-a-dir");
  ASSERT_TRUE(write_file_atomically(blocked, "x").ok());
  const auto r = write_file_atomically(blocked + "/metrics.json", "{}");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find(blocked), std::string::npos) << r.error().message;
}

TEST(AtomicFile, WriterKilledMidWriteLeavesTheOldFile) {
  TempDir dir;
  const std::string path = dir.file("metrics.json");
  ASSERT_TRUE(write_file_atomically(path, kOld).ok());
  ASSERT_TRUE(run_and_kill([&](const std::function<void()>& ready) {
    auto f = AtomicFile::create(path);
    if (!f) ::_exit(3);
    const std::string big = new_content();
    f->write(std::string_view(big).substr(0, big.size() / 2));
    f->flush();
    ready();  // killed here, half written
  }));
  EXPECT_EQ(slurp(path), kOld);
}

TEST(AtomicFile, WriterKilledMidWriteOfANewFileLeavesNone) {
  TempDir dir;
  const std::string path = dir.file("final_field.txt");
  ASSERT_TRUE(run_and_kill([&](const std::function<void()>& ready) {
    auto f = AtomicFile::create(path);
    if (!f) ::_exit(3);
    f->write("# pheromesh final field 1024 x 1024\nlayer target\n0 0 0");
    f->flush();
    ready();
  }));
  EXPECT_FALSE(fs::exists(path));
}

// Kills writers at random moments of the whole write-and-commit, commit
// included: every outcome must be the old file or the whole new one.
TEST(AtomicFile, WritersKilledAtRandomMomentsLeaveTheOldFileOrTheWholeNewOne) {
  TempDir dir;
  const std::string path = dir.file("metrics.json");
  const std::string fresh = new_content();
  std::mt19937 rng(16);
  std::uniform_int_distribution<int> delay_us(0, 20000);
  int old_seen = 0, new_seen = 0;
  for (int round = 0; round < 20; ++round) {
    ASSERT_TRUE(write_file_atomically(path, kOld).ok());
    const int d = delay_us(rng);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      for (int k = 0; k < 200; ++k) {  // bounded; the parent kills it first
        if (!write_file_atomically(path, fresh)) ::_exit(3);
        if (!write_file_atomically(path, kOld)) ::_exit(3);
      }
      ::_exit(0);
    }
    std::this_thread::sleep_for(std::chrono::microseconds(d));
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << "round " << round << ": the writer finished before it was killed";
    const std::string got = slurp(path);
    ASSERT_TRUE(got == kOld || got == fresh) << "round " << round << ": " << got.size() << " bytes, neither file";
    (got == kOld ? old_seen : new_seen)++;
  }
  std::printf("killed 20 writers: the old file left %d times, the new one %d times, never a cut one\n", old_seen,
              new_seen);
}

// Guard: the same kill against a plain truncate-and-write leaves a cut file,
// so the tests above can tell one from a whole file.
TEST(AtomicFile, GuardAPlainWriterKilledMidWriteLeavesATruncatedFile) {
  TempDir dir;
  const std::string path = dir.file("metrics.json");
  ASSERT_TRUE(write_file_atomically(path, kOld).ok());
  ASSERT_TRUE(run_and_kill([&](const std::function<void()>& ready) {
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (f == nullptr) ::_exit(3);
    const std::string big = new_content();
    std::fwrite(big.data(), 1, big.size() / 2, f);
    std::fflush(f);
    ready();
  }));
  const std::string got = slurp(path);
  EXPECT_NE(got, kOld);
  EXPECT_NE(got, new_content());
  EXPECT_EQ(got.size(), new_content().size() / 2);
}

}  // namespace
}  // namespace pheromesh::core
