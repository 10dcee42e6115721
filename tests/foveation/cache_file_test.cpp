// The cache writer (temp file + fsync + rename) and the default cache
// directory, against its known hazards: a symlink planted at the temp or
// final name, concurrent writers, failures that leave files behind, and the
// shared /tmp fallback.
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cache_file.hpp"
#include "foveation/cache_dir.hpp"

namespace fv = foveart::foveation;
namespace fs = std::filesystem;

namespace {

class CacheFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("foveart_cache_file_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    ::chmod(dir_.c_str(), 0755);
    fs::remove_all(dir_);
  }

  // Sized read: GCC 12 -O2 flags istreambuf_iterator's streambuf as a possible null dereference.
  static std::string read(const fs::path& f) {
    std::error_code ec;
    const auto size = fs::file_size(f, ec);
    if (ec) return {};
    std::string bytes(size, '\0');
    std::ifstream in(f, std::ios::binary);
    in.read(bytes.data(), std::streamsize(bytes.size()));
    bytes.resize(std::size_t(in.gcount()));
    return bytes;
  }
  static void write_text(const fs::path& f, const std::string& text) { std::ofstream(f, std::ios::binary) << text; }
  static std::string write(const fs::path& f, const std::string& text) {
    const fv::detail::ByteSpan piece{text.data(), text.size()};
    return fv::detail::write_file_atomically(f, std::span(&piece, 1));
  }
  // Every entry of the directory but the named ones: leftovers.
  std::vector<std::string> others(std::initializer_list<std::string> expected) const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string n = e.path().filename().string();
      if (std::find(expected.begin(), expected.end(), n) == expected.end()) names.push_back(n);
    }
    return names;
  }

  fs::path dir_;
};

TEST_F(CacheFileTest, WritesTheBytesAndLeavesNoTempFile) {
  ASSERT_EQ(write(dir_ / "sub" / "a.bin", "hello"), "");
  EXPECT_EQ(read(dir_ / "sub" / "a.bin"), "hello");
  EXPECT_TRUE(others({"sub"}).empty());
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_ / "sub"), {}), 1);
}

TEST_F(CacheFileTest, SymlinkAtTheFormerTempNameIsNotFollowed) {
  const fs::path victim = dir_ / "victim";
  write_text(victim, "precious");
  fs::create_symlink(victim, dir_ / "a.bin.tmp");
  ASSERT_EQ(write(dir_ / "a.bin", "cache bytes"), "");
  EXPECT_EQ(read(victim), "precious");
  EXPECT_EQ(read(dir_ / "a.bin"), "cache bytes");
}

TEST_F(CacheFileTest, SymlinkAtTheFinalNameIsReplacedNotFollowed) {
  const fs::path victim = dir_ / "victim";
  write_text(victim, "precious");
  fs::create_symlink(victim, dir_ / "a.bin");
  ASSERT_EQ(write(dir_ / "a.bin", "cache bytes"), "");
  EXPECT_EQ(read(victim), "precious");
  EXPECT_FALSE(fs::is_symlink(dir_ / "a.bin"));
  EXPECT_EQ(read(dir_ / "a.bin"), "cache bytes");
}

TEST_F(CacheFileTest, FailedRenameLeavesNothingAndNamesTheFile) {
  fs::create_directories(dir_ / "a.bin" / "occupied");  // a non-empty directory cannot be renamed over
  const std::string error = write(dir_ / "a.bin", "cache bytes");
  EXPECT_NE(error.find((dir_ / "a.bin").string()), std::string::npos) << error;
  EXPECT_TRUE(others({"a.bin"}).empty());
}

TEST_F(CacheFileTest, FailedWriteLeavesNothing) {
  // A child limited to 4 KiB files: the write fails with EFBIG part-way.
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    const std::string error = write(dir_ / "a.bin", std::string(1 << 20, 'x'));
    ::_exit(error.find("write failed") != std::string::npos ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "the child's write did not fail with 'write failed'";
  EXPECT_TRUE(others({}).empty());
}

TEST_F(CacheFileTest, ConcurrentWritersNeverExposeAPartialFile) {
  // Two processes write the same cache file, 4 MiB of 'a' or of 'b', again and
  // again; every read of the final name sees one of them whole.
  constexpr std::size_t kSize = std::size_t{4} << 20;
  std::vector<pid_t> children;
  for (char c : {'a', 'b'}) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      const std::string bytes(kSize, c);
      bool ok = true;
      for (int i = 0; i < 6; ++i) ok = ok && write(dir_ / "a.bin", bytes).empty();
      ::_exit(ok ? 0 : 1);
    }
    children.push_back(child);
  }
  int reads = 0, partial = 0, running = 2;
  while (running > 0) {
    std::string why;
    if (auto m = fv::detail::map_file(dir_ / "a.bin", &why)) {
      ++reads;
      const bool whole = m->size == kSize && (m->bytes[0] == 'a' || m->bytes[0] == 'b') &&
                         std::all_of(m->bytes, m->bytes + m->size, [&](std::uint8_t b) { return b == m->bytes[0]; });
      if (!whole) ++partial;
    }
    running = 0;
    for (pid_t& child : children) {
      int status = 0;
      if (child > 0 && ::waitpid(child, &status, WNOHANG) == child) {
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
        child = 0;
      }
      if (child > 0) ++running;
    }
  }
  EXPECT_EQ(partial, 0) << "of " << reads << " reads";
  EXPECT_EQ(fs::file_size(dir_ / "a.bin"), kSize);
  EXPECT_TRUE(others({"a.bin"}).empty());
}

TEST_F(CacheFileTest, PrivateDirIsCreatedUserOnly) {
  const fs::path d = dir_ / "foveart-me";
  std::string why;
  ASSERT_TRUE(fv::private_cache_dir(d, &why).has_value()) << why;
  struct stat st {};
  ASSERT_EQ(::lstat(d.c_str(), &st), 0);
  EXPECT_TRUE(S_ISDIR(st.st_mode));
  EXPECT_EQ(st.st_mode & 0777, 0700u);
  EXPECT_TRUE(fv::private_cache_dir(d, &why).has_value()) << "an existing private directory is reused: " << why;
}

TEST_F(CacheFileTest, PrivateDirRefusesASymlink) {
  fs::create_directories(dir_ / "elsewhere");
  ::chmod((dir_ / "elsewhere").c_str(), 0700);
  fs::create_directory_symlink(dir_ / "elsewhere", dir_ / "foveart-me");
  std::string why;
  EXPECT_FALSE(fv::private_cache_dir(dir_ / "foveart-me", &why).has_value());
  EXPECT_NE(why.find("symlink"), std::string::npos) << why;
  EXPECT_NE(why.find((dir_ / "foveart-me").string()), std::string::npos) << why;
}

TEST_F(CacheFileTest, PrivateDirRefusesGroupOrWorldWritable) {
  const fs::path d = dir_ / "foveart-me";
  fs::create_directories(d);
  ::chmod(d.c_str(), 01777);
  std::string why;
  EXPECT_FALSE(fv::private_cache_dir(d, &why).has_value());
  EXPECT_NE(why.find("writable"), std::string::npos) << why;
}

TEST_F(CacheFileTest, PrivateDirRefusesAnotherOwner) {
  const fs::path d = dir_ / "foveart-me";
  fs::create_directories(d);
  ::chmod(d.c_str(), 0700);
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to give the directory to another user";
  ASSERT_EQ(::chown(d.c_str(), 65534, 65534), 0);
  std::string why;
  EXPECT_FALSE(fv::private_cache_dir(d, &why).has_value());
  EXPECT_NE(why.find("owned by uid 65534"), std::string::npos) << why;
}

TEST_F(CacheFileTest, PrivateDirRefusesAFile) {
  write_text(dir_ / "foveart-me", "x");
  std::string why;
  EXPECT_FALSE(fv::private_cache_dir(dir_ / "foveart-me", &why).has_value());
  EXPECT_NE(why.find("not a directory"), std::string::npos) << why;
}

// Environment variables of one test, restored afterwards.
class ScopedEnv {
 public:
  void set(const char* name, const char* value) {
    if (const char* old = std::getenv(name)) saved_.emplace_back(name, std::string(old));
    else saved_.emplace_back(name, std::nullopt);
    if (value) ::setenv(name, value, 1);
    else ::unsetenv(name);
  }
  ~ScopedEnv() {
    for (auto it = saved_.rbegin(); it != saved_.rend(); ++it) {
      if (it->second) ::setenv(it->first.c_str(), it->second->c_str(), 1);
      else ::unsetenv(it->first.c_str());
    }
  }

 private:
  std::vector<std::pair<std::string, std::optional<std::string>>> saved_;
};

TEST(DefaultCacheDir, XdgThenHomeThenPerUserTmp) {
  ScopedEnv env;
  std::string why;
  env.set("XDG_CACHE_HOME", "/x/cache");
  env.set("HOME", "/home/u");
  EXPECT_EQ(fv::default_cache_dir(&why), fs::path("/x/cache/foveart"));
  env.set("XDG_CACHE_HOME", "relative/cache");  // the XDG spec ignores a relative path
  EXPECT_EQ(fv::default_cache_dir(&why), fs::path("/home/u/.cache/foveart"));
  env.set("XDG_CACHE_HOME", nullptr);
  EXPECT_EQ(fv::default_cache_dir(&why), fs::path("/home/u/.cache/foveart"));
  env.set("HOME", nullptr);
  const auto dir = fv::default_cache_dir(&why);
  ASSERT_TRUE(dir.has_value()) << why;
  EXPECT_EQ(*dir, fs::path("/tmp/foveart-" + std::to_string(::geteuid())));
  EXPECT_NE(*dir, fs::path("/tmp/foveart")) << "never the shared name";
}

}  // namespace
